"""A recipe as a GLSL fragment shader: ``.frag`` for GStreamer's ``glshader``
(GLSL 3.30, its ``time`` the buffer's timestamp; a vertex shader beside as
``.vert``), ``.fs``, an ISF 2.0 file (VDMX, MadMapper, Millumin, Resolume's
Wire, TouchDesigner's loader; ``TIME``), and Shadertoy's Image tab (``--to
shadertoy``), each a filter over the input or, with ``sheet``, a generator.

The shader is kernels/glsl/prelude.glsl, the renderer's own op sections turned
into GLSL by :mod:`.dialect` (kernels/math.cl, edges.cl, ops/*.cl), the frames'
data of :mod:`.frames` as constant arrays (sampled at ``fps``: time t shows the
frame nearest t * fps) and kernels/glsl/marble.glsl, after the defines and the
host's few lines. Nothing of the recipe's text is written: only its numbers.
"""

from __future__ import annotations

import json
import re
from functools import lru_cache

import numpy as np

from marblevideo.export.dialect import Translator
from marblevideo.export.frames import check_exportable, frame_table
from marblevideo.export.source import literal, one_pixel_defines, walk_types
from marblevideo.limits import EXPORT_CONSTANT_BYTES
from marblevideo.opencl.header import edges_macro, header_source, walk_source
from marblevideo.opencl.program import kernel_source
from marblevideo.ops import REGISTRY
from marblevideo.version import __version__

#: The dialect's files turned into GLSL, in the order they are joined.
DIALECT_FILES = ("math.cl", "edges.cl")
#: GStreamer's vertex shader for a GLSL 3.30 fragment shader (glshader's default is 1.00).
GSTREAMER_VERTEX = """\
#version 330
in vec4 a_position;
in vec2 a_texcoord;
out vec2 v_texcoord;
void main() {
    gl_Position = a_position;
    v_texcoord = a_texcoord;
}
"""
_PER_LINE = 8

_GSTREAMER_HEAD = """\
#version 330
/* marblevideo {version}: a marbling recipe as a fragment shader for GStreamer's glshader.
 * The frame at its buffer's time t shows the recipe at t (in steps of 1/{fps:g} s,
 * the export's --fps; the last from {end:g} s on). glshader runs it between
 * glupload ! glcolorconvert and gldownload (or glimagesink), with GST_GL_API=opengl3
 * and the vertex shader written beside it (vertex=...): docs/export.md has the
 * gst-launch-1.0 command. The file holds no double quote, so that gst-launch-1.0
 * can take it as a property value.
 */
uniform sampler2D tex;
uniform float time;
uniform float width;
uniform float height;
in vec2 v_texcoord;
out vec4 mv_colour;
"""
_GSTREAMER_MAIN = """
void main() {
    ivec2 size = textureSize(tex, 0);
    vec2 o = floor(v_texcoord * vec2(width, height));
    mv_colour = marble_pixel(o.x, o.y, width, height, time, size.x, size.y);
}
"""
_ISF_MAIN = """
void main() {
    vec2 size = RENDERSIZE;
    vec2 o = floor(vec2(isf_FragNormCoord.x, 1.0 - isf_FragNormCoord.y) * size);
    float t = TIME * speed + offset;
    if (loop)
        t = mod(t, MV_LOOP);
#if HAS_INPUT
    ivec2 isz = ivec2(IMG_SIZE(inputImage));
#else
    ivec2 isz = ivec2(size);
#endif
    gl_FragColor = marble_pixel(o.x, o.y, size.x, size.y, t, isz.x, isz.y);
}
"""
_SHADERTOY_HEAD = """\
/* marblevideo {version}: a marbling recipe for Shadertoy's Image tab (WebGL2, GLSL ES
 * 3.00), at iTime (in steps of 1/{fps:g} s; the last from {end:g} s on). {input}
 */
"""
_SHADERTOY_MAIN = """
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec2 o = vec2(floor(fragCoord.x), iResolution.y - 1.0 - floor(fragCoord.y));
    ivec2 isz = ivec2(iChannelResolution[0].xy);
    fragColor = marble_pixel(o.x, o.y, iResolution.x, iResolution.y, iTime, isz.x, isz.y);
}
"""
#: Shadertoy's iChannel0 (rows from the bottom) at row iy from the top.
_SHADERTOY_TEXEL = (
    "#define MV_TEXEL(ix, iy) "
    "texelFetch(iChannel0, ivec2(ix, int(iChannelResolution[0].y) - 1 - (iy)), 0)\n"
)
#: An ISF host's pixel of the input (bottom-left origin) at row iy from the top.
_ISF_TEXEL = (
    "#define MV_TEXEL(ix, iy) IMG_PIXEL(inputImage, "
    "vec2(float(ix) + 0.5, IMG_SIZE(inputImage).y - float(iy) - 0.5))\n"
)
_GSTREAMER_TEXEL = "#define MV_TEXEL(ix, iy) texelFetch(tex, ivec2(ix, iy), 0)\n"


@lru_cache(maxsize=1)
def op_sections() -> str:
    """The math helpers, edges and every op family's sections, as GLSL."""
    op_args = re.search(r"#define OP_ARGS (.*?)\n(?!\s)", kernel_source("prelude.cl"), re.S)
    signature = op_args.group(1).replace("\\\n", " ")
    families = dict.fromkeys(d.family for d in REGISTRY.values())
    names = [*DIALECT_FILES, *(f"ops/{family}.cl" for family in families)]
    sources = {name: kernel_source(name).replace("OP_ARGS", signature) for name in names}
    translator = Translator()
    for text in sources.values():
        translator.learn(text)
    return "\n".join(translator.glsl(text, f"kernels/{name}") for name, text in sources.items())


