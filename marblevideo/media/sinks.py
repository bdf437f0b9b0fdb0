"""Where a video job's frames go (:func:`video_writer`): a file through FFmpeg,
standard output, or an image sequence.

Nothing is lost either way: a file is written to a temporary name beside the
target and renamed when complete (:func:`marblevideo.media.output.atomic_output`);
an image sequence is written as temporary files renamed into place once every
frame is written, and removed on failure; an existing file is replaced only
with ``overwrite``. Standard output gets the stream as it is made (a format
that cannot seek: MP4 and MOV are written fragmented).
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator
from fractions import Fraction
from pathlib import Path

import av

from marblevideo.errors import MediaError, OutputExistsError
from marblevideo.media.encode import Encoder, OutputPlan
from marblevideo.media.formats import sequence_name
from marblevideo.media.images import write_image
from marblevideo.media.output import atomic_output
from marblevideo.media.video import AudioItem, Span, Stats, VideoItem, VideoOptions, job_notify


class SequenceWriter:
    """Frames as numbered stills (``name_%04d.png`` -> ``name_0001.png``, ...),
    written by OpenCV at the still formats' quality; the same interface as
    :class:`~marblevideo.media.encode.Encoder`."""

    def __init__(self, pattern: str | os.PathLike, options: VideoOptions, stats: Stats):
        self.pattern, self.options, self.stats = Path(pattern), options, stats
        self.stream: str | None = None
        self.held: list[AudioItem] = []
        self.written: list[tuple[Path, Path]] = []  # (temporary, target)
        self.span = Span()
        self.time_base = Fraction(1)

    def open_video(self, width: int, height: int, time_base: Fraction, rate, colors) -> None:
        self.stream, self.time_base = "image2", time_base
        self.stats.size = (width, height)

    def open_audio(self, sources) -> None:
        """An image sequence holds no audio (the plan gives none)."""

    def video(self, item: VideoItem) -> None:
        target = sequence_name(self.pattern, len(self.written) + 1)
        tmp = target.with_name(f".{target.stem}.part{target.suffix}")
        self.written.append((tmp, target))
        write_image(tmp, item.rgba, alpha=False, fmt=target.suffix, name=target)
        self.stats.frames += 1
        self.span.extend(item)

    def audio(self, item: AudioItem) -> None:
        """No audio: nothing to write."""

    def flush(self) -> None:
        self.stats.duration = self.span.seconds(self.time_base)

    def commit(self) -> None:
        """Rename every frame into place."""
        for tmp, target in self.written:
            if target.exists() and not self.options.overwrite:
                raise OutputExistsError(f"{target}: already exists; use -y to overwrite")
            try:
                os.replace(tmp, target)
            except OSError as exc:
                raise MediaError(f"{target}: cannot write: {exc.strerror or exc}") from None

    def discard(self) -> None:
        """Remove the temporary frames left (all of them unless committed)."""
        for tmp, _ in self.written:
            with contextlib.suppress(FileNotFoundError):
                tmp.unlink()


def _closing(writer: Encoder, out) -> Iterator[Encoder]:
    ok = False
    try:
        yield writer
        ok = True
    finally:
        try:
            out.close()
        except av.error.FFmpegError as exc:
            if ok:
                raise MediaError(f"cannot finish the output: {exc.strerror}") from None


@contextlib.contextmanager
def video_writer(
    dst: str | os.PathLike,
    plan: OutputPlan,
    options: VideoOptions,
    stats: Stats,
    inputs: list = (),
) -> Iterator[Encoder | SequenceWriter]:
    """The writer of a job's output (see the module): an
    :class:`~marblevideo.media.encode.Encoder`, or a :class:`SequenceWriter`."""
    if plan.sequence:
        writer = SequenceWriter(dst, options, stats)
        try:
            yield writer
            writer.commit()
        finally:
            writer.discard()
        return
    notify = job_notify(options, stats)
    if plan.stream:
        out = av.open(sys.stdout.buffer, "w", format=plan.format, options=plan.container_options)
        try:
            yield from _closing(Encoder(out, plan, options, stats, notify), out)
        finally:
            with contextlib.suppress(OSError):
                sys.stdout.buffer.flush()
        return
    with atomic_output(dst, options.overwrite, inputs) as tmp:
        out = av.open(str(tmp), "w", format=plan.format, options=plan.container_options)
        yield from _closing(Encoder(out, plan, options, stats, notify), out)
