"""``marblevideo presets`` (the bundled recipes) and ``marblevideo ops`` (the op
types and their parameters, from the op registry): what a recipe can start from
and what it can say. Listings are wrapped to the terminal's width."""

from __future__ import annotations

import json
import shutil
import sys
import textwrap
from pathlib import Path

from marblevideo.bundled import preset_path, presets, samples_dir
from marblevideo.cli.arguments import Parser
from marblevideo.errors import MediaError, UsageError
from marblevideo.ops import LAYOUTS, REGISTRY, Param, recipe_types, type_def
from marblevideo.recipe.faults import did_you_mean
from marblevideo.recipe.schema import SIGNAL_KINDS, schema

#: How each parameter kind reads in a listing.
KIND_LABELS = {
    "number": "number",
    "positive": "number > 0",
    "nonnegative": "number >= 0",
    "point": "[x, y]",
    "color": "color",
    "count": "integer >= 1",
    "numberList": "[numbers]",
    "nonzeroList": "[non-zero numbers]",
    "positivePair": "[a, b] > 0",
    "countPair": "[columns, rows]",
    "colorList": "[colors]",
    "seed": "integer >= 0",
    "distribution": "uniform|normal",
    "pointList": "[[x, y], ...]",
    "timeList": "[seconds]",
}
PROGRESS = {"linear": "{} * p", "sqrt": "{} * sqrt(p)"}


def _width() -> int:
    return max(40, min(shutil.get_terminal_size((100, 24)).columns, 120))


def _rows(rows: list[tuple[str, ...]], indent: str = "") -> str:
    """Columns padded to their widest cell, the last wrapped to the terminal (under
    itself, or on lines of its own when too little room is left)."""
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    lead = len(indent) + sum(w + 2 for w in widths)
    room = _width() - lead
    out = []
    for *cells, last in rows:
        head = indent + "".join(c.ljust(w + 2) for c, w in zip(cells, widths, strict=True))
        if room >= 30:
            lines = textwrap.wrap(last, room) or [""]
            out.append(head + lines[0])
            out += [" " * lead + line for line in lines[1:]]
        else:
            out.append(head.rstrip())
            out += textwrap.wrap(last, _width(), initial_indent=indent + "    ",
                                 subsequent_indent=indent + "    ")  # fmt: skip
    return "\n".join(out)


# --------------------------------------------------------------------------- presets


def _description(path: Path) -> str:
    try:
        return str(json.loads(path.read_text(encoding="utf-8")).get("description", ""))
    except (OSError, ValueError) as exc:
        raise MediaError(f"cannot read preset {path}: {exc}") from None


def presets_command(argv: list[str]) -> int:
    p = Parser(
        prog="marblevideo presets",
        description="List the bundled recipes (presets), or print one's JSON.",
        epilog="--ops NAME renders a preset wherever no file NAME exists. To start a recipe "
        "of your own from one: marblevideo presets swirl > my.json",
    )
    p.add_argument("name", nargs="?", help="print this preset's JSON (its file as it is)")
    p.add_argument("--paths", action="store_true", help="show each preset's file")
    args = p.parse_args(argv)
    found = presets()
    if not found:
        raise MediaError(f"no presets in {samples_dir()} (an installation without its samples)")
    if args.name is not None:
        path = preset_path(args.name)
        if path is None:
            hint = did_you_mean(args.name, found, n=3)
            raise UsageError(
                f"presets: no preset {args.name!r}{hint}; there are {', '.join(found)}"
            )
        if args.paths:
            print(path)
        else:
            sys.stdout.write(path.read_text(encoding="utf-8"))
        return 0
    rows = [(name, _description(path)) for name, path in found.items()]
    if args.paths:
        rows = [
            (name, str(path), text) for (name, text), path in zip(rows, found.values(), strict=True)
        ]
    print(_rows(rows))
    return 0


# --------------------------------------------------------------------------- ops


