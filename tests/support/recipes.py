"""Seeded random recipes for tests: every op, ease, progress form, AA pattern, edges mode."""

from __future__ import annotations

import numpy as np

from marblevideo.ops import REGISTRY
from marblevideo.recipe import parse_recipe

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


def _ink(rng, kind, w, h) -> dict:
    size = min(w, h)
    op = {
        "center": _keyed(rng, _point(rng, w, h), size / 10),
        "radius": _keyed(rng, size * rng.uniform(0.05, 0.25), 3),
        "color": _color(rng) if rng.random() < 0.7 else _keyed(rng, _color(rng), 0),
    }
    if isinstance(op["color"], dict):  # colour keys must stay in 0..255
        for key in op["color"]["keys"]:
            key["v"] = [int(np.clip(c, 0, 255)) for c in key["v"]]
    return op


def _tine(rng, kind, w, h) -> dict:
    size = min(w, h)
    op = {
        "point": _point(rng, w, h),
        "angle": _keyed(rng, float(rng.uniform(-180, 360)), 30),
        "alpha": _keyed(rng, float(rng.uniform(-0.2, 0.2) * size), 5),
        "lambda": float(rng.uniform(0.03, 0.2) * size),
    }
    if kind == "comb":
        op["spacing"] = float(rng.uniform(0.15, 0.5) * size)
    return op


def _wave(rng, kind, w, h) -> dict:
    size = min(w, h)
    _point(rng, w, h)  # drawn by every op, as ever: seeded recipes stay the same
    return {
        "amplitude": _keyed(rng, float(rng.uniform(-0.06, 0.06) * size), 2),
        "wavelength": float(rng.uniform(0.3, 1.5) * size),
        "phase": _keyed(rng, float(rng.uniform(0, 360)), 90),
        "angle": float(rng.uniform(0, 360)),
    }


def _circle(rng, kind, w, h) -> dict:
    size = min(w, h)
    return {
        "center": _point(rng, w, h),
        "radius": float(rng.uniform(0, 0.4) * size),
        "alpha": _keyed(rng, float(rng.uniform(-0.4, 0.4) * size), 5),
        "lambda": float(rng.uniform(0.05, 0.3) * size),
    }


def _vortex(rng, kind, w, h) -> dict:
    size = min(w, h)
    return {
        "center": _point(rng, w, h),
        "alpha": _keyed(rng, float(rng.uniform(-0.5, 0.5) * size), 5),
        "lambda": float(rng.uniform(0.1, 0.4) * size),
    }


def _point(rng, w, h) -> list[float]:
    return [float(rng.uniform(0, w)), float(rng.uniform(0, h))]


def valid_op(rng, definition, w: float, h: float) -> dict | None:
    """A random op of ``definition`` (:func:`random_registry_op`) that the
    recipe's own checks accept, drawn up to 200 times; None if none was."""
    from marblevideo.errors import RecipeError

    for _ in range(200):
        op = random_registry_op(rng, definition, w, h)
        try:
            parse_recipe({"canvas": [w, h], "ops": [op]}, "r.json")
        except RecipeError:
            continue
        return op
    return None


def valid_registry_op(rng, kind: str, w: float, h: float) -> dict:
    """A random valid op of registered type ``kind`` (:func:`valid_op`), without
    its type, start and end."""
    op = valid_op(rng, REGISTRY[kind], w, h)
    if op is None:
        raise AssertionError(f"no valid random {kind}")
    return {k: v for k, v in op.items() if k not in ("type", "start", "end")}


def _stroke(rng, kind, w, h) -> dict:
    """A registry stroke cut to its first two points: a stroke across the tests'
    small canvases, not a scribble folding the sheet into filaments thinner than
    their pixels (where the float32 walk and the reference part)."""
    op = valid_registry_op(rng, kind, w, h)
    op["points"] = op["points"][:2]
    if "times" in op:
        op["times"] = op["times"][:2]
    return op


