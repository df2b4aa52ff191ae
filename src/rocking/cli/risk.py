"""``rocking risk``: mean annual frequency of each limit state of a study under a hazard curve.

Reads a study's ``fragility.csv`` (the lognormal fits of the performance spectra) or
``stripe_fragility.csv`` (the multiple-stripe fits; which one is told by its columns) and a
hazard curve (an OpenQuake hazard-curve CSV of PGA, or a power law ``k0,k``), and prints or
writes the risk table: per mode, tan α, R and limit state the mean annual frequency [1/yr],
return period [yr] and probability of exceedance in 50 years (:func:`rocking.risk.risk_table`),
with the median capacity in g and as PGA/(g tan α). ``--json`` prints the table as JSON.
Optionally writes the OpenQuake NRML and pelicun exports of the same fragilities.
"""

from __future__ import annotations

from pathlib import Path

from . import _common, _human

EXAMPLES = """\
  rocking risk --fragility results/paper/elcentro/fragility.csv \\
      --hazard config/hazard/example_hazard_curve.csv
  rocking risk --fragility results/elcentro/fragility.csv --hazard 1e-4,2.5 --mode 3d \\
      --limit-states overturning -o risk.csv
  rocking risk --fragility results/elcentro/fragility.csv --hazard hazard_curve-mean-PGA.csv \\
      --site 3 --im-factor 1.1 --nrml fragility.nrml.xml --pelicun fragility.pelicun.csv"""

HEADER = ("mode", "tan α [-]", "R [m]", "limit state", "median PGA [g]",
          "median PGA/(g tan α) [-]", "β [-]", "λ [1/yr]", "return period [yr]",
          "P(50 yr) [-]", "fit")
"""Columns printed on the terminal (a file or ``--json`` gets every column of the table)."""


def add_parser(subparsers) -> None:
    """Register the ``risk`` subcommand."""
    p = _common.add_command(
        subparsers, "risk", examples=EXAMPLES,
        help="mean annual frequency of each limit state under a hazard curve",
        description="From fragility to risk: integrate each lognormal fragility of a study's "
        "fragility.csv against a hazard curve of PGA [g]. PGA is the pair's vector peak "
        "(RotD100); a hazard of the geometric mean or RotD50 needs --im-factor (docs/risk.md).",
    )
    p.add_argument("--fragility", type=Path, required=True,
                   help="a study's fragility table: results/<study>/fragility.csv or .nc "
                   "(first exceedance), or stripe_fragility.csv (multiple stripes)")
    p.add_argument("--hazard", required=True,
                   help="OpenQuake hazard-curve CSV of PGA, or a power law 'k0,k' "
                   "(annual rate k0 PGA^-k, PGA in g)")
    p.add_argument("--site", type=int, default=0, help="row of the hazard CSV")
    p.add_argument("--im-factor", type=float, default=1.0,
                   help="study PGA / hazard PGA (e.g. RotD100/RotD50)")
    p.add_argument("--mode", default=None, help="only this mode (3d, 3d-damped, 2d-x, 2d-y)")
    p.add_argument("--tan-alpha", type=float, default=None, help="only this slenderness")
    _common.add_dimensions(p)  # only the row of this body (its R and tan alpha)
    p.add_argument("--limit-states", default=None,
                   help="only these, comma-separated (e.g. overturning,tilt:1/3)")
    p.add_argument("-o", "--out", type=Path, default=None,
                   help="write the table to this .csv (default: print it)")
    p.add_argument("--upper", type=float, default=20.0,
                   help="the study's search bound PGA/(g tan alpha), for the NRML maxIML [-]")
    p.add_argument("--nrml", type=Path, default=None,
                   help="also write the OpenQuake NRML 0.5 fragility model here (.xml)")
    p.add_argument("--pelicun", type=Path, default=None,
                   help="also write the pelicun damage model CSV here (.csv)")
    _human.add_json(p, "the table (with the hazard and the fragility it integrates)")
    p.set_defaults(func=run)


def _hazard(args):
    from ..risk.hazard import HazardCurve, parse_hazard

    if Path(args.hazard).exists():
        curve = HazardCurve.from_openquake_csv(args.hazard, site=args.site)
    else:
        curve = parse_hazard(args.hazard)
    return curve.scaled(args.im_factor) if args.im_factor != 1.0 else curve