def _array(ctype: str, name: str, values, write) -> str:
    items = [write(v) for v in values] or [write(0)]
    lines = [", ".join(items[k : k + _PER_LINE]) for k in range(0, len(items), _PER_LINE)]
    body = ",\n    ".join(lines)
    return f"const {ctype} {name}[{len(items)}] = {ctype}[{len(items)}](\n    {body}\n);\n"


def shader_body(recipe, fps: float, sheet: bool, what: str) -> tuple[str, float]:
    """The host-independent part of the shader (defines, tables, sections, the
    pixel) and the time the recipe settles (seconds)."""
    check_exportable(recipe, what)
    canvas = recipe.canvas or (1.0, 1.0)
    table = frame_table(recipe, fps, canvas, EXPORT_CONSTANT_BYTES, raise_limit=False)
    data = [table.rows.ravel(), table.lists, table.background.ravel(), table.samples.ravel()]
    at = np.cumsum([0, *(a.size for a in data)])
    translator = Translator()
    translator.data |= {"lists"}
    walk = translator.glsl(walk_source(walk_types(recipe)))
    defines = [
        *one_pixel_defines(recipe, table),
        f"#define HAS_INPUT {0 if sheet else 1}",
        f"#define MV_FPS {literal(fps)}",
        f"#define MV_LISTS_AT {at[1]}",
        f"#define MV_BACKGROUND_AT {at[2]}",
        f"#define MV_SAMPLES_AT {at[3]}",
        f"#define MV_LOOP {literal(recipe.settled_time() + 1.0)}",
    ]
    header = header_source() + f"#define EDGES {edges_macro(recipe.edges)}\n"
    parts = [
        "\n".join(defines) + "\n",
        header,
        walk,
        _array("float", "MV_DATA", np.concatenate(data), literal),
        _array("int", "MV_ROW_AT", table.row_at, str),
        _array("int", "MV_FIRST", table.first, str),
        _array("int", "MV_COUNT", table.count, str),
        kernel_source("glsl/prelude.glsl"),
        op_sections(),
    ]
    return "\n".join(parts), recipe.settled_time()


def spliced(text: str) -> str:
    """``text`` with its continued lines joined (as C's preprocessor joins them):
    GLSL 3.30 has no line continuation."""
    return text.replace("\\\n", " ")


def gstreamer_shader(recipe, fps: float, sheet: bool) -> str:
    """The ``.frag`` of ``recipe`` for GStreamer's glshader (GLSL 3.30)."""
    body, end = shader_body(recipe, fps, sheet, "a GStreamer shader")
    head = _GSTREAMER_HEAD.format(version=__version__, fps=fps, end=end)
    marble = kernel_source("glsl/marble.glsl")
    return spliced(head + body + _GSTREAMER_TEXEL + marble + _GSTREAMER_MAIN)


def isf_shader(recipe, fps: float, sheet: bool) -> str:
    """The ``.fs`` of ``recipe``: an ISF 2.0 filter, or with ``sheet`` a generator."""
    body, end = shader_body(recipe, fps, sheet, "an ISF shader")
    inputs = [] if sheet else [{"NAME": "inputImage", "TYPE": "image"}]
    inputs += [
        {
            "NAME": "speed",
            "LABEL": "Speed",
            "TYPE": "float",
            "DEFAULT": 1.0,
            "MIN": 0.0,
            "MAX": 4.0,
        },
        {
            "NAME": "offset",
            "LABEL": "Offset (s)",
            "TYPE": "float",
            "DEFAULT": 0.0,
            "MIN": 0.0,
            "MAX": float(round(end + 1.0, 3)),
        },
        {"NAME": "loop", "LABEL": "Loop", "TYPE": "bool", "DEFAULT": False},
    ]
    header = {
        "ISFVSN": "2.0",
        "DESCRIPTION": f"A marbling recipe exported by marblevideo {__version__}: at TIME "
        "* speed + offset seconds (in steps of 1/"
        f"{fps:g} s), held from {end:g} s on unless it loops.",
        "CREDIT": "marblevideo (Mathematical Marbling, Lu et al., TVCG 2012)",
        "CATEGORIES": ["Generator"] if sheet else ["Distortion Effect"],
        "INPUTS": inputs,
    }
    head = "/*" + json.dumps(header, indent=2) + "*/\n"
    texel = "" if sheet else _ISF_TEXEL
    return spliced(head + body + texel + kernel_source("glsl/marble.glsl") + _ISF_MAIN)


def shadertoy_shader(recipe, fps: float, sheet: bool) -> str:
    """The Image tab's code of ``recipe`` for Shadertoy (``mainImage``, ``iTime``,
    ``iResolution``; the input on iChannel0 unless ``sheet``)."""
    body, end = shader_body(recipe, fps, sheet, "a Shadertoy shader")
    said = "A blank sheet." if sheet else "iChannel0: the input (a video, the webcam)."
    head = _SHADERTOY_HEAD.format(version=__version__, fps=fps, end=end, input=said)
    texel = "" if sheet else _SHADERTOY_TEXEL
    return spliced(head + body + texel + kernel_source("glsl/marble.glsl") + _SHADERTOY_MAIN)
