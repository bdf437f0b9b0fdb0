"""A live session: a source marbled in real time.

Pipeline (one thread each, joined by one-slot "latest" mailboxes, so when a
stage is behind, frames are dropped rather than queued and latency stays
bounded)::

    capture -> [latest] -> render (main thread) -> [latest] -> JPEG for the preview
                                                -> [bounded, drops when full] -> recording
                                                -> [latest] -> virtual camera

- A new recipe to show (the designer's preview, a save) marbles the last
  captured frame again at once, for the preview's JPEG only, when that costs
  no captured frame (:mod:`marblevideo.live.redraw`); the outputs and the
  motion see each captured frame once.

- A recipe with ``motion`` renders each frame with the motion strokes its
  frames make (:class:`~marblevideo.live.stirring.LiveMotion`, one tracker for
  the session, kept across edits).
- The recipe file is polled every 0.5 s; a save reloads it. An invalid save
  keeps the previous recipe running; its one-line RecipeError is printed on
  stderr and shown on the preview page (the designer's, in live mode:
  :mod:`marblevideo.design.live`).
- How it plays (clock, bypass, mirror) is
  :class:`~marblevideo.live.playback.Playback`; the preview's JPEGs are
  :class:`~marblevideo.live.jpeg.JpegPreview`'s, the rates and latencies
  :class:`~marblevideo.live.meters.Meters`'.
"""

from __future__ import annotations

import sys
import threading
import time
from pathlib import Path

import numpy as np

from marblevideo.controllers.values import ControllerSignals, SessionSignals
from marblevideo.live.jpeg import JpegPreview
from marblevideo.live.meters import Meters, PreviewTimes
from marblevideo.live.playback import Playback
from marblevideo.live.preview import LivePreview
from marblevideo.live.redraw import LastFrame, redrawn
from marblevideo.live.report import session_stats, session_summary
from marblevideo.live.sources import Source
from marblevideo.live.stirring import LiveMotion
from marblevideo.serve.recipefile import RecipeFile
from marblevideo.signals.live import FrameTimed

RELOAD_POLL = 0.5


