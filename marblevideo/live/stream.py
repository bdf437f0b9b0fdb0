"""Streaming a live session to an RTMP server (FLV: H.264 + AAC), which may go away.

- Encoding and sending run in one thread behind a small bounded queue, as the
  recording's (:mod:`marblevideo.live.recording`): a frame that finds the queue
  full is dropped and counted (``dropped``), so a slow network never holds back
  the live picture.
- Encoder settings are the recording's (``--codec``, ``--crf``, ``--preset``,
  ``--pix-fmt``, ``--encoder-opt``, checked by
  :func:`~marblevideo.media.encode.plan_output` for the ``flv`` format), with a
  keyframe every :data:`KEYFRAME_SECONDS` of capture time, asked of the encoder
  frame by frame (so a session slower than its nominal rate keeps them; the
  encoder's own ``g``, ``--encoder-opt g=N``, can only add more).
- Each connection is a fresh FLV stream: its timestamps (milliseconds, the FLV
  time base) start at its first frame's capture time, frames keep the spacing
  they were captured with; an AAC track (48 kHz stereo, silence: live sources
  bring no sound to the picture) keeps pace with the video, as services ask.
- When the server refuses the connection or drops it, the session goes on:
  one line says so, connecting is tried again after :data:`BACKOFF` (doubling
  up to :data:`BACKOFF_MAX`), the frames shown meanwhile are counted as
  ``lost``, and one line says when the stream resumed.
- Messages name the URL with its last part (the stream key) hidden.
"""

from __future__ import annotations

import contextlib
import queue
import threading
import time
from collections.abc import Callable
from fractions import Fraction

import av
import numpy as np

from marblevideo.errors import UsageError
from marblevideo.media.encode import Encoder, plan_output
from marblevideo.media.formats import is_stream_url, is_url
from marblevideo.media.video import Stats, VideoItem, VideoOptions

TIME_BASE = Fraction(1, 1000)
KEYFRAME_SECONDS = 2.0
BACKOFF = 0.5
BACKOFF_MAX = 2.0
QUEUE = 8
AUDIO_RATE = 48000


def check_stream_url(name: str) -> None:
    """UsageError (one line) for an output URL that cannot be streamed to."""
    if is_url(name) and not is_stream_url(name):
        scheme = name.split("://", 1)[0]
        raise UsageError(
            f"{name}: cannot stream to {scheme}://; a stream goes to rtmp://HOST/APP/KEY"
        )
    parts = name.split("://", 1)[1].split("/")
    if len(parts) < 3 or not all(parts):
        raise UsageError(f"{shown(name)}: expected rtmp://HOST[:PORT]/APP/KEY")


def shown(url: str) -> str:
    """``url`` as messages show it: its last part (the stream key) hidden."""
    head, sep, tail = url.rstrip("/").rpartition("/")
    return f"{head}/***" if sep and "://" in head and head.count("/") >= 3 and tail else url


class _Connection:
    """One FLV stream to the server: an output container, its video encoder and
    a silent AAC track keeping pace. Any error is the server's going away."""

    def __init__(self, url: str, plan, options: VideoOptions, size, fps: float):
        self.out = av.open(url, "w", format="flv", options={"flush_packets": "1"})
        try:
            self.encoder = Encoder(self.out, plan, options, Stats(), lambda msg: None)
            rate = Fraction(fps).limit_denominator(1001) if fps > 0 else None
            self.encoder.open_video(size[0], size[1], TIME_BASE, rate, {})
            self.audio = self.out.add_stream("aac", rate=AUDIO_RATE)
            self.audio.layout = "stereo"
            self.out.start_encoding()  # connects and publishes: a refusal is raised here
        except BaseException:
            self.close()
            raise
        self.origin: float | None = None
        self.last_pts = -1
        self.last_key: int | None = None  # pts of the last keyframe asked for
        self.samples = 0  # audio samples sent

    def send(self, rgba: np.ndarray, ts: float) -> bool:
        """Encode and send one frame captured at ``ts``; False when it shares the
        previous frame's millisecond (not sent)."""
        if self.origin is None:
            self.origin = ts
        pts = round((ts - self.origin) / TIME_BASE)
        if pts <= self.last_pts:
            return False
        self.last_pts = pts
        key = self.last_key is None or pts - self.last_key >= KEYFRAME_SECONDS * 1000
        if key:  # by time, whatever rate the frames come at
            self.last_key = pts
        self.encoder.video(VideoItem(rgba, pts, 0, ts - self.origin, key=key))
        self._silence_until(pts / 1000)
        return True

    def _silence_until(self, seconds: float) -> None:
        """Silent AAC frames up to ``seconds`` (and one frame ahead), so that the
        muxer, which interleaves by time, never holds the video back waiting."""
        size = self.audio.codec_context.frame_size or 1024
        while self.samples <= seconds * AUDIO_RATE:
            frame = av.AudioFrame.from_ndarray(
                np.zeros((2, size), np.float32), format="fltp", layout="stereo"
            )
            frame.sample_rate, frame.pts = AUDIO_RATE, self.samples
            frame.time_base = Fraction(1, AUDIO_RATE)
            self.out.mux(self.audio.encode(frame))
            self.samples += size

    def finish(self) -> None:
        """Send the frames the encoder holds, then close."""
        try:
            self.encoder.flush()
        finally:
            self.close()

    def close(self) -> None:
        with contextlib.suppress(av.error.FFmpegError, OSError):  # the server may be gone
            self.out.close()


