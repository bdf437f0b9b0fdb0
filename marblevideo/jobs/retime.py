"""Frame-rate conversion of a decoded video, as ffmpeg's ``fps`` filter does it
(``round=near``): the output has one frame every 1/rate seconds, each the input
frame shown at that instant; input frames are dropped or repeated to fill the
slots, and the last one is held until the end of its duration (the end rounded
to a slot, as ffmpeg rounds its end of stream: a 1 s clip at 30 fps becomes
10 frames at 10 fps). A clip shorter than one slot still gives one frame.

Each output frame gets its own time ``t`` (the slot's instant on the input's
clock), so an animated recipe moves smoothly at the new rate even where an
input frame repeats. Audio items pass through unchanged.
"""

from __future__ import annotations

from collections.abc import Iterator
from fractions import Fraction

from marblevideo.media.video import AudioItem, VideoItem


def rate_fraction(fps: float) -> Fraction:
    """``fps`` as a fraction (29.97 -> 30000/1001)."""
    return Fraction(fps).limit_denominator(1001)


def retimed(
    items: Iterator[VideoItem | AudioItem], time_base: Fraction, fps: float
) -> Iterator[VideoItem | AudioItem]:
    """``items`` (video pts in ``time_base``) at ``fps``: video pts become slot
    numbers (time base 1/rate), each of duration 1."""
    rate = rate_fraction(fps)
    pending: VideoItem | None = None
    next_slot: int | None = None
    end_slot = start_slot = 0

    def repeat(frame: VideoItem, upto: int) -> Iterator[VideoItem]:
        nonlocal next_slot
        offset = float(frame.pts * time_base) - frame.t  # output clock - input clock
        while next_slot < upto:
            t = float(next_slot / rate) - offset
            yield VideoItem(frame.rgba, next_slot, 1, t, frame.i420, frame.matrix, luma=frame.luma)
            next_slot += 1

    for item in items:
        if not isinstance(item, VideoItem):
            yield item
            continue
        slot = round(item.pts * time_base * rate)
        end_slot = max(end_slot, round((item.pts + item.duration) * time_base * rate))
        if next_slot is None:
            next_slot = start_slot = slot
        if pending is not None and slot > next_slot:
            yield from repeat(pending, slot)
        if slot >= next_slot:  # the later of two frames in one slot wins; an earlier slot's drops
            pending = item
    if pending is not None:
        first = next_slot == start_slot
        yield from repeat(pending, max(end_slot, next_slot + 1) if first else end_slot)
