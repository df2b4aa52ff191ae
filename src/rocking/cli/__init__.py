"""The ``rocking`` command line: one subcommand per module in :mod:`rocking.cli`.

Each ``rocking.cli.<name>`` module defines ``add_parser(subparsers)`` (registering its
options and ``set_defaults(func=run)``) and ``run(args) -> int``, and imports the library
only inside ``run``. Only the subcommand being run (or asked for help) is imported, so
``rocking --help`` loads neither numpy nor the dynamics engine.

Every user error (a missing or unreadable file, a bad value, an unwritable output) ends the
command with one line ``rocking <command>: error: ...`` on stderr and exit code 2; Ctrl-C
with one line and exit code 130; a traceback means a bug.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys
from collections.abc import Iterable, Sequence

from rocking import __version__

SUBCOMMANDS: dict[str, str] = {
    "simulate": "one rocking analysis (free vibration or ground motion) -> history + summary",
    "motions": "record + synthetic RDK pairs -> ensemble file (.nc)",
    "spectra": "critical PGA/(g tan alpha) of cylinders vs R (performance spectrum)",
    "stripes": "multiple-stripe fragility: share of motions exceeding at fixed intensities",
    "risk": "mean annual frequency of each limit state under a hazard curve",
    "portfolio": "every column of an inventory: fragility from a study's surface, lambda, rank",
    "verify": "a run's tables against the committed gallery (results/paper), table by table",
}
"""Subcommand → one-line summary (shown by ``rocking --help`` without importing it)."""

EPILOG = """examples:
  rocking simulate --R 6 --tan-alpha 0.2 --record el-centro-1940 --pga-ratio 2 -o run
  rocking motions --record el-centro-1940 -n 10 -o results/motions/elcentro.nc
  rocking spectra --R 1,2,6 --tan-alpha 0.2 --record el-centro-1940 -o spectrum.csv
  rocking spectra --height 6 --diameter 0.66 --record el-centro-1940
  rocking stripes --R 6 --tan-alpha 0.2 --ensemble results/motions/elcentro.nc --stripes 40
  rocking risk --fragility results/elcentro/stripe_fragility.csv --hazard 1e-4,2.5 --json
  rocking portfolio --surface results/paper/elcentro --inventory columns.csv --hazard h.csv
  rocking verify results --against results/paper

Commands print labelled text with units (and the motion's processing); --json prints JSON
for scripts. `rocking COMMAND --help` lists a command's options with their defaults."""


def build_parser(commands: Iterable[str] | None = None) -> argparse.ArgumentParser:
    """The argument parser; ``commands`` get their full options (default: all)."""
    full = set(SUBCOMMANDS if commands is None else commands)
    parser = argparse.ArgumentParser(
        prog="rocking", epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Seismic rocking of free-standing cylinders (3D) and blocks (2D).",
    )
    parser.add_argument("--version", action="version", version=f"rocking {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, summary in SUBCOMMANDS.items():
        if name in full:
            importlib.import_module(f"rocking.cli.{name}").add_parser(sub)
        else:
            sub.add_parser(name, help=summary)
    return parser


CLI_NAMES = ("dt", "mw", "fc_hz", "pga_ratio", "scale", "max_duration", "stop_at", "rtol", "theta0",
             "phi_dot0", "omega_n", "zeta", "duration", "tan_alpha", "rotation", "highpass")
"""Library parameters that are a command-line option of the same name (``fc_hz`` is
``--fc-hz``): a library message naming one is shown with the option's spelling."""

_PARAMETER = re.compile(rf"(?<![\w.-])({'|'.join(CLI_NAMES)})(?=[=)]| \()")
_MODEL_2D = re.compile(r"model='2d' \(the 2D model under the ([xy]) component\)")


def cli_spelling(message: str) -> str:
    """A library message in the command line's words: ``mw (or fc_hz)`` becomes
    ``--mw (or --fc-hz)``, ``model='2d'`` under the x component ``--mode 2d-x``."""
    message = _MODEL_2D.sub(r"--mode 2d-\1", message)
    return _PARAMETER.sub(lambda m: "--" + m.group(1).replace("_", "-"), message)


def error_message(exc: BaseException) -> str:
    """One line for a user error: the file and the problem for OS errors, library
    parameters spelled as the options that set them."""
    if isinstance(exc, OSError) and exc.filename is not None:
        reason = exc.strerror or type(exc).__name__
        return f"{exc.filename}: {reason}"
    if isinstance(exc, KeyError) and exc.args:
        return cli_spelling(str(exc.args[0]))
    return cli_spelling(str(exc))


INTERRUPTED = ("interrupted; partial results are discarded (a command writes its outputs "
               "only once its work is done)")
"""What Ctrl-C prints (exit code 130): the commands write their outputs after the work,
through :func:`rocking.cli._common.replacing`, so nothing half-written is left."""


def interrupted(exc: BaseException) -> bool:
    """True for Ctrl-C: a KeyboardInterrupt, or an error it caused on its way up (numba's
    dispatcher turns one raised inside a compiled kernel into a chain of SystemError)."""
    seen: set[int] = set()
    node: BaseException | None = exc
    while node is not None and id(node) not in seen:
        if isinstance(node, KeyboardInterrupt):
            return True
        seen.add(id(node))
        node = node.__cause__ or node.__context__
    return False


BROKEN_PIPE = 141
"""Exit code when stdout's reader closed the pipe (128 + SIGPIPE, what a shell reports)."""


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 ok, 1 failed analysis, 2 user error,
    130 interrupted, 141 stdout closed by its reader)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((a for a in argv if a in SUBCOMMANDS), None)
    parser = build_parser([] if command is None else [command])
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except BrokenPipeError:
        # the reader of stdout went away (`rocking spectra --json | head`): stop quietly, as
        # Unix tools do, with stdout pointed at /dev/null so that the exit flush is silent too
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return BROKEN_PIPE
    except (KeyboardInterrupt, Exception) as exc:
        if interrupted(exc):
            print(f"rocking {args.command}: {INTERRUPTED}", file=sys.stderr)
            return 130
        if not isinstance(exc, (ValueError, OSError, KeyError)):
            raise
        # Bad input is reported as one line naming the field or file; tracebacks are for bugs.
        print(f"rocking {args.command}: error: {error_message(exc)}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    raise SystemExit(main())
