"""``rocking stripes``: multiple-stripe fragility of cylinders under an ensemble of motions.

At each stripe intensity every motion is analysed once; the share exceeding each limit state
is fitted by a lognormal CDF by binomial maximum likelihood (:mod:`rocking.fragility.stripes`).
Printed as labelled tables (medians as PGA/(g tan α) and PGA [g] with their intervals, the
motions' processing, each stripe's count) or as JSON (``--json``); ``-o`` writes CSV or JSON.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

from rocking.cli import _common, _human
from rocking.spectra.accuracy import DEFAULT_UPPER, PRESETS

EXAMPLES = """\
  rocking stripes --R 6 --tan-alpha 0.2 --ensemble results/motions/elcentro.nc --mode 3d \\
      --limit-states overturning,tilt:1/3 -o stripes.csv
  rocking stripes --R 2,6 --tan-alpha 0.2 --ensemble results/motions/elcentro.nc --stripes 20
  rocking stripes --height 6 --diameter 0.66 --record el-centro-1940 --intensities 1.5,2,3,4"""

DEFAULT_STRIPES = 40
"""Default number of stripes (:data:`rocking.fragility.stripes.DEFAULT_STRIPES`, checked equal
in the tests; the library is not imported to print the help)."""

DEFAULT_REFINE = 8
"""Default refinement budget (:data:`rocking.fragility.stripes.DEFAULT_REFINE`, likewise)."""

DEFAULT_JITTER = 0.02
"""Default jitter of each analysis in ln s (:data:`rocking.fragility.stripes.JITTER`,
likewise)."""

COMPONENT_NAMES = ("vector_peak", "rotd100", "rotd50", "geometric_mean", "larger")
"""The components of :data:`rocking.motions.measures.COMPONENTS` (held equal by a test)."""


def measure_help() -> str:
    """Help of --measure and --component: the registries of :mod:`rocking.motions.measures`
    in words (tests/test_components.py holds them equal; the library is not imported)."""
    return ("intensity measure of the stripes: pga [g] (default), pgv [m/s] or sa:<T in s> "
            "[g] (e.g. sa:1.0), in the --component (" + ", ".join(COMPONENT_NAMES) + "; "
            "default vector_peak): every motion is scaled so that its measure equals the "
            "stripe's; the stripes are then that measure over g tan alpha")


SUMMARY = ("R", "limit_state", "median", "median_lo", "median_hi", "median_pga_g", "beta",
           "beta_lo", "beta_hi", "status", "reason", "measure", "component", "median_im",
           "median_p05",
           "median_p95", "bracket_lo", "bracket_hi", "n_refined")
STRIPES = ("R", "limit_state", "intensity", "pga_g", "im", "n_exceeding", "n_motions",
           "fraction")


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
                   help="comma-separated: overturning, tilt:<r> (theta > r alpha), "
                   "sliding:<mu> (the body slides in contact: needs more friction than mu "
                   "in a run that does not overturn); "
                   "'default' = the seven goals of Fig 10")
    p.add_argument("--mu", type=float, default=None,
                   help="friction coefficient of the support [-], > 0: adds the fragility "
                   "of sliding:<mu> (a run that does not overturn needs more friction than mu "
                   "while in contact)")
    g = p.add_argument_group("stripes (PGA/(g tan alpha))")
    g.add_argument("--stripes", type=int, default=DEFAULT_STRIPES,
                   help="number of stripes, geometric from --lower to --upper (both "
                   "included: the list of a study's stripes.intensity {start, stop, num, "
                   "spacing: log})")
    g.add_argument("--lower", type=float, default=1.0, help="first stripe (included)")
    g.add_argument("--upper", type=float, default=DEFAULT_UPPER,
                   help="last stripe (included; default: the search's bound %(default)s)")
    g.add_argument("--intensities", type=_common.floats, default=None,
                   help="explicit stripes, comma-separated and increasing (overrides "
                   "--stripes/--lower/--upper)")
    g.add_argument("--measure", default="pga", help=measure_help())
    # the registry's first, the vector peak: the library's DEFAULT_COMPONENT (a test holds it)
    g.add_argument("--component", default=COMPONENT_NAMES[0], choices=COMPONENT_NAMES,
                   type=str.lower,
                   help="horizontal component of --measure (default: %(default)s)")
    g.add_argument("--jitter", type=float, default=DEFAULT_JITTER,
                   help="half-width w in ln intensity of each analysis's jitter about its "
                   "stripe (drawn from the analysis's identity): the share exceeding then "
                   "estimates the motions' mean local exceedance probability; 0 analyses "
                   "the stripes exactly (default: %(default)s)")
    g.add_argument("--refine", type=int, default=DEFAULT_REFINE,
                   help="most stripes added per (R, limit state) where the fit separates "
                   "(bisection in ln intensity), 0 for none (default: %(default)s)")
    g.add_argument("--bootstrap", type=int, default=0,
                   help="resamples of the motions for the 90 %% interval of the median "
                   "(median_p05, median_p95), 0 for none (default)")
    p.add_argument("--accuracy", choices=sorted(PRESETS), default="default",
                   help="ODE tolerances preset (the scan settings do not apply)")
    _common.add_contact(p)
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
        from rocking.motions.ensemble_io import load_ensemble

        if any(getattr(args, k, None) is not None
               for k in ("rotation", "fc_hz", "mw", "max_duration")) or args.highpass != "none":
            raise ValueError("--rotation, --highpass, --fc-hz, --mw and --max-duration process "
                             "a record; the motions of --ensemble are used as stored")
        return load_ensemble(args.ensemble)
    return [_common.motion_from_args(args, default_record="el-centro-1940")]


def tables(results, boot=None):
    """(fits, stripes) as pandas tables over all R, with the columns of SUMMARY / STRIPES.

    ``results``: per R, the StripeFragility of each limit state (refined); ``boot``: per
    (R index, limit state) the resampled medians, or None."""

    import pandas as pd

    from rocking.fragility.stripes import bootstrap_interval

    fits, stripes = [], []
    for i, per_state in enumerate(results):
        for ls, r in per_state.items():
            f = r.summary_frame().assign(R=r.R, median_p05=math.nan, median_p95=math.nan)
            if boot is not None:
                lo, hi = bootstrap_interval(boot[(i, ls)])
                f = f.assign(median_p05=lo * r.scale, median_p95=hi * r.scale)
            fits.append(f)
            stripes.append(r.to_frame().assign(R=r.R))
    return (pd.concat(fits)[list(SUMMARY)].reset_index(drop=True),
            pd.concat(stripes)[list(STRIPES)].reset_index(drop=True))


def _refined(result, body, motions, args, acc) -> dict:
    """Per limit state, the fit refined where separated (--refine stripes at most)."""
    from rocking.fragility.stripes import refine_stripes, stripe_analyzer

    analyze = stripe_analyzer(body, motions, list(result.limit_states), mode=args.mode,
                              accuracy=acc, omega_n=args.omega_n, zeta=args.zeta,
                              measure=args.measure, component=args.component,
                              jitter=args.jitter)
    note = None if args.quiet else (lambda line: print(line, file=sys.stderr))
    return {ls: refine_stripes(result, ls, analyze, args.refine, log=note)
            for ls in result.limit_states}


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
    from rocking.motions.identity import identity

    return identity(motion)["processing"]


def human(fits, stripes, motions, args, accuracy: str, x, unit: str = "g") -> str:
    """The fits and the stripes for people: medians as PGA/(g tan α) and PGA [g] with their
    95 % intervals, β, status; then each stripe's count of motions exceeding."""
    ta = args.tan_alpha
    motion_line, processing_line = _motions_line(motions, args)
    from rocking.motions.measures import Measure

    name = Measure.of(args.measure).label
    scale = Measure.of(args.measure).per_normalized(ta)
    head = _human.block([
        ("motion" if len(motions) == 1 else "motions", motion_line),
        ("processing", processing_line),
        ("cylinders", f"mode {args.mode}, {_human.slenderness(ta)}"),
        ("stripes", f"{len(x)} intensities {name}/(g tan α) = {_human.num(x[0])}–"
                    f"{_human.num(x[-1])} ({name} {_human.num(x[0] * scale)}–"
                    f"{_human.num(x[-1] * scale)} {unit}); accuracy {accuracy}"),
    ])
    rows, notes = [], []
    for r in fits.itertuples(index=False):
        rows.append([_human.num(r.R), r.limit_state, _human.num(r.median),
                     _human.interval(r.median_lo, r.median_hi),
                     _human.num(r.median_im), _human.interval(r.median_p05, r.median_p95),
                     _human.num(r.beta), _human.interval(r.beta_lo, r.beta_hi), r.status,
                     str(r.n_refined)])
        if r.status != "ok":
            notes.append(f"  R = {_human.num(r.R)} m, {r.limit_state}: {r.status}: {r.reason}"
                         f"; median between {_human.num(r.bracket_lo)} and "
                         f"{_human.num(r.bracket_hi)} {unit}")
    fit_table = _human.table(["R [m]", "limit state", f"median {name}/(g tan α) [-]", "95 %",
                              f"median {name} [{unit}]", "90 % bootstrap", "β [-]", "95 %",
                              "status", "added"], rows, left=(1, 8))
    srows = [[_human.num(r.R), r.limit_state, _human.num(r.intensity), _human.num(r.im),
              f"{r.n_exceeding} of {r.n_motions}", _human.num(r.fraction, 3)]
             for r in stripes.itertuples(index=False)]
    stripe_table = _human.table(["R [m]", "limit state", f"{name}/(g tan α) [-]",
                                 f"{name} [{unit}]", "exceeding", "fraction [-]"], srows,
                                left=(1,))
    return "\n".join([head, "", "lognormal fit (binomial maximum likelihood) per R and limit "
                       "state:", fit_table, *notes, "", "stripes:", stripe_table])


