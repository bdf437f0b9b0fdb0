"""A recipe's ``motion`` in a file render: the CLI on a 720p clip of textured discs
going round over a still textured ground, the recipe with ``motion`` against the
same recipe without it and against its take (the same strokes, no analysis;
paired rounds), and in process the analysis alone per
frame (each frame's decoded luma plane seen by a StirredRecipe, as the pipeline's
transform stage sees it)."""

from __future__ import annotations

import json
import math
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import av
import cv2
import numpy as np

from .common import ENV, marble_command
from .e2e import paired_rounds

#: Two slow waves, as a dancer's recipe: the motion strokes draw over them.
WAVES = {
    "marblevideo": 1,
    "antialias": "rgss",
    "edges": "mirror",
    "ops": [
        {"type": "wave", "amplitude": 8, "wavelength": 420, "phase": 0, "angle": 90},
        {"type": "wave", "amplitude": 6, "wavelength": 300, "phase": 0, "angle": 0},
    ],
}
MOTION = {"gain": 1.5, "width": [40, 260], "threshold": 90, "memory": 4, "heal": 2.5}


def disc_clip(path: Path, seconds: int, size=(1280, 720), fps: int = 30) -> Path:
    """Three textured discs (120 px) going round circles of 160 px at 300 px/s over a
    still textured ground, x264 ultrafast crf 18."""
    w, h = size
    rng = np.random.default_rng(1)
    ground = cv2.GaussianBlur(rng.integers(0, 256, (h, w, 3), np.uint8), (0, 0), 2)
    skin = cv2.GaussianBlur(rng.integers(0, 256, (128, 128, 3), np.uint8), (0, 0), 1.5)
    yy, xx = np.mgrid[0:128, 0:128]
    inside = (xx - 63.5) ** 2 + (yy - 63.5) ** 2 <= 60**2
    with av.open(str(path), "w") as out:
        v = out.add_stream("libx264", rate=fps, options={"preset": "ultrafast", "crf": "18"})
        v.width, v.height, v.pix_fmt = w, h, "yuv420p"
        for i in range(seconds * fps):
            frame = ground.copy()
            for k, cx in enumerate((320, 640, 960)):
                a = 300 / 160 * i / fps + k * 2.1
                x, y = int(cx + 160 * math.cos(a)) - 64, int(h / 2 + 160 * math.sin(a)) - 64
                frame[y : y + 128, x : x + 128][inside] = skin[inside]
            out.mux(v.encode(av.VideoFrame.from_ndarray(frame, "rgb24")))
        out.mux(v.encode(None))
    return path


def analysis_ms(clip: Path, recipe: dict) -> tuple[float, float, int]:
    """(median, p95 ms) of StirredRecipe.see per frame over the clip's luma planes, and
    the strokes its take holds."""
    from marblevideo.media.decode import Reader, open_input
    from marblevideo.motion import StirredRecipe
    from marblevideo.recipe import parse_recipe

    stirred, times = None, []
    with open_input(clip) as container:
        for item in Reader(container, None, None, {}, i420=True, luma=True).items():
            if stirred is None:
                size = item.luma.shape[::-1]
                stirred = StirredRecipe(parse_recipe(recipe), size)
            began = time.perf_counter()
            stirred.see(item.luma, item.t)
            times.append((time.perf_counter() - began) * 1e3)
    p95 = float(np.percentile(times, 95))
    return statistics.median(times), p95, len(stirred.tracker.take())


def motion_e2e(device: str | None, seconds: int = 4) -> None:
    """The CLI with and without ``motion`` on the disc clip (medians of 3 paired
    rounds, x264 veryfast crf 23), and the analysis alone per frame."""
    fps = 30
    n = seconds * fps
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        clip = disc_clip(tmp / "discs.mp4", seconds, fps=fps)
        recipes = {"without motion": WAVES, "with motion": {**WAVES, "motion": MOTION}}
        cmds = {}
        for k, (name, recipe) in enumerate(recipes.items()):
            (tmp / f"r{k}.json").write_text(json.dumps(recipe))
            cmds[name] = marble_command(clip, tmp / f"r{k}.json", tmp / f"o{k}.mp4", device)
        take = [*cmds["with motion"], "--automation", str(tmp / "take.json")]
        subprocess.run(take, check=True, env=ENV)  # the take, and a warm kernel cache
        cmds["its take (the same strokes, no analysis)"] = marble_command(
            clip, tmp / "take.json", tmp / "o2.mp4", device
        )
        times = paired_rounds(cmds, rounds=3)
        median, p95, strokes = analysis_ms(clip, recipes["with motion"])
    print(f"\n## Motion: 1280x720 discs, {seconds} s ({n} frames), two waves RGSS, x264 veryfast")
    print("| command | seconds | ms/frame |")
    print("|---|---|---|")
    med = {k: statistics.median(v) for k, v in times.items()}
    for name, s in med.items():
        print(f"| {name} | {s:.2f} | {s / n * 1e3:.1f} |")
    plain, stirred, replay = times.values()
    extra = [(b - a) / n * 1e3 for a, b in zip(plain, stirred, strict=True)]
    analysis = [(b - a) / n * 1e3 for a, b in zip(replay, stirred, strict=True)]
    print(
        f"motion adds {statistics.median(extra):.1f} ms/frame to the command, of which "
        f"{statistics.median(analysis):.1f} beyond rendering its take (paired medians); "
        f"the analysis alone (StirredRecipe.see on the luma plane): {median:.1f} ms median, "
        f"{p95:.1f} ms p95 a frame; {strokes} strokes in the take"
    )
