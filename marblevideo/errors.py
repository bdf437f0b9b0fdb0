"""One error hierarchy, rooted in :class:`MarbleError`.

Each error carries the process exit status the command line uses for it:
2 for a user's mistake (bad recipe, option or path), 1 for a runtime failure.
Like PyAV's errors, each also inherits from the matching builtin, so callers
may catch either (a :class:`RecipeError` is a ``ValueError``).
"""

from __future__ import annotations


class MarbleError(Exception):
    """Root of every error marblevideo raises on purpose."""

    exit_code = 1


class UsageError(MarbleError, ValueError):
    """A bad option, path or combination of options (exit status 2)."""

    exit_code = 2


class RecipeError(UsageError):
    """A recipe that breaks the format: ``FILE: json.path: what was expected, got what``."""

    def __init__(self, source: str, path: str, message: str):
        self.source = source
        self.path = path
        self.message = message
        where = f"{source}: {path}: " if path else f"{source}: "
        super().__init__(where + message)


class OutputExistsError(UsageError, FileExistsError):
    """The output exists and overwriting was not asked for (``-y``)."""


class MediaError(MarbleError, OSError):
    """An input that cannot be read or decoded, or an output that cannot be written (exit 1)."""


class DeviceError(MarbleError, RuntimeError):
    """No usable OpenCL device, or a kernel that failed to build or run (exit 1)."""


class Interrupted(MarbleError):
    """A run stopped by SIGINT (exit 130) or SIGTERM (exit 143)."""

    def __init__(self, signum: int = 2):
        self.exit_code = 128 + signum
        super().__init__("interrupted")
