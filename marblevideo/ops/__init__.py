"""The op registry: every op type, defined once (see :mod:`marblevideo.ops.base`).

Families register in order, and an op's type code (its place in the kernel's
dispatch) is its place in :data:`REGISTRY`.
"""

from __future__ import annotations

from dataclasses import replace

from marblevideo.ops import ink, jiggle, rotation, shear, stroke
from marblevideo.ops.base import (
    COLOR_SLOTS,
    EXAMPLE_CANVAS,
    KINDS,
    NUMERIC_KINDS,
    PSTRIDE,
    OpDef,
    Param,
    identity,
    slider_range,
)
from marblevideo.ops.layouts import LAYOUTS, LayoutDef, expand

FAMILIES = (ink, shear, rotation, jiggle, stroke)


def _register(families) -> dict[str, OpDef]:
    registry: dict[str, OpDef] = {}
    for module in families:
        family = module.__name__.rsplit(".", 1)[1]
        for op in module.OPS:
            if op.type in registry:
                raise ValueError(f"op type {op.type!r} defined twice")
            registry[op.type] = replace(op, family=family, code=len(registry))
    return registry


#: Op type -> its definition, in type-code order.
REGISTRY: dict[str, OpDef] = _register(FAMILIES)


def op_def(type_: str) -> OpDef:
    """The definition of op type ``type_``; ValueError for an unknown one."""
    try:
        return REGISTRY[type_]
    except KeyError:
        raise ValueError(f"unknown op type {type_!r}") from None


def op_types() -> tuple[str, ...]:
    """Every op type, in type-code order."""
    return tuple(REGISTRY)


def type_def(type_: str) -> OpDef | LayoutDef:
    """The definition of an op type or of a drop layout (expanded at load)."""
    if type_ in LAYOUTS:
        return LAYOUTS[type_]
    return op_def(type_)


def recipe_types() -> tuple[str, ...]:
    """Every type a recipe's ``ops`` may hold: the ops, then the layouts."""
    return (*REGISTRY, *LAYOUTS)


def is_ink(type_: str) -> bool:
    """Whether ops of ``type_`` are ink (end the walk with their colour)."""
    return op_def(type_).ink


__all__ = [
    "COLOR_SLOTS",
    "EXAMPLE_CANVAS",
    "FAMILIES",
    "LAYOUTS",
    "LayoutDef",
    "expand",
    "recipe_types",
    "type_def",
    "KINDS",
    "NUMERIC_KINDS",
    "PSTRIDE",
    "REGISTRY",
    "OpDef",
    "Param",
    "identity",
    "is_ink",
    "op_def",
    "op_types",
    "slider_range",
]
