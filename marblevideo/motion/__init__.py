"""Revision 4's ``motion``: what moves in front of the camera stirs the ink.

:class:`MotionSpec` (the recipe's settings), :class:`MotionTracker` (frames in,
stroke ops out), :class:`StirredRecipe` (a recipe with ``motion`` -> the recipe to
render at each frame's time, and its take) and :func:`luma` (the one luma every
caller analyses). See docs/recipe-format.md, "motion".
"""

from marblevideo.motion.flow import luma
from marblevideo.motion.spec import MotionSpec
from marblevideo.motion.stirred import StirredRecipe
from marblevideo.motion.tracker import MotionTracker

__all__ = ["MotionSpec", "MotionTracker", "StirredRecipe", "luma"]
