"""Seeded random recipes for tests: every op, ease, progress form, AA pattern, edges mode."""

from __future__ import annotations

import numpy as np

OPS = ("drop", "spray", "tine", "comb", "wave", "circle", "vortex")
EASES = ("linear", "hold", "ease-in", "ease-out", "ease-in-out", [0.3, 0.1, 0.2, 1.0])
PATTERNS = ("none", "rgss", "quincunx", "checker4", "grid4", "rooks8")
EDGES = ("clamp", "repeat", "mirror", "background")


def _color(rng):
    return [int(c) for c in rng.integers(0, 256, 3)]


def _keyed(rng, value, jitter):
    """Either the value or a track of two or three keys around it, random eases."""
    if rng.random() < 0.6:
        return value
    n = int(rng.integers(2, 4))
    times = np.cumsum(rng.uniform(0.2, 1.5, n)).round(3)
    keys = []
    for k in range(n):
        v = np.asarray(value, float) + rng.uniform(-jitter, jitter, np.shape(value))
        key = {"t": float(times[k]), "v": v.round(3).tolist() if np.ndim(value) else float(v)}
        ease = EASES[int(rng.integers(len(EASES)))]
        if ease != "linear" or rng.random() < 0.5:
            key["ease"] = ease
        keys.append(key)
    return {"keys": keys}


def random_op(rng, kind, w, h):
    pt = [float(rng.uniform(0, w)), float(rng.uniform(0, h))]
    size = min(w, h)
    if kind in ("drop", "spray"):
        op = {
            "center": _keyed(rng, pt, size / 10),
            "radius": _keyed(rng, size * rng.uniform(0.05, 0.25), 3),
            "color": _color(rng) if rng.random() < 0.7 else _keyed(rng, _color(rng), 0),
        }
        if isinstance(op["color"], dict):  # colour keys must stay in 0..255
            for key in op["color"]["keys"]:
                key["v"] = [int(np.clip(c, 0, 255)) for c in key["v"]]
    elif kind in ("tine", "comb"):
        op = {
            "point": pt,
            "angle": _keyed(rng, float(rng.uniform(-180, 360)), 30),
            "alpha": _keyed(rng, float(rng.uniform(-0.2, 0.2) * size), 5),
            "lambda": float(rng.uniform(0.03, 0.2) * size),
        }
        if kind == "comb":
            op["spacing"] = float(rng.uniform(0.15, 0.5) * size)
    elif kind == "wave":
        op = {
            "amplitude": _keyed(rng, float(rng.uniform(-0.06, 0.06) * size), 2),
            "wavelength": float(rng.uniform(0.3, 1.5) * size),
            "phase": _keyed(rng, float(rng.uniform(0, 360)), 90),
            "angle": float(rng.uniform(0, 360)),
        }
    elif kind == "circle":
        op = {
            "center": pt,
            "radius": float(rng.uniform(0, 0.4) * size),
            "alpha": _keyed(rng, float(rng.uniform(-0.4, 0.4) * size), 5),
            "lambda": float(rng.uniform(0.05, 0.3) * size),
        }
    else:
        op = {
            "center": pt,
            "alpha": _keyed(rng, float(rng.uniform(-0.5, 0.5) * size), 5),
            "lambda": float(rng.uniform(0.1, 0.4) * size),
        }
    op = {"type": kind, **op}
    r = rng.random()
    if r < 0.3:
        op["start"] = float(rng.uniform(0, 1))
        op["end"] = op["start"] + float(rng.uniform(0.2, 2))
    elif r < 0.4:
        op["start"] = float(rng.uniform(0, 2))
    return op


def random_recipe(
    seed: int, w: float = 160.0, h: float = 120.0, n_ops: int | None = None, blank: bool = False
) -> dict:
    """A valid recipe dict; every op type appears at least once when n_ops >= 7."""
    rng = np.random.default_rng(seed)
    n = n_ops if n_ops is not None else int(rng.integers(7, 12))
    kinds = list(OPS) + [OPS[int(i)] for i in rng.integers(0, len(OPS), max(0, n - len(OPS)))]
    rng.shuffle(kinds)
    recipe = {
        "marblevideo": 1,
        "canvas": [w, h],
        "background": _color(rng),
        "antialias": PATTERNS[seed % len(PATTERNS)],
        "edges": EDGES[(seed // len(PATTERNS)) % len(EDGES)],
        "ops": [random_op(rng, k, w, h) for k in kinds[:n]],
    }
    if blank:
        recipe["ops"].insert(
            0,
            {
                "type": "drop",
                "center": [w / 2, h / 2],
                "radius": min(w, h) / 3,
                "color": _color(rng),
            },
        )
    return recipe


def make_image(w: int, h: int, seed: int = 0, alpha: bool = False):
    """A smooth, structured RGBA test picture (gradients, rings, stripes)."""
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float64)
    rng = np.random.default_rng(seed)
    fx, fy = rng.uniform(0.05, 0.2, 2)
    r = 127.5 + 127.5 * np.sin(xx * fx)
    g = 127.5 + 127.5 * np.cos(yy * fy)
    b = 255.0 * ((np.hypot(xx - w / 2, yy - h / 2) / 7).astype(int) % 2)
    a = 255.0 * (xx / max(w - 1, 1)) if alpha else np.full_like(xx, 255.0)
    return np.stack([r, g, b, a], axis=2).round().astype(np.uint8)