class Streamer:
    """Frames of a live session to ``url`` (see the module); ``notify`` takes its
    one-line notices."""

    def __init__(self, url: str, options: VideoOptions, notify: Callable[[str], None]):
        check_stream_url(url)
        self.url, self.options, self.notify = url, options, notify
        self.plan = plan_output(url, options)  # every setting checked before anything opens
        self.sent = 0  # frames the server took
        self.lost = 0  # frames shown while the server was away
        self.dropped = 0  # frames the queue had no room for
        self.reconnects = 0
        self.connected = False
        self._queue: queue.Queue = queue.Queue(QUEUE)
        self._thread: threading.Thread | None = None
        self._connection: _Connection | None = None
        self._retry_at = 0.0
        self._failures = 0
        self._away_since: float | None = None
        self._lost_before = 0

    def start(self, width: int, height: int, fps: float) -> None:
        self.size, self.fps = (width, height), fps
        self._thread = threading.Thread(target=self._run, name="marblevideo-stream", daemon=True)
        self._thread.start()

    def add(self, rgba: np.ndarray, ts: float) -> None:
        """Queue a frame captured at ``ts`` (monotonic s); drop it when the queue is full."""
        try:
            self._queue.put_nowait((rgba, ts))
        except queue.Full:
            self.dropped += 1

    def _run(self) -> None:
        try:
            self._send_all()
        except BaseException as exc:  # noqa: BLE001 - said once; the session goes on
            self.notify(f"stream {shown(self.url)}: stopped ({exc or type(exc).__name__})")
            self.connected = False
            while self._queue.get() is not None:  # drain, so that close() never waits
                self.lost += 1

    def _send_all(self) -> None:
        self._connect()  # before the first frame, which then waits for no handshake
        while (item := self._queue.get()) is not None:
            if self._connection is None and not self._connect():
                self.lost += 1
                continue
            try:
                if self._connection.send(*item):
                    self.sent += 1
            except (av.error.FFmpegError, OSError) as exc:
                self.lost += 1
                self._went_away(exc)
        if self._connection is not None:
            try:
                self._connection.finish()
            except (av.error.FFmpegError, OSError) as exc:
                self._went_away(exc)

    def _connect(self) -> bool:
        """Open a connection when its time has come; whether one is open."""
        if time.monotonic() < self._retry_at:
            return False
        try:
            self._connection = _Connection(self.url, self.plan, self.options, self.size, self.fps)
        except (av.error.FFmpegError, OSError) as exc:
            self._went_away(exc)
            return False
        self._up()
        return True

    def _went_away(self, exc: BaseException) -> None:
        """The server refused or dropped the stream: notify it once, retry later."""
        if self._connection is not None:
            self._connection.close()
            self._connection = None
        now = time.monotonic()
        self._retry_at = now + min(BACKOFF_MAX, BACKOFF * 2**self._failures)
        self._failures += 1
        if self.connected or self._away_since is None:
            reason = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
            self.notify(
                f"stream {shown(self.url)}: the server is away ({reason}); the session goes "
                f"on, retrying every {BACKOFF_MAX:g} s at most"
            )
            self._away_since, self._lost_before = now, self.lost
        self.connected = False

    def _up(self) -> None:
        """The server took the stream: connected (said when it had been away)."""
        self.connected, self._failures = True, 0
        if self._away_since is not None:
            self.reconnects += 1
            away = time.monotonic() - self._away_since
            lost = self.lost - self._lost_before
            self.notify(
                f"stream {shown(self.url)}: resumed after {away:.1f} s ({lost} frames lost)"
            )
            self._away_since = None

    def close(self) -> None:
        """Send what is queued and end the stream (a server away is no error)."""
        if self._thread is None:
            return
        with contextlib.suppress(queue.Full):  # a server that hangs holds no session
            self._queue.put(None, timeout=10.0)
        self._thread.join(10.0)
        self._thread = None

    def summary(self) -> str:
        """The stream's part of the session's last line."""
        return (
            f"streamed {self.sent} to {shown(self.url)} ({self.lost} lost while the server "
            f"was away, {self.dropped} dropped, {self.reconnects} reconnects)"
        )

    def figures(self) -> dict:
        """What ``/stats`` shows of this stream."""
        return {
            "url": shown(self.url),
            "connected": self.connected,
            "sent": self.sent,
            "lost": self.lost,
            "dropped": self.dropped,
            "reconnects": self.reconnects,
        }
