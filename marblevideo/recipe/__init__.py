"""The recipe: its model and validation (:mod:`~marblevideo.recipe.load`), its
JSON Schema (:mod:`~marblevideo.recipe.schema`), keyframe tracks, antialiasing
patterns, and what one frame of it is (:mod:`~marblevideo.recipe.frame`: the
values at one instant, and the geometry of a render).

The model's names are imported on first use (:mod:`marblevideo.lazy`), so that a
light submodule (the frame's constants, the keyframes) does not bring in the
loader, jsonschema and NumPy."""

from __future__ import annotations

from typing import TYPE_CHECKING

from marblevideo.lazy import lazy_names

if TYPE_CHECKING:
    from marblevideo.recipe.load import Op, Recipe, load_recipe, parse_recipe

__all__ = ["Op", "Recipe", "load_recipe", "parse_recipe"]
__getattr__ = lazy_names(__name__, dict.fromkeys(__all__, "marblevideo.recipe.load"))
