"""The ``neurov pil`` subcommand's arguments (no heavy import here: the
parser is built for every ``neurov`` command)."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any, epilog: str) -> None:
    pil = sub.add_parser(
        "pil",
        help="processor in the loop: fly a scenario with its NN controller on an emulated Cortex-M7",
        description="Builds (on first use; then cached) the firmware image of the NN controller for QEMU's "
        "Cortex-M7 board mps2-an500, boots it under qemu-system-arm and flies the scenario: each control "
        "period the host sends the measurement over the board's UART and applies the board's answer. "
        "The same run with the float controller built for the host and neurov run's double run are its "
        "references. Writes what neurov run writes, plus pil.json. See docs/firmware.md.",
        epilog=epilog, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    pil.add_argument("scenario", metavar="SCENARIO", help="the scenario file, or a shipped scenario's name")
    pil.add_argument("--out", default=None, metavar="DIR", help="folder for the results")
    pil.add_argument("--image", default=None, metavar="ELF", help="a prebuilt image (default: build it)")
    pil.add_argument("--duration", type=float, default=None, metavar="SECONDS",
                     help="fly only this long (default: the scenario's duration)")
    pil.add_argument("--fault", action="append", default=[], metavar="KIND@SECONDS",
                     help="inject a fault into that step's frame: nan, range, garble or drop (repeatable)")
    pil.add_argument("--watchdog-ms", type=int, default=1000, metavar="MS",
                     help="the board's safe command after this long without a frame (default 1000)")
    pil.add_argument("--check", action="store_true",
                     help="exit with status 1 unless the run is within both tolerances")
    pil.set_defaults(usage_of=pil)


def run(args: argparse.Namespace) -> int:
    if args.watchdog_ms < 1:
        args.usage_of.error("--watchdog-ms must be >= 1")
    import signal

    from neurov.pil.command import check, run_pil

    def stop(signum: int, _frame: Any) -> None:  # SIGTERM unwinds as Ctrl-C does: the board is stopped
        error = KeyboardInterrupt("stopped by SIGTERM")
        error.signum = signum  # type: ignore[attr-defined]
        raise error

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        pil = run_pil(args.scenario, args.out, image=args.image, faults=args.fault, duration=args.duration,
                      watchdog_ms=args.watchdog_ms)
    finally:
        signal.signal(signal.SIGTERM, previous)
    if args.check:
        check(pil)
    return 0
