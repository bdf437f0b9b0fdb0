"""A video cut at its keyframes into segments that render independently, and
the segments joined back into one output.

- :func:`plan_segments` finds keyframes near evenly spaced times by seeking
  (no frame is decoded, the file is not read through): about
  :data:`SEGMENT_SECONDS` seconds a segment, or ``count`` segments.
  Segment *i* owns the frames with ``start <= t < end`` (``t`` on the
  input's clock, as the pipeline's: :mod:`marblevideo.jobs.pipeline`), so
  no frame is lost or doubled; the first has no ``start``, the last no
  ``end``.
- A segment is rendered by :func:`~marblevideo.jobs.pipeline.transcode`
  with the segment's range and ``pts_origin``: video only, in MP4
  (:data:`SEGMENT_FORMAT`), its frames marbled at their times on the whole
  input's clock, written with the source's own timestamps less the
  segment's origin (an MP4 keeps a stream's first timestamp only to the
  millisecond of its edit list, so each segment starts near 0 and the
  origin is added back when joining, exactly).
- :func:`join_segments` copies the segments' packets into the output (no
  re-encode), timestamps restored, and adds the source's audio once, as a
  single render would (copied or re-encoded by the same plan), atomically.
  Where a later segment's first decode timestamps fall before the previous
  segment's last (B-frames over a variable frame rate), they are moved up
  one tick at a time; presentation timestamps never change.
"""

from __future__ import annotations

import contextlib
import heapq
import os
from collections.abc import Iterator
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import av

from marblevideo.errors import MediaError, UsageError
from marblevideo.media.decode import Reader, input_name, open_input, packets
from marblevideo.media.encode import Encoder, OutputPlan, audio_plan
from marblevideo.media.encoders import library_logs
from marblevideo.media.output import atomic_output
from marblevideo.media.video import AudioItem, Stats, VideoOptions, job_notify

SEGMENT_SECONDS = 45.0  # aim of a segment's length; keyframes make it about 30-60 s
SEGMENT_FORMAT = "mp4"
REORDER_PACKETS = 16  # packets after a keyframe that may still show before it (open GOPs)


@dataclass(frozen=True)
class Segment:
    """One segment of a video: ``start``..``end`` seconds on the input's clock
    (None: from the first frame, to the last), its timestamps written less
    ``origin`` (input pts), and ``before``: the time of the frame shown just
    before ``start`` (None for the first segment)."""

    index: int
    count: int
    start: float | None
    end: float | None
    origin: int
    before: float | None = None

    def __str__(self) -> str:
        start = f"{self.start:.2f}" if self.start is not None else "0"
        end = f"{self.end:.2f} s" if self.end is not None else "end"
        return f"segment {self.index + 1} of {self.count} ({start}-{end})"


def keyframe_at(container, video, target: int) -> int | None:
    """The pts of the keyframe at or before ``target`` (pts), by seeking; None
    where the input cannot seek."""
    try:
        container.seek(target, stream=video, backward=True, any_frame=False)
    except (av.error.FFmpegError, OSError):
        return None
    for packet in packets(container, video):
        if packet.pts is not None and packet.is_keyframe:
            return packet.pts
    return None


def shown_before(container, video, boundary: int) -> int | None:
    """The pts of the last frame shown before ``boundary`` (a keyframe's pts):
    the packets from a keyframe before it, read but not decoded. (An MP4 seeks
    by decode time, which may land on ``boundary`` itself: the seek steps back
    until it lands before.)"""
    step, start = 1, None
    while start is None or start >= boundary:
        start = keyframe_at(container, video, boundary - step)
        if start is None or step > boundary - (video.start_time or 0) + 1:
            return None
        step *= 2
    with contextlib.suppress(av.error.FFmpegError, OSError):
        container.seek(start, stream=video, backward=True, any_frame=False)
    best, past = None, 0
    for packet in packets(container, video):
        if packet.pts is None or packet.pts < start:
            continue
        if packet.pts < boundary:
            best = packet.pts if best is None else max(best, packet.pts)
        elif packet.is_keyframe or past:
            past += 1
            if past > REORDER_PACKETS:
                break
    return best


def plan_segments(
    src: str | os.PathLike, count: int | None = None, seconds: float = SEGMENT_SECONDS
) -> list[Segment]:
    """The segments of video file ``src``: ``count`` of them where its keyframes
    allow (fewer where they do not), else one per about ``seconds``."""
    if count is not None and count < 1:
        raise UsageError(f"--segments: expected a count >= 1, got {count}")
    with open_input(src) as container:
        video = container.streams.video[0]
        tb, clock = video.time_base, video.start_time or 0
        if video.duration:
            length = float(video.duration * tb)
        elif container.duration:
            length = container.duration / av.time_base
        else:
            length = 0.0
        if count is None:
            count = max(1, round(length / seconds))
        first = keyframe_at(container, video, clock)
        if first is None or length <= 0:
            return [Segment(0, 1, None, None, clock)]
        bounds = set()
        for k in range(1, count):
            at = keyframe_at(container, video, clock + int(length * k / count / tb))
            if at is not None and at > first:
                bounds.add(at)
        bounds = sorted(bounds)
        befores = [shown_before(container, video, b) for b in bounds]

    def seconds_at(pts: int | None) -> float | None:
        return None if pts is None else float((pts - clock) * tb)

    starts = [None, *bounds]
    ends = [*bounds, None]
    n = len(starts)
    return [
        Segment(
            i,
            n,
            seconds_at(starts[i]),
            seconds_at(ends[i]),
            clock if i == 0 else starts[i],
            seconds_at(befores[i - 1]) if i else None,
        )
        for i in range(n)
    ]


