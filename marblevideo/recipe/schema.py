"""The recipe's JSON Schema (Draft 2020-12), as printed by ``marblevideo schema``.

It is the one structural description of docs/recipe-format.md: the loader
(:mod:`marblevideo.recipe`) validates every recipe against exactly this schema,
so an editor that uses it agrees with the loader. What a schema cannot say
(key times strictly increasing, ``end`` > ``start``, signal names) the loader
checks after it.

Each op is dispatched on its ``type`` with ``if``/``then``, so editors complete
the fields of the op being written and errors name that op's own fields. Every
numeric parameter, point and color may be a keyframe track (numbers also a
signal). The ops, their parameters' kinds (``$defs`` entries) and help texts
come from the op registry (:mod:`marblevideo.ops`). A color's CSS names are an
``enum`` (editors complete it) and, for any case, a pattern
(:mod:`marblevideo.recipe.colors`).
"""

from __future__ import annotations

import copy
from functools import lru_cache

from marblevideo.limits import MAX_COUNT, MAX_LIST, NUMBER_LIMIT
from marblevideo.ops import recipe_types, type_def
from marblevideo.ops.stroke import MAX_POINTS
from marblevideo.recipe.antialias import PATTERNS
from marblevideo.recipe.colors import CSS_NAMES, HEX_PATTERN, NAME_PATTERN, SHAPES
from marblevideo.recipe.frame import EDGE_MODES
from marblevideo.recipe.keyframes import EASE_NAMES
from marblevideo.recipe.motion import motion_schema
from marblevideo.recipe.signals import NAME_FORMS

SCHEMA_ID = "urn:marblevideo:recipe:1"
DRAFT = "https://json-schema.org/draft/2020-12/schema"

#: Largest magnitude of any number (:data:`marblevideo.limits.NUMBER_LIMIT`).
LIMIT = NUMBER_LIMIT
#: The title of a color in the schema (and so in messages).
COLOR_TITLE = f"color ({SHAPES})"
#: Kinds whose keyable parameters may follow a signal instead (numbers).
SIGNAL_KINDS = ("number", "positive", "nonnegative")
#: Longest ``description``, in characters.
MAX_DESCRIPTION = 200

_TIME_HELP = {
    "start": "Seconds: the op appears (progress p goes 0 -> 1) from here.",
    "end": "Seconds: progress p reaches 1 here (needs `start`, must be > `start`).",
}


def _ref(name: str) -> dict:
    return {"$ref": f"#/$defs/{name}"}


def _number(**bounds: float) -> dict:
    return {"type": "number", "minimum": -LIMIT, "maximum": LIMIT, **bounds}


def _track(kind: str) -> dict:
    key = {
        "type": "object",
        "properties": {
            "t": {**_ref("time"), "description": "Seconds; strictly increasing."},
            "v": {**_ref(kind), "description": "The value at t."},
            "ease": _ref("ease"),
        },
        "required": ["t", "v"],
        "additionalProperties": False,
    }
    return {
        "title": 'keyframe track {"keys": [...]}',
        "description": 'Keyframes {"keys": [{"t": 0, "v": ...}, ...]}; before the first key the '
        "first value, after the last the last.",
        "type": "object",
        "properties": {"keys": {"type": "array", "minItems": 1, "items": key}},
        "required": ["keys"],
        "additionalProperties": False,
    }


def _signal(kind: str) -> dict:
    """A number that follows a signal (revision 3): lo + (hi - lo) * y, y in 0..1."""
    seconds = {**_number(minimum=0), "default": 0}
    return {
        "title": 'signal {"signal": NAME, "range": [lo, hi]}',
        "description": "Follows a signal y in 0..1 as lo + (hi - lo) * y: "
        + ", ".join(NAME_FORMS)
        + " (controllers only in a live session).",
        "type": "object",
        "properties": {
            "signal": {
                "type": "string",
                "description": "The signal's name.",
                "examples": list(NAME_FORMS),
            },
            "range": {
                "title": "range [lo, hi]",
                "type": "array",
                "items": _ref(kind),
                "minItems": 2,
                "maxItems": 2,
                "description": "The parameter's values at y = 0 and y = 1.",
            },
            "db": {
                "title": "dB range [d0, d1]",
                "type": "array",
                "items": _number(),
                "minItems": 2,
                "maxItems": 2,
                "default": [-60, 0],
                "description": "Audio: the levels (dB full scale) mapped to 0 and 1, d0 < d1.",
            },
            "attack": {**seconds, "description": "Seconds: the envelope's rise time constant."},
            "release": {**seconds, "description": "Seconds: the envelope's fall time constant."},
            "initial": {
                "type": "number",
                "minimum": 0,
                "maximum": 1,
                "default": 0,
                "description": "Controllers: the value 0..1 before the first message.",
            },
        },
        "required": ["signal", "range"],
        "additionalProperties": False,
    }