def _select(frag, args):
    from ..risk.fragilities import Fragilities
    from ..spectra.limit_states import parse_limit_states

    rows = frag.rows
    if args.mode is not None:
        if args.mode not in set(rows["mode"]):
            raise ValueError(f"--mode {args.mode!r} is not in the table (has "
                             f"{sorted(set(rows['mode']))})")
        rows = rows[rows["mode"] == args.mode]
    if args.tan_alpha is not None:
        rows = rows[(rows["tan_alpha"] - args.tan_alpha).abs() < 1e-9]
        if rows.empty:
            raise ValueError(f"--tan-alpha {args.tan_alpha:g} is not in the table")
    rows = _body_rows(rows, args)
    if args.limit_states is not None:
        names = [ls.name for ls in parse_limit_states(args.limit_states, sort=False)]
        rows = rows[rows["limit_state"].isin(names)]
        if rows.empty:
            raise ValueError(f"--limit-states {args.limit_states!r}: none in the table")
    return Fragilities(rows.reset_index(drop=True), frag.skipped, frag.n_not_computed,
                       frag.kind)


def _body_rows(rows, args):
    """The rows of the body of ``--height``/``--diameter`` (its R and tan α, printed on
    stderr), or a line saying which bodies the table has."""
    import sys

    from ..study.dimensions import AGREE_RTOL, body_line, body_size

    size = body_size(args.height, args.diameter, tan_alpha=args.tan_alpha,
                     names=("--height", "--diameter", "--R", "--tan-alpha"))
    if size is None:
        return rows
    R, tan_alpha = size
    print(f"rocking risk: {body_line(args.height, args.diameter, R, tan_alpha)}",
          file=sys.stderr)
    mine = ((rows["R"] - R).abs() <= AGREE_RTOL * R) \
        & ((rows["tan_alpha"] - tan_alpha).abs() <= AGREE_RTOL * tan_alpha)
    if not mine.any():
        sizes = sorted({float(r) for r in rows["R"]})
        shown = ", ".join(f"{r:g}" for r in sizes[:6]) + (", ..." if len(sizes) > 6 else "")
        raise ValueError(f"--height {args.height:g} --diameter {args.diameter:g} (R = {R:.6g} "
                         f"m, tan alpha = {tan_alpha:.6g}) is not a body of the table (tan "
                         f"alpha {sorted({float(t) for t in rows['tan_alpha']})}, R {shown}); "
                         f"run the study with studies.<name>.height and diameter")
    return rows[mine]


def run(args) -> int:
    """Print or write the risk table (and the exports when asked); returns 0."""
    from ..risk.fragilities import read_fragilities
    from ..risk.nrml import write_nrml
    from ..risk.pelicun import write_pelicun_csv
    from ..risk.table import risk_table

    if args.out is not None:
        _common.check_output(args.out, (".csv",))
    if not args.fragility.exists():
        raise ValueError(f"--fragility: no such file: {str(args.fragility)!r}")
    hazard = _hazard(args)
    frag = _select(read_fragilities(args.fragility), args)
    table = risk_table(frag, hazard)
    if args.nrml is not None:
        write_nrml(frag, args.nrml, search_upper=args.upper)
    if args.pelicun is not None:
        write_pelicun_csv(frag, args.pelicun)
    if args.out is not None:
        with _common.replacing(args.out) as tmp:
            table.to_csv(tmp, index=False, float_format="%.6g")
    if args.json:
        from .. import _json
        from ..units import strip_units

        plain = table.rename(columns={c: strip_units(c) for c in table.columns})
        print(_json.dumps({"hazard": hazard.source, "fragility": frag.kind,
                           "skipped": frag.skipped_note(),
                           "units": {strip_units(c): c.split(" [", 1)[1].rstrip("]")
                                     for c in table.columns if " [" in c},
                           "rows": plain.to_dict(orient="records")}, indent=1))
        return 0
    print(human(table, frag, hazard, args))
    return 0


def human(table, frag, hazard, args) -> str:
    """The risk table for people: the hazard, which fragility, then one row per fit."""
    from ..risk.fragilities import KINDS

    head = _human.block([("hazard", hazard.source),
                         ("fragility", f"{args.fragility}: {KINDS[frag.kind]}")])
    rows = []
    for r in table.itertuples(index=False):
        _, mode, ta, R, ls, median_g, beta, maf, period, p50, _, status = r
        rows.append([mode, _human.num(ta), _human.num(R), ls, _human.num(median_g),
                     _human.num(median_g / ta), _human.num(beta, 3), _human.num(maf, 4),
                     _human.num(period, 4), _human.num(p50, 3), status])
    lines = [head]
    if frag.skipped_note():
        lines.append(frag.skipped_note())
    lines += ["", _human.table(HEADER, rows, left=(0, 3, 10))]
    if args.out is not None:
        lines.append(f"{len(table)} rows (every column) written: {args.out}")
    return "\n".join(lines)
