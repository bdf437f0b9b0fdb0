"""What an input or output name means: the output formats a video job can write
(muxer, default encoder and pixel format, the audio it holds), image-sequence
patterns, standard streams and URLs.

Conventions: a name ``-`` is standard input (as an input) or standard output
(as an output, with a format named by ``--format``); a name with a scheme
(``https://...``, ``rtmp://...``) is a URL FFmpeg opens; a name with one
printf-style frame field (``%d``, ``%04d``) is an image sequence, numbered from
1 when written (as FFmpeg's image2 muxer does).
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from marblevideo.errors import UsageError

STDIO = "-"
#: Still image extensions (read and written by OpenCV).
IMAGE_EXTENSIONS = frozenset({".png", ".jpg", ".jpeg", ".tif", ".tiff", ".webp"})
_FRAME_FIELD = re.compile(r"%0?(\d*)d")
_URL = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*://")
#: URL schemes a stream goes to.
STREAM_SCHEMES = ("rtmp://", "rtmps://")


@dataclass(frozen=True)
class OutputFormat:
    """A video output format: FFmpeg muxer, default video encoder and pixel
    format, the audio re-encoder (None: the format holds no audio), container
    options for a file and for a stream that cannot seek, and the codecs it holds
    beyond those FFmpeg's muxer answers for (``supported_codecs`` lists only a
    muxer's defaults where it cannot be asked, as MPEG-TS)."""

    muxer: str
    codec: str
    audio: str | None
    file_options: dict[str, str] = field(default_factory=dict)
    stream_options: dict[str, str] = field(default_factory=dict)
    pix_fmt: str = "yuv420p"
    also_holds: frozenset[str] = frozenset()


_MP4 = {"movflags": "+faststart"}
_MP4_STREAM = {"movflags": "frag_keyframe+empty_moov+default_base_moof"}
#: What FFmpeg's MPEG-TS muxer writes (libavformat/mpegtsenc.c's stream types).
_TS_CODECS = frozenset(
    [
        "h264",
        "hevc",
        "vvc",
        "av1",
        "mpeg1video",
        "mpeg2video",
        "mpeg4",
        "vc1",
        "dirac",
        "aac",
        "mp2",
        "mp3",
        "ac3",
        "eac3",
        "opus",
    ]
)
#: Output formats by name (the name ``--format`` takes).
FORMATS = {
    "mp4": OutputFormat("mp4", "libx264", "aac", _MP4, _MP4_STREAM),
    "mov": OutputFormat("mov", "libx264", "aac", _MP4, _MP4_STREAM),
    "matroska": OutputFormat("matroska", "libx264", "aac"),
    "webm": OutputFormat("webm", "libvpx-vp9", "libopus"),
    "nut": OutputFormat("nut", "libx264", "aac"),
    "mpegts": OutputFormat("mpegts", "libx264", "aac", also_holds=_TS_CODECS),
    "yuv4mpegpipe": OutputFormat("yuv4mpegpipe", "wrapped_avframe", None),
    "gif": OutputFormat("gif", "gif", None, pix_fmt="pal8"),
    # animations loop forever, as GIF's muxer does by default
    "apng": OutputFormat("apng", "apng", None, {"plays": "0"}, {"plays": "0"}, "rgb24"),
    "webp": OutputFormat("webp", "libwebp_anim", None, {"loop": "0"}, {"loop": "0"}),
    # what a live session streams to an RTMP server (marblevideo.live.stream)
    "flv": OutputFormat("flv", "libx264", "aac"),
}
#: Still encodings ``--format`` names for a still written to standard output.
STILL_FORMATS = {"png": ".png", "jpeg": ".jpg", "jpg": ".jpg", "tiff": ".tif", "tif": ".tif"}
#: Outputs written as vectors.
VECTOR_EXTENSIONS = (".svg", ".pdf")
#: Other names ``--format`` takes.
FORMAT_ALIASES = {"mkv": "matroska", "y4m": "yuv4mpegpipe", "ts": "mpegts"}
#: Output extension -> format (a still extension is a still unless --format says).
EXTENSION_FORMATS = {
    ".mp4": "mp4",
    ".m4v": "mp4",
    ".mov": "mov",
    ".mkv": "matroska",
    ".webm": "webm",
    ".nut": "nut",
    ".ts": "mpegts",
    ".y4m": "yuv4mpegpipe",
    ".gif": "gif",
    ".apng": "apng",
}


def output_kinds() -> str:
    """Every kind of output an ``-o`` name makes, by extension, from the tables
    above: what ``--help`` shows and an unknown extension's error lists."""
    stills = " ".join(sorted(IMAGE_EXTENSIONS))
    video = " ".join(EXTENSION_FORMATS)
    vectors = " ".join(VECTOR_EXTENSIONS)
    return f"stills {stills}; video {video}; an image sequence name_%04d.png; vectors {vectors}"


