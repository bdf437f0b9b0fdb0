"""The NumPy float64 reference of the recipe contract: the oracle every kernel
test compares against (the walk, bilinear sampling, and whole renders)."""

from marblevideo.reference.sampling import sample_bilinear
from marblevideo.reference.shading import ink_colors, render, shade
from marblevideo.reference.walk import contains, forward, inverse, inverse_walk, jacobian

__all__ = [
    "contains",
    "forward",
    "ink_colors",
    "inverse",
    "inverse_walk",
    "jacobian",
    "render",
    "sample_bilinear",
    "shade",
]