#: Op type -> its random values (rng, type, w, h) where it is not the registry's
#: generic law (:func:`valid_registry_op`: random values of the parameters'
#: kinds, retried until the op's own check accepts them): the paper's ops keep
#: their hand-made laws (so seeded recipes stay as they were), the stroke is cut
#: short. Every other registered type, a new one included, is drawn by the
#: generic law with nothing edited here, unless NOT_RANDOM leaves it out.
GENERATORS = {
    "drop": _ink,
    "spray": _ink,
    "tine": _tine,
    "comb": _tine,
    "wave": _wave,
    "circle": _circle,
    "vortex": _vortex,
    "stroke": _stroke,
}
#: Registered op types random recipes leave out, each with the reason.
NOT_RANDOM: dict[str, str] = {
    "jiggle": "its float64 reference inverse (Newton in NumPy) costs some 40 ops' time "
    "(150 ms a 113x89 RGSS frame): in a random recipe it would double the kernel tests' "
    "time; test_vocabulary walks it on the device against that inverse, alone and mixed",
}


def generator(kind: str):
    """The random law of op type ``kind``: its own (GENERATORS) or the generic one."""
    return GENERATORS.get(kind, valid_registry_op)


def random_types(registry) -> tuple[str, ...]:
    """The op types of random recipes: every registered one but NOT_RANDOM's, in
    type-code order."""
    return tuple(t for t in registry if t not in NOT_RANDOM)


#: The op types of random recipes, in type-code order.
OPS = random_types(REGISTRY)


def random_op(rng, kind, w, h):
    """A random op of type ``kind`` (:func:`generator`), sometimes with a start
    and an end or a start alone (not a stroke with ``times``)."""
    op = {"type": kind, **generator(kind)(rng, kind, w, h)}
    r = rng.random()
    if "times" in op:
        pass
    elif r < 0.3:
        op["start"] = float(rng.uniform(0, 1))
        op["end"] = op["start"] + float(rng.uniform(0.2, 2))
    elif r < 0.4:
        op["start"] = float(rng.uniform(0, 2))
    return op


def random_recipe(
    seed: int, w: float = 160.0, h: float = 120.0, n_ops: int | None = None, blank: bool = False
) -> dict:
    """A valid recipe dict of ``n_ops`` ops (7 to 11 by default), of distinct
    types while there are types left (every one of :data:`OPS` when n_ops >=
    len(OPS)), then of types at random."""
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


def random_value(rng, param, w: float, h: float):
    """A random value of ``param`` for a w x h canvas, by its kind and slider law."""
    size = min(w, h)
    kind, law = param.kind, param.slider
    if kind == "point":
        if param.name == "offset":
            return [float(rng.uniform(-0.2, 0.2) * w), float(rng.uniform(-0.2, 0.2) * h)]
        return [float(rng.uniform(0, w)), float(rng.uniform(0, h))]
    if kind == "color":
        return _color(rng)
    if kind == "count":
        return int(rng.integers(1, 9))
    if kind == "numberList":
        return [float(v) for v in rng.uniform(-0.4, 0.4, int(rng.integers(1, 9))) * size]
    if kind == "pointList":  # a stroke's path: 2..6 points over the canvas
        n = int(rng.integers(2, 7))
        return [[float(rng.uniform(0, w)), float(rng.uniform(0, h))] for _ in range(n)]
    if kind == "timeList":  # a gesture's times: its stroke sets one per point
        return []
    if kind == "nonzeroList":
        radii = rng.uniform(0.05, 0.45, int(rng.integers(1, 7))) * size
        return [float(r if rng.random() < 0.6 else -r) for r in radii]
    ranges = {
        "angle": (-180, 360),
        "phase": (0, 360),
        "shift": (-0.2 * size, 0.2 * size),
        "amplitude": (-0.05 * size, 0.05 * size),
        "length": (0.05 * size, 0.4 * size),
        "area": (-0.3 * size * size, 0.3 * size * size),
        "time": (0.0, 3.0),
        "share": (-4.0, 4.0),
    }
    lo, hi = ranges[law]
    if kind != "number":  # positive or nonnegative
        lo, hi = max(lo, 0.0), max(hi, 1e-3)
        if law == "area":
            lo, hi = 0.01 * size * size, 0.1 * size * size
        if kind == "positive":
            lo = max(lo, 1e-3 * size)
    return float(rng.uniform(lo, hi))


