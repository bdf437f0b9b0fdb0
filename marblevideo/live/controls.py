"""``marblevideo live``: marble a camera, a file/URL or a test pattern in real time.

Pipeline (one thread each, joined by one-slot "latest" mailboxes, so when a
stage is behind, frames are dropped rather than queued and latency stays
bounded)::

    capture -> [latest] -> render (main thread) -> [latest] -> JPEG for the preview
                                                -> [bounded, drops when full] -> recording
                                                -> [latest] -> virtual camera

- The animation clock is wall-clock time since the start (``t = 0`` at the
  first frame); the preview can pause it (the source keeps flowing; the design
  holds still) and restart it at 0.
- The recipe file is polled every 0.5 s; a save reloads it. An invalid save
  keeps the previous recipe running; its one-line RecipeError is printed on
  stderr and shown on the preview page. Slider overrides are reset by a reload.
- Sliders: every op parameter that is a constant number (not keyframed) can be
  overridden from the preview; keyframed ones are shown as animated.
- Mirror flips the source left-right (selfie view) before marbling.
- Stopping: ``--duration``, the end of a file source without ``--loop``, or
  SIGINT (Ctrl-C) / SIGTERM, which are the normal end of a live session: the
  recording so far is finalized and kept and the exit status is 0. A second
  Ctrl-C while finalizing aborts (exit 130, no recording left).
"""

from __future__ import annotations

import argparse
import math
import signal
import statistics
import sys
import threading
import time
from collections import deque
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

from marblevideo.cli import add_encoder_arguments, configure_logging, parse_encoder_opts
from marblevideo.errors import MarbleError, RecipeError, UsageError
from marblevideo.live.sources import Latest, Source, open_source
from marblevideo.ops import NUMERIC_KINDS, op_def, slider_range
from marblevideo.recipe.keyframes import Track

DEFAULT_PORT = 8765
RELOAD_POLL = 0.5
VCAM_HELP = (
    "pip install 'marblevideo[vcam]' (pyvirtualcam), and on Linux a v4l2loopback device: "
    "sudo apt-get install v4l2loopback-dkms && "
    "sudo modprobe v4l2loopback devices=1 exclusive_caps=1"
)


class Clock:
    """Wall-clock seconds since the start; pausable and restartable."""

    def __init__(self):
        self._lock = threading.Lock()
        self._origin = time.monotonic()
        self._paused_at: float | None = None

    @property
    def paused(self) -> bool:
        return self._paused_at is not None

    def now(self) -> float:
        with self._lock:
            ref = self._paused_at if self._paused_at is not None else time.monotonic()
            return ref - self._origin

    def pause(self, paused: bool = True) -> None:
        with self._lock:
            now = time.monotonic()
            if paused and self._paused_at is None:
                self._paused_at = now
            elif not paused and self._paused_at is not None:
                self._origin += now - self._paused_at
                self._paused_at = None

    def restart(self) -> None:
        with self._lock:
            self._origin = time.monotonic()
            if self._paused_at is not None:
                self._paused_at = self._origin


# ---------------------------------------------------------------------------- sliders


def sliders(recipe, canvas: tuple[float, float] | None) -> list[dict]:
    """What the preview shows per op: each numeric parameter, adjustable if constant."""
    size = max(recipe.canvas or canvas or (1000.0, 1000.0))
    ops = []
    for op in recipe.ops:
        params = []
        for param in op_def(op.type).params:
            if param.kind not in NUMERIC_KINDS:
                continue
            name = param.name
            track = op.params[name]
            if track.keyed:
                params.append({"name": name, "animated": True})
                continue
            v = float(track.keys[0].v[0])
            lo, hi, step = slider_range(param, v, size)
            params.append(
                {"name": name, "value": v, "min": lo, "max": hi, "step": step, "animated": False}
            )
        ops.append({"index": op.index, "type": op.type, "params": params})
    return ops


def with_overrides(recipe, overrides: dict[tuple[int, str], float]):
    """``recipe`` with constant parameters replaced: {(op index, name): value}."""
    if not overrides:
        return recipe
    ops = list(recipe.ops)
    for (i, name), value in overrides.items():
        params = dict(ops[i].params)
        params[name] = Track.constant(float(value))
        ops[i] = replace(ops[i], params=params)
    return replace(recipe, ops=tuple(ops))


