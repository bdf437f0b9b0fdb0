"""Regenerate samples/coffee.mp4: a slow pan over samples/coffee.jpg with a soft chord.

4 s, 480x270, 25 fps, H.264 + AAC. Run from the repository root:
``python samples/make_sample_video.py``.
"""

from fractions import Fraction
from pathlib import Path

import av
import cv2
import numpy as np

HERE = Path(__file__).resolve().parent
W, H, FPS, SECONDS, RATE = 480, 270, 25, 4, 44100


def main() -> None:
    photo = cv2.cvtColor(cv2.imread(str(HERE / "coffee.jpg")), cv2.COLOR_BGR2RGB)
    with av.open(str(HERE / "coffee.mp4"), "w") as out:
        video = out.add_stream("libx264", rate=FPS, options={"crf": "30", "preset": "slow"})
        video.width, video.height, video.pix_fmt = W, H, "yuv420p"
        audio = out.add_stream("aac", rate=RATE, layout="stereo")
        audio.bit_rate = 48000
        n = FPS * SECONDS
        for i in range(n):
            u = i / (n - 1)
            zoom = 1.0 + 0.25 * u  # crop window shrinks: a slow push-in with a pan
            cw, ch = 600 / zoom, 600 / zoom * H / W
            x0, y0 = (600 - cw) * (0.2 + 0.6 * u), (400 - ch) * 0.5
            m = np.float32([[W / cw, 0, -x0 * W / cw], [0, H / ch, -y0 * H / ch]])
            frame = cv2.warpAffine(photo, m, (W, H), flags=cv2.INTER_AREA)
            for packet in video.encode(av.VideoFrame.from_ndarray(frame, format="rgb24")):
                out.mux(packet)
        t = np.arange(RATE * SECONDS) / RATE
        chord = sum(np.sin(2 * np.pi * f * t) for f in (220.0, 277.18, 329.63)) / 6
        chord *= np.minimum(1, np.minimum(t, SECONDS - t) * 4)  # fade in and out
        samples = np.stack([chord, chord]).astype(np.float32)
        for start in range(0, samples.shape[1], 1024):
            chunk = np.ascontiguousarray(samples[:, start : start + 1024])
            frame = av.AudioFrame.from_ndarray(chunk, format="fltp", layout="stereo")
            frame.sample_rate, frame.pts, frame.time_base = RATE, start, Fraction(1, RATE)
            for packet in audio.encode(frame):
                out.mux(packet)
        for stream in (video, audio):
            for packet in stream.encode():
                out.mux(packet)


if __name__ == "__main__":
    main()
