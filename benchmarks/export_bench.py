"""The exports run by their hosts, beside marblevideo and the hosts' own plain
pipelines: ``python -m benchmarks.export_bench [--seconds 10] [--rounds 2]``.

A 1280x720 clip of ``--seconds`` at 30 fps through samples/swirl.json, whole
commands timed in paired rounds (every command once a round; wall and CPU
seconds of the process and its children):

- ffmpeg with the exported ``.cl`` (``program_opencl`` on the OpenCL device
  ffmpeg finds first), x264 veryfast crf 23, the audio copied;
- ``marblevideo`` on the same clip and recipe, the same encoder settings;
- ffmpeg's plain transcode (the same encode, no filter);
- GStreamer's ``glshader`` with the exported ``.frag`` (under ``xvfb-run`` where
  there is no display: Mesa's llvmpipe on the CPU), and the same pipeline
  without the shader (GL upload and download kept), both to MPEG-4 Part 2.

Prints a Markdown report; BENCHMARKS.md ("Export") records its numbers.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .common import ENV, cpu_summary, make_clip

FFMPEG_HW = ["-init_hw_device", "opencl=ocl", "-filter_hw_device", "ocl"]
X264 = ["-c:v", "libx264", "-preset", "veryfast", "-crf", "23", "-c:a", "copy"]


def timed(cmd: list[str], env: dict) -> tuple[float, float]:
    """(wall, CPU) seconds of ``cmd`` and every process it waited for."""
    began = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - began
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"export_bench: {' '.join(cmd[:3])} ... failed: {err[-800:]}")
    return wall, usage.ru_utime + usage.ru_stime


def commands(folder: Path, clip: Path) -> dict[str, list[str]]:
    """Each timed command by name (see the module)."""
    cl, frag = folder / "swirl.cl", folder / "swirl.frag"
    mv = [sys.executable, "-m", "marblevideo"]
    subprocess.run([*mv, "export", "swirl", "-o", str(cl), "-y", "-q"], check=True, env=ENV)
    subprocess.run([*mv, "export", "swirl", "-o", str(frag), "-y", "-q"], check=True, env=ENV)
    vf = f"format=rgba,hwupload,program_opencl=source={cl}:kernel=marble,hwdownload,format=rgba"
    ff = ["ffmpeg", "-v", "error", "-y", "-nostdin"]
    gl = "glupload ! glcolorconvert"
    shader = (
        f'glshader fragment="{frag.read_text()}" vertex="{frag.with_suffix(".vert").read_text()}"'
    )
    tail = "gldownload ! videoconvert ! avenc_mpeg4 bitrate=4000000 ! avimux ! filesink"

    def gst(middle: str, out: str) -> list[str]:
        words = f"filesrc location={clip} ! decodebin ! videoconvert ! {gl} ! {middle}{tail}"
        launch = ["gst-launch-1.0", "-q", *_gst_words(f"{words} location={folder / out}")]
        return launch if os.environ.get("DISPLAY") else ["xvfb-run", "-a", *launch]

    return {
        "ffmpeg + swirl.cl": [*ff, *FFMPEG_HW, "-i", str(clip), "-vf", f"{vf},format=yuv420p",
                              *X264, str(folder / "ff.mp4")],
        "marblevideo": [*mv, str(clip), "--ops", "swirl", "-o", str(folder / "mv.mp4"), "-y",
                        "-q", "--preset", "veryfast", "--crf", "23"],
        "ffmpeg plain": [*ff, "-i", str(clip), *X264, str(folder / "plain.mp4")],
        "GStreamer + swirl.frag": gst(f"{shader} ! ", "gst.avi"),
        "GStreamer plain": gst("", "gst-plain.avi"),
    }  # fmt: skip


def _gst_words(pipeline: str) -> list[str]:
    """gst-launch-1.0's words, quoted property values kept whole (quotes included)."""
    import re

    return re.findall(r'[^\s"]*"[^"]*"[^\s"]*|\S+', pipeline)


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seconds", type=int, default=10, help="the clip's length (default 10)")
    p.add_argument("--rounds", type=int, default=2, help="paired rounds (default 2)")
    args = p.parse_args(argv)
    missing = [t for t in ("ffmpeg", "gst-launch-1.0") if shutil.which(t) is None]
    if missing:
        raise SystemExit(f"export_bench: needs {', '.join(missing)}")
    env = {**ENV, "GST_GL_API": "opengl3", "XDG_RUNTIME_DIR": tempfile.gettempdir()}
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        clip = make_clip(folder / "clip.mp4", (1280, 720), seconds=args.seconds)
        cmds = commands(folder, clip)
        runs: dict[str, list[tuple[float, float]]] = {name: [] for name in cmds}
        loads = []
        for _ in range(args.rounds):
            for name, cmd in cmds.items():
                runs[name].append(timed(cmd, env))
            loads.append(os.getloadavg()[0])
    frames = args.seconds * 30
    print(f"## Export: the hosts running the exported files ({time.strftime('%Y-%m-%d')})\n")
    print(f"Machine: {cpu_summary()}; {os.cpu_count()} cores; load after each round: "
          f"{', '.join(f'{x:.1f}' for x in loads)}.")  # fmt: skip
    print(f"Clip: 1280x720, {args.seconds} s ({frames} frames), samples/swirl.json (3 ops, rgss).")
    print(f"Medians of {args.rounds} paired rounds.\n")
    print("| command | wall s | CPU s | ms a frame (wall) | vs marblevideo (wall) |")
    print("|---|---|---|---|---|")
    base = runs["marblevideo"]
    for name, times in runs.items():
        wall = statistics.median(t[0] for t in times)
        cpu = statistics.median(t[1] for t in times)
        ratio = statistics.median(t[0] / b[0] for t, b in zip(times, base, strict=True))
        print(f"| {name} | {wall:.1f} | {cpu:.1f} | {wall / frames * 1e3:.0f} | {ratio:.2f}x |")


if __name__ == "__main__":
    main()
