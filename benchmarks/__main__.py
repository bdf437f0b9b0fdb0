"""``python -m benchmarks [PART ...] [options]``, from the checkout: the parts
named (the package's docstring says what each measures), one Markdown report on
standard output. ``python -m benchmarks compare BASE [HEAD]`` runs the end-to-end
commands of two commits side by side (benchmarks/compare.py); ``python -m
benchmarks fuzz --minutes N [HARNESS ...]`` runs the fuzz harnesses for N minutes
each with fresh seeds (benchmarks/fuzz.py). ``lanes-child`` is
one process of ``lanes`` (internal)."""

from __future__ import annotations

import argparse
import importlib

from . import __doc__ as PACKAGE_DOC
from .common import animated12, header, make_clip, turn12

#: what ``python -m benchmarks`` runs with no part named
DEFAULT_PARTS = ("table1", "e2e", "numpy", "memory")


#: part name -> the (module, function, arguments) it runs, in order; arguments
#: names one of :func:`arguments`' forms (the function runs once per tuple)
PARTS = {
    "table1": [("kernel", "table1", "device")],
    "pst": [("kernel", "pst_row", "device")],
    "numpy": [("kernel", "numpy_baseline", "device")],
    "bullseye": [("kernel", "bullseye", "device")],
    "series": [("kernel", "series", "device")],
    "animations": [("kernel", "animations", "device")],
    "busy": [("kernel", "busy", "device")],
    "svg": [("svg", "svg_part", "device")],
    "lanes": [("lanes", "lanes", "device")],
    "e2e": [("e2e", "e2e", "lengths")],
    "bounds": [("e2e", "bounds", "lengths")],
    "memory": [("e2e", "memory", "memory")],
    "cluster": [("cluster_bench", "cluster_part", "cluster")],
    "lattice": [
        ("lattice_bench", "lattice_part", "animated"),
        ("lattice_bench", "cost_part", "cost"),
    ],
    "live1080": [("lattice_bench", "live1080_part", "device")],
    "strokes": [("stroke_bench", "strokes_part", "device")],
    "pst-stir": [("pst_bench", "pst_stir_part", "device")],
    "kernels": [("kernels_bench", "kernels_part", "profile")],
    "motion-e2e": [("motion_e2e", "motion_e2e", "lengths")],
}


def arguments(form: str, args: argparse.Namespace) -> list[tuple]:
    """The argument tuples of a part's function: one call per tuple."""
    return {
        "device": lambda: [(args.device,)],
        "lengths": lambda: [(args.device, s) for s in args.seconds],  # one per clip length
        "memory": lambda: [(args.device, args.long)],
        "cluster": lambda: [(args.device, make_clip, animated12)],
        "animated": lambda: [(args.device, animated12)],
        "cost": lambda: [(args.device, animated12, turn12)],
        "profile": lambda: [(args.device, args.profile)],
        "compare": lambda: [(args.device, args.parts[1:], s, args.rounds) for s in args.seconds],
    }[form]()


def function(module: str, name: str):
    """``benchmarks.MODULE.NAME``, imported when its part runs (cluster needs the
    extra 'ray', svg cairosvg)."""
    return getattr(importlib.import_module(f".{module}", __package__), name)


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m benchmarks",
        description=PACKAGE_DOC.splitlines()[0],
        epilog=f"parts: {' '.join(PARTS)} (default: {' '.join(DEFAULT_PARTS)})",
    )
    p.add_argument("parts", nargs="*", default=list(DEFAULT_PARTS), metavar="PART")
    p.add_argument("--device", help="OpenCL device (see `marblevideo devices`)")
    p.add_argument(
        "--long", type=int, default=600, help="seconds of the long memory clip (default 600)"
    )
    p.add_argument(
        "--seconds",
        type=int,
        nargs="+",
        default=[4, 20],
        metavar="S",
        help="lengths of the e2e, bounds and compare clips in seconds (default 4 20)",
    )
    p.add_argument(
        "--profile",
        action="store_true",
        help="kernels: time each kernel on a profiling queue",
    )
    p.add_argument("--rounds", type=int, default=5, help="compare: paired rounds (default 5)")
    p.add_argument(
        "--minutes", type=float, default=1.0, help="fuzz: minutes per harness (default 1)"
    )
    return p


def main(argv: list[str] | None = None) -> None:
    args = parser().parse_args(argv)
    if args.parts == ["lanes-child"]:
        return function("lanes", "lanes_child")(args.device)
    if args.parts[:1] == ["fuzz"]:
        from .fuzz import HARNESSES
        from .fuzz import main as fuzz

        names = [p.replace("-", " ").replace("HTTP API", "HTTP API") for p in args.parts[1:]]
        if args.minutes <= 0 or any(n not in HARNESSES for n in names):
            known = ", ".join(n.replace(" ", "-") for n in HARNESSES)
            parser().error(f"fuzz [HARNESS ...] --minutes N (> 0); harnesses: {known}")
        header()
        raise SystemExit(fuzz(args.minutes, names))
    if args.parts[:1] == ["compare"]:
        if not 2 <= len(args.parts) <= 3 or args.rounds < 1:
            parser().error("compare BASE [HEAD]: one or two commits, --rounds at least 1")
        header()
        for call in arguments("compare", args):
            function("compare", "compare")(*call)
        return None
    unknown = [p for p in args.parts if p not in PARTS]
    if unknown:
        parser().error(f"unknown part(s) {', '.join(unknown)}; parts: {' '.join(PARTS)}")
    header()
    for part in args.parts:
        for module, name, form in PARTS[part]:
            for call in arguments(form, args):
                function(module, name)(*call)


if __name__ == "__main__":
    main()
