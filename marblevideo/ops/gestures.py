"""How the designer's pointer draws an op: an op definition's :class:`Tool` s
and :class:`Setting` s, and the small expression language they are written in.

A tool is a gesture (:data:`GESTURES`) and a ``make`` mapping: each parameter
of the op it makes (in the order it is written), given as an expression of the
gesture's measures. The page (``marblevideo/design/web/tools.js``) evaluates
the same expressions as :func:`evaluate`; a test runs both on the same
gestures. Expressions are JSON:

- a number is itself; a list is evaluated item by item;
- a string names a measure of the gesture (:func:`gesture_env`), a setting
  (``setting.NAME``), a parameter made before it (``op.NAME``), or an item of
  one (``a.0``: the x of a);
- ``{"OP": args}`` with OP one of :data:`OPERATIONS`.

Measures, in canvas units (origin top-left, y down) and degrees: ``a`` where
the hand went down, ``b`` where it is now; ``dx``, ``dy``, ``len`` from a to b,
or a tenth of the canvas's smaller ``side`` to the right when the hand has not
moved 3 frame pixels (``clicked``); ``tip`` is a + (dx, dy); ``angle`` the
direction a -> b (0: +x, 90: +y), to 0.1; ``pi``; ``color``, the ink chosen,
and ``inks``, it and the palette's others; ``seed``, a random integer;
``path``, the points a ``path`` gesture drew (simplified to a frame pixel).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

#: The gestures that draw ops: a click (a drag sizes it), a line dragged from a
#: to b, a drag out from a centre a, a free-hand path.
GESTURES = ("click", "line", "centre", "path")


@dataclass(frozen=True)
class Tool:
    """A tool of the page: the ``gesture`` that draws the op and how its values
    are ``make``-d from it; ``name`` is the tool's (default: the op type);
    ``label`` is the parameter shown beside the hand while it drags."""

    gesture: str
    make: Mapping[str, object]
    name: str = ""
    label: str | None = None

    def __post_init__(self):
        if self.gesture not in GESTURES:
            raise ValueError(f"tool {self.name}: unknown gesture {self.gesture!r}")


@dataclass(frozen=True)
class Setting:
    """A number the page asks once for all of an op's tools (``setting.NAME``),
    in a field shown beside the tools (``initial``: its text at load; empty:
    ``default``, an expression of the gesture). A value typed there is taken
    when it is a finite number (> 0 when ``positive``), clamped to
    ``low``..``high`` and rounded when ``integer``; else ``default``."""

    name: str
    help: str
    default: object
    initial: str = ""
    positive: bool = False
    low: float | None = None
    high: float | None = None
    integer: bool = False


#: Each tool's shortcut key on the page (one letter; the page's other keys are
#: M, Delete, Backspace, Escape, Ctrl with Z or Y, + - 0 and the arrows) and its
#: one-line hint, by tool name. Every tool has one (a test checks).
TOOL_KEYS: dict[str, tuple[str, str]] = {
    "drop": ("D", "a drop of ink: pushes what is there aside"),
    "spray": ("S", "a droplet that covers without pushing"),
    "rings": ("R", "concentric rings of the palette's inks"),
    "line-drops": ("L", "a row of drops along the line"),
    "grid-drops": ("G", "a grid of drops over the rectangle dragged"),
    "scatter-drops": ("A", "drops scattered at random around the centre"),
    "tine": ("T", "one tine pulled along the line"),
    "comb": ("C", "a comb of parallel tines pulled along the line"),
    "wave": ("W", "a wave across the line, its wavelength the line's length"),
    "shift": ("H", "the whole tank moved by the line"),
    "rake": ("K", "a rake: tines with an exponential fall-off"),
    "circle": ("O", "a tine moved round a circle"),
    "vortex": ("V", "a swirl winding tighter to its centre"),
    "turn": ("U", "the whole tank turned about the centre"),
    "stir": ("I", "tines stirred round concentric circles"),
    "stir-turn": ("N", "two rings stirred opposite ways"),
    "oseen": ("E", "a viscous vortex: rigid core, free outside"),
    "jiggle": ("J", "the tank shaken back and forth"),
    "stroke": ("P", "a stylus drawn free-hand"),
    "comb-stroke": ("B", "a comb of styluses drawn free-hand"),
    "curl": ("F", "a small French curl loop (no times: it appears whole)"),
}


def round1(v: float) -> float:
    """To 0.1, halves up (JavaScript's Math.round, as the page rounds)."""
    return math.floor(v * 10 + 0.5) / 10


def _loop(centre, radius) -> list[list[float]]:
    """1.25 turns clockwise on screen, from the left of ``centre`` going up."""
    turns = (math.pi + 2.5 * math.pi * k / 40 for k in range(41))
    return [
        [round1(centre[0] + radius * math.cos(a)), round1(centre[1] + radius * math.sin(a))]
        for a in turns
    ]


def _each(f, v):
    return [_each(f, x) for x in v] if isinstance(v, list) else f(v)


def _product(args):
    out = args[0]
    for x in args[1:]:
        out *= x
    return out


def _sum(args):
    out = args[0]
    for x in args[1:]:
        out += x
    return out


#: The operations of ``{"OP": args}`` (args evaluated first; a list of them
#: where there are several).
OPERATIONS = {
    "mul": _product,
    "add": _sum,
    "div": lambda a: a[0] / a[1],
    "sub": lambda a: a[0] - a[1],
    "min": min,
    "max": max,
    "abs": abs,
    "round1": lambda v: _each(round1, v),
    "positive": lambda v: max(0.1, round1(v)),  # a size: to 0.1, at least 0.1
    "or": lambda a: a[0] if a[0] != 0 else a[1],  # the first unless it is 0
    "clicked": None,  # [if clicked, else]: evaluated in evaluate
    "loop": lambda a: _loop(a[0], a[1]),
    "centred": lambda a: [(k - (a[0] - 1) / 2) * a[1] for k in range(int(a[0]))],
}


def lookup(env: Mapping, name: str):
    """``a``, ``a.0``, ``setting.width``, ``op.spacing.1``: a measure or an item of one."""
    first, *rest = name.split(".")
    value = env[first]
    for part in rest:
        value = value[int(part)] if isinstance(value, list) else value[part]
    return value


def evaluate(expr, env: Mapping):
    """The value of the tool expression ``expr`` in the gesture ``env``."""
    if isinstance(expr, bool) or expr is None:
        raise ValueError(f"tool expression: unexpected {expr!r}")
    if isinstance(expr, int | float):
        return expr
    if isinstance(expr, str):
        return lookup(env, expr)
    if isinstance(expr, list):
        return [evaluate(x, env) for x in expr]
    ((op, args),) = expr.items()
    if op == "clicked":
        return evaluate(args[0] if env["clicked"] else args[1], env)
    return OPERATIONS[op](evaluate(args, env))


def gesture_env(a, b, *, side: float, scale: float, **more) -> dict:
    """The measures of a gesture from canvas point ``a`` to ``b`` (see the module
    docstring) on a canvas whose smaller side is ``side``, drawn at ``scale``
    frame pixels per canvas unit; ``more``: color, inks, seed, path, setting."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dx, dy)
    clicked = length < 3 / scale
    if clicked:
        dx, dy, length = side / 10, 0, side / 10
    angle = round1(math.atan2(dy, dx) * 180 / math.pi)
    tip = [a[0] + dx, a[1] + dy]
    env = {"a": list(a), "b": list(b), "dx": dx, "dy": dy, "len": length, "tip": tip}
    return {**env, "clicked": clicked, "angle": angle, "side": side, "pi": math.pi, **more}


def make_op(type_: str, tool: Tool, env: Mapping) -> dict:
    """The op ``tool`` makes in the gesture ``env`` (settings in ``env["setting"]``)."""
    op: dict = {"type": type_}
    scope = {**env, "op": op}
    for name, expr in tool.make.items():
        op[name] = evaluate(expr, scope)
    return op
