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
from marblevideo.lazy import lazy_names
from marblevideo.version import __version__

#: The parts that need NumPy, jsonschema, OpenCL or PyAV, imported on first use
#: (``import marblevideo`` and ``marblevideo --version`` load none of them): name -> module.
_LAZY = {
    "Recipe": "marblevideo.recipe",
    "load_recipe": "marblevideo.recipe",
    "parse_recipe": "marblevideo.recipe",
    "Marbler": "marblevideo.marbler",
    "render_image": "marblevideo.api",
    "render_still": "marblevideo.api",
    "render_video": "marblevideo.api",
    "marbled_frames": "marblevideo.api",
    "run_batch": "marblevideo.scale.batch",
    "render_split": "marblevideo.scale.segmented",
}


__getattr__ = lazy_names(__name__, _LAZY)


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
