"""The recipe: its model and validation (:mod:`~marblevideo.recipe.load`), its
JSON Schema (:mod:`~marblevideo.recipe.schema`), keyframe tracks, antialiasing
patterns, and what one frame of it is (:mod:`~marblevideo.recipe.frame`: the
values at one instant, and the geometry of a render)."""

from marblevideo.recipe.load import Op, Recipe, load_recipe, parse_recipe
from marblevideo.recipe.schema import schema

__all__ = ["Op", "Recipe", "load_recipe", "parse_recipe", "schema"]
