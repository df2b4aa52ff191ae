"""``rocking simulate``: one free-vibration or ground-motion analysis → history CSV + summary.

Examples::

    rocking simulate --R 6 --tan-alpha 0.2 --theta0 0.1 --phi-dot0 1e-8 --duration 20 --out run
    rocking simulate --R 6 --tan-alpha 0.2 --record el-centro-1940 --pga-ratio 2 --out run
    rocking simulate --R 6 --tan-alpha 0.2 --record x.AT2,y.AT2 --scale 1.5 --model 2d --out run
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pandas as pd

from ..constants import G
from ..dynamics.analysis import MODELS, free_vibration, ground_response
from ..dynamics.bodies import Block, Cylinder


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "simulate", help="one rocking analysis (free vibration or ground motion)",
        description="Run one analysis; write history.csv and summary.json to --out.")
    p.add_argument("--R", type=float, required=True, help="semi-diagonal [m]")
    p.add_argument("--tan-alpha", type=float, required=True, help="slenderness b/h [-]")
    p.add_argument("--body", choices=("cylinder", "block"), default="cylinder",
                   help="rigid body (a block only with --model 2d)")
    p.add_argument("--model", choices=MODELS, default="3d")
    p.add_argument("--rtol", type=float, default=None, help="relative tolerance")
    p.add_argument("--stop-at", type=float, default=None, help="stop once |theta| > this [rad]")
    p.add_argument("--omega-n", type=float, default=2000.0, help="3d-damped contact [rad/s]")
    p.add_argument("--zeta", type=float, default=5.0, help="3d-damped damping ratio [-]")
    fv = p.add_argument_group("free vibration")
    fv.add_argument("--theta0", type=float, help="initial tilt [rad]")
    fv.add_argument("--phi-dot0", type=float, default=0.0, help="initial spin [rad/s]")
    fv.add_argument("--duration", type=float, help="length [s]")
    gm = p.add_argument_group("ground motion")
    gm.add_argument("--record", help="'el-centro-1940' or PATH[,PATH2] (x then y)")
    amp = gm.add_mutually_exclusive_group()
    amp.add_argument("--scale", type=float, default=None, help="factor on the record [-]")
    amp.add_argument("--pga-ratio", type=float, default=None,
                     help="scale so that the vector PGA/(g tan alpha) equals this [-]")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.set_defaults(func=run)


def _motion(spec: str):
    from ..motions.motion import GroundMotion
    from ..motions.records import load_record, read_pair, read_record

    paths = [s for s in spec.split(",") if s]
    if len(paths) == 1 and not Path(paths[0]).exists():
        return load_record(paths[0])
    if len(paths) == 2:
        return read_pair(paths[0], paths[1], name=f"{Path(paths[0]).stem}+{Path(paths[1]).stem}")
    if len(paths) == 1:  # one component, on x (for model="2d")
        rec = read_record(paths[0])
        return GroundMotion(rec.acc, None, rec.dt, name=Path(paths[0]).stem, metadata=rec.meta)
    raise ValueError(f"record must be a name or PATH[,PATH2], got {spec!r}")


def run(args: argparse.Namespace) -> int:
    body = (Block if args.body == "block" else Cylinder)(args.R, args.tan_alpha)
    common = dict(model=args.model, rtol=args.rtol, omega_n=args.omega_n, zeta=args.zeta)
    if args.record:
        motion = _motion(args.record)
        scale = 1.0
        if args.pga_ratio is not None:
            scale = args.pga_ratio * G * body.tan_alpha / motion.pga
        elif args.scale is not None:
            scale = args.scale
        res = ground_response(body, motion, scale=scale, stop_at=args.stop_at, **common)
        meta = {"record": motion.name, "scale": scale, "pga_ratio": scale * motion.pga / (
            G * body.tan_alpha)}
    else:
        if args.theta0 is None or args.duration is None:
            raise ValueError("free vibration needs --theta0 and --duration (or give --record)")
        res = free_vibration(body, args.theta0, args.phi_dot0, duration=args.duration,
                             **common)
        meta = {"theta0": args.theta0, "phi_dot0": args.phi_dot0, "duration": args.duration}
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    cols = {"t": res.t, "theta": res.theta, "phi": res.phi, "theta_dot": res.theta_dot,
            "phi_dot": res.phi_dot}
    if res.w is not None:
        cols.update(w=res.w, w_dot=res.w_dot, contact_force=res.contact_force)
    pd.DataFrame(cols).to_csv(out / "history.csv", index=False)
    summary = {**res.summary(), "R": body.R, "tan_alpha": body.tan_alpha,
               "body": args.body, **meta}
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(json.dumps(summary))
    return 0 if res.ok else 1
