"""The recipe model and its validation (docs/recipe-format.md).

:func:`load_recipe` and :func:`parse_recipe` turn a JSON file or a Python dict
into a :class:`Recipe`, validating it fully first: structure against the
published JSON Schema (:mod:`marblevideo.recipe.schema`), then what a schema cannot
say (key times strictly increasing, ``end`` > ``start``, each op's own rules; the
messages come from :mod:`marblevideo.recipe.faults`). The first fault in
document order (structural faults before those) raises
:class:`~marblevideo.errors.RecipeError`, whose text is
``FILE: json.path: what was expected, got what``, the path written like
``ops[3].center.keys[1].t`` (empty for the whole document).

Decisions beyond the contract: ``end`` without ``start`` is an error (its
progress would be undefined); an empty ``ops`` list is valid (identity);
non-finite numbers (NaN, Infinity, 1e400) and magnitudes over 1e30 (float32
range) are refused; so is nesting deeper than :data:`MAX_DEPTH` (a valid recipe
needs 7 levels), before anything recurses into it.

:meth:`Recipe.at` resolves every track and applies each op's progress,
giving the :class:`~marblevideo.recipe.frame.FrameSpec` the renderers read.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field
from typing import Any

from marblevideo.bundled import preset_name, preset_path, presets, recipe_file
from marblevideo.errors import RecipeError, UsageError
from marblevideo.ops import LAYOUTS, expand, op_def, type_def
from marblevideo.recipe.accepted import is_accepted, remember_accepted, text_digest
from marblevideo.recipe.colors import color_components
from marblevideo.recipe.document import check_depth, normalize, parse_json
from marblevideo.recipe.faults import (
    Fault,
    describe,
    did_you_mean,
    make_fault,
    schema_fault,
    validator,
)
from marblevideo.recipe.frame import FrameSpec, OpState
from marblevideo.recipe.keyframes import Key, Track
from marblevideo.recipe.motion import MotionSpec, motion_faults
from marblevideo.recipe.signals import (
    SignalTrack,
    SignalValues,
    check_at_ends,
    signal_faults,
    signal_track,
)

DEFAULT_BACKGROUND = "#ffffff"
#: Parameter kinds whose value is one number (the others are tuples).
SCALAR_KINDS = ("number", "positive", "nonnegative", "count", "seed")
DEFAULT_ANTIALIAS = "rgss"
DEFAULT_EDGES = "clamp"


# --------------------------------------------------------------------------- model


@dataclass(frozen=True)
class Op:
    """One op of a recipe: its parameters as tracks, ``start``/``end`` in seconds
    (None when absent), ``heal`` (t0, t1) in seconds (None when absent), its
    ``index`` in :attr:`Recipe.ops`, ``entry``: its index in the file's ``ops``
    and, for the drops a layout stands for, ``layout``: the layout's type and
    index in the recipe file. Hidden ops are not in
    :attr:`Recipe.ops`, so ``index`` and ``entry`` may differ."""

    type: str
    params: dict[str, Track | SignalTrack] = field(hash=False)
    start: float | None
    end: float | None
    index: int
    layout: tuple[str, int] | None = None
    entry: int = -1
    heal: tuple[float, float] | None = None

    def progress(self, t: float) -> float:
        """The contract's p(t): 0 before ``start``, linear up to ``end``, then 1;
        a jump at ``start`` without ``end``; 1 always without either."""
        if self.start is None:
            return 1.0
        if t < self.start:
            return 0.0
        if self.end is None or t >= self.end:
            return 1.0
        return (t - self.start) / (self.end - self.start)

    def healing(self, t: float) -> float:
        """The contract's h(t) of ``heal`` [t0, t1]: 1 before t0, falling linearly
        to 0 at t1, 0 from then on (from t0 when t0 = t1); 1 always without it."""
        if self.heal is None:
            return 1.0
        t0, t1 = self.heal
        if t < t0:
            return 1.0
        if t >= t1:
            return 0.0
        return 1.0 - (t - t0) / (t1 - t0)

    def at(self, t: float, signals: SignalValues | None = None) -> OpState:
        """The op at time ``t``: tracks resolved (signals from ``signals``), what
        its definition takes from the time itself (a timed stroke's stylus), its
        progress laws applied at p(t) h(t) (e.g. ink radius * sqrt(p h), alpha * p h;
        see :mod:`marblevideo.ops`)."""
        values = {name: track.at(t, signals) for name, track in self.params.items()}
        definition = op_def(self.type)
        if definition.clock is not None:
            definition.clock(values, t)
        p = self.progress(t) * self.healing(t)
        return OpState(self.type, definition.at_progress(values, p))

    @property
    def times(self) -> tuple[float, ...]:
        """Every key time of its tracks, its ``start``/``end`` and a stroke's
        ``times`` (not ``heal``: the design is finished before it heals)."""
        own = tuple(x for x in (self.start, self.end) if x is not None)
        drawn = self.params["times"].at(0.0) if "times" in self.params else ()
        return own + drawn + tuple(t for track in self.params.values() for t in track.key_times)

    @property
    def signal_params(self) -> dict[str, SignalTrack]:
        """Its parameters that follow a signal, by name."""
        return {n: track for n, track in self.params.items() if isinstance(track, SignalTrack)}


@dataclass(frozen=True)
class Recipe:
    """A validated recipe. ``canvas`` is None when the recipe leaves it to the input.

    ``ops``: what is rendered, the file's ops in order with layouts expanded and
    hidden ops left out; ``entries``: the length of the file's ``ops``.
    ``source`` is the name used in messages (the file as given, or ``<dict>``);
    ``description`` is the recipe's own (empty if it gives none; not rendered).
    ``signals``: where parameters that follow a signal take their values
    (:meth:`bind`); None gives each signal's resting value.
    """

    ops: tuple[Op, ...]
    canvas: tuple[float, float] | None
    background: Track
    antialias: str = DEFAULT_ANTIALIAS
    edges: str = DEFAULT_EDGES
    source: str = "<dict>"
    description: str = ""
    entries: int = 0
    signals: SignalValues | None = field(default=None, compare=False, repr=False)
    #: marblevideo extension: animated frames over an input may interpolate the map
    #: from a walked lattice (False: every subsample walked; see Marbler)
    lattice: bool = True
    #: revision 4's ``motion``: the input's movement becomes strokes (None: it does not)
    motion: MotionSpec | None = None

    @classmethod
    def from_dict(cls, data: object, source: str = "<dict>") -> Recipe:
        """Validate and build a recipe given as Python data (as :func:`parse_recipe`)."""
        return parse_recipe(data, source)

    @property
    def is_animated(self) -> bool:
        """Whether any value depends on time (keys, start/end, a stroke's times,
        heal, signals, motion)."""
        keyed = bool(self.background.key_times) or any(op.times or op.heal for op in self.ops)
        return keyed or bool(self.signal_uses()) or self.motion is not None

    def signal_uses(self) -> list[tuple[str, SignalTrack]]:
        """(JSON path of the parameter, its track) for every parameter rendered
        that follows a signal, in document order."""
        return [
            (f"ops[{op.entry}].{name}", track)
            for op in self.ops
            for name, track in op.signal_params.items()
        ]

    def bind(self, signals: SignalValues | None) -> Recipe:
        """This recipe with its signals taken from ``signals``."""
        return dataclasses.replace(self, signals=signals)

    def end_time(self) -> float:
        """When the animation is finished: the largest key time, op start/end and
        stroke time, else 0 (a ``heal`` does not count). A still is rendered at this
        time by default."""
        times = [*self.background.key_times, *(t for op in self.ops for t in op.times)]
        return max(times, default=0.0)

    def settled_time(self) -> float:
        """When nothing changes any more: :meth:`end_time`, or the last op's healing
        end when later. A video of a still runs this long (plus a second) by default."""
        heals = [op.heal[1] for op in self.ops if op.heal is not None]
        return max([self.end_time(), *heals])

    def at(self, t: float, canvas: tuple[float, float] | None = None) -> FrameSpec:
        """The frame at time ``t`` (seconds). ``canvas`` (the input's size) is used
        only when the recipe gives none; one of the two is required."""
        size = self.canvas or canvas
        if size is None:
            raise UsageError(f"{self.source}: the recipe has no canvas and there is no input size")
        r, g, b = self.background.at(t)
        return FrameSpec(
            ops=tuple(op.at(t, self.signals) for op in self.ops),
            background=(r, g, b),
            antialias=self.antialias,
            edges=self.edges,
            canvas=(float(size[0]), float(size[1])),
        )


# --------------------------------------------------------------------------- loading


def load_recipe(path: str | os.PathLike[str]) -> Recipe:
    """Read, validate and build the recipe file at ``path`` (named as given in
    messages) or, when no such file exists, the preset ``path`` names (a bundled
    sample recipe: ``"swirl"`` or ``"swirl.json"``, named by its file).

    Raises UsageError if the file cannot be read, RecipeError if it is not a valid recipe.
    """
    return read_recipe(path)[1]


def read_recipe(path: str | os.PathLike[str]) -> tuple[object, Recipe]:
    """:func:`load_recipe`, with the JSON the recipe was built from: both from one
    read of the file (an editor's document and what it renders always agree)."""
    path = recipe_file(path)
    source = os.fspath(path)
    try:
        with open(path, encoding="utf-8-sig") as f:
            text = f.read()
    except UnicodeDecodeError as exc:
        raise UsageError(
            f"cannot read recipe {source}: not UTF-8 text (a recipe is JSON text; byte "
            f"{exc.object[exc.start]:#04x} at offset {exc.start:,} is not UTF-8)"
        ) from None
    except OSError as exc:
        reason = exc.strerror or str(exc)
        stem = preset_name(source)
        if isinstance(exc, FileNotFoundError) and stem is not None:
            reason += f", nor a preset of that name{did_you_mean(stem, presets(), n=3)}; "
            reason += "`marblevideo presets` lists them"
        elif isinstance(exc, FileNotFoundError) and preset_path(os.path.basename(source)):
            name = preset_name(os.path.basename(source))
            reason += f"; a preset has that name: --ops {name} (`marblevideo presets` lists them)"
        raise UsageError(f"cannot read recipe {source}: {reason}") from None
    data = parse_json(text, source)
    key = text_digest(text)
    known = is_accepted(key)  # then the schema is skipped, the loader's own rules are not
    recipe = _parse(data, source, schema=not known)
    if not known:
        remember_accepted(key)
    return data, recipe


def parse_recipe(data: object, source: str = "<dict>") -> Recipe:
    """Validate ``data`` (parsed JSON, or Python dicts/lists/tuples) and build the recipe.

    ``source`` names it in messages. Raises RecipeError for the first fault.
    """
    return _parse(data, source)


def _parse(data: object, source: str, schema: bool = True) -> Recipe:
    """:func:`parse_recipe`; ``schema`` False: ``data`` is known to pass the JSON
    Schema (:mod:`marblevideo.recipe.accepted`), so only the loader's own rules run."""
    check_depth(data, source)
    doc = normalize(data)
    faults = [schema_fault(e, doc) for e in validator().iter_errors(doc)] if schema else []
    if not faults:
        faults = _semantic_faults(doc)
    if faults:
        first = min(faults, key=lambda f: f.position)
        raise RecipeError(source, first.path, first.message)
    return _build(doc, source)


def _params(op: dict) -> dict[str, Track]:
    """The Tracks of a valid op's parameters: those it gives, and the defaults of
    optional ones it leaves out."""
    params = {}
    for param in op_def(op["type"]).params:
        if param.name in op:
            params[param.name] = _track(op[param.name], param.kind)
        elif param.default is not None:
            params[param.name] = _track(param.default, param.kind)
    return params


def build_op(op: dict, index: int, entry: int = -1, layout: tuple | None = None) -> Op:
    """The Op of a valid op (of a recipe :func:`parse_recipe` accepted, or one
    known valid by construction: a motion stroke growing); nothing is checked."""
    start, end, heal = op.get("start"), op.get("end"), op.get("heal")
    return Op(
        type=op["type"],
        params=_params(op),
        start=None if start is None else float(start),
        end=None if end is None else float(end),
        index=index,
        layout=layout,
        entry=entry,
        heal=None if heal is None else (float(heal[0]), float(heal[1])),
    )


def _build(doc: dict, source: str) -> Recipe:
    ops = []
    expanded = [
        (d, n, (op["type"], n) if op["type"] in LAYOUTS else None)
        for n, op in enumerate(doc["ops"])
        if not op.get("hidden", False)
        for d in (expand(op) if op["type"] in LAYOUTS else [op])
    ]
    for index, (op, entry, layout) in enumerate(expanded):
        ops.append(build_op(op, index, entry, layout))
    canvas = doc.get("canvas")
    return Recipe(
        ops=tuple(ops),
        canvas=None if canvas is None else (float(canvas[0]), float(canvas[1])),
        background=_track(doc.get("background", DEFAULT_BACKGROUND), "color"),
        antialias=doc.get("antialias", DEFAULT_ANTIALIAS),
        edges=doc.get("edges", DEFAULT_EDGES),
        source=source,
        description=doc.get("description", ""),
        entries=len(doc["ops"]),
        lattice=doc.get("lattice", True),
        motion=MotionSpec.from_json(doc["motion"]) if "motion" in doc else None,
    )


def _components(value: Any) -> tuple[float, ...]:
    """A valid number, point, color or list as a tuple of floats (colors 0..255)."""
    if isinstance(value, str):
        return color_components(value)
    if isinstance(value, list):  # a point list is flattened: (x0, y0, x1, y1, ...)
        return tuple(float(c) for v in value for c in (v if isinstance(v, list) else [v]))
    return (float(value),)


def _track(value: Any, kind: str) -> Track | SignalTrack:
    """A valid parameter value (constant, ``{"keys": [...]}`` or a signal) as a
    Track or SignalTrack."""
    scalar = kind in SCALAR_KINDS
    if isinstance(value, dict) and "signal" in value:
        return signal_track(value)
    if not isinstance(value, dict):
        return Track((Key(0.0, _components(value)),), scalar=scalar, keyed=False)
    return Track(tuple(_key(key) for key in value["keys"]), scalar=scalar)


def _key(key: dict) -> Key:
    ease = key.get("ease", "linear")
    return Key(
        float(key["t"]),
        _components(key["v"]),
        ease if isinstance(ease, str) else tuple(float(c) for c in ease),
    )


# --------------------------------------------------------------------------- rules


def _semantic_faults(doc: dict) -> list[Fault]:
    """What the schema cannot check, on a structurally valid document."""
    faults = [make_fault(doc, ["motion", *p], m) for p, m in motion_faults(doc.get("motion", {}))]
    tracks: list[tuple[list, Any]] = [(["background"], doc.get("background"))]
    for i, op in enumerate(doc["ops"]):
        params = type_def(op["type"]).params
        tracks += [(["ops", i, p.name], op[p.name]) for p in params if p.tracked and p.name in op]
        if "end" in op and op["end"] <= op["start"]:
            message = f"must be > start ({describe(op['start'])}), got {describe(op['end'])}"
            faults.append(make_fault(doc, ["ops", i, "end"], message))
        if "heal" in op and op["heal"][1] < op["heal"][0]:
            t0, t1 = (describe(t) for t in op["heal"])
            message = f"must be [t0, t1] with t0 <= t1, got [{t0}, {t1}]"
            faults.append(make_fault(doc, ["ops", i, "heal"], message))
    for path, track in tracks:
        if isinstance(track, dict) and "signal" in track:
            faults += [make_fault(doc, [*path, *sub], m) for sub, m in signal_faults(track)]
        if not isinstance(track, dict) or "signal" in track:
            continue
        keys = track["keys"]
        for k in range(1, len(keys)):
            if keys[k]["t"] <= keys[k - 1]["t"]:
                message = (
                    f"key times must increase strictly: got {describe(keys[k]['t'])} "
                    f"after {describe(keys[k - 1]['t'])}"
                )
                faults.append(make_fault(doc, [*path, "keys", k, "t"], message))
    if faults:
        return faults
    for i, op in enumerate(doc["ops"]):  # the ops' own rules, on well-formed tracks
        check = type_def(op["type"]).check
        tracks = {} if op["type"] in LAYOUTS else _params(op)
        for path, message in check_at_ends(check, op, tracks) if check is not None else ():
            faults.append(make_fault(doc, ["ops", i, *path], message))
    return faults
