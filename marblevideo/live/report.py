"""What a live session says of itself: ``GET /stats`` (:func:`session_stats`) and
the line at the end (:func:`session_summary`)."""

from __future__ import annotations

import time


def session_stats(session) -> dict:
    """``GET /stats`` of :class:`~marblevideo.live.session.LiveSession` ``session``:
    the counters, the meters' figures and the playback's state; ``redrawn``: the
    last captured frame marbled again for the preview (a new recipe between frames);
    ``preview_times``: when each of the designer's last previews was taken, first
    rendered and first in a JPEG (:class:`~marblevideo.live.meters.PreviewTimes`)."""
    now, recorder = time.monotonic(), session.recorder
    return {
        "frames": session.frames,
        **session.meters.figures(now),
        "dropped": session.source.frames.dropped,
        "preview_skipped": session.preview.skipped,
        "redrawn": session.last.count,
        "record_dropped": recorder.dropped if recorder else 0,
        "recorded": recorder.frames if recorder else 0,
        "jpeg_seq": session.preview.seq,
        "preview_times": session.times.figures(),
        "size": list(session.source.size),
        "source": session.source.name,
        "recipe_version": session.file.snapshot()[2],
        "recipe_error": session.file.error,
        "uptime": round(now - session.started, 2),
        "controllers": dict(session.controllers.counts),
        "streams": [stream.figures() for stream in session.streams],
        "ndi": session.ndi.figures() if session.ndi is not None else None,
        **session.state(),
    }


def session_summary(session) -> str:
    """The line said when ``session`` ends: frames, rate, drops, latency, outputs."""
    s = session.stats()
    elapsed = max(time.monotonic() - session.started, 1e-9)
    text = (
        f"live: {session.frames} frames in {elapsed:.1f} s ({session.frames / elapsed:.1f} fps), "
        f"{s['dropped']} source frames dropped"
    )
    if s["latency_ms"] is not None:
        text += f", latency median {s['latency_ms']} ms (p95 {s['latency_p95_ms']} ms)"
    recorder = session.recorder
    if recorder is not None:
        text += f", recorded {recorder.frames} ({recorder.dropped} dropped)"
    for stream in session.streams:
        text += f", {stream.summary()}"
    if session.ndi is not None:
        text += f", NDI {session.ndi.sent} sent as {session.ndi.full_name}"
    return text
