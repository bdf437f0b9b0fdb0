"""The end-to-end baseline: a plain PyAV decode + encode, as a user would script it.

    python benchmarks/plain_transcode.py SRC DST

does what ``ffmpeg -i SRC -c:v libx264 -preset veryfast -crf 23 -c:a copy DST``
does; the e2e part times it in its own process (imports only PyAV) beside the
marblevideo command, and in-process for the per-frame figures.
"""

from __future__ import annotations

import sys
from pathlib import Path

import av


def plain_transcode(src: Path, dst: Path) -> None:
    """Decode ``src`` and encode its video with libx264 veryfast crf 23; audio copied."""
    with av.open(str(src)) as inp, av.open(str(dst), "w") as out:
        vin = inp.streams.video[0]
        vin.thread_type = "AUTO"
        ain = inp.streams.audio[0]
        v = out.add_stream(
            "libx264", rate=vin.average_rate, options={"preset": "veryfast", "crf": "23"}
        )
        v.width, v.height, v.pix_fmt = vin.width, vin.height, "yuv420p"
        v.thread_type = "AUTO"
        a = out.add_stream_from_template(ain)
        for packet in inp.demux(vin, ain):
            if packet.stream is ain:
                if packet.dts is not None:
                    packet.stream = a
                    out.mux(packet)
                continue
            for frame in packet.decode():
                frame.pict_type = av.video.frame.PictureType.NONE
                out.mux(v.encode(frame))
        out.mux(v.encode(None))


if __name__ == "__main__":
    plain_transcode(Path(sys.argv[1]), Path(sys.argv[2]))
