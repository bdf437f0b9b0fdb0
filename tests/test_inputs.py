"""Inputs classified once, at the edge (:mod:`marblevideo.media.inputs`): the kind
from the name, the file checked once, and the readers taking the typed input as
it is. Real files, nothing mocked; fast (no OpenCL)."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from clips import write_clip
from helpers import subprocess_env

from marblevideo.errors import MediaError
from marblevideo.media.decode import open_input
from marblevideo.media.images import read_image, write_image
from marblevideo.media.inputs import Input, classify, name_kind

pytestmark = pytest.mark.tier("fast")

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize(
    ("name", "kind", "local"),
    [
        (None, "blank", False),
        ("photo.PNG", "image", True),
        ("film.mp4", "video", True),
        ("frames_%04d.png", "sequence", True),
        ("https://example.com/a.mp4", "video", False),
        ("rtsp://camera/stream", "video", False),
    ],
)
def test_the_kind_comes_from_the_name(name, kind, local):
    source = classify(name)
    assert (source.kind, source.local) == (kind, local)
    assert source.names == ([name] if local else [])
    assert classify(source) is source  # classified once: passed down as it is


def test_the_name_alone_reads_nothing():
    """What the command line's option checks use: standard input is "stdin" until read."""
    assert [name_kind(n) for n in (None, "-", "a.jpg", "a_%02d.tif", "a.mkv")] == [
        "blank",
        "stdin",
        "image",
        "sequence",
        "video",
    ]


def test_a_file_is_checked_once_and_kept(tmp_path):
    image = np.full((6, 8, 4), 200, np.uint8)
    path = tmp_path / "in.png"
    write_image(path, image, alpha=True, fmt=".png")
    source = classify(str(path)).checked()
    assert source.path == path
    assert source.checked() is source
    rgba, alpha = read_image(source)
    assert rgba.shape == (6, 8, 4) and alpha


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda p: p, "no such file"),
        (lambda p: (p.mkdir(), p)[1], "is a folder, not a video"),
        (lambda p: (p.write_bytes(b""), p)[1], "empty file"),
    ],
)
def test_a_bad_file_is_one_media_error(tmp_path, make, message):
    path = make(tmp_path / "in.mp4")
    with pytest.raises(MediaError, match=message):
        classify(str(path)).checked()


def test_sequences_and_urls_are_not_checked_as_files():
    for name in ("missing_%03d.png", "https://example.com/missing.mp4"):
        source = classify(name)
        assert source.checked() is source and source.path is None


def test_open_input_takes_a_classified_video(tmp_path):
    clip = tmp_path / "clip.mp4"
    write_clip(clip, frames=3)
    source = classify(str(clip)).checked()
    with open_input(source) as container:
        assert container.streams.video


def test_standard_input_is_read_once_into_its_kind(tmp_path):
    """A still on standard input is read whole into the Input; a video is left to
    stream, from its first byte."""
    image = tmp_path / "in.png"
    write_image(image, np.zeros((4, 4, 4), np.uint8), alpha=False, fmt=".png")
    clip = tmp_path / "clip.mp4"
    write_clip(clip, frames=2)
    script = textwrap.dedent(
        """
        from marblevideo.media.decode import open_input
        from marblevideo.media.inputs import classify
        source = classify("-")
        if source.kind == "image":
            print("image", len(source.data))
        else:
            with open_input(source) as container:
                print("video", sum(1 for _ in container.decode(video=0)))
        """
    )
    env = subprocess_env()
    for path, expected in ((image, f"image {image.stat().st_size}"), (clip, "video 2")):
        with open(path, "rb") as stdin:
            proc = subprocess.run(
                [sys.executable, "-c", script], stdin=stdin, capture_output=True, text=True, env=env
            )
        assert proc.returncode == 0, proc.stderr
        assert proc.stdout.strip() == expected


def test_an_input_is_a_small_value():
    assert Input("blank") == classify(None)
