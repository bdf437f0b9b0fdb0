"""The command line: ``marblevideo [INPUT] --ops RECIPE -o OUTPUT`` (:mod:`.render`),
``devices`` and ``schema`` (:mod:`.info`), ``presets`` and ``ops`` (:mod:`.catalog`),
``live`` (:mod:`.live`), ``batch`` (:mod:`.batch`), ``design`` (:mod:`.design`),
``midi`` (:mod:`.controllers`), ``import`` (:mod:`.importer`: a pst-marble design),
``export`` (:mod:`.export`: a recipe as a program for ffmpeg).

Exit status: 0 done, 1 runtime failure, 2 usage or recipe error, 130/143
interrupted (SIGINT/SIGTERM), 141 standard output closed early (SIGPIPE's, as
``marblevideo presets --paths | head`` ends). Errors are one line on stderr.
"""

from __future__ import annotations

import os
import signal
import sys

from marblevideo.errors import Interrupted


def _devices(argv: list[str]) -> int:
    from marblevideo.cli.info import devices_command

    return devices_command(argv)


def _schema(argv: list[str]) -> int:
    from marblevideo.cli.info import schema_command

    return schema_command(argv)


def _presets(argv: list[str]) -> int:
    from marblevideo.cli.catalog import presets_command

    return presets_command(argv)


def _ops(argv: list[str]) -> int:
    from marblevideo.cli.catalog import ops_command

    return ops_command(argv)


def _design(argv: list[str]) -> int:
    from marblevideo.cli.design import design_command

    return design_command(argv)


def _batch(argv: list[str]) -> int:
    from marblevideo.cli.batch import batch_command

    return batch_command(argv)


def _live(argv: list[str]) -> int:
    from marblevideo.cli.live import run_live

    return run_live(argv)


def _import(argv: list[str]) -> int:
    from marblevideo.cli.importer import import_command

    return import_command(argv)


def _export(argv: list[str]) -> int:
    from marblevideo.cli.export import export_command

    return export_command(argv)


def _midi(argv: list[str]) -> int:
    from marblevideo.cli.controllers import midi_command

    return midi_command(argv)


COMMANDS = {
    "devices": _devices,
    "schema": _schema,
    "presets": _presets,
    "ops": _ops,
    "live": _live,
    "batch": _batch,
    "design": _design,
    "midi": _midi,
    "import": _import,
    "export": _export,
}


def _on_sigterm(signum, frame):
    raise Interrupted(signum)


def run(argv: list[str]) -> int:
    """Dispatch a command line; raises MarbleError for the caller to report."""
    if argv and argv[0] in COMMANDS:
        return COMMANDS[argv[0]](argv[1:])
    from marblevideo.cli.render import render_command

    return render_command(argv)


def main(argv: list[str] | None = None) -> int:
    """The ``marblevideo`` command: its exit status (errors as one line on stderr)."""
    from marblevideo.cli.arguments import reported

    argv = sys.argv[1:] if argv is None else list(argv)
    previous = signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        status = reported("marblevideo", lambda: run(argv))
        sys.stdout.flush()  # here, where a closed pipe is caught, not at exit
        return status
    except BrokenPipeError:  # the reader left (| head): quietly, as the Python docs do
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # the flush at exit writes nowhere
        return 128 + signal.SIGPIPE
    finally:
        signal.signal(signal.SIGTERM, previous)
