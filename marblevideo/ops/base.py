"""What an op is, once: :class:`OpDef` and its :class:`Param` s.

Everything else about an op is derived from its definition: the recipe's JSON
Schema and help texts, the animation progress, which ops are ink, the kernel's
type codes, parameter packing and walk dispatch, the NumPy reference, the SVG
forward maps, the live page's sliders and the docs tables. Adding an op means
one definition in a family module (:mod:`marblevideo.ops.ink`, ...), one
``op_<type>`` section in ``kernels/ops/<family>.cl`` and one paragraph in
docs/recipe-format.md.

Conventions (docs/recipe-format.md): canvas units, origin top-left, x right,
y down; angles in degrees (0 is +x, 90 is +y, so positive turns are clockwise
on screen); colours are (r, g, b) floats 0..255. The maps take ``v``, the op's
values at one instant (a mapping of parameter name to float or tuple of
floats, progress applied), and canvas points as broadcastable float64 arrays.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from marblevideo.ops.gestures import Setting, Tool

Value = float | tuple[float, ...]
Values = Mapping[str, Value]
Points = tuple[np.ndarray, np.ndarray]
Map = Callable[[Values, np.ndarray, np.ndarray], Points]

#: Value kinds of parameters: the recipe schema's ``$defs`` of the same names.
#: The first five may be keyframe tracks; lists, counts and the layouts' kinds
#: are constants.
KINDS = (
    "number",
    "positive",
    "nonnegative",
    "point",
    "color",
    "count",
    "numberList",
    "nonzeroList",
    "positivePair",
    "countPair",
    "colorList",
    "seed",
    "distribution",
    "pointList",
)
#: Kinds whose values may be keyframe tracks.
KEYABLE_KINDS = ("number", "positive", "nonnegative", "point", "color")
#: Kinds a slider can move (numbers).
NUMERIC_KINDS = ("number", "positive", "nonnegative")
#: Floats per op in the kernel's parameter buffer; the last holds the type code.
PSTRIDE = 12
#: Where an ink op packs its colour (red, green, blue) for the kernel's INK_COLOR.
COLOR_SLOTS = (3, 4, 5)
#: Progress laws: how an op's parameter scales with its progress p in 0..1.
PROGRESS_LAWS = {
    "linear": lambda value, p: value * p,
    "sqrt": lambda value, p: value * math.sqrt(p),  # a poured area growing linearly
}
#: The canvas every op definition's ``example`` is drawn for.
EXAMPLE_CANVAS = (80.0, 60.0)
#: Slider laws of the live page: (min, max, step) for a value v on a canvas of side size.
SLIDER_LAWS = ("angle", "phase", "shift", "amplitude", "length", "area", "time", "share")


@dataclass(frozen=True)
class Param:
    """One parameter: ``kind`` (one of :data:`KINDS`), its help text (the schema's
    description), the live page's ``slider`` law (:data:`SLIDER_LAWS`; None for
    all but numbers), and whether it may be left out (``optional``; then
    ``default``, if not None, stands in). Keyable kinds may be keyframe tracks
    unless ``keyable`` is False (a layout's fields are constants). A point is a
    place the designer shows as a handle unless ``handle`` is False (a motion)."""

    name: str
    kind: str
    help: str
    slider: str | None = None
    optional: bool = False
    default: object = None
    keyable: bool = True
    handle: bool = True

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"param {self.name}: unknown kind {self.kind!r}")
        if (self.slider is None) != (self.kind not in NUMERIC_KINDS):
            raise ValueError(f"param {self.name}: numbers have a slider law, others none")
        if self.slider is not None and self.slider not in SLIDER_LAWS:
            raise ValueError(f"param {self.name}: unknown slider law {self.slider!r}")
        if self.kind not in KEYABLE_KINDS:
            object.__setattr__(self, "keyable", False)

    @property
    def tracked(self) -> bool:
        """Whether the value may be a keyframe track."""
        return self.keyable and self.kind in KEYABLE_KINDS

    def but(self, **changes) -> Param:
        """This parameter with some fields changed (e.g. an op's own help text)."""
        return replace(self, **changes)


def identity(v: Values, x: np.ndarray, y: np.ndarray) -> Points:
    """The map of an op that moves nothing (a spray)."""
    return x.copy(), y.copy()


@dataclass(frozen=True)
class OpDef:
    """An op type.

    - ``params``: in the order the recipe documents them.
    - ``progress``: (parameter, law) pairs: at progress p the parameter becomes
      ``PROGRESS_LAWS[law](value, p)`` (points and colours componentwise).
    - ``pack(v, lists)``: the op's values as at most PSTRIDE - 1 floats for its
      kernel section (angles as direction cosines, no trigonometry left for the
      kernel); variable-length data is appended to ``lists`` (floats), its
      offset and length packed. Ink ops put their colour at :data:`COLOR_SLOTS`.
    - ``inverse``, ``forward``: the NumPy float64 maps P' -> P and P -> P'.
    - ``contains(v, x, y)``: for ink ops, whether each point is ink (ends the
      walk with the op's ``color``); None for ops that are not ink.
    - ``check(op, tracks)``: what a schema cannot say about one op of a recipe
      (``op`` as JSON, ``tracks`` its parameters' Tracks): a list of (JSON path
      below the op, message); None when the schema says it all.
    - ``settle(values)``: the values at one instant made renderable where the
      recipe leaves them out of range between keys (in place); None: as they are.
    - ``travels``: progress is a stylus' travel along the op's path, not a
      scaled parameter: :meth:`at_progress` puts p in ``values["travel"]``.
    - ``example``: a valid op of this type as JSON, drawn for :data:`EXAMPLE_CANVAS`
      (for tests, the device check and docs).
    - ``family``: the module that defines it, and so the kernel file
      ``kernels/ops/<family>.cl`` that holds its ``op_<type>`` section.
    - ``tools``: the designer's tools that draw it (:mod:`marblevideo.ops.gestures`);
      ``settings``: the numbers those tools ask for once, beside them.
    """

    type: str
    help: str
    params: tuple[Param, ...]
    pack: Callable[[Values, list], Sequence[float]]
    inverse: Map
    forward: Map
    example: Mapping
    progress: tuple[tuple[str, str], ...] = ()
    contains: Callable[[Values, np.ndarray, np.ndarray], np.ndarray] | None = None
    check: Callable[[Mapping, Mapping], list] | None = None
    settle: Callable[[dict], dict] | None = None
    travels: bool = False
    tools: tuple[Tool, ...] = ()
    settings: tuple[Setting, ...] = ()
    family: str = ""
    code: int = field(default=-1, compare=False)

    @property
    def ink(self) -> bool:
        return self.contains is not None

    @property
    def kinds(self) -> dict[str, str]:
        """Parameter name -> value kind, in order."""
        return {p.name: p.kind for p in self.params}

    @property
    def kernel_function(self) -> str:
        """The name of the op's section in the kernel."""
        return f"op_{self.type}"

    def absent(self, values: Values) -> bool:
        """Whether the op is absent at these values: an ink op of radius 0 (at
        progress 0) holds no point and moves nothing."""
        return self.ink and values["radius"] <= 0

    def still(self, values: Values) -> bool:
        """Whether the op moves nothing and holds no ink at these values: an
        absent ink op, or one whose every progress-scaled parameter is 0 (at
        progress 0, before its ``start``, or given as 0). The kernel skips it."""
        if self.ink:
            return self.absent(values)
        if self.travels:
            return values.get("travel", 1.0) <= 0 or values.get("drag") == 0
        return bool(self.progress) and all(
            all(c == 0 for c in v) if isinstance(v := values[name], tuple) else v == 0
            for name, _ in self.progress
        )

    def param(self, name: str) -> Param:
        for p in self.params:
            if p.name == name:
                return p
        raise KeyError(f"{self.type} has no parameter {name!r}")

    def at_progress(self, values: dict[str, Value], p: float) -> dict[str, Value]:
        """``values`` with the progress laws applied at progress ``p``, then settled
        (in place)."""
        if self.travels:
            values["travel"] = p
        for name, law in self.progress:
            scale = PROGRESS_LAWS[law]
            value = values[name]
            values[name] = (
                tuple(scale(c, p) for c in value) if isinstance(value, tuple) else scale(value, p)
            )
        return self.settle(values) if self.settle is not None else values

    def packed(self, values: Values, lists: list) -> list[float]:
        """:attr:`pack`, checked: at most PSTRIDE - 1 floats."""
        row = [float(x) for x in self.pack(values, lists)]
        if len(row) > PSTRIDE - 1:
            raise ValueError(f"{self.type} packs {len(row)} floats, more than {PSTRIDE - 1}")
        return row


#: The slider laws as data (the page evaluates the same: marblevideo/design/web/
#: range.js): hi = max(times * |v| (v when not ``absolute``; rounded up with
#: ``ceil``), least * size**power / per); lo is -hi (``mirror``), 0 (``zero``) or
#: hi / 1000 (``thousandth``); the step is hi / steps, or ``step``. ``kinds``
#: changes some of these for a parameter of that kind.
SLIDER_SPECS: dict[str, dict] = {
    "angle": {"times": 1, "least": 180, "ceil": True, "step": 1, "units": "degrees"},
    "phase": {"times": 1, "least": 360, "ceil": True, "step": 1, "units": "degrees"},
    "shift": {"times": 2, "least": 1, "power": 1, "per": 4, "units": "canvas units"},
    "amplitude": {"times": 2, "least": 1, "power": 1, "per": 40, "units": "canvas units"},
    "length": {
        "times": 4,
        "absolute": False,
        "least": 1,
        "power": 1,
        "per": 10,
        "lo": "thousandth",
        "steps": 1000,
        "units": "canvas units",
        "kinds": {"nonnegative": {"lo": "zero"}},
    },
    "area": {
        "times": 2,
        "least": 1,
        "power": 2,
        "per": 4,
        "lo": "thousandth",
        "steps": 1000,
        "units": "canvas units squared",
        "kinds": {"number": {"lo": "mirror", "steps": 500}, "nonnegative": {"lo": "zero"}},
    },
    "time": {"times": 4, "absolute": False, "least": 10, "lo": "zero", "steps": 1000, "units": "s"},
    "share": {"times": 0, "least": 4, "step": 0.01, "units": ""},
}
_SPEC_DEFAULTS = {
    "absolute": True,
    "ceil": False,
    "power": 0,
    "per": 1,
    "lo": "mirror",
    "steps": 500,
}


def slider_spec(param: Param) -> dict:
    """The slider law of ``param`` (a number) as data, for its kind."""
    spec = {**_SPEC_DEFAULTS, **SLIDER_SPECS[param.slider]}
    kinds = spec.pop("kinds", {})
    return {**spec, **kinds.get(param.kind, {})}


def spec_range(spec: Mapping, v: float, size: float) -> tuple[float, float, float]:
    """(min, max, step) of a slider of law ``spec`` (:func:`slider_spec`) for a value
    ``v`` on a canvas whose larger side is ``size``."""
    term = spec["times"] * (abs(v) if spec["absolute"] else v)
    if spec["ceil"]:
        term = math.ceil(term)
    least = spec["least"]
    for _ in range(spec["power"]):
        least *= size
    hi = max(term, least / spec["per"])
    lo = {"mirror": -hi, "zero": 0.0, "thousandth": hi / 1000}[spec["lo"]]
    return lo, hi, spec.get("step") or hi / spec["steps"]


def slider_range(param: Param, v: float, size: float) -> tuple[float, float, float]:
    """(min, max, step) of ``param``'s slider for a value ``v`` on a canvas whose
    larger side is ``size``: angles +-180 and phases +-360 degrees (or |v|) in
    whole degrees; signed shifts (arc lengths, alpha) at least +-size/4 and
    amplitudes at least +-size/40, else twice |v|; lengths (radii, lambda,
    spacing, wavelength) up to four times v or size/10, from 0 where 0 is
    allowed (:data:`SLIDER_SPECS`)."""
    if param.slider is None:
        raise ValueError(f"{param.name} has no slider")
    return spec_range(slider_spec(param), v, size)


def direction(degrees: float) -> tuple[float, float]:
    """(cos a, sin a) of an angle in degrees: M of the contract (N is (-sin a, cos a))."""
    a = math.radians(degrees)
    return math.cos(a), math.sin(a)


# Parameters several ops share (an op may change one's help with Param.but).
CENTER = Param("center", "point", "Centre [x, y] in canvas units (origin top-left, y down).")
POINT = Param(
    "point", "point", "A point [x, y] on the line, in canvas units (origin top-left, y down)."
)
RADIUS = Param("radius", "positive", "Radius in canvas units.", "length")
COLOR = Param(
    "color", "color", 'Ink color: "#rrggbb", "#rgb", a CSS color name or [r, g, b] (0..255).'
)
ANGLE = Param("angle", "number", "Direction in degrees: 0 points to +x, 90 to +y (down).", "angle")
ALPHA = Param(
    "alpha", "number", "Maximum shift in canvas units; negative reverses the motion.", "shift"
)
LAMBDA = Param(
    "lambda",
    "positive",
    "Sharpness, > 0: the shift falls to half at distance lambda.",
    "length",
)
FALLOFF = Param(
    "falloff", "positive", "Fall-off length L > 0: the pull is alpha e^(-d/L).", "length"
)
