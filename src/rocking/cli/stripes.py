"""``rocking stripes``: multiple-stripe fragility of cylinders under an ensemble of motions.

At each stripe intensity every motion is analysed once; the share exceeding each limit state
is fitted by a lognormal CDF by binomial maximum likelihood (:mod:`rocking.spectra.stripes`).
Printed as labelled tables (medians as PGA/(g tan α) and PGA [g] with their intervals, the
motions' processing, each stripe's count) or as JSON (``--json``); ``-o`` writes CSV or JSON.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from ..spectra.accuracy import PRESETS
from . import _common, _human

EXAMPLES = """\
  rocking stripes --R 6 --tan-alpha 0.2 --ensemble results/motions/elcentro.nc --mode 3d \\
      --limit-states overturning,tilt:1/3 -o stripes.csv
  rocking stripes --R 2,6 --tan-alpha 0.2 --ensemble results/motions/elcentro.nc --stripes 20
  rocking stripes --height 6 --diameter 0.66 --record el-centro-1940 --intensities 1.5,2,3,4"""

DEFAULT_STRIPES = 40
"""Default number of stripes (:data:`rocking.spectra.stripes.DEFAULT_STRIPES`, checked equal
in the tests; the library is not imported to print the help)."""

SUMMARY = ("R", "limit_state", "median", "median_lo", "median_hi", "median_pga_g", "beta",
           "beta_lo", "beta_hi", "status", "reason")
STRIPES = ("R", "limit_state", "intensity", "pga_g", "n_exceeding", "n_motions", "fraction")


def add_parser(subparsers) -> None:
    """Register the ``stripes`` subcommand."""
    p = _common.add_command(
        subparsers, "stripes", examples=EXAMPLES,
        help="multiple-stripe fragility: share of motions exceeding at fixed intensities",
        description="Multiple-stripe fragility of cylinders: every motion (all motions of "
        "--ensemble, or the one motion given) is analysed once at each stripe intensity "
        "PGA/(g tan alpha); the share exceeding each limit state is fitted by a lognormal "
        "CDF by binomial maximum likelihood. Prints the median (with its 95 %% interval) "
        "and beta per R and limit state, then the stripes; NaN with a reason where the fit "
        "has no finite maximum.",
    )
    _common.add_cylinders(p)
    p.add_argument("--limit-states", default="overturning,tilt:1/3",
                   help="comma-separated: overturning, tilt:<r> (theta > r alpha); "
                   "'default' = the seven goals of Fig 10")
    g = p.add_argument_group("stripes (PGA/(g tan alpha))")
    g.add_argument("--stripes", type=int, default=DEFAULT_STRIPES,
                   help="number of stripes, geometric in (--lower, --upper]")
    g.add_argument("--lower", type=float, default=1.0, help="start of the stripes (excluded)")
    g.add_argument("--upper", type=float, default=20.0, help="last stripe")
    g.add_argument("--intensities", type=_common.floats, default=None,
                   help="explicit stripes, comma-separated and increasing (overrides "
                   "--stripes/--lower/--upper)")
    p.add_argument("--accuracy", choices=sorted(PRESETS), default="default",
                   help="ODE tolerances preset (the scan settings do not apply)")
    p.add_argument("--omega-n", type=float, default=None,
                   help="contact spring frequency of mode 3d-damped [rad/s] (default: 2000)")
    p.add_argument("--zeta", type=float, default=None,
                   help="contact damping ratio of mode 3d-damped [-] (default: 5)")
    _common.add_motion_source(p)
    _common.add_processing(p)
    p.add_argument("-o", "--out", type=Path, default=None,
                   help="also write the results to this .csv (the fits; the stripes go to "
                   "<stem>_stripes.csv) or .json (both)")
    _human.add_json(p, "the fits and stripes (the document --out x.json writes)")
    _common.add_quiet(p)
    p.set_defaults(func=run)


def _motions(args):
    """Every motion of --ensemble (or the one named by --motion), else the one record."""
    if args.ensemble is not None and args.motion is None:
        from ..motions.ensemble_io import load_ensemble

        if any(getattr(args, k, None) is not None
               for k in ("rotation", "fc_hz", "mw", "max_duration")) or args.highpass != "none":
            raise ValueError("--rotation, --highpass, --fc-hz, --mw and --max-duration process "
                             "a record; the motions of --ensemble are used as stored")
        return load_ensemble(args.ensemble)
    return [_common.motion_from_args(args, default_record="el-centro-1940")]


def tables(results):
    """(fits, stripes) as pandas tables over all R, with the columns of SUMMARY / STRIPES."""
    import pandas as pd

    fits, stripes = [], []
    for r in results:
        fits.append(r.summary_frame().assign(R=r.R))
        stripes.append(r.to_frame().assign(R=r.R))
    return (pd.concat(fits)[list(SUMMARY)].reset_index(drop=True),
            pd.concat(stripes)[list(STRIPES)].reset_index(drop=True))


def _motions_line(motions, args) -> tuple[str, str]:
    """(motion, processing) lines: the one motion, or the ensemble's count and its record."""
    stored = args.ensemble is not None
    if len(motions) == 1:
        return _identity_line(motions[0]), _human.processing(motions[0], stored)
    names = ", ".join(m.name for m in motions[:3]) + (", …" if len(motions) > 3 else "")
    kinds = {_human.processing(m, stored) for m in motions}
    return (f"{len(motions)} motions of {args.ensemble} ({names})",
            "; ".join(sorted(kinds)) if len(kinds) <= 2
            else f"{len(kinds)} different processings (see --json)")


