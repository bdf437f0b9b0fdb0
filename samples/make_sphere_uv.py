"""Write samples/sphere-uv.png: an analytic UV pass of a sphere, as Blender exports one.

16-bit RGBA PNG, 256 x 256: R = u (longitude), G = v (latitude, v = 0 at the
bottom as in Blender), alpha 0 where there is no surface. The sphere is seen
orthographically, tilted 25 degrees towards the viewer, and u covers the
visible hemisphere twice over (two turns of the texture around the equator) so
that the close-up of the design is visible. Run: python samples/make_sphere_uv.py
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

SIZE = 256
TILT = np.radians(25.0)


def sphere_uv(size: int = SIZE) -> np.ndarray:
    c = (np.arange(size) + 0.5) / size * 2.2 - 1.1
    x, y = np.meshgrid(c, -c)  # y up
    r2 = x * x + y * y
    inside = r2 < 1.0
    z = np.sqrt(np.clip(1.0 - r2, 0.0, None))
    # undo the tilt about the x axis: the point in the sphere's own frame
    yy = y * np.cos(TILT) + z * np.sin(TILT)
    zz = -y * np.sin(TILT) + z * np.cos(TILT)
    lon = np.arctan2(x, zz)  # -pi..pi, 0 facing the viewer
    lat = np.arcsin(np.clip(yy, -1.0, 1.0))
    u = np.mod(lon / np.pi + 0.5, 1.0)  # two turns around: the front spans 0..1
    v = lat / np.pi + 0.5
    rgba = np.zeros((size, size, 4), np.uint16)
    rgba[..., 0] = np.round(u * 65535)
    rgba[..., 1] = np.round(v * 65535)
    rgba[..., 3] = np.where(inside, 65535, 0)
    rgba[~inside, :3] = 0
    return rgba


if __name__ == "__main__":
    out = Path(__file__).resolve().parent / "sphere-uv.png"
    rgba = sphere_uv()
    cv2.imwrite(str(out), cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGRA))
    print(f"wrote {out}")
