"""pst-marble's actions as recipe ops (``pst-marble.pro``, v1.6, read once).

Conventions (docs/pst-marble.md has the table): pst-marble's action units are
canvas units, its y points up from its origin (:class:`Frame` turns a point
over); rake, jiggle, shift and line-drops take compass bearings b (0 up, 90
right), a recipe angle b - 90; concentric-rings lists colours innermost first;
jiggle's amplitudes are peak to peak; its viscosity is one setting for all.
Seeded layouts and sprays draw pst-marble's own RC4 numbers
(:mod:`marblevideo.pstmarble.random`), so they import as the drops it draws.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from marblevideo.limits import MAX_IMPORT_OPS, MAX_LIST
from marblevideo.pstmarble.postscript import Interpreter, PsFault, PsString, bounded, describe
from marblevideo.pstmarble.random import Rc4

#: pst-marble's most saturated colour component (it clamps to 0.999).
COLOUR_MAX = 0.999
#: Actions pst-marble has that no recipe op can say.
REFUSED = {
    "wriggle": "a radial jiggle",
    "jiggle-shade": "a shading",
    "wriggle-shade": "a shading",
    "shading": "a shading",
    "edgy-color": "a drop's soft edge",
}


@dataclass
class Frame:
    """pst-marble's action frame on the canvas: x right from ``x_lo``, y up to ``y_hi``."""

    x_lo: float
    y_hi: float

    def point(self, x: float, y: float) -> list[float]:
        return [_r(x - self.x_lo), _r(self.y_hi - y)]


@dataclass
class Design:
    """What the actions read (frame, viscosity, colours, seed) and the ops they make."""

    frame: Frame
    viscosity: float
    colors: list
    seed: str
    ops: list = field(default_factory=list)
    sprays: list = field(default_factory=list)
    notes: list = field(default_factory=list)  # (offset, what the import changes)
    rng: Rc4 = field(init=False)

    def __post_init__(self):
        self.rng = Rc4(self.seed)


def _r(v: float) -> float:
    return round(float(v), 6)


def colour(value, at: int, exact: bool = False) -> list:
    """pst-marble's color-norm: [r g b] in 0..1 (0..255 when a component is > 1) or
    a hex string (rrggbb); each clamped to 1e-9..0.999; as recipe 0..255, whole
    (as 8-bit output rounds them) unless ``exact``."""
    if isinstance(value, PsString):
        try:
            n = int(value.text.strip(), 16)
        except ValueError:
            raise PsFault(f"({value.text}): not a hex colour", at) from None
        value = [float(n >> 16 & 255), float(n >> 8 & 255), float(n & 255)]
    if not (
        isinstance(value, list) and len(value) == 3 and all(isinstance(c, float) for c in value)
    ):
        raise PsFault(f"expected a colour [r g b] or (rrggbb), got {describe(value)}", at)
    if any(c > 1 for c in value):
        value = [c / 255 for c in value]
    scaled = [min(max(c, 1e-9), COLOUR_MAX) * 255 for c in value]
    return scaled if exact else [round(c) for c in scaled]


def colours(value, at: int) -> list[list[float]]:
    """color-norm*: one colour or an array of them."""
    if isinstance(value, list) and value and all(isinstance(c, float) for c in value):
        return [colour(value, at)]
    if isinstance(value, PsString):
        return [colour(value, at)]
    if not isinstance(value, list) or not value:
        raise PsFault(f"expected colours [[r g b] ...], got {describe(value)}", at)
    return [colour(c, at) for c in value]


def _numbers(ps: Interpreter, at: int, n: int) -> list[float]:
    return [ps.pop_number(at) for _ in range(n)][::-1]


def _drop(d: Design, x: float, y: float, radius: float, rgb: list) -> None:
    d.ops.append(
        {"type": "drop", "center": d.frame.point(x, y), "radius": _r(radius), "color": rgb}
    )


def _bearing(b: float) -> float:
    """A compass bearing (0 up, 90 right, y up) as a recipe angle (0 +x, 90 down)."""
    return _r(((b - 90.0) + 180.0) % 360.0 - 180.0)


def drop(d: Design, ps: Interpreter, at: int) -> None:
    rgb = ps.pop(at, "a colour")
    x, y, radius = _numbers(ps, at, 3)
    _drop(d, x, y, radius, colour(rgb, at))


