"""pst-marble designs as recipes: ``marblevideo import design.tex -o recipe.json``.

:func:`import_design` reads the first ``\\psMarble`` of a LaTeX or .pst file (its
size, ``background``, ``colors``, ``viscosity``, ``seed``, ``overscan``,
``actions`` and ``spractions``), or a file that is only a PostScript list of
actions (then the frame is pst-marble's for a square: -500..500), and returns
the recipe as JSON. The canvas is pst-marble's action frame: the larger side
is 1000 units times ``overscan``, y turned down (docs/pst-marble.md). An
action no op can say is refused naming it and its line and column (exit 2), and
so is a design that makes no ops, a LaTeX file with no ``\\psMarble``, and work
over the limits of :mod:`marblevideo.limits` (``MAX_DESIGN_BYTES``, the
interpreter's ``PS_*``, ``MAX_COUNT``, ``MAX_IMPORT_OPS``), before it is done.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

from marblevideo.errors import MediaError, UsageError
from marblevideo.limits import MAX_DESIGN_BYTES
from marblevideo.pstmarble.actions import ACTIONS, SPRAYS, Design, Frame, colour, colours, words
from marblevideo.pstmarble.latex import Marble, find_marble
from marblevideo.pstmarble.postscript import Interpreter, PsFault, describe, tokens
from marblevideo.recipe import parse_recipe

#: pst-marble's defaults (pst-marble.tex).
DEFAULTS = {
    "background": "[1 1 1]",
    "colors": "[0.275 0.569 0.796] [0.965 0.882 0.302] [0.176 0.353 0.129] "
    "[0.635 0.008 0.094] [0.078 0.165 0.518] [0.824 0.592 0.031] [0.059 0.522 0.392] "
    "[0.816 0.333 0.475] [0.365 0.153 0.435] [0.624 0.588 0.439]",
    "viscosity": "1000",
    "overscan": "1",
    "seed": "Mathematical Marbling",
    "actions": "0 0 36 colors 35 concentric-rings",
    "spractions": "",
    "shadings": "",
}
#: The op types an import makes that pour ink.
INK = ("drop", "spray")
#: A TeX control word: a file with one is LaTeX (or .pst), not a list of actions.
_TEX = re.compile(r"\\[A-Za-z@]+")


def _value(marble: Marble, key: str) -> tuple[str, int]:
    return marble.options.get(key, (DEFAULTS[key], -1))


def _evaluate(text: str, at: int, what: str):
    """The one value the PostScript ``text`` leaves."""
    ps = Interpreter({})
    ps.run(tokens(text, max(at, 0)))
    if len(ps.stack) != 1:
        raise PsFault(f"{what}: expected one value, got {len(ps.stack)}", max(at, 0))
    return ps.stack[0]


def _number(marble: Marble, key: str) -> float:
    """The number option ``key`` holds."""
    text, at = _value(marble, key)
    value = _evaluate(text, at, key)
    if not isinstance(value, float):
        raise PsFault(f"{key}: expected a number, got {describe(value)}", max(at, 0))
    return value


def _run(design: Design, text: str, at: int, table: dict) -> None:
    ps = Interpreter(words(design, table))
    ps.run(tokens(text, max(at, 0)))
    if ps.stack:
        raise PsFault(f"{len(ps.stack)} value(s) left over after the last action", max(at, 0))


def design_recipe(text: str) -> tuple[dict, list[tuple[int, str]]]:
    """The recipe (JSON) of a pst-marble design's text, and notes (offset, text) on
    what it changes; PsFault where it cannot be."""
    marble = find_marble(text)
    if marble is None:
        tex = _TEX.search(text)
        if tex is not None:
            raise PsFault(
                f"no \\psMarble in this file ({tex.group()} is LaTeX, not an action)", tex.start()
            )
        # a plain list of actions: pst-marble's frame of a square
        marble = Marble((-500.0, -500.0, 500.0, 500.0), {"actions": (text, 0)})
    x0, y0, x1, y1 = marble.corners
    overscan = _number(marble, "overscan")
    if not overscan > 0:
        raise PsFault(
            f"overscan must be > 0, got {overscan:g}", max(_value(marble, "overscan")[1], 0)
        )
    scale = 1000.0 * overscan / max(x1 - x0, y1 - y0)  # action units per unit
    viscosity = abs(_number(marble, "viscosity"))
    if viscosity == 0:
        raise PsFault("viscosity must not be 0", max(_value(marble, "viscosity")[1], 0))
    text_c, at_c = _value(marble, "colors")
    palette = _evaluate(f"[{text_c}]", at_c - 1, "colors")
    colours(palette, max(at_c, 0))  # checked once here
    design = Design(Frame(x0 * scale, y1 * scale), viscosity, palette, _value(marble, "seed")[0])
    shadings, at_s = _value(marble, "shadings")
    if shadings.strip():
        raise PsFault("shadings: no marblevideo op can say a shading", max(at_s, 0))
    _run(design, *_value(marble, "actions"), ACTIONS)
    _run(design, *_value(marble, "spractions"), SPRAYS)
    if not design.ops and not design.sprays:
        raise PsFault(
            "the design makes no ops (its actions are empty)", max(_value(marble, "actions")[1], 0)
        )
    background = colour(_evaluate(*_value(marble, "background"), "background"), 0)
    canvas = [round((x1 - x0) * scale, 6), round((y1 - y0) * scale, 6)]
    doc = {"marblevideo": 1, "canvas": canvas, "background": background,
           "ops": design.ops + design.sprays}  # fmt: skip
    return doc, design.notes


def animate(doc: dict, seconds: float) -> dict:
    """``doc`` with its ops one after another over ``seconds`` (a pst-marble design is
    a still; this makes it a video): the ink (drops, sprays) takes half the time and
    the motions the other half, each op of a kind an equal window (all of it when
    the design has one kind only)."""
    ops = doc["ops"]
    ink = [op["type"] in INK for op in ops]
    counts = {True: sum(ink), False: len(ops) - sum(ink)}
    kinds = sum(1 for c in counts.values() if c)
    t, timed = 0.0, []
    for op, is_ink in zip(ops, ink, strict=True):
        span = seconds / kinds / counts[is_ink]
        timed.append({**op, "start": round(t, 6), "end": round(t + span, 6)})
        t += span
    return {**doc, "ops": timed}


def _where(text: str, at: int) -> str:
    line = text.count("\n", 0, at) + 1
    return f"{line}:{at - (text.rfind(chr(10), 0, at) + 1) + 1}"


def import_design(path: str | Path, notify: Callable[[str], None] | None = None) -> dict:
    """The recipe of the pst-marble design in file ``path``, validated. UsageError
    (exit 2) naming the file, line and column of what cannot be imported;
    ``notify`` takes a line on each action imported as another model."""
    try:
        size = Path(path).stat().st_size
        if size > MAX_DESIGN_BYTES:
            raise UsageError(
                f"{path}: {size:,} bytes, over the limit of {MAX_DESIGN_BYTES:,} for a design "
                "(MAX_DESIGN_BYTES)"
            )
        text = Path(path).read_text(encoding="utf-8", errors="replace")
    except FileNotFoundError:
        raise UsageError(f"{path}: no such file") from None
    except OSError as exc:
        raise MediaError(f"{path}: cannot read: {exc.strerror}") from None
    try:
        doc, notes = design_recipe(text)
    except PsFault as fault:
        raise UsageError(f"{path}:{_where(text, fault.at)}: {fault}") from None
    except (ArithmeticError, ValueError) as exc:
        raise UsageError(f"{path}: cannot evaluate the design: {exc}") from None
    parse_recipe(doc, f"{path} (imported)")
    for at, note in notes if notify is not None else ():
        notify(f"{path}:{_where(text, at)}: note: {note}")
    return doc
