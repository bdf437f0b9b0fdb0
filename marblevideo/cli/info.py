"""``marblevideo devices`` (and ``--check``) and ``marblevideo schema``."""

from __future__ import annotations

import json

from marblevideo.cli.arguments import Parser
from marblevideo.errors import UsageError


def devices_command(argv: list[str]) -> int:
    from marblevideo.opencl.device import describe_devices, list_devices

    p = Parser(
        prog="marblevideo devices",
        description="List OpenCL devices; with --check, test each one against the NumPy reference.",
        epilog="--check renders a fixed set of small recipes (every op type, "
        "antialiasing pattern and edges mode, over an input and on a blank sheet, a "
        "long recipe, I420 frames, reused maps) on each device and compares them with "
        "the NumPy reference. Exit status: 0 every checked device agrees, 1 one "
        "disagrees or fails, 2 usage error.",
    )
    p.add_argument(
        "--check", action="store_true", help="render test recipes on each device and compare"
    )
    p.add_argument("--device", help="check only this device: P:D or a name (with --check)")
    p.add_argument("-v", "--verbose", action="store_true", help="--check: every case's detail")
    args = p.parse_args(argv)
    if not args.check:
        if args.device or args.verbose:
            raise UsageError(f"{'--device' if args.device else '--verbose'} goes with --check")
        print(describe_devices())
        return 0 if list_devices() else 1
    from marblevideo.opencl.selfcheck import run_check

    return run_check(args.device, verbose=args.verbose)


def schema_command(argv: list[str]) -> int:
    from marblevideo.recipe.schema import schema

    Parser(prog="marblevideo schema", description="Print the recipe JSON Schema.").parse_args(argv)
    print(json.dumps(schema(), indent=2))
    return 0
