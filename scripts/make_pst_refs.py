"""Render the pst-marble designs of tests/data/pst/ with the real pst-marble and
store them beside their sources as the PNGs the tests compare against.

Needs latex, dvips (Debian: texlive-latex-base, texlive-pstricks) and
ghostscript. Each NAME.tex is a one-page document whose page is its
\\psMarble's size in TeX points (``unit=1pt``, raster mode ``oversample=1``);
ghostscript at 72.27 dpi makes one pixel of each point. Run from anywhere:

    python scripts/make_pst_refs.py [NAME ...]
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

DATA = Path(__file__).resolve().parent.parent / "tests" / "data" / "pst"
TOOLS = ("latex", "dvips", "gs")


def render(tex: Path, out: Path) -> None:
    """latex, dvips and ghostscript on ``tex`` in a scratch folder; the PNG to ``out``."""
    with tempfile.TemporaryDirectory() as scratch:
        work = Path(scratch)
        shutil.copy(tex, work / tex.name)
        run = {"cwd": work, "check": True, "capture_output": True}
        subprocess.run(["latex", "-interaction=nonstopmode", tex.name], **run)
        subprocess.run(["dvips", "-q", tex.with_suffix(".dvi").name, "-o", "page.ps"], **run)
        png = work / "page.png"
        gs = ["gs", "-q", "-dSAFER", "-dBATCH", "-dNOPAUSE", "-sDEVICE=png16m", "-r72.27"]
        subprocess.run([*gs, f"-sOutputFile={png}", "page.ps"], **run)
        shutil.copy(png, out)


def main(names: list[str]) -> int:
    missing = [t for t in TOOLS if shutil.which(t) is None]
    if missing:
        print(f"make_pst_refs: needs {', '.join(missing)} (texlive-pstricks, ghostscript)")
        return 1
    sources = [DATA / f"{n}.tex" for n in names] if names else sorted(DATA.glob("*.tex"))
    for tex in sources:
        out = tex.with_suffix(".png")
        render(tex, out)
        print(f"{out.relative_to(DATA.parent.parent.parent)}: {out.stat().st_size} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
