"""Make every picture the README and docs/*.md show, and the numbers the README
quotes about them, from the samples: ``python scripts/make_docs.py [--check]``.

Each picture comes from the command the README shows (found in its ```sh
blocks by its output name, run from the repository root with only the output
and, where noted, ``--size`` or ``--time`` changed) or from the Python API it
shows. Numbers go into README.md between ``<!-- make_docs:NAME -->`` and
``<!-- /make_docs -->``. ``--check`` makes everything in a temporary folder
instead and lists the docs files that differ (pictures by their pixels,
within a small tolerance); exit status 1 if any does. For developers; CI runs
the tests.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import re
import shlex
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
DOCS = ROOT / "docs"
MARKER = re.compile(r"(<!-- make_docs:([\w-]+) -->)(.*?)(<!-- /make_docs -->)", re.S)
#: the Figure-6 stage the SVG picture shows
SVG_STAGE = "e"
#: seconds of samples/coffee.mp4 shown marbled by samples/swirl.json
SWIRL_TIMES = (1.5, 3.0)
JPEG_QUALITY = 85
#: the classic-pattern samples the README shows, and the size of their pictures
CLASSICS = ("nonpareil", "bouquet", "chevron", "spanish-wave", "stone-sprays")
CLASSIC_SIZE = "360x240"
#: the free-hand stroke presets the README shows (issue 32), and their pictures' sizes
STROKES = {"tulip": "240x300", "heart": "240x300", "french-curl": "360x240", "bird": "360x240"}
#: what :func:`make` writes into docs/
PICTURES = (
    "figure6.png",
    "figure6-steps.png",
    "zoom.png",
    "sphere.png",
    "tile-2x2.png",
    "figure6-e.svg",
    "coffee-comb-wave.jpg",
    "coffee-swirl.jpg",
    *(f"{name}.jpg" for name in CLASSICS),
    "bouquet-steps.jpg",
    *(f"{name}.jpg" for name in STROKES),
    "export-hosts.jpg",
)
#: docs/export.md's commands: the frame of the video shown (seconds), the sheet's size
EXPORT_TIME, EXPORT_SHEET = 3.0, "360x240"


def readme_command(output: str, text: str | None = None) -> list[str]:
    """The README's ```sh command that writes ``-o output``, as argv (comment dropped)."""
    text = README.read_text() if text is None else text
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        for line in block.splitlines():
            argv = shlex.split(line, comments=True)
            if "-o" in argv and argv[argv.index("-o") + 1] == output:
                return argv
    raise SystemExit(f"make_docs: README.md shows no command writing -o {output}")


def with_option(argv: list[str], option: str, value: str) -> list[str]:
    """``argv`` with ``option`` set to ``value`` (replaced where given, else added)."""
    argv = list(argv)
    if option in argv:
        argv[argv.index(option) + 1] = value
    else:
        argv += [option, value]
    return argv


def run(argv: list[str], output: Path) -> str:
    """Run a README command line in this process, writing ``output``; its stderr."""
    from marblevideo import cli, gallery

    argv = with_option(argv, "-o", str(output)) + ["-y"]
    if argv[:3] == ["python", "-m", "marblevideo.gallery"]:
        main, args = gallery.main, argv[3:]
    elif argv[0] == "marblevideo":
        main, args = cli.main, argv[1:]
    else:
        raise SystemExit(f"make_docs: not a marblevideo command: {shlex.join(argv)}")
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        status = main(args)
    if status != 0:
        raise SystemExit(f"make_docs: {shlex.join(argv)} failed ({status}): {err.getvalue()}")
    return err.getvalue()


def read_rgb(path: Path) -> np.ndarray:
    from marblevideo.media.images import read_image

    return read_image(path)[0][..., :3]


def write(path: Path, rgb: np.ndarray) -> None:
    """PNG at the best compression, JPEG at :data:`JPEG_QUALITY`."""
    import cv2

    bgr = cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2BGR)
    if path.suffix == ".jpg":
        params = [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY, cv2.IMWRITE_JPEG_OPTIMIZE, 1]
    else:
        params = [cv2.IMWRITE_PNG_COMPRESSION, 9]
    ok, data = cv2.imencode(path.suffix, bgr, params)
    assert ok, path
    path.write_bytes(data.tobytes())


