"""``rocking simulate``: one free-vibration or ground-motion analysis → history CSV + summary.

``--out DIR`` receives ``history.csv`` (column titles with units; the 2D model writes only
t, theta, theta_dot) and ``summary.json`` (strict JSON, with a ``units`` map). stdout gets
the summary in labelled lines (θmax in rad and as θmax/α, the intensity as PGA in g and
PGA/(g tan α), the motion's processing), or with ``--json`` the summary as one line of JSON.
Exit code 1 when the analysis failed. A squat body whose
restitution formula is negative (2D modes) gets a one-line note on stderr and
``restitution_clipped``/``restitution_note`` in the summary.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from rocking.cli import _common, _human
from rocking.dynamics.names import DAMPED_OMEGA_N, DAMPED_ZETA, MODEL_2D, MODEL_3D, MODEL_3D_DAMPED
from rocking.spectra.modes import MODE_3D, MODES

EXAMPLES = """\
  rocking simulate --R 6 --tan-alpha 0.2 --theta0 0.1 --phi-dot0 1e-8 --duration 20 -o run
  rocking simulate --R 6 --tan-alpha 0.2 --record el-centro-1940 --pga-ratio 2 -o run
  rocking simulate --height 6 --diameter 0.66 --record el-centro-1940 --pga-g 0.5 -o run
  rocking simulate --R 1 --tan-alpha 0.25 --files x.AT2 y.AT2 --scale 1.5 --mode 2d-x \\
      --body block -o run
  rocking simulate --R 6 --tan-alpha 0.2 --ensemble results/motions/elcentro.nc \\
      --motion el-centro-1940-rdk-000 --mode 3d-damped -o run"""

HISTORY_COLUMNS = {
    MODEL_3D: ("t", "theta", "theta_dot", "phi", "phi_dot", "normal_force", "mu_required"),
    MODEL_3D_DAMPED: ("t", "theta", "theta_dot", "phi", "phi_dot", "w", "w_dot",
                      "contact_force", "normal_force", "mu_required"),
    MODEL_2D: ("t", "theta", "theta_dot", "normal_force", "mu_required"),
}
"""Columns of history.csv per dynamics model (the 2D model has no phi, w)."""


def add_parser(subparsers) -> None:
    """Register the ``simulate`` subcommand."""
    p = _common.add_command(
        subparsers, "simulate", examples=EXAMPLES,
        help="one rocking analysis (free vibration or ground motion) -> history + summary",
        description="Run one analysis of a cylinder (3D or 2D) or a block (2D): free "
        "vibration from --theta0, or the response to a ground motion; write history.csv "
        "and summary.json to --out.")
    p.add_argument("--R", type=float, default=None,
                   help="semi-diagonal [m] (or --height and --diameter)")
    p.add_argument("--tan-alpha", type=float, default=None,
                   help="slenderness b/h [-] (or --height and --diameter)")
    _common.add_dimensions(p)
    p.add_argument("--body", choices=("cylinder", "block"), default="cylinder",
                   help="rigid body (a block only in the 2D modes)")
    p.add_argument("--mode", choices=list(MODES), default=MODE_3D,
                   help="model and excitation: 3d, 3d-damped, the 3D model under the x or y "
                   "component alone (3d-x, 3d-y: a small spin at each uplift, --phi-dot0), or "
                   "the 2D model under one (2d-x, 2d-y); in free vibration the component "
                   "does not matter")
    p.add_argument("--rtol", type=float, default=None,
                   help="relative tolerance (default: the model's, 1e-8)")
    p.add_argument("--stop-at", type=float, default=None, help="stop once |theta| > this [rad]")
    p.add_argument("--omega-n", type=float, default=DAMPED_OMEGA_N,
                   help="contact spring frequency of mode 3d-damped [rad/s]")
    p.add_argument("--mu", type=float, default=None,
                   help="friction coefficient of the support [-], > 0: the summary says "
                   "whether the body needed more (slides)")
    p.add_argument("--vertical", action="store_true",
                   help="with --record: include its vertical component (UP/DWN file); three "
                   "--files (x y z) imply it")
    p.add_argument("--zeta", type=float, default=DAMPED_ZETA,
                   help="contact damping ratio of mode 3d-damped [-]")
    fv = p.add_argument_group("free vibration (when no ground motion is given)")
    fv.add_argument("--theta0", type=float, help="initial tilt [rad]")
    fv.add_argument("--phi-dot0", type=float, default=None,
                    help="initial spin [rad/s] (default 0); under a ground motion the spin at "
                    "each uplift of modes 3d-x, 3d-y (default theirs, 1e-4)")
    fv.add_argument("--duration", type=float, help="length [s]")
    _common.add_motion_source(p)
    _common.add_processing(p)
    amp = p.add_argument_group("intensity (default: the motion as it is)") \
        .add_mutually_exclusive_group()
    amp.add_argument("--scale", type=float, default=None, help="factor on the motion [-]")
    amp.add_argument("--pga-ratio", type=float, default=None,
                     help="scale so that the pair's vector PGA/(g tan alpha) equals this [-]")
    amp.add_argument("--pga-g", type=float, default=None,
                     help="scale so that the pair's vector PGA equals this [g]")
    p.add_argument("-o", "--out", type=Path, required=True, help="output folder")
    _human.add_json(p, "the summary (summary.json, on one line)")
    _common.add_quiet(p)
    p.set_defaults(func=run)


def _ground(args, body, model: str, motion, common: dict):
    from rocking.constants import G
    from rocking.dynamics.analysis import ground_response
    from rocking.motions.identity import identity
    from rocking.spectra.modes import excitation

    excited, start = excitation(args.mode, motion, args.phi_dot0)
    # the pair's vector PGA normalizes the intensity in every mode, as in the spectra
    scale = args.scale if args.scale is not None else 1.0
    if args.pga_ratio is not None:
        scale = args.pga_ratio * G * body.tan_alpha / motion.pga
    if args.pga_g is not None:
        scale = args.pga_g / motion.pga_g
    res = ground_response(body, excited, scale=scale, stop_at=args.stop_at, model=model,
                          **start, **common)
    who = identity(motion)
    meta = {"motion": motion.name, "source_record": who["source_record"],
            "processing": who["processing"], "scale": scale, **start,
            "pga_ratio": scale * motion.pga / (G * body.tan_alpha),
            "pga_g": scale * motion.pga_g}
    return res, meta


def run(args: argparse.Namespace) -> int:
    """Run the analysis, write history.csv and summary.json; 0, or 1 if it failed."""
    import numpy as np

    from rocking import _json
    from rocking._validate import positive_finite
    from rocking.dynamics.analysis import free_vibration
    from rocking.dynamics.bodies import Block, Cylinder
    from rocking.units import QUANTITIES, header

    _common.resolve_body(args, "simulate", many=False)
    for option, value in (("--scale", args.scale), ("--pga-ratio", args.pga_ratio),
                          ("--pga-g", args.pga_g)):
        if value is not None:
            positive_finite(option, value)
    model = MODES[args.mode].model
    if args.body == "block" and model != MODEL_2D:
        raise ValueError(f"--body block has only the 2D model: use --mode 2d-x or 2d-y, "
                         f"got --mode {args.mode}")
    body = (Block if args.body == "block" else Cylinder)(args.R, args.tan_alpha,
                                                         mu=_common.friction(args))
    common = dict(rtol=args.rtol, omega_n=args.omega_n, zeta=args.zeta)
    motion = _common.motion_from_args(args)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out must be a folder, {str(out)!r} is a file")
    _common.writable_folder(out)
    if motion is None and (args.theta0 is None or args.duration is None):
        raise ValueError("free vibration needs --theta0 and --duration (or give a ground "
                         "motion: --record, --files or --ensemble)")
    with _common.saying_compile("simulate", args.mode, args.quiet):
        if motion is not None:
            res, meta = _ground(args, body, model, motion, common)
        else:
            spin = 0.0 if args.phi_dot0 is None else args.phi_dot0
            res = free_vibration(body, args.theta0, spin, duration=args.duration,
                                 model=model, **common)
            meta = {"theta0": args.theta0, "phi_dot0": spin, "duration": args.duration}
    cols = HISTORY_COLUMNS[model]
    # numpy, not pandas: the table is plain numbers and pandas costs half a second to load
    with _common.replacing(out / "history.csv") as tmp:
        np.savetxt(tmp, np.column_stack([getattr(res, c) for c in cols]),
                   delimiter=",", fmt="%.17g", header=",".join(header(c) for c in cols),
                   comments="")
    summary = {**res.summary(), "mode": args.mode, "R": body.R, "tan_alpha": body.tan_alpha,
               "body": args.body, **meta}
    if model == MODEL_2D:  # the 2D model has impacts, not quasi-impacts
        summary["n_impacts"] = summary.pop("n_quasi_impacts")
    summary["units"] = {k: u for k, u in SUMMARY_UNITS.items() if k in summary} | {
        c: QUANTITIES[c][1] for c in cols}
    with _common.replacing(out / "summary.json") as tmp:
        _json.write(tmp, summary)
    if summary.get("restitution_clipped"):  # stdout stays one JSON document
        print(f"rocking simulate: note: {summary['restitution_note']}", file=sys.stderr)
    if args.json:
        print(_json.dumps(summary))
    else:
        words = (_human.processing(motion, stored=args.ensemble is not None)
                 if motion is not None else "")
        print(human(summary, body.alpha, out, words))
    return 0 if res.ok else 1


def _outcome(s: dict) -> str:
    if s["status"] != "ok":
        return f"{s['status']}: {s.get('reason') or 'see summary.json'}"
    if s.get("overturned"):
        return "ok: overturned"
    return "ok: rocked, did not overturn" if s.get("uplifted") else "ok: did not uplift"


def human(s: dict, alpha: float, out: Path, processing: str = "") -> str:
    """The summary in labelled lines: body, motion and ``processing`` (in words, or the free
    vibration), intensity, outcome, peak tilt in rad and as θmax/α, uplift, impacts, files."""
    rows = [("body", _human.body_line(s["body"], s["R"], s["tan_alpha"])),
            ("mode", s["mode"] + (f", spin {_human.num(s['phi_dot0'])} rad/s at each uplift"
                                  if "motion" in s and "phi_dot0" in s else ""))]
    if "motion" in s:
        rows += [("motion", s["processing"]),
                 ("processing", processing),
                 ("intensity", f"{_human.intensity(s['pga_ratio'], s['tan_alpha'])} "
                               f"(the motion × {_human.num(s['scale'])})")]
    else:
        rows += [("free vibration", f"from θ0 = {_human.tilt(s['theta0'], alpha)}, spin "
                                    f"{_human.num(s['phi_dot0'])} rad/s, "
                                    f"{_human.num(s['duration'])} s")]
    rows += [("outcome", _outcome(s)),
             ("peak tilt", f"θmax = {_human.tilt(s['theta_max'], alpha)} at t = "
                           f"{_human.num(s['t_theta_max'])} s")]
    rows.append(("uplift", "never" if s.get("t_uplift") is None
                 or not math.isfinite(s["t_uplift"]) else f"at t = {_human.num(s['t_uplift'])} s"))
    impacts = s.get("n_impacts", s.get("n_quasi_impacts"))
    if impacts is not None:
        rows.append(("impacts" if "n_impacts" in s else "quasi-impacts", str(impacts)))
    if "dissipated" in s:
        rows.append(("dissipated", f"{_human.num(s['dissipated'])} J/kg (contact dashpot)"))
    if "contact_force_min" in s:
        rows.append(("min contact force", f"{_human.num(s['contact_force_min'])} N/kg"))
    if s.get("mu_required_max") is not None:
        verdict = {True: "SLIDES", False: "holds",
                   None: "not judged (it overturned: the fall needs unbounded friction)"}
        held = "" if s.get("mu") is None else (
            f"; μ = {_human.num(s['mu'])}: " + verdict[s.get("slides")])
        jump = "; LIFTS OFF (N ≤ 0)" if s.get("lifts_off") else ""
        rows.append(("support", f"needs μ ≥ {_human.num(s['mu_required_max'])}, "
                                f"N ≥ {_human.num(s['normal_force_min'])} mg{held}{jump}"))
    rows.append(("written", f"{out / 'history.csv'}, {out / 'summary.json'}"))
    return _human.block(rows)


SUMMARY_UNITS = {
    "theta_max": "rad", "t_theta_max": "s", "t_uplift": "s (null: never uplifted)", "R": "m",
    "tan_alpha": "-", "scale": "-", "pga_ratio": "g tan(alpha)", "pga_g": "g",
    "theta0": "rad", "phi_dot0": "rad/s", "duration": "s", "free_tail_peak": "rad",
    "restitution": "- (theta_dot after / before an impact)",
    "dissipated": "J/kg (energy dissipated by the contact dashpot, per unit mass)",
    "contact_force_min": "N/kg (smallest normal contact force per unit mass)",
    "normal_force_min": "m g (smallest normal force the support supplies; < 0: lift-off)",
    "t_normal_force_min": "s", "t_mu_required_max": "s", "mu": "-",
    "mu_required_max": "- (largest friction coefficient the body needs, |F|/N)",
}
"""Units of the summary fields (``summary.json`` → ``units``)."""
