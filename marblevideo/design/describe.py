"""``GET /api/ops``: the op types as the page needs them, derived from the op
definitions (:mod:`marblevideo.ops`) and the recipe schema, so the page names
no op type of its own.

The answer maps each type a recipe's ``ops`` may hold (the ops in type-code
order, the drop layouts after the ink family) to:

- ``help``, ``family`` (the ops' module; ``layouts`` for a layout), ``ink``,
  ``layout`` (expanded into drops at load);
- ``params``: name, ``kind`` (the schema's ``$defs``), ``title`` of the kind,
  ``help``, ``optional``, ``default``, ``keyable`` (may be keyframes),
  ``timing`` (``start``/``end``, which every op takes), ``handle`` (a point the
  page shows as a handle), ``choices`` (a kind that is one of some strings),
  ``units`` for points (canvas units: origin top-left, y down), and for
  numbers ``slider`` (the law), ``units`` and ``range`` (the law as data:
  :data:`marblevideo.ops.base.SLIDER_SPECS`, evaluated by ``range.js``);
- ``tools``: the designer's tools that draw it (name, ``gesture``, ``make``,
  ``label``: :mod:`marblevideo.ops.gestures`, evaluated by ``tools.js``; ``key``
  and ``hint``, the tool's shortcut key and one-line hint,
  :data:`marblevideo.ops.gestures.TOOL_KEYS`), and
  ``settings``, the numbers those tools ask for beside them.
"""

from __future__ import annotations

import dataclasses
from functools import lru_cache

from marblevideo.ops import LAYOUTS, REGISTRY
from marblevideo.ops.base import SLIDER_SPECS, Param, slider_spec
from marblevideo.ops.gestures import TOOL_KEYS
from marblevideo.recipe.schema import schema

#: ``start`` and ``end``, every op's: seconds, constants (no slider).
TIMING = tuple(
    Param(name, "nonnegative", "", "time", optional=True, keyable=False)
    for name in ("start", "end")
)


def describe_param(p: Param, defs: dict, op_schema: dict) -> dict:
    """One parameter of an op (see the module docstring)."""
    kind = defs.get(p.kind, {})
    out = {
        "name": p.name,
        "kind": p.kind,
        "title": kind.get("title", p.kind),
        "help": p.help or op_schema["properties"][p.name].get("description", ""),
        "optional": p.optional,
        "default": p.default,
        "keyable": p.tracked,
        "timing": p in TIMING,
        "handle": p.kind == "point" and p.handle,
        "slider": None if p in TIMING else p.slider,
    }
    if "enum" in kind:
        out["choices"] = list(kind["enum"])
    if p.kind in ("point", "pointList"):
        out["units"] = "canvas units"
    if p.slider is not None:
        spec = slider_spec(p)
        out["units"] = SLIDER_SPECS[p.slider]["units"]
        out["range"] = {k: v for k, v in spec.items() if k != "units"}
    return out


def _tool(definition, t) -> dict:
    name = t.name or definition.type
    key, hint = TOOL_KEYS.get(name, ("", ""))
    out = {"name": name, "gesture": t.gesture, "make": t.make, "label": t.label}
    return {**out, "key": key, "hint": hint}


def _tools(definition) -> list[dict]:
    return [_tool(definition, t) for t in definition.tools]


def _describe(definition, family: str, ink: bool, defs: dict) -> dict:
    op_schema = defs[definition.type]
    params = [describe_param(p, defs, op_schema) for p in (*definition.params, *TIMING)]
    settings = [dataclasses.asdict(s) for s in getattr(definition, "settings", ())]
    out = {"help": definition.help, "family": family, "ink": ink, "params": params}
    return {**out, "tools": _tools(definition), "settings": settings}


@lru_cache(maxsize=1)
def describe_ops() -> dict:
    """``GET /api/ops``: every type a recipe's ``ops`` may hold (module docstring)."""
    defs = schema()["$defs"]
    ops = {t: _describe(d, d.family, d.ink, defs) for t, d in REGISTRY.items()}
    layouts = {
        t: {**_describe(d, "layouts", True, defs), "layout": True} for t, d in LAYOUTS.items()
    }
    ink = {t: v for t, v in ops.items() if v["family"] == "ink"}
    return {**ink, **layouts, **{t: v for t, v in ops.items() if t not in ink}}


@lru_cache(maxsize=1)
def describe_motion() -> tuple[dict, ...]:
    """The recipe's ``motion`` fields as the page edits them (``GET /api/motion``'s
    ``fields``): name, ``help``, ``default`` (a pair for ``width``), ``integer``,
    and the schema's ``minimum`` and ``maximum`` where it gives them."""
    from marblevideo.recipe.motion import FIELDS, motion_schema

    props = motion_schema()["properties"]
    fields = []
    for name, default, text in FIELDS:
        prop = props[name]
        bounds = prop.get("items", prop)
        field = {
            "name": name,
            "help": text,
            "default": list(default) if isinstance(default, tuple) else default,
            "integer": prop.get("type") == "integer",
        }
        for key in ("minimum", "maximum"):
            if key in bounds:
                field[key] = bounds[key]
        fields.append(field)
    return tuple(fields)
