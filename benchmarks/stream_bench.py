"""Benchmark of streaming a live session to an RTMP server: throughput and
latency from capture to the server's output, beside the same session without
the stream (the baseline, in the same run).

Runs the real pipeline in process: the built-in test pattern (1280x720 at 30 fps
by default) -> live_bench's 6-op animated recipe -> the stream (FLV, libx264
veryfast, as ``live -o rtmp://...``) to nginx-rtmp on 127.0.0.1 (started here,
a child process; Debian's nginx-light and libnginx-mod-rtmp) -> a player (PyAV)
reading the stream back from the server. Latency: a frame's capture time to the
player decoding it (its pts is its capture time since the stream's first frame).

    python -m benchmarks.stream_bench [--size 1280x720] [--fps 30] [--seconds 10]
        [--encoder-opt tune=zerolatency] [--bypass] [--device P:D]

``--bypass`` shows the frames unmarbled: what the stream alone (encoding,
sending, the server, the player) sustains.

Not a test: numbers depend on the machine (see BENCHMARKS.md).
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import statistics
import subprocess
import tempfile
import threading
import time
from pathlib import Path

from .common import header
from .live_bench import RECIPE

CONF = """\
load_module /usr/lib/nginx/modules/ngx_rtmp_module.so;
worker_processes 1;
error_log {folder}/error.log warn;
pid {folder}/nginx.pid;
events {{ worker_connections 64; }}
rtmp {{ server {{ listen 127.0.0.1:{port}; application live {{ live on; }} }} }}
"""


def _nginx(folder: Path) -> tuple[subprocess.Popen, int]:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    conf = folder / "nginx.conf"
    conf.write_text(CONF.format(folder=folder, port=port))
    cmd = ["nginx", "-p", str(folder), "-e", str(folder / "error.log"), "-c", str(conf)]
    proc = subprocess.Popen([*cmd, "-g", "daemon off;"], stderr=subprocess.DEVNULL)
    for _ in range(200):
        with socket.socket() as s:
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return proc, port
        time.sleep(0.05)
    proc.terminate()
    raise RuntimeError("nginx-rtmp did not start (apt-get install nginx-light libnginx-mod-rtmp)")


def _player(url: str, streamer, stop: threading.Event, seen: list) -> None:
    """Read the stream back from the server; (decoded at, capture time) per frame."""
    import av

    options = {"rw_timeout": "10000000", "fflags": "nobuffer"}
    with av.open(url, options=options) as container:
        if not container.streams.video:
            return
        container.streams.video[0].thread_count = 1  # no frame threads' delay
        for frame in container.decode(video=0):
            now = time.monotonic()
            connection = streamer._connection
            if connection is not None and connection.origin is not None:
                seen.append((now, connection.origin + float(frame.pts * frame.time_base)))
            if stop.is_set():
                return


def run(size, fps, seconds, warmup, device, encoder_opts, stream: bool, bypass: bool) -> dict:
    from marblevideo.cli.arguments import parse_size
    from marblevideo.live.session import LiveSession
    from marblevideo.live.sources import TestPattern
    from marblevideo.live.stream import Streamer
    from marblevideo.media.video import VideoOptions

    w, h = parse_size(size)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        recipe = folder / "bench.json"
        recipe.write_text(json.dumps(RECIPE))
        session = LiveSession(recipe, TestPattern((w, h), fps), device=device, quiet=True)
        session.playback.bypass = bypass  # the stream alone: frames shown unmarbled
        nginx, port = _nginx(folder) if stream else (None, 0)
        url = f"rtmp://127.0.0.1:{port}/live/bench"
        streamer, seen, stop = None, [], threading.Event()
        if stream:
            options = VideoOptions(
                preset="veryfast", encoder_opts=dict(encoder_opts), audio="none", format="flv"
            )
            streamer = Streamer(url, options, lambda message: None)
            streamer.start(w, h, fps)
            session.streams = [streamer]
        marks = {}

        def sample():
            time.sleep(warmup / 2)
            if stream:
                args = (url, streamer, stop, seen)
                threading.Thread(target=_player, args=args, daemon=True).start()
            time.sleep(warmup / 2)
            marks["start"] = (time.monotonic(), session.frames, len(seen), _sent(streamer))
            session.meters.clear()
            time.sleep(seconds)
            marks["end"] = (time.monotonic(), session.frames, len(seen), _sent(streamer))
            session.stop_event.set()

        threading.Thread(target=sample, daemon=True).start()
        try:
            session.run()
        finally:
            stop.set()
            session.close()
            if streamer is not None:
                streamer.close()
            if nginx is not None:
                nginx.terminate()
                nginx.wait(10)
        (t0, f0, p0, s0), (t1, f1, p1, s1) = marks["start"], marks["end"]
        span = t1 - t0
        lags = sorted(1000 * (at - captured) for at, captured in seen if at >= t0)
        return {
            "stream": stream,
            "marbled": not bypass,
            "size": f"{w}x{h}",
            "source_fps": fps,
            "encoder_opts": " ".join(f"{k}={v}" for k, v in encoder_opts) or "-",
            "marbled_fps": round((f1 - f0) / span, 1),
            "sent_fps": round((s1 - s0) / span, 1) if stream else None,
            "player_fps": round((p1 - p0) / span, 1) if stream else None,
            "latency_median_ms": round(statistics.median(lags)) if lags else None,
            "latency_p95_ms": round(lags[int(0.95 * (len(lags) - 1))]) if lags else None,
            "stream_dropped": streamer.dropped if stream else None,
            "device": session.renderer.info.name,
        }


def _sent(streamer) -> int:
    return streamer.sent if streamer is not None else 0


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--size", default="1280x720")
    p.add_argument("--fps", type=float, default=30.0, help="test pattern rate")
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--warmup", type=float, default=4.0)
    p.add_argument("--device")
    p.add_argument("--encoder-opt", action="append", default=[], metavar="KEY=VALUE")
    p.add_argument(
        "--bypass", action="store_true", help="frames unmarbled: the stream's own throughput"
    )
    args = p.parse_args()
    opts = [tuple(item.split("=", 1)) for item in args.encoder_opt]
    header()
    print(f"# load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(
        "| stream | marbled | size | fps asked | encoder opts | shown fps | sent fps | player fps "
        "| latency median ms | p95 ms | stream dropped | device |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for stream, extra in ((False, []), (True, []), *([(True, opts)] if opts else [])):
        r = run(
            args.size, args.fps, args.seconds, args.warmup, args.device, extra, stream, args.bypass
        )
        print("| " + " | ".join(str(v) for v in r.values()) + " |", flush=True)
    print(f"# load average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
