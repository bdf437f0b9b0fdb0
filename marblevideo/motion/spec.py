"""The ``motion`` settings, :class:`MotionSpec` (defined beside the loader, in
:mod:`marblevideo.recipe.motion`, which builds it from a recipe; the contract's
ranges are checked there, by the recipe's schema)."""

from marblevideo.recipe.motion import MotionSpec

__all__ = ["MotionSpec"]
