"""Names a package exports but imports on first use (PEP 562), so that importing
the package, or a light module of it, does not bring in NumPy, OpenCL or PyAV:
``marblevideo --version`` and ``--help`` load none of them."""

from __future__ import annotations

import importlib
from collections.abc import Callable


def lazy_names(package: str, table: dict[str, str]) -> Callable[[str], object]:
    """A module ``__getattr__`` for ``package``: each name of ``table`` (name ->
    the module that defines it) imported from its module when first asked for."""

    def __getattr__(name: str) -> object:
        if name in table:
            return getattr(importlib.import_module(table[name]), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    return __getattr__