def is_stdio(name: str | os.PathLike | None) -> bool:
    return name is not None and os.fspath(name) == STDIO


def is_url(name: str | os.PathLike | None) -> bool:
    return name is not None and bool(_URL.match(os.fspath(name)))


def is_stream_url(name: str) -> bool:
    """Whether an output name is a stream to a server (``rtmp://``, ``rtmps://``)."""
    return name.lower().startswith(STREAM_SCHEMES)


def is_image_path(path: str | os.PathLike) -> bool:
    """Whether ``path`` names a still image, by its extension."""
    return Path(path).suffix.lower() in IMAGE_EXTENSIONS


def is_local(name: str | os.PathLike | None) -> bool:
    """A name on this machine's file system (not ``-``, not a URL)."""
    return name is not None and not is_stdio(name) and not is_url(name)


def frame_field(name: str | os.PathLike) -> re.Match | None:
    """The printf-style frame field of an image-sequence name (``%04d``), or None."""
    return _FRAME_FIELD.search(Path(os.fspath(name)).name)


def is_sequence(name: str | os.PathLike | None) -> bool:
    """Whether ``name`` is an image sequence: one frame field and a still extension."""
    if name is None or is_stdio(name) or is_url(name):
        return False
    text = Path(os.fspath(name)).name
    return (
        len(_FRAME_FIELD.findall(text)) == 1
        and Path(text).suffix.lower() in IMAGE_EXTENSIONS
        and "%" not in _FRAME_FIELD.sub("", text)
    )


def is_image_name(name: str | os.PathLike | None) -> bool:
    """A single still image file (not a sequence, stream or URL)."""
    if name is None or is_stdio(name) or is_url(name) or is_sequence(name):
        return False
    return Path(os.fspath(name)).suffix.lower() in IMAGE_EXTENSIONS


def format_named(name: str) -> str:
    """The format called ``name`` by ``--format`` (aliases resolved), or UsageError."""
    key = FORMAT_ALIASES.get(name.lower(), name.lower())
    if key not in FORMATS:
        known = ", ".join(sorted({*FORMATS, *FORMAT_ALIASES}))
        stills = ", ".join(STILL_FORMATS)
        raise UsageError(
            f"--format: unknown format {name!r}; video: {known}; a still to -o -: {stills}"
        )
    return key


def output_kind(dst: str | os.PathLike, forced: str | None = None) -> str:
    """What an output name (and ``--format``) makes: "vector" (.svg, .pdf), "still"
    (a still extension; ``-`` with a still encoding) or "video" (anything else,
    unknown extensions included: :func:`marblevideo.media.encode.plan_output`
    refuses those)."""
    if is_stdio(dst):
        return "still" if forced is not None and forced.lower() in STILL_FORMATS else "video"
    if forced is None and Path(os.fspath(dst)).suffix.lower() in VECTOR_EXTENSIONS:
        return "vector"
    return "still" if forced is None and is_image_name(dst) else "video"


def still_extension(dst: str | os.PathLike, forced: str | None = None) -> str:
    """The still format of a still output, as its extension (.png, .jpg, ...)."""
    if is_stdio(dst):
        if forced is None or forced.lower() not in STILL_FORMATS:
            names = ", ".join(STILL_FORMATS)
            raise UsageError(f"-o -: name the still's format with --format ({names})")
        return STILL_FORMATS[forced.lower()]
    if forced is not None:
        raise UsageError(f"--format {forced}: {dst} is a still; its extension decides")
    return Path(os.fspath(dst)).suffix.lower()


def output_format(dst: str | os.PathLike, forced: str | None = None) -> str | None:
    """The format of a video output: ``forced`` (``--format``), else by extension;
    None where the name makes no video (a still, a sequence, an unknown extension)."""
    if forced is not None:
        return format_named(forced)
    if is_stdio(dst):
        return None
    return EXTENSION_FORMATS.get(Path(os.fspath(dst)).suffix.lower())


def sequence_names(pattern: str | os.PathLike, folder_names: list[str]) -> list[str]:
    """The names in ``folder_names`` that ``pattern``'s frame field matches."""
    text = Path(os.fspath(pattern)).name
    match = frame_field(text)
    width = match.group(1)
    digits = rf"\d{{{int(width)},}}" if width else r"\d+"
    regex = re.escape(text[: match.start()]) + digits + re.escape(text[match.end() :])
    return sorted(n for n in folder_names if re.fullmatch(regex, n))


def sequence_name(pattern: str | os.PathLike, number: int) -> Path:
    """The file of frame ``number`` of a sequence ``pattern``."""
    path = Path(os.fspath(pattern))
    match = frame_field(path.name)
    width = int(match.group(1) or 0)
    name = path.name[: match.start()] + f"{number:0{width}d}" + path.name[match.end() :]
    return path.with_name(name)
