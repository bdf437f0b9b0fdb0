"""marblevideo: closed-form marbling for video, live sources and stills.

Implements the transforms of Lu, Jaffer, Jin, Zhao and Mao, "Mathematical
Marbling" (IEEE TVCG 2012) following docs/recipe-format.md. Data flows one
way: recipe (:mod:`marblevideo.recipe`, its ops defined in :mod:`marblevideo.ops`)
-> per-frame parameters (:mod:`marblevideo.recipe.frame`) -> renderer
(:mod:`marblevideo.opencl`, with :mod:`marblevideo.reference` as the NumPy
oracle) -> encoder (:mod:`marblevideo.media`).
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
from marblevideo.version import __version__

#: The parts that need OpenCL or PyAV, imported on first use: name -> module.
_LAZY = {
    "Marbler": "marblevideo.marbler",
    "render_image": "marblevideo.api",
    "render_still": "marblevideo.api",
    "render_video": "marblevideo.api",
    "marbled_frames": "marblevideo.api",
    "run_batch": "marblevideo.scale.batch",
    "render_split": "marblevideo.scale.segmented",
}


def __getattr__(name: str):
    """Lazy access to :data:`_LAZY`'s names."""
    import importlib

    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'marblevideo' has no attribute {name!r}")


__all__ = [
    "DeviceError",
    "Marbler",
    "Recipe",
    "load_recipe",
    "marbled_frames",
    "parse_recipe",
    "render_image",
    "render_split",
    "render_still",
    "render_video",
    "run_batch",
    "samples_path",
    "MarbleError",
    "MediaError",
    "OutputExistsError",
    "RecipeError",
    "UsageError",
    "__version__",
]