def run(args) -> int:
    """Analyse every stripe and motion, fit, and write; returns 0."""
    from rocking import _json
    from rocking.dynamics.bodies import Cylinder
    from rocking.fragility.stripes import (
        MEASURE_COLUMNS,
        bootstrap_stripes,
        stripe_fragility,
        stripe_intensities,
    )
    from rocking.motions.identity import identity
    from rocking.motions.measures import Measure
    from rocking.spectra.accuracy import Accuracy
    from rocking.spectra.limit_states import parse_limit_states
    from rocking.units import CSV_FLOAT_FORMAT, QUANTITIES, header

    out = args.out
    _common.resolve_body(args, "stripes", many=True)
    if out is not None:
        _common.check_output(out, (".csv", ".json"))
    states = parse_limit_states(args.limit_states, sort=False)
    if _common.friction(args) is not None:  # sliding's answer is its own fragility
        states = parse_limit_states([*states, f"sliding:{args.mu!r}"], sort=False)
    x = (stripe_intensities(args.stripes, args.lower, args.upper) if args.intensities is None
         else args.intensities)
    acc = Accuracy.of(args.accuracy)
    motions = _motions(args)
    bodies = [Cylinder(R, args.tan_alpha) for R in args.R]  # bad R fails before any analysis
    t0 = time.perf_counter()
    if args.refine < 0 or args.bootstrap < 0:
        raise ValueError(f"--refine and --bootstrap must be >= 0, got {args.refine} and "
                         f"{args.bootstrap}")
    if not 0.0 <= args.jitter < 0.5:
        raise ValueError(f"--jitter must be in [0, 0.5), got {args.jitter:g}")
    Measure.of(args.measure)
    with _common.saying_compile("stripes", args.mode, args.quiet):
        results = [stripe_fragility(b, motions, states, mode=args.mode, intensities=x,
                                    accuracy=acc, omega_n=args.omega_n, zeta=args.zeta,
                                    progress=not args.quiet, measure=args.measure,
                                    component=args.component, jitter=args.jitter)
                   for b in bodies]
        refined = [_refined(r, b, motions, args, acc)
                   for r, b in zip(results, bodies, strict=True)]
    boot = None
    if args.bootstrap:
        boot = {(i, ls): bootstrap_stripes(r, args.bootstrap)[ls]["median"]
                for i, per in enumerate(refined) for ls, r in per.items()}
    seconds = time.perf_counter() - t0
    fits, stripes = tables(refined, boot)
    unit = Measure.of(args.measure).unit

    def titles(c: str) -> str:  # the measure's columns in its unit
        return f"{c} [{unit}]" if c in (*MEASURE_COLUMNS, "im") else header(c)
    doc = {"motions": [m.name for m in motions], "mode": args.mode, "measure": args.measure,
           "component": args.component,
           "tan_alpha": args.tan_alpha, "limit_states": [s.name for s in states],
           "accuracy": acc.to_dict(), "intensities": [float(v) for v in results[0]
                                                      .intensities],
           "seconds": seconds,
           "units": {**{k: QUANTITIES[k][1] for k in (*SUMMARY, *STRIPES)
                        if k in QUANTITIES and QUANTITIES[k][1]},
                     **{k: unit for k in (*MEASURE_COLUMNS, "im")}},
           "fits": fits.to_dict(orient="records"),
           "stripes": stripes.to_dict(orient="records"),
           # what was done to each motion (the command line's and the workflow's defaults
           # differ: docs/cli.md)
           "processing": {m.name: identity(m)["processing"] for m in motions}}
    if out is not None:
        out.parent.mkdir(parents=True, exist_ok=True)
    if out is not None and out.suffix.lower() == ".csv":
        with _common.replacing(out) as tmp:
            fits.rename(columns=titles).to_csv(tmp, index=False,
                                               float_format=CSV_FLOAT_FORMAT)
        with _common.replacing(out.with_name(f"{out.stem}_stripes.csv")) as tmp:
            stripes.rename(columns=titles).to_csv(tmp, index=False,
                                                  float_format=CSV_FLOAT_FORMAT)
    elif out is not None:
        with _common.replacing(out) as tmp:
            _json.write(tmp, doc, indent=1)
    if args.json:
        print(_json.dumps(doc, indent=1))
    else:
        print(human(fits, stripes, motions, args, acc.name, results[0].intensities, unit))
        if out is not None:
            print(f"written: {out}" + (f", {out.with_name(f'{out.stem}_stripes.csv')}"
                                       if out.suffix.lower() == ".csv" else ""))
    if not args.quiet:
        # each limit state's refined result counts the shared stripes as asked again
        n = sum(r.n_analyses + sum(f.n_analyses - r.n_analyses for f in per.values())
                for r, per in zip(results, refined, strict=True))
        print(f"{len(results)} body(ies) x {len(motions)} motion(s), {n} analyses, "
              f"{seconds:.2f} s", file=sys.stderr)
    return 0
