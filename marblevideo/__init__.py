"""marblevideo: closed-form marbling for video, live sources and stills.

Implements the transforms of Lu, Jaffer, Jin, Zhao and Mao, "Mathematical
Marbling" (IEEE TVCG 2012) following shared/recipe-format.md. Data flows one
way: recipe -> per-frame parameters (:mod:`marblevideo.frame`) -> renderer
(OpenCL, with :mod:`marblevideo.reference` as the NumPy oracle) -> encoder.
"""

from marblevideo.errors import (
    DeviceError,
    MarbleError,
    MediaError,
    OutputExistsError,
    RecipeError,
    UsageError,
)

__version__ = "0.1.0"

__all__ = [
    "DeviceError",
    "MarbleError",
    "MediaError",
    "OutputExistsError",
    "RecipeError",
    "UsageError",
    "__version__",
]