def segment_plan(plan: OutputPlan, dst: str | os.PathLike) -> OutputPlan:
    """The plan of a segment of output ``dst`` (``plan``'s): the same encoder
    settings, video only, in MP4; UsageError where MP4 cannot hold the codec
    or ``dst`` is not a file in one piece."""
    if plan.sequence or plan.stream or plan.palette:
        raise UsageError(f"--cluster: {dst} is not written in one piece; give a video file")
    with av.open(os.devnull, "w", format=SEGMENT_FORMAT) as probe:
        supported = set(probe.supported_codecs)
    codec = av.Codec(plan.codec, "w")
    if codec.canonical_name not in supported and codec.name not in supported:
        raise UsageError(
            f"--cluster: segments are MP4, which cannot hold {codec.canonical_name} ({plan.codec})"
        )
    return OutputPlan(
        SEGMENT_FORMAT,
        plan.codec,
        plan.pix_fmt,
        dict(plan.codec_options),
        {},
        None,
        supported,
        plan.even,
    )


def round_half_away(value: Fraction) -> int:
    """``value`` rounded to the nearest integer, halves away from zero (FFmpeg's
    AV_ROUND_NEAR_INF, as the muxer rescales timestamps)."""
    whole = (abs(value.numerator) * 2 + value.denominator) // (2 * value.denominator)
    return whole if value >= 0 else -whole


def _video_packets(
    parts: list[tuple[Path, int]], src_tb: Fraction, out_tb: Fraction, extradata: bytes | None
) -> Iterator[tuple[float, int, av.Packet]]:
    """(seconds, 0, packet) of every segment's video, timestamps restored in ``out_tb``
    and decode timestamps kept increasing."""
    last_dts = None
    for path, origin in parts:
        with av.open(str(path)) as part:
            stream = part.streams.video[0]
            if stream.codec_context.extradata != extradata:
                raise MediaError(f"{path}: encoded with other settings than the first segment")
            shift = origin * src_tb
            for packet in packets(part, stream):
                if not packet.size or packet.pts is None:
                    continue
                tb = packet.time_base
                pts = round_half_away((packet.pts * tb + shift) / out_tb)
                dts = (
                    pts
                    if packet.dts is None
                    else round_half_away((packet.dts * tb + shift) / out_tb)
                )
                if last_dts is not None and dts <= last_dts:
                    dts = last_dts + 1
                    if dts > pts:
                        raise MediaError(f"{path}: decodes before the segment before it ends")
                last_dts = dts
                duration = round_half_away(packet.duration * tb / out_tb) if packet.duration else 0
                packet.pts, packet.dts, packet.duration = pts, dts, duration
                packet.time_base = out_tb
                yield float(dts * out_tb), 0, packet


def _audio_items(reader: Reader) -> Iterator[tuple[float, int, AudioItem]]:
    for item in reader.audio_only():
        payload = item.payload
        stamp = payload.dts if isinstance(payload, av.Packet) else None
        stamp = payload.pts if stamp is None else stamp
        yield float((stamp or 0) * payload.time_base), 1, item


def join_segments(
    src: str | os.PathLike,
    parts: list[tuple[Path, int]],
    dst: str | os.PathLike,
    plan: OutputPlan,
    options: VideoOptions,
) -> Stats:
    """Write ``dst`` atomically: the video packets of the segment files ``parts``
    ((path, origin) in order, see the module) and the audio of ``src`` as the
    options say. Returns what was written."""
    stats = Stats()
    notify = job_notify(options, stats)
    with open_input(src) as container:
        vin = container.streams.video[0]
        audio = audio_plan(container, plan, options, f"{Path(dst).suffix} files", notify)
        encoders = set(audio.values()) - {"copy"}
        stats.audio = encoders.pop() if encoders else "copy" if audio else "none"
        reader = Reader(container, None, None, audio)
        with av.open(str(parts[0][0])) as first:
            template = first.streams.video[0]
            extradata = template.codec_context.extradata
            with (
                atomic_output(dst, options.overwrite, [src]) as tmp,
                library_logs(options.verbose),
            ):
                out = av.open(str(tmp), "w", format=plan.format, options=plan.container_options)
                try:
                    video = out.add_stream_from_template(template)
                    video.time_base = vin.time_base
                    writer = Encoder(out, plan, options, stats, notify)
                    writer.open_audio({i: (container.streams[i], how) for i, how in audio.items()})
                    out.start_encoding()
                    stats.size = (template.codec_context.width, template.codec_context.height)
                    _mux(out, video, writer, parts, vin.time_base, extradata, reader, stats)
                    writer.flush()
                except av.error.FFmpegError as exc:
                    raise MediaError(f"{dst}: cannot join the segments: {exc.strerror}") from None
                finally:
                    out.close()
    if reader.corrupt:
        notify(f"{input_name(container)}: skipped {reader.corrupt} corrupt audio packet(s)")
    return stats


def _mux(out, video, writer: Encoder, parts, src_tb, extradata, reader: Reader, stats) -> None:
    """Video packets and audio items, merged in time order, into ``out``."""
    span = [None, None]  # first pts, end of the last frame (output time base)
    merged = heapq.merge(
        _video_packets(parts, src_tb, video.time_base, extradata),
        _audio_items(reader),
        key=lambda entry: (entry[0], entry[1]),
    )
    for _, kind, payload in merged:
        if kind == 1:
            writer.audio(payload)
            continue
        payload.stream = video
        first, end = span
        span[0] = payload.pts if first is None else min(first, payload.pts)
        span[1] = max(end or payload.pts, payload.pts + (payload.duration or 0))
        out.mux(payload)
        stats.frames += 1
    if span[0] is not None:
        stats.duration = float((span[1] - span[0]) * video.time_base)