def recompress(path: Path) -> None:
    """Rewrite an opaque picture with :func:`write` (same pixels, fewer bytes)."""
    write(path, read_rgb(path))


def make(out: Path, tmp: Path) -> dict[str, str]:
    """Write every picture into ``out``; returns the README's numbers by marker name."""
    from marblevideo import load_recipe, marbled_frames, samples_path
    from marblevideo.cli.arguments import parse_view
    from marblevideo.gallery import stages

    numbers = {}

    # the design (the README's first picture)
    run(with_option(readme_command("design.png"), "--size", "512x512"), out / "figure6.png")
    recompress(out / "figure6.png")

    # the gallery, as many columns and pictures as before: 5 x 136 px
    steps = readme_command("steps.png")
    run(with_option(steps, "--size", "136"), out / "figure6-steps.png")
    recompress(out / "figure6-steps.png")
    recipe = steps[steps.index("--ops") + 1] if "--ops" in steps else samples_path("figure6.json")
    found = stages(load_recipe(recipe))
    numbers["stages"] = f"({found[0].label})-({found[-1].label})"

    # deep zoom, through a UV pass, tiles
    zoom = readme_command("zoom.png")
    run(zoom, out / "zoom.png")
    recompress(out / "zoom.png")
    x, y, w, h = parse_view(zoom[zoom.index("--view") + 1])
    canvas = load_recipe(zoom[zoom.index("--ops") + 1]).canvas
    numbers["zoom"] = f"`--view {zoom[zoom.index('--view') + 1]}` ({min(canvas) / max(w, h):.0f}x)"
    run(readme_command("sphere.png"), out / "sphere.png")  # RGBA: kept as written
    run(with_option(readme_command("tile.png"), "--size", "192x192"), tmp / "tile.png")
    write(out / "tile-2x2.png", np.tile(read_rgb(tmp / "tile.png"), (2, 2, 1)))

    # SVG: the numbers of the README's command, the picture after stage (e) at 512 px
    svg = readme_command("design.svg")
    said = run(svg, tmp / "design.svg")
    numbers["svg-stats"] = f"`{said.split(': ', 1)[1].strip()}`"
    (stage,) = (s for s in stages(load_recipe(svg[svg.index("--ops") + 1])) if s.label == SVG_STAGE)
    svg_e = with_option(with_option(svg, "--size", "512x512"), "--time", f"{stage.time:g}")
    run(svg_e, out / "figure6-e.svg")

    # the classic patterns, and the bouquet stage by stage
    for name in CLASSICS:
        run(with_option(readme_command(f"{name}.png"), "--size", CLASSIC_SIZE), tmp / f"{name}.png")
        write(out / f"{name}.jpg", read_rgb(tmp / f"{name}.png"))
    run(with_option(readme_command("bouquet-steps.png"), "--size", "120"), tmp / "steps.png")
    write(out / "bouquet-steps.jpg", read_rgb(tmp / "steps.png"))

    make_strokes(out, tmp)
    make_export(out, tmp)

    # photos: the README's still command, and frames of the video through the API
    run(readme_command("out.png"), tmp / "comb-wave.png")
    write(out / "coffee-comb-wave.jpg", read_rgb(tmp / "comb-wave.png"))
    video = readme_command("out.mp4")
    src, recipe = video[1], video[video.index("--ops") + 1]
    frames = list(marbled_frames(src, recipe, start=SWIRL_TIMES[0], end=SWIRL_TIMES[-1] + 0.05))
    picked = [min(frames, key=lambda f, t=t: abs(f[0] - t))[1][..., :3] for t in SWIRL_TIMES]
    write(out / "coffee-swirl.jpg", np.concatenate(picked, axis=1))
    at = " and ".join(f"{t:g} s" for t in SWIRL_TIMES)
    numbers["swirl"] = f"`{src}` through `{recipe}`, at {at}"
    return numbers


def make_strokes(out: Path, tmp: Path) -> None:
    """The stroke presets' pictures (``python -c "...make_strokes(DOCS, tmp)"`` makes
    only these)."""
    for name, size in STROKES.items():
        run(with_option(readme_command(f"{name}.png"), "--size", size), tmp / f"{name}.png")
        write(out / f"{name}.jpg", read_rgb(tmp / f"{name}.png"))