def random_registry_op(rng, definition, w: float, h: float) -> dict:
    """A random op of ``definition`` (any registered type): every required
    parameter and some optional ones, numbers sometimes keyframed, sometimes a
    start/end; the caller retries when the op's own check refuses it."""
    op = {"type": definition.type}
    for param in definition.params:
        if param.optional and rng.random() < 0.5:
            continue
        value = random_value(rng, param, w, h)
        if param.tracked and param.kind != "color" and rng.random() < 0.3:
            value = _keyed(rng, value, 0.1 * abs(np.max(np.abs(value))) + 1e-3)
            if isinstance(value, dict) and param.kind in ("positive", "nonnegative"):
                for key in value["keys"]:  # positive kinds stay positive at every key
                    key["v"] = abs(key["v"]) or 1e-3
        op[param.name] = value
    if definition.type == "stroke":
        # a comb of 1..3 tines 1.5 widths apart and |drag| <= 2, as strokes are drawn:
        # random close tines and strong drags crossing their own path fold the sheet
        # into filaments far thinner than the tests' pixels
        m, w_ = len(op.get("tines", [0])[:3]), op.get("width", 24)
        if "tines" in op:
            op["tines"] = [(k - (m - 1) / 2) * 1.5 * w_ for k in range(m)]
        if isinstance(op.get("drag"), float):
            op["drag"] /= 2
        elif isinstance(op.get("drag"), dict):  # keyed, as its keys
            for key in op["drag"]["keys"]:
                key["v"] /= 2
        if "times" in op:  # a drawn gesture, one time per point (then no start/end)
            op["times"] = sorted(float(t) for t in rng.uniform(0, 2, len(op["points"])))
    r = rng.random()
    if r < 0.3 and "times" not in op:
        op["start"] = float(rng.uniform(0, 1))
        op["end"] = op["start"] + float(rng.uniform(0.2, 2))
    elif 0.3 <= r < 0.4:  # healing over a window that may start before the end
        op["heal"] = sorted(float(t) for t in rng.uniform(0.5, 3, 2))
    return op


#: animated for 0.3 s, then still: later frames reuse the renderer's maps
BRIEF = {
    "marblevideo": 1,
    "antialias": "rgss",
    "edges": "mirror",
    "ops": [
        {
            "type": "wave",
            "amplitude": {"keys": [{"t": 0, "v": 0}, {"t": 0.3, "v": 18}]},
            "wavelength": 40,
            "phase": 0,
            "angle": 90,
        },
        {"type": "vortex", "center": [48, 32], "alpha": 200, "lambda": 20},
    ],
}


def blank_design(seed: int, w: float = 320, h: float = 240):
    """Seeded blank-sheet design: drops (and a spray) then combs, a wave and a vortex."""
    rng = np.random.default_rng(seed)
    size = min(w, h)

    def pt():
        return [float(rng.uniform(0, w)), float(rng.uniform(0, h))]

    def color():
        return [int(c) for c in rng.integers(0, 256, 3)]

    ops = [
        {"type": "drop", "center": pt(), "radius": float(rng.uniform(0.05, 0.2) * size),
         "color": color()}
        for _ in range(int(rng.integers(6, 12)))
    ]  # fmt: skip
    ops.append({"type": "spray", "center": pt(), "radius": 0.05 * size, "color": color()})
    for kind in rng.permutation(["comb", "comb", "wave", "vortex"]):
        if kind == "comb":
            op = {"point": pt(), "angle": float(rng.uniform(0, 360)),
                  "spacing": float(rng.uniform(0.15, 0.4) * size),
                  "alpha": float(rng.uniform(-0.15, 0.15) * size),
                  "lambda": float(rng.uniform(0.03, 0.1) * size)}  # fmt: skip
        elif kind == "wave":
            op = {"amplitude": float(rng.uniform(-0.05, 0.05) * size),
                  "wavelength": float(rng.uniform(0.3, 1) * size),
                  "phase": float(rng.uniform(0, 360)),
                  "angle": float(rng.uniform(0, 360))}  # fmt: skip
        else:
            op = {"center": pt(), "alpha": float(rng.uniform(-0.3, 0.3) * size),
                  "lambda": float(rng.uniform(0.1, 0.3) * size)}  # fmt: skip
        ops.append({"type": str(kind), **op})
    return parse_recipe({"canvas": [w, h], "background": color(), "ops": ops})
