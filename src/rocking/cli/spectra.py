"""``rocking spectra``: one seismic performance rocking spectrum, printed as a labelled table
(the critical intensity as PGA/(g tan α) and PGA [g], the quantity it is, flags, the motion's
processing) or as JSON (``--json``), and written to CSV or JSON (``-o``).

The numbers are those of the workflow's stores when asked the same thing: the same motion
(``--ensemble FILE --motion NAME``), mode, limit states, accuracy and search bound give the
store's ``pga_crit`` bit for bit (README, "Reproduce a number from the study").
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from rocking.cli import _common, _human
from rocking.spectra.accuracy import DEFAULT_UPPER, PRESETS
from rocking.spectra.quantity import QUANTITIES, Quantity

EXAMPLES = """\
  rocking spectra --R 0.5,1,2,5,10 --tan-alpha 0.2 --record el-centro-1940 -o spectrum.csv
  rocking spectra --height 6 --diameter 0.66 --record loma-prieta-corralitos
  rocking spectra --R 6 --tan-alpha 0.2 --ensemble results/motions/elcentro.nc \\
      --motion el-centro-1940 --mode 3d --limit-states overturning,tilt:1/3 --accuracy default
  rocking spectra --R 2 --tan-alpha 0.2 --files RSN801_LOMAP_SJTE315.AT2 \\
      RSN801_LOMAP_SJTE225.AT2 --rotation auto --highpass oscillator --mw 6.93 -o sjte.json"""

COLUMNS = ("mode", "motion", "R", "tan_alpha", "limit_state", "quantity", "quantity_p",
           "quantity_w", "pga_crit", "pga_crit_g", "i50", "first_exceedance", "scan_step",
           "plateau", "not_reached", "non_monotonic", "failed", "slides", "lifts_off",
           "n_analyses", "lower", "upper", "accuracy", "mu", "source_record", "processing")
"""Columns of the CSV (titles with units) and keys of the JSON results."""


def add_parser(subparsers) -> None:
    """Register the ``spectra`` subcommand."""
    p = _common.add_command(
        subparsers, "spectra", examples=EXAMPLES,
        help="critical PGA/(g tan alpha) of cylinders vs R (performance spectrum)",
        description="Seismic performance rocking spectrum of one ground-motion pair: for each "
        "R and limit state, the critical intensity as PGA/(g tan alpha) (pga_crit) and as PGA "
        "in g (pga_crit_g). By default it is I10 = inf{s: P(s) >= 0.1}, the lowest intensity "
        "around which 10 %% of the intensities within +-2 %% (in ln s) exceed the limit state "
        "(the smallest exceeding intensity itself does not converge: docs/performance.md); "
        "--quantity first_exceedance gives the first exceedance on the search's scan grid. "
        "PGA is the pair's vector PGA in every mode.",
    )
    _common.add_cylinders(p)
    p.add_argument("--limit-states", default="default",
                   help="comma-separated, in the order wanted: overturning, tilt:<r> "
                   "(theta > r alpha, e.g. tilt:1/3), sliding:<mu> (the body needs more "
                   "friction than mu); 'default' = tilt:0.1,0.2,1/3,0.5,0.75,1 "
                   "and overturning")
    p.add_argument("--mu", type=float, default=None,
                   help="friction coefficient of the support [-], > 0: each answer says "
                   "whether an analysis up to it that did not overturn needed more while in "
                   "contact (slides); every analysis is "
                   "then monitored to the end of its record")
    p.add_argument("--accuracy", choices=sorted(PRESETS), default="default",
                   help="search and ODE tolerances preset")
    p.add_argument("--quantity", choices=QUANTITIES, default=Quantity().name,
                   help="what the critical intensity is: exceedance_quantile (I_p = "
                   "inf{s: P(s) >= p}) or first_exceedance (the smallest exceeding "
                   "intensity on the scan grid, labelled with its step)")
    p.add_argument("--p", type=float, default=Quantity().p,
                   help="exceedance share p of I_p, in (0, 1) (0.1: I10)")
    p.add_argument("--w", type=float, default=Quantity().w,
                   help="half-width w of the window of P(s) in ln s, in (0, 0.5)")
    p.add_argument("--upper", type=float, default=DEFAULT_UPPER,
                   help="highest PGA/(g tan alpha) searched [-]")
    _common.add_contact(p)
    _common.add_motion_source(p)
    _common.add_processing(p)
    p.add_argument("-o", "--out", type=Path, default=None,
                   help="also write the results to this .csv or .json file")
    _human.add_json(p, "the results (the document --out x.json writes)")
    _common.add_quiet(p)
    p.set_defaults(func=run)


def rows(results, motion) -> list[dict]:
    """One dict per (R, limit state) with the columns of :data:`COLUMNS`."""
    from rocking.motions.identity import identity

    who = identity(motion)
    out = []
    for res in results:
        for rec in res.to_records():
            rec["pga_crit"] = rec.pop("intensity")
            rec["pga_crit_g"] = rec.pop("pga_g")
            rec.update(source_record=who["source_record"], processing=who["processing"])
            out.append({k: rec[k] for k in COLUMNS})
    return out


FLAG_NOTES = {
    "not_reached": "not reached: no exceedance up to the search bound",
    "plateau": "plateau: P(s) rises near p without crossing it more than a window below "
               "the answer; there the answer is ill-conditioned (a small change of the "
               "response may move it down)",
    "non_monotonic": "non_monotonic: an analysed intensity exceeded and a larger one did "
                     "not (the response is not monotonic in the intensity; nearly every I_p "
                     "answer is, so the command line says it of first exceedances only)",
    "failed": "failed: an analysis failed (the answer is not usable)",
    "slides": "slides: an analysis up to the answer that did not overturn needed more "
              "friction than --mu while in contact (the body would have slid: the rocking "
              "answer does not describe it)",
    "lifts_off": "lifts_off: an analysis up to the answer had a normal force N <= 0 (the "
                 "body left its support; every fall of an overturning body does)",
}
"""One line per flag, printed under the table when the flag appears."""


def human(table, motion, args, accuracy, quantity: Quantity) -> str:
    """The spectrum for people: motion, processing, cylinders, the quantity, then one row per
    (R, limit state) with the critical intensity as PGA/(g tan α) and as PGA [g], and the
    flags (non_monotonic only for the first exceedance: nearly every I_p answer is)."""
    ta = args.tan_alpha
    label = quantity.label
    head = _human.block([
        ("motion", table["processing"].iloc[0] if len(table) else motion.name),
        ("processing", _human.processing(motion, stored=args.ensemble is not None)),
        ("cylinders", f"mode {args.mode}, {_human.slenderness(ta)}"),
        ("answer", quantity.describe(accuracy.scan_step)),
        ("search", f"accuracy {accuracy.name}, from uplift up to PGA/(g tan α) = "
                   f"{args.upper:g} (PGA {args.upper * ta:.4g} g)"),
        ("support", "no friction coefficient given (sliding and lift-off not checked: "
                    "--mu to check)" if args.mu is None
         else f"friction coefficient μ = {args.mu:g}"),
    ])
    body, seen = [], []
    notes = {f: n for f, n in FLAG_NOTES.items()
             if not (f == "non_monotonic" and quantity.is_quantile)}
    for r in table.itertuples(index=False):
        # a flag that says nothing (slides without --mu: None or NaN) is not shown
        flags = [f for f in notes if getattr(r, f) is True or getattr(r, f) == 1]
        seen += [f for f in flags if f not in seen]
        if r.not_reached:
            crit, crit_g = f"> {args.upper:g}", f"> {args.upper * ta:.4g}"
        else:
            crit, crit_g = _human.num(r.pga_crit, 6), _human.num(r.pga_crit_g, 6)
        body.append([_human.num(r.R), r.limit_state, crit, crit_g,
                     ", ".join(flags) or "—", str(r.n_analyses)])
    text = head + "\n\n" + _human.table(
        ["R [m]", "limit state", f"{label}: PGA/(g tan α) [-]", "PGA [g]", "flags",
         "analyses"], body, left=(1, 4))
    if seen:
        text += "\n" + "\n".join(f"  {FLAG_NOTES[f]}" for f in seen)
    return text


def _check_numbers(args) -> None:
    """``--R`` non-empty, without repeats, finite and > 0; ``--upper`` > 1 (as the
    workflow's ``search.upper``): refused before any work, naming the option."""
    import math

    R = list(args.R)
    if not R:
        raise ValueError("--R: give at least one size R [m], got none")
    bad = [r for r in R if not (math.isfinite(r) and r > 0)]
    if bad:
        raise ValueError(f"--R must hold finite sizes > 0 [m], got {bad}")
    repeated = sorted({r for r in R if R.count(r) > 1})
    if repeated:
        raise ValueError(f"--R repeats {repeated}: each size is computed once, give it once")
    if not (math.isfinite(args.upper) and args.upper > 1):
        raise ValueError(f"--upper must be a finite number > 1 (the search starts at "
                         f"PGA/(g tan alpha) = 1), got {args.upper!r}")
    _common.friction(args)


def quantity_of(args) -> Quantity:
    """The quantity ``--quantity``, ``--p`` and ``--w`` ask for, checked once: a bad value
    is one line naming the option."""
    try:
        return Quantity(args.quantity, args.p, args.w)
    except ValueError as exc:
        text = str(exc)
        for key, option in (("quantity.p", "--p"), ("quantity.w", "--w"),
                            ("quantity", "--quantity")):
            text = text.replace(key, option, 1) if text.startswith(key) else text
        raise ValueError(text) from None


def run(args) -> int:
    """Compute the spectrum and write it; returns 0."""
    import pandas as pd

    from rocking import _json
    from rocking.motions.identity import identity
    from rocking.spectra.accuracy import Accuracy
    from rocking.spectra.critical import critical_intensity_batch
    from rocking.spectra.limit_states import parse_limit_states
    from rocking.units import CSV_FLOAT_FORMAT, QUANTITIES, header

    _common.resolve_body(args, "spectra", many=True)
    _check_numbers(args)
    out = args.out
    if out is not None:
        _common.check_output(out, (".csv", ".json"))
    states = parse_limit_states(args.limit_states, sort=False)
    acc = Accuracy.of(args.accuracy)
    quantity = quantity_of(args)
    acc.check_window(quantity.w)
    motion = _common.motion_from_args(args, default_record="el-centro-1940")
    tasks = [(R, args.tan_alpha, motion, args.mode) for R in args.R]
    t0 = time.perf_counter()
    with _common.saying_compile("spectra", args.mode, args.quiet):
        results = critical_intensity_batch(tasks, states, accuracy=acc, quantity=quantity,
                                           upper=args.upper, omega_n=args.omega_n,
                                           zeta=args.zeta, mu=args.mu,
                                           progress=not args.quiet)
    seconds = time.perf_counter() - t0
    table = pd.DataFrame(rows(results, motion), columns=list(COLUMNS))
    doc = {
        "motion": {"name": motion.name, **identity(motion), "dt": motion.dt,
                   "npts": motion.npts, "metadata": motion.metadata},
        "mode": args.mode,
        "tan_alpha": args.tan_alpha,
        "limit_states": [s.name for s in states],
        "accuracy": acc.to_dict(),
        "quantity": {**quantity.to_dict(), "label": quantity.label,
                     "description": quantity.describe(acc.scan_step)},
        "upper": args.upper,
        "mu": args.mu,
        "seconds": seconds,
        "units": {k: QUANTITIES[k][1] for k in COLUMNS if QUANTITIES[k][1]},
        # a not-reached intensity (NaN) is written as null: strict JSON
        "results": table.to_dict(orient="records"),
    }
    if out is not None and out.suffix.lower() == ".csv":
        with _common.replacing(out) as tmp:
            table.rename(columns=header).to_csv(tmp, index=False,
                                                float_format=CSV_FLOAT_FORMAT)
    elif out is not None:
        with _common.replacing(out) as tmp:
            _json.write(tmp, doc, indent=1)
    if args.json:
        print(_json.dumps(doc, indent=1))
    else:
        print(human(table, motion, args, acc, quantity))
        if out is not None:
            print(f"written: {out}")
    if not args.quiet:
        n = sum(r.n_analyses for r in results)
        print(f"{len(results)} spectrum point(s), {n} analyses, {seconds:.2f} s",
              file=sys.stderr)
    return 0
