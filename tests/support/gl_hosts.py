"""The real shader hosts the export tests run: GStreamer's glshader under Xvfb on
Mesa's llvmpipe, and glslangValidator inside the preludes an ISF host (VVISF)
puts before an ISF file's body."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import cv2
import numpy as np

#: What the tests need; a test module skips without them.
TOOLS = ("gst-launch-1.0", "xvfb-run", "glslangValidator")
#: A GLSL 3.30 vertex shader for glshader (as the export writes beside a .frag).
VERTEX = """#version 330
in vec4 a_position;
in vec2 a_texcoord;
out vec2 v_texcoord;
void main() { gl_Position = a_position; v_texcoord = a_texcoord; }
"""
#: ISF's built-ins on glshader's uniforms: how the tests stand in for an ISF host's
#: own wrapping (v_texcoord has (0, 0) at the top-left, ISF at the bottom-left).
ISF_ON_GLSHADER = """#version 330
uniform sampler2D tex;
uniform float time;
uniform float width;
uniform float height;
in vec2 v_texcoord;
out vec4 isf_FragColor;
#define gl_FragColor isf_FragColor
#define TIME time
#define RENDERSIZE vec2(width, height)
#define isf_FragNormCoord vec2(v_texcoord.x, 1.0 - v_texcoord.y)
#define IMG_SIZE(img) vec2(textureSize(img, 0))
#define IMG_PIXEL(img, c) texture(img, vec2((c).x, IMG_SIZE(img).y - (c).y) / IMG_SIZE(img))
#define inputImage tex
"""
#: The preludes VVISF inserts for GL 3.3 and GL ES 3.0 (the #version line, the
#: output, precision under ES), with ISF's built-ins and the file's inputs declared.
ISF_PRELUDES = {
    "330": "#version 330\n",
    "300 es": "#version 300 es\nprecision highp float;\nprecision highp int;\n",
}
ISF_BUILTINS = """out vec4 isf_FragColor;
#define gl_FragColor isf_FragColor
uniform float TIME;
uniform float TIMEDELTA;
uniform int FRAMEINDEX;
uniform vec2 RENDERSIZE;
in vec2 isf_FragNormCoord;
#define IMG_SIZE(img) vec2(textureSize(img, 0))
#define IMG_PIXEL(img, c) texture(img, (c) / IMG_SIZE(img))
#define IMG_NORM_PIXEL(img, c) texture(img, c)
"""
_UNIFORM_TYPES = {"image": "sampler2D", "float": "float", "bool": "bool", "long": "int"}


def missing() -> str | None:
    """The first tool that is not installed, or None."""
    return next((t for t in TOOLS if shutil.which(t) is None), None)


def isf_parts(text: str) -> tuple[dict, str]:
    """An ISF file's JSON header and its body."""
    m = re.match(r"/\*(.*?)\*/", text, re.S)
    assert m, "an ISF file begins with its JSON comment"
    return json.loads(m.group(1)), text[m.end() :]


def isf_uniforms(header: dict) -> str:
    """The uniforms a host declares for the file's inputs."""
    lines = [f"uniform {_UNIFORM_TYPES[i['TYPE']]} {i['NAME']};" for i in header["INPUTS"]]
    return "\n".join(lines) + "\n"


def glslang(source: str, folder: Path, name: str) -> subprocess.CompletedProcess:
    """glslangValidator on a fragment shader's source."""
    path = folder / f"{name}.frag"
    path.write_text(source)
    return subprocess.run(["glslangValidator", str(path)], capture_output=True, text=True)


def write_frames(folder: Path, frames: list[np.ndarray]) -> Path:
    folder.mkdir()
    for k, frame in enumerate(frames):
        cv2.imwrite(str(folder / f"{k:03d}.png"), cv2.cvtColor(frame, cv2.COLOR_RGBA2BGRA))
    return folder


def glshader(
    fragment: str,
    folder: Path,
    size: tuple[int, int],
    frames: int,
    fps: int,
    inputs: Path | None = None,
    uniforms: str = "",
    vertex: str = VERTEX,
) -> list[np.ndarray]:
    """The RGBA frames glshader draws with ``fragment``: over the PNG frames in
    ``inputs`` (at ``fps``: frame k's timestamp is k / fps) or, without, over
    videotestsrc's (a generator's clock), each ``size``."""
    out = folder / "out"
    out.mkdir()
    w, h = size
    if inputs is not None:
        source = (
            f"multifilesrc location={inputs}/%03d.png index=0 stop-index={frames - 1} "
            f'caps="image/png,framerate={fps}/1" ! pngdec ! videoconvert ! '
            "video/x-raw,format=RGBA"
        )
    else:
        caps = f"video/x-raw,width={w},height={h},framerate={fps}/1"
        source = f"videotestsrc num-buffers={frames} ! {caps}"
    props = f'fragment="{fragment}" vertex="{vertex}"'
    if uniforms:
        props += f' uniforms="uniforms, {uniforms}"'
    pipeline = (
        f"{source} ! glupload ! glcolorconvert ! glshader {props} ! gldownload ! videoconvert "
        f"! video/x-raw,format=RGBA ! pngenc ! multifilesink location={out}/%03d.png"
    )
    env = {**os.environ, "GST_GL_API": "opengl3", "XDG_RUNTIME_DIR": str(folder)}
    done = subprocess.run(
        ["xvfb-run", "-a", "gst-launch-1.0", "-q", *_argv(pipeline)],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    got = [cv2.imread(str(out / f"{k:03d}.png"), cv2.IMREAD_UNCHANGED) for k in range(frames)]
    assert all(g is not None for g in got), sorted(p.name for p in out.iterdir())
    return [cv2.cvtColor(g, cv2.COLOR_BGRA2RGBA) for g in got]


def _argv(pipeline: str) -> list[str]:
    """The pipeline as gst-launch-1.0's words (it joins its arguments again): the
    quoted property values kept whole, quotes included."""
    return re.findall(r'[^\s"]*"[^"]*"[^\s"]*|\S+', pipeline)


#: What Shadertoy puts around an Image tab's code (WebGL2: GLSL ES 3.00).
SHADERTOY_PRELUDE = """#version 300 es
precision highp float;
precision highp int;
uniform vec3 iResolution;
uniform float iTime;
uniform float iTimeDelta;
uniform int iFrame;
uniform vec4 iMouse;
uniform sampler2D iChannel0;
uniform vec3 iChannelResolution[4];
out vec4 shadertoy_color;
"""
SHADERTOY_MAIN = "void main() { mainImage(shadertoy_color, gl_FragCoord.xy); }\n"


def isf_in_prelude(text: str, profile: str) -> str:
    """An ISF file's body inside the prelude a host inserts for ``profile``."""
    header, body = isf_parts(text)
    return ISF_PRELUDES[profile] + ISF_BUILTINS + isf_uniforms(header) + body


def shadertoy_in_prelude(text: str) -> str:
    """An Image tab's code inside Shadertoy's prelude and main."""
    return SHADERTOY_PRELUDE + text + SHADERTOY_MAIN