# ---------------------------------------------------------------------------- session


class _Window:
    """Rates and latencies over the last few seconds."""

    def __init__(self, span: float = 2.0, keep: int = 120):
        self.span = span
        self.times: deque[float] = deque()
        self.values: deque[float] = deque(maxlen=keep)

    def add(self, now: float, value: float | None = None) -> None:
        self.times.append(now)
        while self.times and self.times[0] < now - self.span:
            self.times.popleft()
        if value is not None:
            self.values.append(value)

    def rate(self, now: float) -> float:
        recent = [t for t in self.times if t >= now - self.span]
        if len(recent) < 2:
            return 0.0
        return (len(recent) - 1) / max(recent[-1] - recent[0], 1e-9)

    def median(self) -> float | None:
        return statistics.median(self.values) if self.values else None

    def quantile(self, q: float) -> float | None:
        if not self.values:
            return None
        ordered = sorted(self.values)
        return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


class LiveSession:
    """A running live job: source, recipe (watched), controls, outputs and counters."""

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
        say=None,
    ):
        from marblevideo.api import Marbler
        from marblevideo.opencl.renderer import Renderer
        from marblevideo.recipe import load_recipe

        self._load = load_recipe
        self.recipe_path = Path(recipe_path)
        self.recipe = load_recipe(recipe_path)  # a bad recipe stops the start (exit 2)
        self._stamp = self._file_stamp()
        self.source = source
        self.renderer = renderer or Renderer(device)
        self._Marbler = Marbler
        self.quiet = quiet
        self._say = say or (lambda msg: print(f"marblevideo: {msg}", file=sys.stderr, flush=True))
        self.clock = Clock()
        self.bypass = False
        self.mirror = False
        self.overrides: dict[tuple[int, str], float] = {}
        self.recipe_version = 1
        self.recipe_error: str | None = None
        self._lock = threading.Lock()
        self._marbler = None
        self._dirty = True
        # outputs
        self.shown = Latest()  # rendered frames for the JPEG encoder
        self.jpeg = jpeg
        self.preview_width = preview_width
        self.jpeg_quality = jpeg_quality
        self.jpeg_cond = threading.Condition()
        self.jpeg_bytes: bytes | None = None
        self.jpeg_seq = 0
        self.recorder = None
        self.vcam = None
        # counters
        self.frames = 0
        self.started = time.monotonic()
        self._rendered = _Window()
        self._latency = _Window()  # capture -> JPEG ready, seconds
        self._render_ms = _Window()
        self._threads: list[threading.Thread] = []
        self.stop_event = threading.Event()

    # -- recipe -------------------------------------------------------------
    def _file_stamp(self):
        try:
            st = self.recipe_path.stat()
        except OSError:
            return None
        return (st.st_mtime_ns, st.st_size)

    def check_reload(self) -> bool:
        """Reload the recipe if its file changed; returns whether it did."""
        stamp = self._file_stamp()
        if stamp is None or stamp == self._stamp:
            return False
        self._stamp = stamp
        try:
            recipe = self._load(self.recipe_path)
        except RecipeError as exc:
            with self._lock:
                self.recipe_error = str(exc)
            self._say(f"{exc} (keeping the previous recipe)")
            return False
        with self._lock:
            self.recipe = recipe
            self.recipe_version += 1
            self.recipe_error = None
            self.overrides.clear()
            self._dirty = True
        if not self.quiet:
            self._say(f"reloaded {self.recipe_path}")
        return True

    def _watch(self) -> None:
        while not self.stop_event.wait(RELOAD_POLL):
            try:
                self.check_reload()
            except Exception as exc:  # noqa: BLE001 - an unreadable save is reported, not fatal
                with self._lock:
                    self.recipe_error = f"{self.recipe_path}: {exc}"
                self._say(f"{self.recipe_path}: {exc} (keeping the previous recipe)")

    def _current(self):
        with self._lock:
            if self._dirty:
                recipe = with_overrides(self.recipe, self.overrides)
                self._marbler = self._Marbler(recipe, renderer=self.renderer)
                self._dirty = False
            return self._marbler, self.bypass, self.mirror

    # -- controls (from the preview) ----------------------------------------
    def params(self) -> dict:
        with self._lock:
            recipe, overrides, version = self.recipe, dict(self.overrides), self.recipe_version
        ops = sliders(recipe, self.source.size)
        for op in ops:
            for p in op["params"]:
                key = (op["index"], p["name"])
                if key in overrides:
                    p["value"] = overrides[key]
        return {"version": version, "source": str(self.recipe_path), "ops": ops}

    def control(self, request: dict) -> dict:
        """Apply a control request; UsageError on a bad one. Returns the new state.

        Fields (all optional): ``paused`` (bool), ``restart`` (true), ``bypass``
        (bool), ``mirror`` (bool), ``param`` ({"op": i, "name": n, "value": v}),
        ``reset`` (true: drop every slider override).
        """
        if not isinstance(request, dict):
            raise UsageError("control: expected a JSON object")
        known = {"paused", "restart", "bypass", "mirror", "param", "reset"}
        unknown = set(request) - known
        if unknown:
            raise UsageError(f"control: unknown field {sorted(unknown)[0]!r}")
        for name in ("paused", "bypass", "mirror", "restart", "reset"):
            if name in request and not isinstance(request[name], bool):
                raise UsageError(f"control: {name} must be true or false")
        param = request.get("param")
        if param is not None:
            key, value = self._check_param(param)
        with self._lock:
            if "paused" in request:
                self.clock.pause(request["paused"])
            if request.get("restart"):
                self.clock.restart()
            if "bypass" in request:
                self.bypass = request["bypass"]
            if "mirror" in request:
                self.mirror = request["mirror"]
            if request.get("reset"):
                self.overrides.clear()
                self._dirty = True
            if param is not None:
                self.overrides[key] = value
                self._dirty = True
        return self.state()

    def _check_param(self, param) -> tuple[tuple[int, str], float]:
        if not isinstance(param, dict) or set(param) != {"op", "name", "value"}:
            raise UsageError('control: param must be {"op": INDEX, "name": NAME, "value": NUMBER}')
        i, name, value = param["op"], param["name"], param["value"]
        with self._lock:
            ops = self.recipe.ops
        if not isinstance(i, int) or isinstance(i, bool) or not 0 <= i < len(ops):
            raise UsageError(f"control: param.op must be an op index 0..{len(ops) - 1}, got {i!r}")
        kind = op_def(ops[i].type).kinds.get(name)
        if kind not in NUMERIC_KINDS:
            raise UsageError(f"control: ops[{i}] ({ops[i].type}) has no numeric {name!r}")
        if ops[i].params[name].keyed:
            raise UsageError(f"control: ops[{i}].{name} is keyframed (animated), not adjustable")
        ok = isinstance(value, int | float) and not isinstance(value, bool)
        if not ok or not math.isfinite(value) or abs(value) > 1e30:
            raise UsageError(f"control: ops[{i}].{name}: expected a finite number, got {value!r}")
        if (kind == "positive" and value <= 0) or (kind == "nonnegative" and value < 0):
            raise UsageError(f"control: ops[{i}].{name}: must be {kind}, got {value}")
        return (i, name), float(value)

    def state(self) -> dict:
        return {
            "paused": self.clock.paused,
            "bypass": self.bypass,
            "mirror": self.mirror,
            "t": round(self.clock.now(), 3),
            "overrides": [
                {"op": i, "name": n, "value": v} for (i, n), v in sorted(self.overrides.items())
            ],
        }

    def stats(self) -> dict:
        now = time.monotonic()
        lat = self._latency.median()
        p95 = self._latency.quantile(0.95)
        render = self._render_ms.median()
        with self._lock:
            error, version = self.recipe_error, self.recipe_version
        return {
            "frames": self.frames,
            "fps": round(self._rendered.rate(now), 2),
            "latency_ms": None if lat is None else round(lat * 1000, 1),
            "latency_p95_ms": None if p95 is None else round(p95 * 1000, 1),
            "render_ms": None if render is None else round(render * 1000, 2),
            "dropped": self.source.frames.dropped,
            "preview_skipped": self.shown.dropped,
            "record_dropped": self.recorder.dropped if self.recorder else 0,
            "recorded": self.recorder.frames if self.recorder else 0,
            "jpeg_seq": self.jpeg_seq,
            "size": list(self.source.size),
            "source": self.source.name,
            "recipe_version": version,
            "recipe_error": error,
            "uptime": round(now - self.started, 2),
            **self.state(),
        }

    # -- threads ------------------------------------------------------------
    def _spawn(self, name: str, target) -> None:
        thread = threading.Thread(target=target, name=f"marblevideo-{name}", daemon=True)
        self._threads.append(thread)
        thread.start()

    def _encode_jpeg(self) -> None:
        params = [cv2.IMWRITE_JPEG_QUALITY, int(self.jpeg_quality)]
        while not self.stop_event.is_set():
            item = self.shown.get(timeout=0.2)
            if item is None:
                continue
            rgba, ts = item
            if self.preview_width and self.preview_width < rgba.shape[1]:
                h = max(1, round(rgba.shape[0] * self.preview_width / rgba.shape[1]))
                rgba = cv2.resize(rgba, (self.preview_width, h), interpolation=cv2.INTER_AREA)
            ok, buf = cv2.imencode(".jpg", cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGR), params)
            if not ok:
                continue
            done = time.monotonic()
            self._latency.add(done, done - ts)
            with self.jpeg_cond:
                self.jpeg_bytes = buf.tobytes()
                self.jpeg_seq += 1
                self.jpeg_cond.notify_all()

    def latest_jpeg(self, after: int, timeout: float = 1.0) -> tuple[int, bytes | None]:
        """Wait for a JPEG newer than sequence ``after``: (seq, bytes), or (after, None)."""
        with self.jpeg_cond:
            self.jpeg_cond.wait_for(
                lambda: self.jpeg_seq > after or self.stop_event.is_set(), timeout
            )
            if self.jpeg_seq > after and self.jpeg_bytes is not None:
                return self.jpeg_seq, self.jpeg_bytes
            return after, None

    # -- the loop -------------------------------------------------------------
    def run(self, duration: float | None = None) -> None:
        """Render until ``stop_event``, ``duration`` seconds, or the end of the source."""
        self._spawn("watch", self._watch)
        if self.jpeg:
            self._spawn("jpeg", self._encode_jpeg)
        self.source.start()
        self.started = time.monotonic()
        self.clock.restart()
        deadline = None if duration is None else self.started + duration
        while not self.stop_event.is_set():
            if deadline is not None and time.monotonic() >= deadline:
                break
            wait = 0.1 if deadline is None else max(0.0, min(0.1, deadline - time.monotonic()))
            cap = self.source.frames.get(timeout=wait)
            if cap is None:
                if self.source.error is not None:
                    raise self.source.error
                if self.source.ended:
                    break
                continue
            self.show(cap.rgba, cap.ts)

    def show(self, rgba: np.ndarray, ts: float) -> np.ndarray:
        """Marble one captured frame and hand it to every output."""
        marbler, bypass, mirror = self._current()
        if mirror:
            rgba = np.ascontiguousarray(rgba[:, ::-1])
        start = time.monotonic()
        out = rgba if bypass else marbler.render(rgba, self.clock.now())
        now = time.monotonic()
        self._render_ms.add(now, now - start)
        self._rendered.add(now)
        self.frames += 1
        if self.jpeg:
            self.shown.put((out, ts))
        if self.recorder is not None:
            self.recorder.add(out, ts)
        if self.vcam is not None:
            self.vcam.send(out)
        return out

    def close(self) -> None:
        self.stop_event.set()
        self.source.stop()
        self.shown.close()
        with self.jpeg_cond:
            self.jpeg_cond.notify_all()
        for thread in self._threads:
            thread.join(5.0)

    def summary(self) -> str:
        s = self.stats()
        elapsed = max(time.monotonic() - self.started, 1e-9)
        text = (
            f"live: {self.frames} frames in {elapsed:.1f} s ({self.frames / elapsed:.1f} fps), "
            f"{s['dropped']} source frames dropped"
        )
        if s["latency_ms"] is not None:
            text += f", latency median {s['latency_ms']} ms (p95 {s['latency_p95_ms']} ms)"
        if self.recorder is not None:
            text += f", recorded {self.recorder.frames} ({self.recorder.dropped} dropped)"
        return text


