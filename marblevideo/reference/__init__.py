"""The NumPy float64 reference of the recipe contract: the oracle every kernel
test compares against (the walk, bilinear sampling, and whole renders)."""

from marblevideo.reference.shading import (
    contains,
    forward,
    ink_colors,
    inverse,
    inverse_walk,
    jacobian,
    render,
    sample_bilinear,
    shade,
)

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
