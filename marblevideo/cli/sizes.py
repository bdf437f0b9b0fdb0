"""``--size W`` and ``--size xH``: one side given, the other kept to the input's
aspect and rounded to an even number (as ffmpeg's ``scale=W:-2``), so 4:2:0
video encodes without padding. The input's size is its first frame's as shown
(display rotation applied); a blank sheet has no size of its own to keep."""

from __future__ import annotations

import os

from marblevideo.cli.arguments import parse_size
from marblevideo.errors import MediaError, UsageError
from marblevideo.limits import MAX_SIDE


def one_side(text: str) -> tuple[int | None, int | None] | None:
    """(W, None) for ``W``, (None, H) for ``xH``; None when ``text`` gives both sides."""
    lowered = text.strip().lower()
    if lowered.isdigit():
        return int(lowered), None
    if lowered.startswith("x") and lowered[1:].isdigit():
        return None, int(lowered[1:])
    return None


def even(value: float) -> int:
    """The nearest even number, at least 2."""
    return max(2, round(value / 2) * 2)


def keep_aspect(side: tuple[int | None, int | None], natural: tuple[int, int]) -> tuple[int, int]:
    """The (W, H) with the given side and the other one at ``natural``'s aspect, even."""
    width, height = side
    if width is not None:
        return width, even(width * natural[1] / natural[0])
    return even(height * natural[0] / natural[1]), height


def resolve_size(text: str | None, src) -> tuple[int, int] | None:
    """``--size`` as (W, H): WxH as given, or one side and the other from ``src``'s
    aspect; UsageError (one line) for a bad size or a blank sheet with one side."""
    if text is None:
        return None
    side = one_side(text)
    if side is None:
        return parse_size(text)
    given = side[0] if side[0] is not None else side[1]
    if not 0 < given <= MAX_SIDE:
        raise UsageError(f"--size: each side must be 1..{MAX_SIDE}, got {text!r}")
    if src is None:
        raise UsageError(f"--size {text}: a blank sheet has no aspect to keep; give WxH")
    if os.fspath(src) == "-":
        raise UsageError(f"--size {text}: standard input is read once; give WxH")
    return keep_aspect(side, natural_size(src))


def natural_size(src) -> tuple[int, int]:
    """(W, H) of ``src``'s first frame as shown: a still or a video (MediaError)."""
    from marblevideo.media.formats import is_image_name

    if is_image_name(src):
        import cv2

        image = cv2.imread(os.fspath(src), cv2.IMREAD_UNCHANGED)
        if image is None:
            raise MediaError(f"{src}: not a readable image")
        return image.shape[1], image.shape[0]
    from marblevideo.media.decode import open_input, upright

    with open_input(src) as container:
        for frame in container.decode(video=0):
            rgba = upright(frame)
            return rgba.shape[1], rgba.shape[0]
    raise MediaError(f"{src}: no video frame")