def _op(op: str) -> dict:
    definition = type_def(op)
    props: dict = {"type": {"const": op}}
    for param in definition.params:
        kind = f"{param.kind}Param" if param.tracked else param.kind
        props[param.name] = {**_ref(kind), "description": param.help}
        if param.default is not None:
            props[param.name]["default"] = param.default
    for name, help_ in _TIME_HELP.items():
        props[name] = {**_ref("time"), "description": help_}
    props["heal"] = {
        "title": "heal [t0, t1]",
        "type": "array",
        "items": _ref("time"),
        "minItems": 2,
        "maxItems": 2,
        "description": "Seconds [t0, t1], t0 <= t1: the op heals (its progress falls to 0) "
        "from t0 to t1, and is absent from t1 on.",
    }
    props["hidden"] = {
        "type": "boolean",
        "default": False,
        "description": "marblevideo: true keeps the op in the file but leaves it out of every "
        "render (the designer's hide).",
    }
    return {
        "title": f"{op} op",
        "description": definition.help,
        "type": "object",
        "properties": props,
        "required": ["type", *(p.name for p in definition.params if not p.optional)],
        "additionalProperties": False,
        "dependentRequired": {"end": ["start"]},
    }


def _value_kinds() -> dict:
    """The kinds a keyable parameter may have (each also a keyframe track)."""
    return {
        "number": _number(),
        "positive": _number(exclusiveMinimum=0),
        "nonnegative": _number(minimum=0),
        "point": {
            "title": "point [x, y]",
            "type": "array",
            "items": _ref("number"),
            "minItems": 2,
            "maxItems": 2,
        },
        "color": {
            "title": COLOR_TITLE,
            "anyOf": [
                {"title": 'color "#rrggbb" or "#rgb"', "type": "string", "pattern": HEX_PATTERN},
                {"title": "CSS color name", "type": "string", "enum": list(CSS_NAMES)},
                {"title": "CSS color name (any case)", "type": "string", "pattern": NAME_PATTERN},
                {
                    "title": "color [r, g, b]",
                    "type": "array",
                    "items": {"type": "integer", "minimum": 0, "maximum": 255},
                    "minItems": 3,
                    "maxItems": 3,
                },
            ],
        },
    }


def _constant_kinds() -> dict:
    """The kinds that are never keyframe tracks, those some op's parameter uses."""
    positive_pair = {"type": "array", "items": _ref("positive"), "minItems": 2, "maxItems": 2}
    count_pair = {"type": "array", "items": _ref("count"), "minItems": 2, "maxItems": 2}
    constants = {
        "count": {
            "title": "count (a whole number >= 1)",
            "type": "integer",
            "minimum": 1,
            "maximum": MAX_COUNT,
        },
        "numberList": {
            "title": f"list of 1..{MAX_LIST} numbers",
            "type": "array",
            "items": _ref("number"),
            "minItems": 1,
            "maxItems": MAX_LIST,
        },
        "nonzeroList": {
            "title": f"list of 1..{MAX_LIST} non-zero numbers",
            "type": "array",
            "items": {**_ref("number"), "not": {"const": 0}},
            "minItems": 1,
            "maxItems": MAX_LIST,
        },
        "positivePair": {"title": "pair [a, b] of numbers > 0", **positive_pair},
        "countPair": {"title": "pair [columns, rows] of whole numbers >= 1", **count_pair},
        "colorList": {
            "title": f"list of 1..{MAX_LIST} colors",
            "type": "array",
            "items": _ref("color"),
            "minItems": 1,
            "maxItems": MAX_LIST,
        },
        "seed": {
            "title": "seed (a whole number 0..2^63-1)",
            "type": "integer",
            "minimum": 0,
            "maximum": 2**63 - 1,
        },
        "distribution": {"title": "distribution", "type": "string", "enum": ["uniform", "normal"]},
        "pointList": {
            "title": f"list of 2..{MAX_POINTS} points [x, y]",
            "type": "array",
            "items": _ref("point"),
            "minItems": 2,
            "maxItems": MAX_POINTS,
        },
        "timeList": {
            "title": f"list of 2..{MAX_POINTS} times (seconds)",
            "type": "array",
            "items": _ref("time"),
            "minItems": 2,
            "maxItems": MAX_POINTS,
        },
    }
    used = {p.kind for t in recipe_types() for p in type_def(t).params}
    return {kind: schema_ for kind, schema_ in constants.items() if kind in used}