def _default(param: Param) -> str:
    if param.default is not None:
        return f"= {json.dumps(param.default)}"
    return "optional" if param.optional else "required"


def _param_rows(params) -> list[tuple[str, str, str, str]]:
    return [(p.name, KIND_LABELS[p.kind], _default(p), p.help) for p in params]


def _overview() -> str:
    note = (
        "Every op also takes `start` and `end` (seconds, optional) and `hidden` (true keeps "
        "it in the file, out of every render). The numbers, points and "
        'colors of ops may be keyframe tracks {"keys": [{"t": ..., "v": ...}, ...]}; lists, '
        "counts and the layouts' fields are constants. `marblevideo ops TYPE` shows one in "
        "full; docs/recipe-format.md gives the formulas."
    )
    groups = (
        ("ops", REGISTRY),
        ("drop layouts (expanded into drops when the recipe loads)", LAYOUTS),
    )
    parts = [textwrap.fill(note, _width())]
    for title, types in groups:
        parts.append(f"{title}:")
        for type_ in types:
            definition = type_def(type_)
            header = textwrap.fill(f"{type_}: {definition.help}", _width(), initial_indent="  ",
                                   subsequent_indent=" " * (len(type_) + 4))  # fmt: skip
            parts.append(header + "\n" + _rows(_param_rows(definition.params), "    "))
    return "\n\n".join(parts)


def _animates(param) -> str:
    """How a parameter may change in time, for its help line."""
    if not param.tracked:
        return ""
    signal = " May follow a signal (audio.low, osc:/...)." if param.kind in SIGNAL_KINDS else ""
    return " May be a keyframe track." + signal


def _detail(type_: str) -> str:
    definition = type_def(type_)
    fields = schema()["$defs"][type_]["properties"]
    rows = [
        (name, kind, default, help_ + _animates(p))
        for p, (name, kind, default, help_) in zip(
            definition.params, _param_rows(definition.params), strict=True
        )
    ]
    rows += [
        (name, "seconds", "optional", fields[name]["description"]) for name in ("start", "end")
    ]
    rows.append(("heal", "[t0, t1] seconds", "optional", fields["heal"]["description"]))
    rows.append(("hidden", "true/false", "false", fields["hidden"]["description"]))
    if type_ in LAYOUTS:
        notes = [
            "A drop layout: it stands for drops, expanded when the recipe loads. Its fields are "
            "constants; with start and end, each drop gets its own equal part of the window, in "
            "order."
        ]
    else:
        laws = ", ".join(PROGRESS[law].format(name) for name, law in definition.progress)
        if definition.travels:
            laws = (
                "the stylus travels the path (step k of n acts by clamp(p n - k, 0, 1)); "
                "with times, the stylus is where the gesture was at t"
            )
        notes = [
            f"Progress p (0 -> 1 from start to end): {laws or 'none'}. "
            "With heal [t0, t1], p is multiplied by h(t), 1 before t0 falling to 0 at t1."
        ]
        if definition.ink:
            notes.append("Ink: a point inside it takes its color (the walk ends there).")
    width = _width()
    return "\n".join(
        [
            textwrap.fill(f"{type_}: {definition.help}", width),
            "",
            _rows(rows, "  "),
            "",
            *(textwrap.fill(note, width) for note in notes),
            "Example (JSON):",
            "  " + json.dumps(definition.example),
        ]
    )


def ops_command(argv: list[str]) -> int:
    p = Parser(
        prog="marblevideo ops",
        description="List the op types a recipe's `ops` may hold, with their parameters.",
    )
    p.add_argument("type", nargs="?", help="show this op type in full")
    args = p.parse_args(argv)
    if args.type is None:
        print(_overview())
        return 0
    if args.type not in recipe_types():
        hint = did_you_mean(args.type, recipe_types())
        raise UsageError(f"ops: unknown op type {args.type!r}{hint}; see marblevideo ops")
    print(_detail(args.type))
    return 0
