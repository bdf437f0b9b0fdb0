"""marblevideo: closed-form marbling for video, live sources and stills.

Implements the transforms of Lu, Jaffer, Jin, Zhao and Mao, "Mathematical
Marbling" (IEEE TVCG 2012) following shared/recipe-format.md. Data flows one
way: recipe -> per-frame parameters (:mod:`marblevideo.recipe.frame`) -> renderer
(OpenCL, with :mod:`marblevideo.reference` as the NumPy oracle) -> encoder.
"""

from marblevideo.bundled import samples_path
from marblevideo.errors import (
    DeviceError,
    MarbleError,
    MediaError,
    OutputExistsError,
    RecipeError,
    UsageError,
)
from marblevideo.recipe import Recipe, load_recipe, parse_recipe

__version__ = "0.1.0"


def __getattr__(name: str):
    """Lazy access to the parts that need OpenCL or PyAV (imported on first use)."""
    import importlib

    api = importlib.import_module("marblevideo.api")
    if name in ("Marbler", "render_image", "render_still", "render_video", "marbled_frames"):
        return getattr(api, name)
    raise AttributeError(f"module 'marblevideo' has no attribute {name!r}")


__all__ = [
    "DeviceError",
    "Marbler",
    "Recipe",
    "load_recipe",
    "marbled_frames",
    "parse_recipe",
    "render_image",
    "render_still",
    "render_video",
    "samples_path",
    "MarbleError",
    "MediaError",
    "OutputExistsError",
    "RecipeError",
    "UsageError",
    "__version__",
]
