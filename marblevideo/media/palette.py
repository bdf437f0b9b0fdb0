"""GIF frames with one palette computed for the whole clip, as ffmpeg's
``palettegen`` / ``paletteuse`` two-pass recipe does, through PyAV's filter graph.

The first pass feeds every frame to ``palettegen`` (statistics of the whole
clip) while the frames are kept in a temporary file (raw RGBA, so memory stays
flat however long the clip); the second reads them back through
``paletteuse`` (Sierra-2-4A error diffusion, ffmpeg's default) with the clip's
palette. Frame times are kept: the GIF muxer turns them into frame delays
(hundredths of a second).
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from fractions import Fraction

import av
import av.filter
import numpy as np

#: ``palettegen`` options: statistics over every pixel of every frame.
PALETTEGEN = "stats_mode=full"
#: ``paletteuse`` options (ffmpeg's default dithering).
PALETTEUSE = "dither=sierra2_4a"


def _drain(sink, emit: Callable[[av.VideoFrame], None]) -> None:
    while True:
        try:
            frame = sink.pull()
        except (av.error.BlockingIOError, av.error.EOFError):
            return
        emit(frame)


class PaletteFrames:
    """Collect RGBA frames (:meth:`add`), then give them as pal8 frames with the
    clip's palette (:meth:`finish`). Sizes in pixels; times in ``time_base``."""

    def __init__(self, width: int, height: int, time_base: Fraction):
        self.width, self.height, self.time_base = width, height, time_base
        self.spill = tempfile.TemporaryFile(prefix="marblevideo-gif-")  # noqa: SIM115 (closed in finish)
        self.times: list[tuple[int, int]] = []  # (pts, duration) of each frame
        self.palettes: list[av.VideoFrame] = []  # palettegen's answer (at the end)
        self.graph = av.filter.Graph()
        self.source = self._buffer(self.graph, width, height, "rgba")
        generate = self.graph.add("palettegen", PALETTEGEN)
        self.sink = self.graph.add("buffersink")
        self.source.link_to(generate)
        generate.link_to(self.sink)
        self.graph.configure()

    def _buffer(self, graph, width: int, height: int, pix_fmt: str):
        return graph.add_buffer(
            width=width, height=height, format=pix_fmt, time_base=self.time_base
        )

    def _frame(self, rgba: np.ndarray, pts: int) -> av.VideoFrame:
        frame = av.VideoFrame.from_ndarray(rgba, format="rgba")
        frame.pts, frame.time_base = pts, self.time_base
        return frame

    def add(self, rgba: np.ndarray, pts: int, duration: int) -> None:
        """Take frame ``rgba`` (h, w, 4) uint8 shown from ``pts`` for ``duration``."""
        self.source.push(self._frame(rgba, pts))
        # pulled at once: a frame pushed is queued in the buffer source until the
        # graph is asked for output (a 7 s GIF at 1600x900 held 0.9 GB of them,
        # found by tests/test_fuzz_inputs.py under its 1 GiB limit)
        _drain(self.sink, self.palettes.append)
        self.spill.write(np.ascontiguousarray(rgba).tobytes())
        self.times.append((pts, duration))

    def finish(self, emit: Callable[[av.VideoFrame], None]) -> None:
        """Give every frame, in order, as pal8 with the clip's palette to ``emit``."""
        try:
            if not self.times:
                return
            self.source.push(None)
            _drain(self.sink, self.palettes.append)
            palette = self.palettes[-1]
            graph = av.filter.Graph()
            frames = self._buffer(graph, self.width, self.height, "rgba")
            colours = self._buffer(graph, palette.width, palette.height, palette.format.name)
            use = graph.add("paletteuse", PALETTEUSE)
            sink = graph.add("buffersink")
            frames.link_to(use, 0, 0)
            colours.link_to(use, 0, 1)
            use.link_to(sink)
            graph.configure()
            palette.pts = 0
            colours.push(palette)
            colours.push(None)
            durations = dict(self.times)

            def timed(frame: av.VideoFrame) -> None:
                if durations.get(frame.pts):
                    frame.duration = durations[frame.pts]
                emit(frame)

            self.spill.seek(0)
            size = self.width * self.height * 4
            for pts, _ in self.times:
                data = self.spill.read(size)
                rgba = np.frombuffer(data, np.uint8).reshape(self.height, self.width, 4)
                frames.push(self._frame(rgba, pts))
                _drain(sink, timed)
            frames.push(None)
            _drain(sink, timed)
        finally:
            self.spill.close()

    def close(self) -> None:
        self.spill.close()