def concentric_rings(d: Design, ps: Interpreter, at: int) -> None:
    """xc yc w [c] n: radius w sqrt(2k+1) for k = n-1 down to 0, colour c[k mod len]."""
    count = ps.pop_count(at, "concentric-rings", "rings")
    rgb = colours(ps.pop(at, "colours"), at)
    x, y, width = _numbers(ps, at, 3)
    for k in range(count - 1, -1, -1):
        _drop(d, x, y, width * math.sqrt(2 * k + 1), rgb[k % len(rgb)])


def line_drops(d: Design, ps: Interpreter, at: int) -> None:
    """xc yc b [r] [c] drad: drops at (xc, yc) + r (sin b, cos b)."""
    radius = ps.pop_number(at)
    rgb = colours(ps.pop(at, "colours"), at)
    offsets = _floats(bounded(ps.pop_array(at), "line-drops", "drops", at), at)
    x, y, b = _numbers(ps, at, 3)
    s, c = math.sin(math.radians(b)), math.cos(math.radians(b))
    for k, r in enumerate(offsets):
        _drop(d, x + r * s, y + r * c, radius, rgb[k % len(rgb)])


def _place(x: float, y: float, th: float, xc: float, yc: float) -> tuple[float, float]:
    """(x, y) turned by th degrees (counter-clockwise, y up), then moved to (xc, yc)."""
    c, s = math.cos(math.radians(th)), math.sin(math.radians(th))
    return x * c - y * s + xc, x * s + y * c + yc


def serpentine_drops(d: Design, ps: Interpreter, at: int) -> None:
    """xc yc [xr] [yr] th [c] drad: rows yr, each the other way, turned by -th."""
    radius = ps.pop_number(at)
    rgb = colours(ps.pop(at, "colours"), at)
    th = -ps.pop_number(at)
    ys, xs = _floats(ps.pop_array(at), at), _floats(ps.pop_array(at), at)
    x, y = _numbers(ps, at, 2)
    bounded(range(len(xs) * len(ys)), "serpentine-drops", "drops", at)
    k = 0
    for row, yr in enumerate(ys):
        for xr in xs if row % 2 == 0 else xs[::-1]:
            _drop(d, *_place(xr, yr, th, x, y), radius, rgb[k % len(rgb)])
            k += 1


def coil_drops(d: Design, ps: Interpreter, at: int) -> None:
    """xc yc r th arcinc rinc [c] n drad: a spiral of drops at bearings th."""
    radius, count = ps.pop_number(at), ps.pop_count(at, "coil-drops", "drops")
    rgb = colours(ps.pop(at, "colours"), at)
    x, y, r, th, arc, step = _numbers(ps, at, 6)
    for k in range(count):
        b = math.radians(th)
        _drop(d, x + r * math.sin(b), y + r * math.cos(b), radius, rgb[k % len(rgb)])
        ratio = max(-1.0, min(1.0, arc / r)) if r else 1.0
        th += math.degrees(math.asin(ratio))
        r += step


def _scatter(d: Design, ps: Interpreter, at: int, name: str, size=None) -> list:
    """The drops of normal-drops / uniform-drops (xc yc Lx Ly angle [c] n drad) or
    the action ``name`` made of one, as (x, y, radius, colour); ``size(drad)`` draws
    each one's radius right after its place (a spray's), else every radius is drad."""
    normal = not name.startswith("uniform")
    radius, count = ps.pop_number(at), ps.pop_count(at, name, "drops")
    rgb = colours(ps.pop(at, "colours"), at)
    x, y, lx, ly, angle = _numbers(ps, at, 5)
    out = []
    for k in range(count):
        if normal:
            gx, gy = d.rng.normal2()
            px, py = gy * lx / math.sqrt(8), gx * ly / math.sqrt(8)
        else:
            px = (d.rng.uniform() - 0.5) * lx
            py = (d.rng.uniform() - 0.5) * ly
        r = size(radius) if size is not None else radius
        out.append((*_place(px, py, -angle, x, y), r, rgb[k % len(rgb)]))
    return out


def scatter_drops(name: str):
    def action(d: Design, ps: Interpreter, at: int) -> None:
        for x, y, radius, rgb in _scatter(d, ps, at, name):
            _drop(d, x, y, radius, rgb)

    return action


def gaussian_drops(d: Design, ps: Interpreter, at: int) -> None:
    """xc yc r angle ecc [c] n drad: normal-drops of sides 2r/sqrt(ecc), 2r sqrt(ecc)."""
    radius, count, rgb = ps.pop(at), ps.pop(at), ps.pop(at)
    x, y, r, angle, ecc = _numbers(ps, at, 5)
    e = math.sqrt(ecc)
    ps.stack += [x, y, 2 * r / e, 2 * r * e, angle, rgb, count, radius]
    scatter_drops("Gaussian-drops")(d, ps, at)