def _ease() -> dict:
    unit = {"type": "number", "minimum": 0, "maximum": 1}
    return {
        "description": "Shapes the segment leaving this key (default linear).",
        "anyOf": [
            {"title": "ease name", "type": "string", "enum": list(EASE_NAMES)},
            {
                "title": "cubic-bezier [x1, y1, x2, y2]",
                "type": "array",
                "prefixItems": [unit, _number(), unit, _number()],
                "minItems": 4,
                "maxItems": 4,
            },
        ],
    }


def _op_dispatch() -> dict:
    """Any op: its ``type`` picks the op's own schema (``if``/``then``)."""
    return {
        "type": "object",
        "required": ["type"],
        "properties": {
            "type": {"title": "op type", "type": "string", "enum": list(recipe_types())},
        },
        "allOf": [
            {
                "if": {"properties": {"type": {"const": op}}, "required": ["type"]},
                "then": _ref(op),
            }
            for op in recipe_types()
        ],
    }


def _defs() -> dict:
    kinds = _value_kinds()
    return {
        **kinds,
        **_constant_kinds(),
        **{f"{kind}Track": _track(kind) for kind in kinds},
        **{f"{kind}Signal": _signal(kind) for kind in SIGNAL_KINDS},
        **{
            f"{kind}Param": {
                "anyOf": [
                    _ref(kind),
                    _ref(f"{kind}Track"),
                    *([_ref(f"{kind}Signal")] if kind in SIGNAL_KINDS else []),
                ]
            }
            for kind in kinds
        },
        "time": _number(),
        "ease": _ease(),
        **{op: _op(op) for op in recipe_types()},
        "op": _op_dispatch(),
    }


def _properties() -> dict:
    """The recipe's top-level fields."""
    return {
        "$schema": {"type": "string", "description": "Ignored; lets editors find this schema."},
        "description": {
            "type": "string",
            "maxLength": MAX_DESCRIPTION,
            "description": "One line on what the recipe makes; ignored by the renderer.",
        },
        "marblevideo": {
            "title": "recipe format version",
            "type": "integer",
            "const": 1,
            "default": 1,
            "description": "Format version; only 1 exists.",
        },
        "canvas": {
            "title": "size [W, H]",
            "type": "array",
            # each side 1/LIMIT at least: a frame's pixels per canvas unit stay finite
            # (a side of 5e-324 gave the SVG writer an infinite scale: the API fuzz)
            "items": _number(minimum=1e-30),  # 1 / LIMIT
            "minItems": 2,
            "maxItems": 2,
            "description": "Size of the design in canvas units (default: the input's size).",
        },
        "background": {
            **_ref("colorParam"),
            "default": "#ffffff",
            "description": 'The empty sheet, and the outside of the input for edges "background".',
        },
        "antialias": {
            "title": "antialias pattern",
            "type": "string",
            "enum": list(PATTERNS),
            "default": "rgss",
            "description": "Subsample pattern per output pixel.",
        },
        "edges": {
            "title": "edge mode",
            "type": "string",
            "enum": list(EDGE_MODES),
            "default": "clamp",
            "description": "What the input shows outside itself.",
        },
        "lattice": {
            "type": "boolean",
            "default": True,
            "description": "marblevideo: animated frames over an input interpolate the "
            "map from a walked lattice where it is smooth; false walks every subsample.",
        },
        "motion": motion_schema(),
        "ops": {
            "type": "array",
            "items": _ref("op"),
            "description": "Applied in order: ops[0] first, the last op is the most visible.",
        },
    }


def _build() -> dict:
    return {
        "$schema": DRAFT,
        "$id": SCHEMA_ID,
        "title": "marblevideo recipe",
        "description": "A marbling design: ops applied in order (ops[0] first). "
        "Canvas units, origin top-left, y down; angles in degrees; times in seconds.",
        "type": "object",
        "properties": _properties(),
        "required": ["ops"],
        "additionalProperties": False,
        "$defs": _defs(),
    }


@lru_cache(maxsize=1)
def _cached() -> dict:
    return _build()


def schema() -> dict:
    """The recipe JSON Schema (a fresh copy: callers may modify it)."""
    return copy.deepcopy(_cached())