def make_export(out: Path, tmp: Path) -> None:
    """docs/export.md's picture: its ```sh blocks that run a host, run by bash as
    written (the exports, then the real ffmpeg and GStreamer; under xvfb-run without
    a display), from a folder with the samples, the sheet at EXPORT_SHEET; each
    video's frame at EXPORT_TIME and the sheet's last frame, side by side."""
    import subprocess

    import av
    import cv2

    folder = tmp / "export"
    folder.mkdir()
    (folder / "samples").symlink_to(ROOT / "samples")
    path = f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"
    env = {**os.environ, "PATH": path, "XDG_RUNTIME_DIR": str(folder)}
    frames = []
    for block in re.findall(r"```sh\n(.*?)```", (DOCS / "export.md").read_text(), re.S):
        if "ffmpeg " not in block and "gst-launch-1.0" not in block:
            continue
        argv = ["bash", "-euc", block.replace("size=1280x720", f"size={EXPORT_SHEET}")]
        if "gst-launch-1.0" in block and not os.environ.get("DISPLAY"):
            argv = ["xvfb-run", "-a", *argv]
        done = subprocess.run(argv, cwd=folder, env=env, capture_output=True)
        if done.returncode:
            raise SystemExit(f"make_docs: docs/export.md's commands failed: {done.stderr[-800:]}")
        written = folder / block.split()[-1].removeprefix("location=")
        with av.open(str(written)) as f:
            decoded = [(float(fr.time), fr.to_ndarray(format="rgb24")) for fr in f.decode(video=0)]
        sheet = "openclsrc" in block
        pick = decoded[-1] if sheet else min(decoded, key=lambda d: abs(d[0] - EXPORT_TIME))
        frames.append(pick[1])
    h = min(f.shape[0] for f in frames)
    scaled = [
        cv2.resize(f, (round(f.shape[1] * h / f.shape[0]), h), interpolation=cv2.INTER_AREA)
        for f in frames
    ]
    write(out / "export-hosts.jpg", np.concatenate(scaled, axis=1))


def with_numbers(text: str, numbers: dict[str, str]) -> str:
    """README text with each marker's content replaced by its number."""
    present = {m[1] for m in MARKER.findall(text)}
    if present != set(numbers):
        raise SystemExit(
            f"make_docs: README.md's markers {sorted(present)} are not {sorted(numbers)}"
        )
    return MARKER.sub(lambda m: m[1] + numbers[m[2]] + m[4], text)


def pixels(path: Path) -> np.ndarray:
    """A picture's RGBA pixels (SVG rasterized by cairosvg at its own size)."""
    import cv2

    if path.suffix == ".svg":
        import cairosvg

        data = np.frombuffer(cairosvg.svg2png(url=str(path)), np.uint8)
        return cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    return image if image.ndim == 3 else image[..., None]


def same_picture(a: Path, b: Path) -> bool:
    """Same size, and under 2 % of pixels off by more than 48 levels in a channel."""
    pa, pb = pixels(a), pixels(b)
    if pa.shape != pb.shape:
        return False
    off = np.abs(pa.astype(np.int16) - pb.astype(np.int16)).max(axis=2) > 48
    return bool(off.mean() < 0.02)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--check", action="store_true", help="list docs files that differ; exit 1")
    args = p.parse_args(argv)
    sys.path.insert(0, str(ROOT))  # this checkout's marblevideo, not an installed one
    os.chdir(ROOT)  # the README's commands name samples/ relative to the root
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        out = scratch / "docs" if args.check else DOCS
        out.mkdir(exist_ok=True)
        (scratch / "tmp").mkdir()
        numbers = make(out, scratch / "tmp")
        text = README.read_text()
        new_text = with_numbers(text, numbers)
        if not args.check:
            README.write_text(new_text)
            for name, value in numbers.items():
                print(f"README {name}: {value}")
            print(f"wrote docs/: {', '.join(PICTURES)}")
            return 0
        differ = [] if new_text == text else ["README.md (numbers)"]
        for name in PICTURES:
            kept = DOCS / name
            if not kept.exists() or not same_picture(out / name, kept):
                differ.append(f"docs/{name}")
        for line in differ:
            print(f"differs: {line}")
        print("docs are up to date" if not differ else "run python scripts/make_docs.py")
        return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
