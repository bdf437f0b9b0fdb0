"""Recipe files the JSON Schema accepted before, by digest: reading one again skips
the schema (jsonschema's import and its walk of the document, together about
0.1 s of every command's start) and goes straight to the loader's own rules.

A digest is of the file's text together with what decides the schema's verdict:
the schema itself, marblevideo's version and the jsonschema installed (its
files' modification time), so an entry never outlives any of them. Only
acceptances are kept (a refused file is validated again, for its message), in
one file of the cache (:mod:`marblevideo.cache`), the :data:`KEEP` most recent.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import os
from functools import lru_cache
from pathlib import Path

from marblevideo.cache import cache_dir, write_atomically
from marblevideo.version import __version__

#: How many accepted files' digests are kept (the file is trimmed to these
#: when it holds twice as many).
KEEP = 512
_NAME = "accepted-recipes"


@lru_cache(maxsize=1)
def _verdict_key() -> bytes:
    """What the schema's verdict on a text depends on, besides the text."""
    from marblevideo.recipe.schema import schema

    spec = importlib.util.find_spec("jsonschema")  # found, not imported
    installed = os.stat(spec.origin).st_mtime_ns if spec and spec.origin else 0
    text = json.dumps(schema(), sort_keys=True)
    return f"{__version__}\0{installed}\0{text}\0".encode()


def text_digest(text: str) -> str:
    """The digest under which the schema's acceptance of ``text`` is kept."""
    return hashlib.sha256(_verdict_key() + text.encode("utf-8", "surrogatepass")).hexdigest()


def _file() -> Path | None:
    folder = cache_dir("recipes")
    return None if folder is None else folder / _NAME


def _kept(path: Path) -> list[str]:
    try:
        return path.read_text(encoding="ascii").split()
    except (OSError, UnicodeDecodeError):
        return []


def is_accepted(key: str) -> bool:
    """Whether the schema accepted the text of digest ``key`` before."""
    path = _file()
    return path is not None and key in _kept(path)


def remember_accepted(key: str) -> None:
    """Keep that the schema accepted the text of digest ``key``."""
    path = _file()
    if path is None:
        return
    try:  # one short line appended: concurrent writers do not tear each other's
        with open(path, "a", encoding="ascii") as f:
            f.write(key + "\n")
    except OSError:
        return
    kept = _kept(path)
    if len(kept) > 2 * KEEP:
        write_atomically(path, "".join(f"{k}\n" for k in kept[-KEEP:]).encode("ascii"))
