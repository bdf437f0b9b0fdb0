"""Rough edges of the command line a new user meets (issue 34): what an unknown
output extension lists, interrupted banded stills, stills too big for their
format, a still of an animation that comes back to rest, and a blank sheet at
another aspect than its canvas. Each through the real command in a subprocess
(exit status and stderr are the contract) on the real OpenCL device."""

from __future__ import annotations

import pytest
from conftest import files, one_line

from marblevideo.media.formats import (
    EXTENSION_FORMATS,
    IMAGE_EXTENSIONS,
    VECTOR_EXTENSIONS,
    output_kinds,
)


@pytest.mark.parametrize("src, dst", [(None, "o.xyz"), (None, "o"), ("in.mp4", "o.avi")])
def test_an_unknown_extension_lists_every_kind(cli, tmp_path, src, dst):
    """Stills, video, sequences and vectors, as --help lists them (one table)."""
    proc = cli(*([src] if src else []), "--ops", "figure6", "-o", dst)
    assert proc.returncode == 2
    line = one_line(proc)
    assert "unknown output extension" in line
    for ext in (*IMAGE_EXTENSIONS, *EXTENSION_FORMATS, *VECTOR_EXTENSIONS, "name_%04d.png"):
        assert f" {ext}" in line, ext
    assert output_kinds() in " ".join(cli("--help").stdout.split())
    assert files(tmp_path) == []
