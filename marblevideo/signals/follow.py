"""A file render's signals: which audio a recipe follows, or why it cannot.

:func:`check` refuses, before any work and in one line (exit 2), a recipe that
uses a controller signal (they exist only in a live session) or an audio signal
with no audio to follow; :func:`follow` then binds the recipe to the analysis of
``--soundtrack`` (which wins; its first sample at t = 0) or of the input's first
audio stream (a0 from the container's timestamps). The analysis covers the whole
file from its start, so any segment of a render sees the same envelope.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from marblevideo.errors import UsageError
from marblevideo.media.formats import is_local, is_stdio
from marblevideo.media.inputs import Input, name_kind

if TYPE_CHECKING:
    from marblevideo.recipe import Recipe


def has_audio(path: str | os.PathLike) -> bool:
    """Whether the media file at ``path`` has an audio stream (False if unreadable)."""
    import av  # PyAV and the analysis are imported by a recipe that follows audio only

    try:
        with av.open(os.fspath(path)) as container:
            return bool(container.streams.audio)
    except (av.error.FFmpegError, OSError):
        return False


def check_soundtrack(soundtrack: str | os.PathLike) -> None:
    """UsageError unless ``soundtrack`` is a readable file with an audio stream."""
    if not os.path.isfile(soundtrack):
        raise UsageError(f"--soundtrack {soundtrack}: no such file")
    if not has_audio(soundtrack):
        raise UsageError(f"--soundtrack {soundtrack}: no audio stream to read")


def _no_audio(src) -> str | None:
    """Why the input ``src`` (a name or an :class:`~marblevideo.media.inputs.Input`)
    gives no audio to follow, or None when it does."""
    name = src.name if isinstance(src, Input) else src
    if name is None:
        return "a blank sheet has no audio"
    if is_stdio(name) or not is_local(name):
        return f"{'standard input' if is_stdio(name) else name} cannot be read twice for its audio"
    if name_kind(name) in ("image", "sequence"):
        return f"{name} is an image, with no audio"
    if not has_audio(name):
        return f"{name} has no audio stream"
    return None


def check(recipe: Recipe, src, soundtrack=None) -> None:
    """Refuse (UsageError, one line naming the parameter) a controller signal, or an
    audio signal where neither ``soundtrack`` nor the input ``src`` gives audio."""
    uses = recipe.signal_uses()
    for path, track in uses:
        if track.signal.controller:
            raise UsageError(
                f"{recipe.source}: {path}: follows the controller {track.signal.name}, which only "
                f"a live session hears (marblevideo live); its --automation FILE records what "
                f"the controllers did as keyframes that a file render takes"
            )
    audio = [(path, track) for path, track in uses if not track.signal.controller]
    if not audio:
        return
    if soundtrack is not None:
        check_soundtrack(soundtrack)
        return
    why = _no_audio(src)
    if why is not None:
        path, track = audio[0]
        raise UsageError(
            f"{recipe.source}: {path}: follows {track.signal.name}, but there is no audio to "
            f"follow ({why}); give one with --soundtrack FILE"
        )


def follow(recipe: Recipe, src, soundtrack=None) -> Recipe:
    """``recipe`` bound to the audio it follows (:func:`check` first); as it is when
    it follows none or is bound already."""
    if recipe.signals is not None or not recipe.signal_uses():
        return recipe
    from marblevideo.signals.audio import analyse
    from marblevideo.signals.values import AudioSignals

    check(recipe, src, soundtrack)  # a controller is refused: what is left is audio
    own = soundtrack is None
    if isinstance(src, Input):
        src = src.name
    return recipe.bind(AudioSignals(analyse(src if own else soundtrack, own=own)))
