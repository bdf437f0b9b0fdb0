"""A real RTMP server on loopback for the stream tests: Debian's nginx with
libnginx-mod-rtmp, run as a child process on a free 127.0.0.1 port with a
temporary configuration, recording every stream it receives (one FLV file per
publish) into ``folder/rec``."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import time
from pathlib import Path

MODULE = Path("/usr/lib/nginx/modules/ngx_rtmp_module.so")
MISSING = (
    "nginx with the RTMP module is not installed "
    "(apt-get install nginx-light libnginx-mod-rtmp, or scripts/setup.sh --test)"
)

CONF = """\
load_module {module};
{user}
worker_processes 1;
error_log {folder}/error.log warn;
pid {folder}/nginx.pid;
events {{ worker_connections 64; }}
rtmp {{
  server {{
    listen 127.0.0.1:{port};
    application live {{
      live on;
      record all;
      record_path {folder}/rec;
      record_unique on;
    }}
  }}
}}
"""


def missing() -> str | None:
    """Why no server can run here, or None."""
    if shutil.which("nginx") is None or not MODULE.exists():
        return MISSING
    return None


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class RtmpServer:
    """nginx-rtmp on 127.0.0.1:``port`` (:meth:`start`, :meth:`stop`, again)."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.port = free_port()
        (folder / "rec").mkdir(parents=True, exist_ok=True)
        self.conf = folder / "nginx.conf"
        # under root nginx's worker would run as nobody, who cannot enter pytest's folders
        user = "user root;" if os.geteuid() == 0 else ""
        self.conf.write_text(CONF.format(module=MODULE, user=user, folder=folder, port=self.port))
        self.proc: subprocess.Popen | None = None

    def url(self, key: str) -> str:
        return f"rtmp://127.0.0.1:{self.port}/live/{key}"

    def start(self, timeout: float = 10.0) -> None:
        cmd = ["nginx", "-p", str(self.folder), "-e", str(self.folder / "error.log")]
        cmd += ["-c", str(self.conf), "-g", "daemon off;"]
        self.proc = subprocess.Popen(cmd, stderr=subprocess.DEVNULL)
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", self.port)) == 0:
                    return
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        log = (
            (self.folder / "error.log").read_text() if (self.folder / "error.log").exists() else ""
        )
        raise AssertionError(f"nginx did not listen on {self.port}: {log[-500:]}")

    def stop(self) -> None:
        """Stop at once (nginx's fast shutdown: every connection dropped)."""
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait(10)
        self.proc = None

    def recordings(self) -> list[Path]:
        """The streams received, oldest first (nginx names them KEY-TIME.flv)."""
        return sorted((self.folder / "rec").glob("*.flv"), key=os.path.getmtime)
