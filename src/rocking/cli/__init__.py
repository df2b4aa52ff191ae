"""The ``rocking`` command line: one subcommand per module in :mod:`rocking.cli`.

Each ``rocking.cli.<name>`` module defines ``add_parser(subparsers)`` (registering its
options and ``set_defaults(func=run)``) and ``run(args) -> int``. Subcommands are imported
only when listed here, so a broken optional stage never hides the others' help.
"""

from __future__ import annotations

import argparse
import importlib
import sys

SUBCOMMANDS = ("simulate", "motions", "spectra")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rocking",
        description="Seismic rocking of free-standing cylinders (3D) and blocks (2D).",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for name in SUBCOMMANDS:
        try:
            module = importlib.import_module(f"rocking.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"rocking.cli.{name}":
                raise
            continue
        module.add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except ValueError as exc:
        # Bad input is reported as one line naming the field; tracebacks are for bugs.
        print(f"rocking {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    raise SystemExit(main())