def spray(name: str):
    """normal-spray / uniform-spray: dots drawn over the marbling, each of radius
    e^((g + 9 log10 drad) / 3), g the first of a normal pair drawn after its place."""

    def action(d: Design, ps: Interpreter, at: int) -> None:
        def size(drad: float) -> float:
            return math.exp((d.rng.normal2()[0] + 9 * math.log10(drad)) / 3)

        for x, y, radius, rgb in _scatter(d, ps, at, name, size):
            d.sprays.append(
                {"type": "spray", "center": d.frame.point(x, y), "radius": _r(radius), "color": rgb}
            )

    return action


def _floats(values: list, at: int) -> list[float]:
    if not all(isinstance(v, float) for v in values):
        raise PsFault("expected an array of numbers", at)
    return values


def tines(d: Design, ps: Interpreter, at: int) -> None:
    """n s o tines: offsets i s + o for i from int(-(n - 1) / 2), n of them (at
    most MAX_LIST, a rake's)."""
    s, o = _numbers(ps, at, 2)
    n = ps.pop_count(at, "tines", "tines", MAX_LIST, "MAX_LIST")
    first = int(-(n - 1) / 2)
    ps.stack += [float(i * s + o) for i in range(first, first + n)]


def _positive(value: float, name: str, at: int) -> float:
    if not value > 0:
        raise PsFault(f"{name} must be > 0, got {value:g}", at)
    return value


def rake(d: Design, ps: Interpreter, at: int) -> None:
    """b [r] V tU D: the recipe's rake, alpha tU, falloff V D^2 / viscosity."""
    depth = _positive(abs(ps.pop_number(at)), "D", at)
    shift = ps.pop_number(at)
    speed = _positive(abs(ps.pop_number(at)), "V", at)
    offsets = _floats(ps.pop_array(at), at)
    b = ps.pop_number(at)
    d.ops.append({"type": "rake", "point": d.frame.point(0, 0), "angle": _bearing(b),
                  "alpha": _r(shift), "falloff": _r(speed * depth**2 / d.viscosity),
                  "tines": [_r(o) for o in offsets]})  # fmt: skip


def stir(d: Design, ps: Interpreter, at: int) -> None:
    """x y [r] w th D: the revision-4 stir with turn th, falloff w pi D^2 / (180 nu)."""
    depth, th = ps.pop_number(at), ps.pop_number(at)
    w = _positive(abs(ps.pop_number(at)), "w", at)
    radii = _floats(ps.pop_array(at), at)
    x, y = _numbers(ps, at, 2)
    if not radii or any(r == 0 for r in radii):
        raise PsFault("stir needs non-zero radii", at)
    falloff = _positive(w * math.pi * depth**2 / (180 * d.viscosity), "w pi D^2", at)
    d.ops.append({"type": "stir", "center": d.frame.point(x, y), "radii": [_r(r) for r in radii],
                  "turn": _r(th), "falloff": _r(falloff)})  # fmt: skip


def vortex(d: Design, ps: Interpreter, at: int) -> None:
    """x y G t: the recipe's oseen with pst-marble's viscosity."""
    x, y, g, t = _numbers(ps, at, 4)
    d.ops.append({"type": "oseen", "center": d.frame.point(x, y), "circulation": _r(g),
                  "viscosity": _r(d.viscosity), "time": _r(_positive(t, "t", at))})  # fmt: skip


def jiggle(d: Design, ps: Interpreter, at: int) -> None:
    """b P o A B: angle b - 90, wavelength P, major A/2, minor -B/2, phase from the
    canvas corner: 360 (o + x_lo sin b + y_hi cos b) / P degrees."""
    b, period, offset, major, minor = _numbers(ps, at, 5)
    period = _positive(abs(period), "the period", at)
    if math.pi * abs(major) / period >= 1:
        raise PsFault(
            f"jiggle: major {major:g} too large for period {period:g} (pi A / P >= 1)", at
        )
    rb = math.radians(b)
    corner = d.frame.x_lo * math.sin(rb) + d.frame.y_hi * math.cos(rb)
    phase = (360.0 * (offset + corner) / period) % 360.0
    d.ops.append({"type": "jiggle", "angle": _bearing(b), "wavelength": _r(period),
                  "phase": _r(phase), "major": _r(major / 2), "minor": _r(-minor / 2)})  # fmt: skip


