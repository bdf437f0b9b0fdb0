"""``marblevideo live``'s controller options (``--osc``, ``--midi``,
``--automation``) and ``marblevideo midi`` (:mod:`marblevideo.controllers`)."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from marblevideo.cli.arguments import Parser
from marblevideo.errors import UsageError


def add_controller_arguments(p: argparse.ArgumentParser, automation: bool = True) -> None:
    g = p.add_argument_group("controllers (signals osc:/ADDRESS, midi:cc:CH:N, midi:note:CH:N)")
    g.add_argument(
        "--osc", metavar="[HOST:]PORT", help="listen for OSC over UDP (host 127.0.0.1 by default)"
    )
    g.add_argument(
        "--midi",
        nargs="?",
        const="",
        metavar="PORT",
        help="take MIDI from input PORT (default: the first; see `marblevideo midi`); "
        "needs the extra marblevideo[midi]",
    )
    if not automation:
        return
    g.add_argument(
        "--automation",
        metavar="FILE",
        help="when the session ends, write the recipe with each controller signal "
        "replaced by keyframes of what it did, and its motion strokes as stroke ops "
        "(renders anywhere)",
    )


def check_controllers(args, recipe) -> None:
    """Refuse bad controller options before anything opens (UsageError, exit 2);
    a note when the recipe uses controllers no option feeds."""
    from marblevideo.controllers.midi import mido_backend, pick_port
    from marblevideo.controllers.osc import parse_endpoint
    from marblevideo.media.output import check_output

    if args.osc is not None:
        parse_endpoint(args.osc)
    sources = {t.signal.source for _, t in recipe.signal_uses() if t.signal.controller}
    if args.midi is not None or "midi" in sources:
        mido_backend()  # names the extra when it is missing
    if args.midi is not None:
        pick_port(args.midi or None)  # the port exists (it opens once the session is built)
    if getattr(args, "automation", None) is not None:
        for option, other in (("--ops", args.ops), ("-o", args.output)):
            if other is not None and Path(other).resolve() == Path(args.automation).resolve():
                raise UsageError(f"--automation: {args.automation} is also {option}; name another")
        check_output(args.automation, args.overwrite)
    for source, option in (("osc", args.osc), ("midi", args.midi)):
        if source in sources and option is None and not args.quiet:
            print(
                f"marblevideo: the recipe's {source.upper()} signals stay at their initial "
                f"values without --{source}",
                file=sys.stderr,
                flush=True,
            )


def start_controllers(args, session) -> list:
    """Open the listeners ``args`` asks for, feeding ``session.controllers``; them
    (each has ``close()``)."""
    from marblevideo.controllers.midi import MidiInput
    from marblevideo.controllers.osc import OscListener, parse_endpoint

    opened = []
    try:
        if args.osc is not None:
            host, port = parse_endpoint(args.osc)
            osc = OscListener(session.controllers, host, port).start()
            opened.append(osc)
            print(f"osc: {osc.address[0]}:{osc.port}", flush=True)
        if args.midi is not None:
            midi = MidiInput(session.controllers, args.midi or None)
            opened.append(midi)
            if not args.quiet:
                print(f"marblevideo: MIDI from {midi.name}", file=sys.stderr, flush=True)
    except BaseException:
        close_all(opened)
        raise
    return opened


def close_all(listeners: list) -> None:
    for listener in listeners:
        listener.close()


def report_controllers(args, session) -> None:
    """One line of what the listeners received (with --osc or --midi, unless -q)."""
    if args.quiet or (args.osc is None and args.midi is None):
        return
    c = session.controllers.counts
    print(
        f"marblevideo: controllers: {c['messages']} messages ({c['unknown']} to names the "
        f"recipe does not use), {c['dropped']} dropped",
        file=sys.stderr,
        flush=True,
    )


def write_take(args, session) -> None:
    """``--automation``: the take, from the session's start to now (with the motion
    strokes made as ``stroke`` ops, :meth:`~marblevideo.live.session.LiveSession.take_document`)."""
    from marblevideo.controllers.automation import write_automation

    end = time.monotonic() - session.started
    doc = session.take_document()
    write_automation(args.automation, doc, session.controllers, end, args.overwrite)
    if not args.quiet:
        print(f"marblevideo: wrote {args.automation}", file=sys.stderr, flush=True)


def midi_command(argv: list[str]) -> int:
    """``marblevideo midi``: the MIDI input ports, one a line."""
    from marblevideo.controllers.midi import input_names

    Parser(
        prog="marblevideo midi",
        description="List MIDI input ports (for `marblevideo live --midi PORT`); "
        "needs the extra marblevideo[midi].",
    ).parse_args(argv)
    names = input_names()
    for name in names:
        print(name)
    if not names:
        print("marblevideo: no MIDI input ports", file=sys.stderr)
    return 0
