"""Every video and animated-image output decodes without an error in a reader
that is not ours: FFmpeg's own command (``ffmpeg -v error -i OUT -f null -``,
Debian's ffmpeg; ``scripts/setup.sh --test`` installs it), with and without
audio, written to a file and to a pipe (and read back from one). FFmpeg has no
animated-WebP decoder, so Pillow reads that one, frame by frame."""

from __future__ import annotations

import io
import json
import shutil
import subprocess

import pytest
from clips import write_clip
from PIL import Image

from marblevideo.media.formats import EXTENSION_FORMATS, FORMATS

FFMPEG = shutil.which("ffmpeg")
pytestmark = [
    pytest.mark.tier("integration"),
    pytest.mark.skipif(FFMPEG is None, reason="ffmpeg is not installed (apt-get install ffmpeg)"),
]

FRAMES = 6
#: Each video extension, with whether its format holds audio.
EXTENSIONS = [(ext, FORMATS[name].audio is not None) for ext, name in EXTENSION_FORMATS.items()]
#: What --format names for -o -: every format but animated WebP (read by Pillow).
STREAMS = [(name, fmt.audio is not None) for name, fmt in FORMATS.items() if name != "webp"]
CASES = [
    (ext, audio) for ext, holds in EXTENSIONS for audio in ((False, True) if holds else (False,))
]
#: Formats whose FFmpeg demuxer seeks, so it reads what came down the pipe from a
#: file (``cat x.apng | ffmpeg -i -``: "pipe:: Function not implemented", ours or not).
SEEKING_DEMUXERS = {"apng"}
PIPED = [
    (name, audio) for name, holds in STREAMS for audio in ((False, True) if holds else (False,))
]


@pytest.fixture(scope="module")
def clips(tmp_path_factory):
    folder = tmp_path_factory.mktemp("clips")
    for audio in (False, True):
        write_clip(folder / f"in-{audio}.mp4", size=(64, 48), frames=FRAMES, fps=12, audio=audio)
    return folder


def ffmpeg_reads(data_or_path, expect_audio: bool) -> None:
    """``ffmpeg -v error`` decodes every stream to the null muxer, silently, and
    ffprobe finds the video stream (and the audio one where it is expected)."""
    piped = isinstance(data_or_path, bytes)
    source = "-" if piped else str(data_or_path)
    kwargs = {"input": data_or_path} if piped else {}
    decode = subprocess.run([FFMPEG, "-v", "error", "-i", source, "-f", "null", "-"],
                            capture_output=True, timeout=60, **kwargs)  # fmt: skip
    assert decode.returncode == 0 and decode.stderr == b"", decode.stderr.decode()
    probe = subprocess.run(
        [shutil.which("ffprobe"), "-v", "error", "-show_entries", "stream=codec_type",
         "-of", "json", source],
        capture_output=True, timeout=60, **kwargs,
    )  # fmt: skip
    assert probe.returncode == 0 and probe.stderr == b"", probe.stderr.decode()
    kinds = sorted(s["codec_type"] for s in json.loads(probe.stdout)["streams"])
    assert kinds == (["audio", "video"] if expect_audio else ["video"]), kinds


@pytest.mark.parametrize("ext, audio", CASES)
def test_every_video_file_decodes_in_ffmpeg(cli, clips, tmp_path, ext, audio):
    out = tmp_path / f"out{ext}"
    proc = cli(clips / f"in-{audio}.mp4", "--ops", "swirl", "-o", out, "-q")
    assert proc.returncode == 0, proc.stderr
    ffmpeg_reads(out, audio)


@pytest.mark.parametrize("name, audio", PIPED)
def test_every_stream_from_a_pipe_decodes_in_ffmpeg(cli, clips, tmp_path, name, audio):
    proc = cli(clips / f"in-{audio}.mp4", "--ops", "swirl", "-o", "-", "--format", name, "-q",
               input=b"")  # fmt: skip
    assert proc.returncode == 0, proc.stderr.decode()
    if name in SEEKING_DEMUXERS:
        (tmp_path / "piped").write_bytes(proc.stdout)
        ffmpeg_reads(tmp_path / "piped", audio)
    else:
        ffmpeg_reads(proc.stdout, audio)


@pytest.mark.parametrize("to_pipe", [False, True])
def test_animated_webp_decodes_in_pillow(cli, clips, tmp_path, to_pipe):
    dst = "-" if to_pipe else tmp_path / "out.webp"
    proc = cli(clips / "in-False.mp4", "--ops", "swirl", "-o", dst, "--format", "webp", "-q",
               input=b"")  # fmt: skip
    assert proc.returncode == 0, proc.stderr.decode()
    data = proc.stdout if to_pipe else dst.read_bytes()
    with Image.open(io.BytesIO(data)) as image:
        assert image.format == "WEBP" and image.n_frames == FRAMES and image.is_animated
        for index in range(image.n_frames):
            image.seek(index)
            image.load()
            assert image.size == (64, 48)
