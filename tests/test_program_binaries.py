"""Built programs kept between processes (marblevideo.opencl.binaries): a second
renderer of the same program loads the kept binary and draws the same pixels; a
binary that is damaged or refused is built again from source, never handed on."""

from __future__ import annotations

import os

import numpy as np
import pytest
from helpers import ROOT, fresh_renderer

from marblevideo.marbler import Marbler
from marblevideo.opencl.binaries import KEEP, load_binary, store_binary

pytestmark = pytest.mark.tier("fast")

RECIPE = ROOT / "samples" / "figure6.json"


@pytest.fixture
def kept(tmp_path, monkeypatch):
    """The folder of the kept programs, empty, for this test alone."""
    monkeypatch.setenv("MARBLEVIDEO_CACHE", str(tmp_path))
    return tmp_path / "programs"


def _draw() -> np.ndarray:
    return Marbler(str(RECIPE), fresh_renderer()).render(None, None, (40, 24))


def test_a_second_renderer_loads_the_kept_binary(kept):
    first = _draw()
    (entry,) = kept.glob("*.bin")
    os.utime(entry, (0, 0))
    inode = entry.stat().st_ino
    again = _draw()
    assert entry.stat().st_ino == inode  # not written again: built from the binary
    assert entry.stat().st_mtime > 0  # marked as used
    assert np.array_equal(first, again)


@pytest.mark.parametrize("damage", ["truncated", "foreign"])
def test_a_damaged_or_refused_binary_is_built_again(kept, damage):
    """A truncated file fails its digest (PoCL would crash on it); a binary with a
    good digest that the driver refuses (here: not a binary) is built from source."""
    first = _draw()
    (entry,) = kept.glob("*.bin")
    if damage == "truncated":
        entry.write_bytes(entry.read_bytes()[:5000])
    else:
        store_binary(entry.stem, b"not a program binary" * 50)
    assert np.array_equal(_draw(), first)
    assert load_binary(entry.stem) not in (None, b"not a program binary" * 50)


def test_only_the_most_recently_used_are_kept(kept):
    for i in range(KEEP + 3):
        store_binary(f"{i:064x}", b"x")
        os.utime(kept / f"{i:064x}.bin", ns=(i, i))
    store_binary("f" * 64, b"y")
    names = {p.stem for p in kept.glob("*.bin")}
    assert len(names) == KEEP and "f" * 64 in names
    assert f"{0:064x}" not in names and f"{KEEP + 2:064x}" in names
