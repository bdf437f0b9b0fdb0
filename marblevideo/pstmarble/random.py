"""pst-marble's random numbers: RC4 keyed with the ``seed`` setting, seven bytes
per uniform number (``random:uniform``), and its normal pairs (``random:normal2``),
so that its seeded layouts and sprays import as the very drops it draws."""

from __future__ import annotations

import math


class Rc4:
    """The RC4 stream keyed with ``key`` (pst-marble's ``rc4setkey``)."""

    def __init__(self, key: str):
        data = key.encode("latin-1", "replace") or b"\0"
        self.a = list(range(256))
        j = 0
        for i in range(256):
            j = (j + self.a[i] + data[i % len(data)]) & 255
            self.a[i], self.a[j] = self.a[j], self.a[i]
        self.x = self.y = 0

    def byte(self) -> int:
        a = self.a
        self.x = (self.x + 1) & 255
        self.y = (a[self.x] + self.y) & 255
        a[self.x], a[self.y] = a[self.y], a[self.x]
        return a[(a[self.x] + a[self.y]) & 255]

    def uniform(self) -> float:
        """A number in [0, 1): seven bytes b, v = (v + b) / 256 in turn."""
        v = 0.0
        for _ in range(7):
            v = (v + self.byte()) / 256.0
        return v

    def normal2(self) -> tuple[float, float]:
        """(r cos t, r sin t), t = 360 u1 degrees, r = sqrt(-2 ln u2)."""
        t = math.radians(self.uniform() * 360.0)
        r = math.sqrt(-2.0 * math.log(self.uniform()))
        return r * math.cos(t), r * math.sin(t)