# ---------------------------------------------------------------------------- virtual camera


class VirtualCamera:
    """Frames to a virtual camera through pyvirtualcam (optional extra ``vcam``)."""

    def __init__(self, width: int, height: int, fps: float):
        try:
            import pyvirtualcam
        except ImportError:
            raise MarbleError(f"--vcam needs pyvirtualcam: {VCAM_HELP}") from None
        try:
            self.cam = pyvirtualcam.Camera(width, height, fps, fmt=pyvirtualcam.PixelFormat.RGB)
        except Exception as exc:  # noqa: BLE001 - the library raises RuntimeError and others
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise MarbleError(f"--vcam: no virtual camera device ({first}); {VCAM_HELP}") from None
        self.frames = Latest()
        self._thread = threading.Thread(target=self._run, name="marblevideo-vcam", daemon=True)
        self._thread.start()

    def send(self, rgba: np.ndarray) -> None:
        self.frames.put(rgba)

    def _run(self) -> None:
        while (rgba := self.frames.get()) is not None:
            self.cam.send(np.ascontiguousarray(rgba[..., :3]))

    def close(self) -> None:
        self.frames.close()
        self._thread.join(2.0)
        self.cam.close()


# ---------------------------------------------------------------------------- command line


def build_parser(parser_class=argparse.ArgumentParser) -> argparse.ArgumentParser:
    p = parser_class(
        prog="marblevideo live",
        description="Marble a camera, a video file or URL, or a test pattern in real time; "
        "preview it in a browser, send it to a virtual camera, record it.",
        epilog="examples:\n"
        "  marblevideo live test --ops samples/swirl.json --preview\n"
        "  marblevideo live 0 --ops samples/swirl.json --vcam\n"
        "  marblevideo live clip.mp4 --loop --ops swirl.json --preview -o take1.mp4\n\n"
        "Ctrl-C (SIGINT) or SIGTERM ends a session normally: the recording is kept, exit 0.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "source",
        nargs="?",
        help="camera index or /dev/videoN, a video file or URL, or 'test' (default: camera 0)",
    )
    p.add_argument("--source", dest="source_opt", metavar="SOURCE", help="same as SOURCE")
    p.add_argument("--ops", required=True, metavar="RECIPE", help="recipe JSON file (watched)")
    p.add_argument("--preview", action="store_true", help="serve a preview page on 127.0.0.1")
    p.add_argument("--port", type=int, default=DEFAULT_PORT, help=f"preview port ({DEFAULT_PORT})")
    p.add_argument("--vcam", action="store_true", help="send frames to a virtual camera")
    p.add_argument("-o", "--output", help="record what is shown (.mp4 .mov .mkv .webm)")
    p.add_argument("-y", "--overwrite", action="store_true", help="replace an existing recording")
    p.add_argument("--size", metavar="WxH", help="test pattern size, or the size asked of a camera")
    p.add_argument("--fps", type=float, help="test pattern rate (30), or asked of a camera")
    p.add_argument("--loop", action="store_true", help="file sources: start again at the end")
    p.add_argument("--duration", type=float, metavar="S", help="stop after S seconds")
    p.add_argument("--device", help="OpenCL device: P:D, a name, see `marblevideo devices`")
    p.add_argument(
        "--preview-width", type=int, metavar="W", help="encode the preview at most W pixels wide"
    )
    p.add_argument("--jpeg-quality", type=int, default=80, help="preview JPEG quality (80)")
    p.add_argument("-q", "--quiet", action="store_true", help="no notes on stderr")
    p.add_argument(
        "--verbose",
        action="store_true",
        help="say which device and vector width render, and show OpenCL build logs",
    )
    v = p.add_argument_group("recording (as the file mode)")
    add_encoder_arguments(v, preset_default="here: veryfast, for real time")
    return p