def wiggle(d: Design, ps: Interpreter, at: int) -> None:
    """b P o depth: pst-marble's jiggle b (360^2 / P) ((o + 90) / 0.75) 0 (2 depth)."""
    b, period, offset, depth = _numbers(ps, at, 4)
    ps.stack += [b, 360.0**2 / period, (offset + 90) / 0.75, 0.0, 2 * depth]
    jiggle(d, ps, at)


def shift(d: Design, ps: Interpreter, at: int) -> None:
    """b r: the tank moved r along bearing b."""
    b, r = _numbers(ps, at, 2)
    rb = math.radians(b)
    d.ops.append({"type": "shift", "offset": [_r(r * math.sin(rb)), _r(-r * math.cos(rb))]})


def turn(d: Design, ps: Interpreter, at: int) -> None:
    x, y, angle = _numbers(ps, at, 3)
    d.ops.append({"type": "turn", "center": d.frame.point(x, y), "angle": _r(angle)})


def stylus(d: Design, ps: Interpreter, at: int) -> None:
    """bx by ex ey V D: a stroke from b to e, 4 L wide (L = V D^2 / viscosity): the
    stroke's model (vortex-pair steps), not pst-marble's (a moving Oseen stylus)."""
    depth, speed = ps.pop_number(at), abs(ps.pop_number(at))
    bx, by, ex, ey = _numbers(ps, at, 4)
    width = _positive(4 * speed * depth**2 / d.viscosity, "V D^2", at)
    d.notes.append((at, "stylus imported as a stroke: another model (docs/pst-marble.md)"))
    d.ops.append({"type": "stroke", "points": [d.frame.point(bx, by), d.frame.point(ex, ey)],
                  "width": _r(width), "drag": 1})  # fmt: skip


def _tinted(power: float, shade: bool):
    def f(c: float) -> float:
        p = 2 - power
        if shade:
            return 1 - (1 - c) ** p if 1 - c >= 1e-30 else c
        return c**p if c >= 1e-30 else c

    return f


def tint(shade: bool):
    """v pwr tint (or shade): pst-marble's colour tints, on a normalised colour."""

    def action(d: Design, ps: Interpreter, at: int) -> None:
        power = ps.pop_number(at)
        rgb = [c / 255 for c in colour(ps.pop(at, "a colour"), at, exact=True)]
        darker = shade if power >= 0 else not shade
        ps.stack.append([float(_tinted(abs(power), darker)(c)) for c in rgb])

    return action


ACTIONS: dict[str, Callable] = {
    "drop": drop,
    "concentric-rings": concentric_rings,
    "line-drops": line_drops,
    "serpentine-drops": serpentine_drops,
    "coil-drops": coil_drops,
    "normal-drops": scatter_drops("normal-drops"),
    "uniform-drops": scatter_drops("uniform-drops"),
    "Gaussian-drops": gaussian_drops,
    "rake": rake,
    "stir": stir,
    "vortex": vortex,
    "jiggle": jiggle,
    "wiggle": wiggle,
    "shift": shift,
    "turn": turn,
    "stylus": stylus,
    "stroke": stylus,
}
SPRAYS: dict[str, Callable] = {"normal-spray": spray("normal-spray"),
                               "uniform-spray": spray("uniform-spray")}  # fmt: skip
HELPERS: dict[str, Callable] = {"tines": tines, "tint": tint(False), "shade": tint(True)}


def words(design: Design, table: dict[str, Callable]) -> dict[str, Callable]:
    """The names a list of actions may call, bound to ``design``; the refused ones
    raise a fault naming the action."""
    bound = {name: _bind(design, f) for name, f in {**HELPERS, **table}.items()}
    for name, what in REFUSED.items():
        bound[name] = _refuse(name, what)
    bound["colors"] = lambda ps, at: ps.stack.append(list(design.colors))
    return bound


def _bind(design: Design, f: Callable) -> Callable:
    def action(ps: Interpreter, at: int) -> None:
        f(design, ps, at)
        made = len(design.ops) + len(design.sprays)
        if made > MAX_IMPORT_OPS:
            limit = f"over the limit of {MAX_IMPORT_OPS:,} (MAX_IMPORT_OPS)"
            raise PsFault(f"the design makes {made:,} ops, {limit}", at)

    return action


def _refuse(name: str, what: str) -> Callable:
    def refuse(ps: Interpreter, at: int) -> None:
        raise PsFault(f"{name}: {what}, no marblevideo op can say it", at)

    return refuse