class LiveSession:
    """A running live job: source, recipe (watched), playback, outputs and counters."""

    def __init__(
        self,
        recipe_path: str | Path,
        source: Source,
        *,
        device: str | None = None,
        renderer=None,
        jpeg: bool = False,
        preview_width: int | None = None,
        jpeg_quality: int = 80,
        quiet: bool = False,
        notify=None,
        audio=None,
        audio_by_frame: bool = False,
        lattice: bool = True,
    ):
        from marblevideo.marbler import Marbler
        from marblevideo.opencl.renderer import Renderer

        self._notify = notify or (
            lambda msg: print(f"marblevideo: {msg}", file=sys.stderr, flush=True)
        )
        self.recipe_path = Path(recipe_path)
        # a bad recipe stops the start (exit 2); later bad saves are said and kept out
        self.file = RecipeFile(self.recipe_path, create=False, notify=self._notify)
        self.source = source
        self.renderer = renderer or Renderer(device, loop_walk=True)  # an edit never stalls a build
        self._Marbler = Marbler
        #: animated frames interpolate the map from a lattice (False: --exact-walk)
        self.lattice = lattice
        self.quiet = quiet
        self.playback = Playback()
        self.controllers = ControllerSignals()  # OSC and MIDI, fed by their listeners
        self._lock = threading.Lock()
        self._marbler = None
        self._marbled_for: object = None  # the recipe's version (or a preview's serial)
        #: the stroke being drawn on the designer's page, shown until a save
        self.drawing = LivePreview(str(self.recipe_path))
        self.motion = LiveMotion(source.fps)  # the recipe's motion, when it has one
        self.last = LastFrame(source.fps)  # marbled again when the recipe changes
        # other signals (audio, marblevideo.signals.live), beside the controllers: by
        # the shown frame's time in its file when audio_by_frame
        self.media_t = 0.0
        self.signals = FrameTimed(audio, lambda: self.media_t) if audio_by_frame else audio
        # outputs
        self.jpeg = jpeg  # whether frames shown go to the preview
        self.times = PreviewTimes()  # each preview's way through (GET /stats)
        self.preview = JpegPreview(preview_width, jpeg_quality, self.times.mark)
        self.recorder = None
        self.vcam = None
        self.streams: list = []  # marblevideo.live.stream.Streamer, one per server
        self.ndi = None  # marblevideo.live.ndi.NdiSender
        # counters
        self.frames = 0
        self.started = time.monotonic()
        self.meters = Meters()
        self._threads: list[threading.Thread] = []
        self.stop_event = threading.Event()

    # -- recipe -------------------------------------------------------------
    @property
    def recipe(self):
        """The recipe now (:class:`~marblevideo.serve.recipefile.RecipeFile`'s)."""
        return self.file.recipe

    @property
    def recipe_version(self) -> int:
        return self.file.version

    def check_reload(self) -> bool:
        """Take the recipe file's contents if another program changed it; whether it
        did. A change that does not validate is said and kept out."""
        if not self.file.check_reload():
            return False
        if not self.quiet:
            self._notify(f"reloaded {self.recipe_path}")
        return True

    def put(self, doc: object) -> int:
        """Validate ``doc``, save it atomically and take it from now (:meth:`redraw`);
        its version. RecipeError, nothing saved, when invalid."""
        version = self.file.put(doc)
        self.source.frames.wake()
        return version

    def show_preview(self, doc: object, version: object, sent: object = None) -> int:
        """Take the designer's preview (:meth:`~marblevideo.live.preview.LivePreview.put`)."""
        serial = self.drawing.put(doc, version, sent)
        self.times.mark(serial, "received")
        self.source.frames.wake()
        return serial

    def _watch(self) -> None:
        while not self.stop_event.wait(RELOAD_POLL):
            try:
                self.check_reload()
            except Exception as exc:  # noqa: BLE001 - an unreadable save is reported, not fatal
                self.file.error = f"{self.recipe_path}: {exc} (keeping the previous recipe)"
                self._notify(self.file.error)

    @property
    def clock(self):
        """The animation clock (:class:`~marblevideo.live.playback.Clock`)."""
        return self.playback.clock

    def _wanted(self):
        """(the recipe to show now, its key, the designer's preview's serial or 0)."""
        return self.drawing.shown(*self.file.snapshot()[1:])

    def _current(self):
        bypass, mirror = self.playback.snapshot()
        recipe, key, serial = self._wanted()
        with self._lock:
            if self._marbled_for != key:
                self._marbler = self._Marbler(
                    self._bound(recipe), renderer=self.renderer, lattice=self.lattice
                )
                self._marbled_for = key
            return self._marbler, bypass, mirror, serial

    def take_document(self) -> dict:
        """The recipe's JSON now, with the motion strokes made as ordinary
        ``stroke`` ops and without ``motion`` (``--automation``'s take)."""
        return self.motion.take_document(self.file.snapshot()[0])

    def _bound(self, recipe):
        """``recipe`` with its signals taken from the session's controllers (and
        the controllers told which names it uses)."""
        uses = recipe.signal_uses()
        self.controllers.known = frozenset(t.signal.name for _, t in uses if t.signal.controller)
        return recipe.bind(SessionSignals(self.controllers, self.signals)) if uses else recipe

    # -- playback (from the preview) ----------------------------------------
    def control(self, request: dict) -> dict:
        """Apply a control request (see Playback.apply); the new state."""
        return self.playback.apply(request, self.recipe)

    def state(self) -> dict:
        return self.playback.state()

    def stats(self) -> dict:
        """``GET /stats``: the counters, the meters' figures and the playback's state."""
        return session_stats(self)

    # -- threads ------------------------------------------------------------
    def _spawn(self, name: str, target) -> None:
        thread = threading.Thread(target=target, name=f"marblevideo-{name}", daemon=True)
        self._threads.append(thread)
        thread.start()

    def latest_jpeg(self, after: int, timeout: float = 1.0):
        """A JPEG newer than ``after`` (:meth:`JpegPreview.latest`)."""
        return self.preview.latest(after, timeout)

    # -- the loop -------------------------------------------------------------
    def run(self, duration: float | None = None) -> None:
        """Render until ``stop_event``, ``duration`` seconds, or the end of the source.
        The program is built (a blank frame of the source's size rendered) before
        the source and the clock start, so a cold build delays no frame."""
        w, h = self.source.size
        if w > 0 and h > 0:  # a source that knows its size before it starts
            self._current()[0].render(np.zeros((h, w, 4), np.uint8), 0.0)
        self._spawn("watch", self._watch)
        if self.jpeg:
            self._spawn("jpeg", lambda: self.preview.run(self.stop_event, self.meters.latency))
        self.source.start()
        self.started = time.monotonic()
        self.clock.restart()
        self.controllers.start(self.started)
        deadline = None if duration is None else self.started + duration
        while not self.stop_event.is_set():
            if deadline is not None and time.monotonic() >= deadline:
                break
            wait = 0.1 if deadline is None else max(0.0, min(0.1, deadline - time.monotonic()))
            cap = self.source.frames.get(timeout=wait)  # or None, woken by a new recipe
            if cap is None and self.redraw():
                continue
            if cap is None:
                if self.source.error is not None:
                    raise self.source.error
                if self.source.ended:
                    break
                continue
            if cap.media_t is not None:
                self.media_t = cap.media_t
            frame_t = self.motion.frame_time(cap.media_t, cap.ts, self.started)
            self.show(cap.rgba, cap.ts, frame_t, cap.luma)

    def show(
        self, rgba: np.ndarray, ts: float, frame_t: float | None = None, luma=None
    ) -> np.ndarray:
        """Marble one captured frame and hand it to every output; ``frame_t``: its
        time for the motion (default: ``ts`` from the session's start); ``luma``:
        its decoded luma plane, which the motion sees (default: the RGBA's luma)."""
        marbler, bypass, mirror, serial = self._current()
        captured = rgba
        if mirror:
            rgba = np.ascontiguousarray(rgba[:, ::-1])
            luma = None if luma is None else luma[:, ::-1]
        start = time.monotonic()
        frame_t = ts - self.started if frame_t is None else frame_t
        seen, shown = (rgba if luma is None else luma), self.clock.now()
        marbler = self.motion.marbler(marbler, seen, frame_t, shown)  # on while bypassed
        out = rgba if bypass else marbler.render(rgba, shown, animated=True)
        now = time.monotonic()
        self.times.rendered(serial, now - start)
        self.meters.frame(now, now - start)
        self.last.captured(captured, ts, self.meters.render.median() or now - start)
        self.frames += 1
        if self.jpeg:
            self.preview.put(out, ts, 0 if bypass else serial, None if bypass else shown)
        if self.recorder is not None:
            self.recorder.add(out, ts)
        if self.vcam is not None:
            self.vcam.send(out)
        for stream in self.streams:
            stream.add(out, ts)
        if self.ndi is not None:
            self.ndi.send(out)
        return out

    def redraw(self) -> bool:
        """Marble the last captured frame again for the preview's JPEG only, when the
        recipe to show is not the one it was marbled with and that costs no captured
        frame (:mod:`marblevideo.live.redraw`); whether the recipe was taken."""
        stale = self.jpeg and self._wanted()[1] != self._marbled_for
        if not (stale and self.last.allows(time.monotonic(), self.source.frames.waiting)):
            return False
        marbler, bypass, mirror, serial = self._current()
        if not bypass:  # (bypassed, the frame shown is the captured one: as it is)
            rgba = np.ascontiguousarray(self.last.rgba[:, ::-1] if mirror else self.last.rgba)
            with self.times.rendering(serial):  # (shown: the clock time it is marbled at)
                out = redrawn(marbler, self.motion, rgba, shown := self.clock.now())
            self.last.count += 1
            self.preview.put(out, None, serial, shown)
        return True

    def close(self) -> None:
        self.stop_event.set()
        self.source.stop()
        self.preview.close()
        for thread in self._threads:
            thread.join(5.0)

    def summary(self) -> str:
        """The line said at the end: frames, rate, drops, latency, outputs."""
        return session_summary(self)