def _recorder(args):
    from marblevideo.live.recording import Recorder
    from marblevideo.media.encode import PRESET_CODECS
    from marblevideo.media.video import VideoOptions

    opts = parse_encoder_opts(args.encoder_opt)
    suffix = Path(args.output).suffix.lower()
    codec = args.codec or ("libvpx-vp9" if suffix == ".webm" else "libx264")
    preset = args.preset
    if preset is None and codec in PRESET_CODECS:
        preset = "veryfast"
    if codec == "libvpx-vp9":
        opts.setdefault("deadline", "realtime")
        opts.setdefault("cpu-used", "8")
    options = VideoOptions(
        codec=args.codec,
        crf=args.crf,
        preset=preset,
        pix_fmt=args.pix_fmt,
        encoder_opts=opts,
        audio="none",
        overwrite=args.overwrite,
        quiet=args.quiet,
        verbose=args.verbose,
        progress="off",
    )
    return Recorder(args.output, options)


def run_live(argv: list[str], parser_class=argparse.ArgumentParser) -> int:
    """The ``live`` command; returns the exit status (MarbleError propagates)."""
    from marblevideo.api import parse_size
    from marblevideo.recipe import load_recipe

    args = build_parser(parser_class).parse_args(argv)
    configure_logging(args.verbose)
    if args.source and args.source_opt and args.source != args.source_opt:
        raise UsageError("give the source once: SOURCE or --source")
    spec = args.source_opt or args.source or "0"
    load_recipe(args.ops)  # a bad recipe is refused before anything opens (exit 2)
    size = parse_size(args.size) if args.size else None
    if args.fps is not None and args.fps <= 0:
        raise UsageError(f"--fps: must be > 0, got {args.fps}")
    if args.duration is not None and args.duration <= 0:
        raise UsageError(f"--duration: must be > 0, got {args.duration}")
    if not 0 <= args.port <= 65535:
        raise UsageError(f"--port: must be 0..65535, got {args.port}")
    if not 1 <= args.jpeg_quality <= 100:
        raise UsageError(f"--jpeg-quality: must be 1..100, got {args.jpeg_quality}")
    if args.preview_width is not None and args.preview_width < 16:
        raise UsageError(f"--preview-width: must be >= 16, got {args.preview_width}")
    if args.vcam:
        try:
            import pyvirtualcam  # noqa: F401 - checked before anything opens
        except ImportError:
            raise MarbleError(f"--vcam needs pyvirtualcam: {VCAM_HELP}") from None
    recorder = _recorder(args) if args.output else None  # settings checked up front

    source = open_source(spec, size, args.fps, args.loop)
    session = server = None
    stop = threading.Event()
    ok = False
    previous: dict[int, object] = {}

    def on_signal(signum, frame):
        if stop.is_set():  # a second Ctrl-C while finishing: abort
            raise KeyboardInterrupt
        stop.set()
        if session is not None:
            session.stop_event.set()

    try:
        session = LiveSession(
            args.ops,
            source,
            device=args.device,
            jpeg=args.preview,
            preview_width=args.preview_width,
            jpeg_quality=args.jpeg_quality,
            quiet=args.quiet,
        )
        width, height = source.size
        if args.vcam:
            session.vcam = VirtualCamera(width, height, source.fps)
        if recorder is not None:
            recorder.start(width, height, source.fps)
            session.recorder = recorder
        if args.preview:
            from marblevideo.live.preview import PreviewServer

            server = PreviewServer(session, args.port)
            server.start()
            print(f"preview: {server.url}", flush=True)
        for signum in (signal.SIGINT, signal.SIGTERM):
            previous[signum] = signal.signal(signum, on_signal)
        if not args.quiet:
            print(
                f"marblevideo: live from {source.name} ({width}x{height}); Ctrl-C to stop",
                file=sys.stderr,
                flush=True,
            )
        session.run(args.duration)
        ok = True
    finally:
        if server is not None:
            server.stop()
        if session is not None:
            session.close()
        else:
            source.stop()
        if session is not None and session.vcam is not None:
            session.vcam.close()
        if recorder is not None:
            recorder.close(ok=ok)
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    if not args.quiet:
        print(f"marblevideo: {session.summary()}", file=sys.stderr, flush=True)
        if recorder is not None:
            print(f"marblevideo: wrote {args.output}", file=sys.stderr, flush=True)
    return 0
