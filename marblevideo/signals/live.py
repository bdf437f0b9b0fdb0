"""Audio signals in a live session: a file source's own audio, heard at the time
of the frame being shown (its place in the file, which a ``--loop`` starts
again), or ``--soundtrack FILE`` on the session's clock (its first sample when
the session starts). Cameras and the test pattern have no audio of their own.

The analysis (:mod:`marblevideo.signals.audio`) is made before the session
starts when the recipe follows audio, else the first time a saved edit does.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable

from marblevideo.errors import UsageError
from marblevideo.recipe import Recipe
from marblevideo.recipe.signals import Signal
from marblevideo.signals.audio import analyse
from marblevideo.signals.follow import check_soundtrack, has_audio
from marblevideo.signals.values import AudioSignals


class LazyAudio:
    """:class:`~marblevideo.signals.values.AudioSignals` of a file, analysed on first use."""

    def __init__(self, path: str | os.PathLike, own: bool):
        self.path, self.own = path, own
        self._audio: AudioSignals | None = None
        self._lock = threading.Lock()

    def ready(self) -> AudioSignals:
        with self._lock:
            if self._audio is None:
                self._audio = AudioSignals(analyse(self.path, own=self.own))
            return self._audio

    def at(self, signal: Signal, t: float) -> float:
        return self.ready().at(signal, t)


class FrameTimed:
    """Audio heard at ``now()`` (the shown frame's time in its file), whatever t
    the recipe is evaluated at (the session's animation clock)."""

    def __init__(self, audio, now: Callable[[], float]):
        self.audio, self.now = audio, now

    def at(self, signal: Signal, t: float) -> float:
        return self.audio.at(signal, self.now())


def live_audio(recipe: Recipe, source, soundtrack=None) -> tuple[LazyAudio | None, bool]:
    """(the audio a session's signals hear, whether it is heard by the frames'
    own times): ``soundtrack`` (session clock), else a local file source's own
    audio (its frames' times), else none. UsageError (exit 2) when the recipe
    follows audio and there is none, naming the parameter and --soundtrack."""
    if soundtrack is not None:
        check_soundtrack(soundtrack)
        audio, by_frames = LazyAudio(soundtrack, own=False), False
    else:
        url = getattr(source, "url", None)
        local = url is not None and "://" not in url and os.path.isfile(url)
        audio = LazyAudio(url, own=True) if local and has_audio(url) else None
        by_frames = True
    uses = [(p, t) for p, t in recipe.signal_uses() if not t.signal.controller]
    if uses and audio is None:
        path, track = uses[0]
        raise UsageError(
            f"{recipe.source}: {path}: follows {track.signal.name}, but the source "
            f"{source.name} has no audio to follow; give one with --soundtrack FILE"
        )
    if uses:
        audio.ready()  # before the clock starts
    return audio, by_frames