def _identity_line(motion) -> str:
    from ..motions.identity import identity

    return identity(motion)["processing"]


def human(fits, stripes, motions, args, accuracy: str, x) -> str:
    """The fits and the stripes for people: medians as PGA/(g tan α) and PGA [g] with their
    95 % intervals, β, status; then each stripe's count of motions exceeding."""
    ta = args.tan_alpha
    motion_line, processing_line = _motions_line(motions, args)
    head = _human.block([
        ("motion" if len(motions) == 1 else "motions", motion_line),
        ("processing", processing_line),
        ("cylinders", f"mode {args.mode}, {_human.slenderness(ta)}"),
        ("stripes", f"{len(x)} intensities PGA/(g tan α) = {_human.num(x[0])}–"
                    f"{_human.num(x[-1])} (PGA {_human.num(x[0] * ta)}–{_human.num(x[-1] * ta)}"
                    f" g); accuracy {accuracy}"),
    ])
    rows, notes = [], []
    for r in fits.itertuples(index=False):
        rows.append([_human.num(r.R), r.limit_state, _human.num(r.median),
                     _human.interval(r.median_lo, r.median_hi),
                     _human.num(r.median_pga_g), _human.num(r.beta),
                     _human.interval(r.beta_lo, r.beta_hi), r.status])
        if r.status != "ok":
            notes.append(f"  R = {_human.num(r.R)} m, {r.limit_state}: {r.status}: {r.reason}")
    fit_table = _human.table(["R [m]", "limit state", "median PGA/(g tan α) [-]", "95 %",
                              "median PGA [g]", "β [-]", "95 %", "status"], rows,
                             left=(1, 7))
    srows = [[_human.num(r.R), r.limit_state, _human.num(r.intensity), _human.num(r.pga_g),
              f"{r.n_exceeding} of {r.n_motions}", _human.num(r.fraction, 3)]
             for r in stripes.itertuples(index=False)]
    stripe_table = _human.table(["R [m]", "limit state", "PGA/(g tan α) [-]", "PGA [g]",
                                 "exceeding", "fraction [-]"], srows, left=(1,))
    return "\n".join([head, "", "lognormal fit (binomial maximum likelihood) per R and limit "
                       "state:", fit_table, *notes, "", "stripes:", stripe_table])


def run(args) -> int:
    """Analyse every stripe and motion, fit, and write; returns 0."""
    from .. import _json
    from ..dynamics.bodies import Cylinder
    from ..motions.identity import identity
    from ..spectra.accuracy import get_accuracy
    from ..spectra.limit_states import parse_limit_states
    from ..spectra.stripes import stripe_fragility, stripe_intensities
    from ..units import CSV_FLOAT_FORMAT, QUANTITIES, header

    out = args.out
    _common.resolve_body(args, "stripes", many=True)
    if out is not None:
        _common.check_output(out, (".csv", ".json"))
    states = parse_limit_states(args.limit_states, sort=False)
    x = (stripe_intensities(args.stripes, args.lower, args.upper) if args.intensities is None
         else args.intensities)
    acc = get_accuracy(args.accuracy)
    motions = _motions(args)
    bodies = [Cylinder(R, args.tan_alpha) for R in args.R]  # bad R fails before any analysis
    t0 = time.perf_counter()
    results = [stripe_fragility(b, motions, states, mode=args.mode, intensities=x,
                                accuracy=acc, omega_n=args.omega_n, zeta=args.zeta,
                                progress=not args.quiet) for b in bodies]
    seconds = time.perf_counter() - t0
    fits, stripes = tables(results)
    doc = {"motions": [m.name for m in motions], "mode": args.mode,
           "tan_alpha": args.tan_alpha, "limit_states": [s.name for s in states],
           "accuracy": acc.to_dict(), "intensities": [float(v) for v in results[0]
                                                      .intensities],
           "seconds": seconds,
           "units": {k: QUANTITIES[k][1] for k in (*SUMMARY, *STRIPES)
                     if k in QUANTITIES and QUANTITIES[k][1]},
           "fits": fits.to_dict(orient="records"),
           "stripes": stripes.to_dict(orient="records"),
           # what was done to each motion (the command line's and the workflow's defaults
           # differ: docs/cli.md)
           "processing": {m.name: identity(m)["processing"] for m in motions}}
    if out is not None:
        out.parent.mkdir(parents=True, exist_ok=True)
    if out is not None and out.suffix.lower() == ".csv":
        with _common.replacing(out) as tmp:
            fits.rename(columns=header).to_csv(tmp, index=False,
                                               float_format=CSV_FLOAT_FORMAT)
        with _common.replacing(out.with_name(f"{out.stem}_stripes.csv")) as tmp:
            stripes.rename(columns=header).to_csv(tmp, index=False,
                                                  float_format=CSV_FLOAT_FORMAT)
    elif out is not None:
        with _common.replacing(out) as tmp:
            _json.write(tmp, doc, indent=1)
    if args.json:
        print(_json.dumps(doc, indent=1))
    else:
        print(human(fits, stripes, motions, args, acc.name, results[0].intensities))
        if out is not None:
            print(f"written: {out}" + (f", {out.with_name(f'{out.stem}_stripes.csv')}"
                                       if out.suffix.lower() == ".csv" else ""))
    if not args.quiet:
        n = sum(r.n_analyses for r in results)
        print(f"{len(results)} body(ies) x {len(motions)} motion(s), {n} analyses, "
              f"{seconds:.2f} s", file=sys.stderr)
    return 0
