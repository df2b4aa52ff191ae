"""``rocking motions``: a record and its synthetic RDK pairs, written as one ensemble file.

Pipeline (spec §5): read the pair (named record or two files) → rotate to its principal axes
(x = major; ``--rotation auto`` or a forced offset such as the paper's 22.33°) → high-pass
(critically damped oscillator at the Brune corner of the event, "baseline corrected via a
high-pass filter based on Brune's source model") → fit the Rezaeian–Der Kiureghian model to
both principal components → simulate N pairs with independent seeded noise and the same
high-pass → write the record first, then the pairs, with :mod:`rocking.motions.ensemble_io`, and the
fitted parameters as JSON.

Example::

    rocking motions --record el-centro-1940 -n 10 --seed 2017 \\
        -o results/motions/elcentro.nc
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..motions.motion import GroundMotion

HIGHPASS_KINDS = ("oscillator", "butterworth", "none")


@dataclass
class EnsembleBuild:
    """What :func:`build_ensemble` produced.

    Attributes
    ----------
    motions : list of GroundMotion
        The processed record first, then the synthetic pairs [m/s²].
    fit : object
        The :class:`rocking.motions.stochastic.RDKFit` (None when no pair was simulated).
    info : dict
        Settings and derived values (rotation, corner frequency, seed, timings [s]).
    """

    motions: list[GroundMotion]
    fit: Any
    info: dict[str, Any] = field(default_factory=dict)

    def parameters(self) -> dict[str, Any]:
        """JSON-able summary: the settings plus the fitted RDK parameters."""
        out = dict(self.info)
        out["fit"] = None if self.fit is None else self.fit.to_dict()
        return out


def _progress(message: str, quiet: bool) -> None:
    if not quiet:
        print(f"rocking motions: {message}", file=sys.stderr, flush=True)


def read_motion(
    record: str | None = None, paths: list[str | Path] | None = None, name: str | None = None
) -> GroundMotion:
    """The recorded pair: a named record, or two files (x, y).

    ``"loma-prieta-sjte"`` without ``paths`` gives the labelled Corralitos stand-in
    (:func:`rocking.motions.records.loma_prieta_pair`).
    """
    from ..motions.records import load_record, loma_prieta_pair

    if record == "loma-prieta-sjte":
        return loma_prieta_pair(paths)
    if record is None:
        if not paths:
            raise ValueError("give a record name or two component files")
        return load_record(name or Path(paths[0]).stem, paths)
    return load_record(record, paths)


def build_ensemble(
    motion: GroundMotion,
    n: int,
    seed: int,
    *,
    rotation: float | str | None = "auto",
    highpass: str = "oscillator",
    fc_hz: float | None = None,
    mw: float | None = None,
    stress_bar: float = 50.0,
    beta_kms: float = 3.5,
    order: int = 4,
    method: str = "time",
    axes: str = "principal",
    max_duration: float | None = None,
    quiet: bool = True,
) -> EnsembleBuild:
    """Process a recorded pair and synthesize ``n`` pairs like it.

    Parameters
    ----------
    motion : GroundMotion
        The recorded pair [m/s²].
    n : int
        Number of synthetic pairs (0: only the processed record).
    seed : int
        Root seed of the simulation and of the ζ_f search.
    rotation : "auto", None or float
        Principal-axis rotation (see :func:`rocking.motions.principal.to_principal_axes`) [deg].
    highpass : {"oscillator", "butterworth", "none"}
        High-pass applied to the record and to the synthetic pairs.
    fc_hz : float, optional
        Corner frequency [Hz]; default the Brune corner of ``mw`` (or the record's
        ``metadata["mw"]``) with ``stress_bar`` [bar] and ``beta_kms`` [km/s].
    order : int
        Butterworth order.
    method : {"time", "spectral"}
        RDK discretization.
    axes : {"principal", "record"}
        Axes of the synthetic pairs (the record stays on its principal axes).
    max_duration : float, optional
        Keep only the first ``max_duration`` seconds of every motion [s].
    quiet : bool
        No progress lines on stderr.

    Returns
    -------
    EnsembleBuild
    """
    from ..motions.highpass import brune_corner, highpass_motion
    from ..motions.principal import to_principal_axes

    if highpass not in HIGHPASS_KINDS:
        raise ValueError(f"highpass must be one of {HIGHPASS_KINDS}, got {highpass!r}")
    if isinstance(n, bool) or int(n) != n or n < 0:
        raise ValueError(f"n must be an integer >= 0, got {n!r}")
    if highpass != "none" and fc_hz is None:
        mw = mw if mw is not None else motion.metadata.get("mw")
        if mw is None:
            raise ValueError(f"mw (or fc_hz) is needed for the high-pass of {motion.name!r}")
        fc_hz = brune_corner(mw, stress_bar, beta_kms)
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    rotated, angle = to_principal_axes(motion, rotation)
    meta = rotated.metadata
    _progress(
        f"{motion.name}: principal angle {meta['principal_angle_deg']:.3f} deg "
        f"({meta['principal_offset_deg']:.3f} deg from axis {meta['principal_reference_axis']}),"
        f" rotated by {angle:.3f} deg", quiet,
    )
    record = rotated
    if highpass != "none":
        record = highpass_motion(rotated, highpass, fc_hz, order)
        _progress(f"high-pass {highpass} at {fc_hz:.4f} Hz", quiet)
    timings["process_s"] = time.perf_counter() - t0
    motions = [record]
    fit = None
    if n > 0:
        from ..motions.stochastic import fit_rdk, synthesize

        t1 = time.perf_counter()
        # Fit the rotated record before its high-pass (spec §5: the high-pass post-processes
        # simulations; a Butterworth's padding would shift the envelope). It is on its
        # principal axes already: a forced 0 keeps it there.
        fit = fit_rdk(rotated, 0.0, seed=seed)
        timings["fit_s"] = time.perf_counter() - t1
        _progress(
            f"RDK fit in {timings['fit_s']:.1f} s: zeta_f major {fit.major.zeta_f:.3f}, "
            f"minor {fit.minor.zeta_f:.3f}", quiet,
        )
        t2 = time.perf_counter()
        kw: dict[str, Any] = {"method": method, "axes": axes, "order": order}
        if highpass == "none":
            kw["highpass"] = False
        else:
            kw.update(highpass=highpass, fc_hz=fc_hz)
        motions += synthesize(fit, n, seed, **kw)
        timings["synthesize_s"] = time.perf_counter() - t2
        _progress(f"{n} synthetic pairs in {timings['synthesize_s']:.1f} s", quiet)
    if max_duration is not None:
        motions = [_cut(m, max_duration) for m in motions]
    info = {
        "record": motion.name,
        "label": motion.metadata.get("label", motion.name),
        "stand_in": bool(motion.metadata.get("stand_in", False)),
        "stand_in_for": motion.metadata.get("stand_in_for"),
        "record_source": {k: motion.metadata.get(k) for k in ("source", "files", "sha256")},
        "principal_angle_deg": meta["principal_angle_deg"],
        "principal_offset_deg": meta["principal_offset_deg"],
        "rotation_deg": angle,
        "forced_angle_deg": meta["forced_angle_deg"],
        "highpass": {"kind": highpass, "fc_hz": fc_hz, "order": order, "mw": mw,
                     "stress_bar": stress_bar, "beta_kms": beta_kms},
        "n_synthetic": int(n),
        "seed": int(seed),
        "method": method,
        "axes": axes,
        "max_duration": max_duration,
        "timings": timings,
    }
    return EnsembleBuild(motions, fit, info)


def _cut(motion: GroundMotion, max_duration: float) -> GroundMotion:
    """The first ``max_duration`` seconds of a motion."""
    from .._validate import positive_finite

    keep = int(round(positive_finite("max_duration", max_duration) / motion.dt)) + 1
    if keep >= motion.npts:
        return motion
    meta = dict(motion.metadata)
    meta["processing"] = [*meta.get("processing", []),
                          {"step": "truncate", "max_duration": max_duration, "npts": keep}]
    return GroundMotion(motion.ax[:keep], motion.ay[:keep], motion.dt, motion.name, meta)


def _rotation(text: str) -> float | str:
    if text.strip().lower() == "auto":
        return "auto"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"rotation must be 'auto' or degrees, got {text!r}") \
            from None


def add_parser(subparsers) -> None:
    """Register the ``motions`` subcommand."""
    p = subparsers.add_parser(
        "motions",
        help="record + synthetic RDK pairs to an ensemble file",
        description="Rotate a record pair to its principal axes, high-pass it, fit the "
        "Rezaeian-Der Kiureghian model and write the record plus N synthetic pairs.",
    )
    src = p.add_mutually_exclusive_group()
    src.add_argument("--record", default=None,
                     help="named record (el-centro-1940, loma-prieta-corralitos, "
                     "loma-prieta-sjte); default el-centro-1940")
    src.add_argument("--files", nargs=2, metavar=("X", "Y"), default=None,
                     help="two component files (AT2 or text, in g)")
    p.add_argument("--paths", nargs=2, metavar=("X", "Y"), default=None,
                   help="files for a named record (e.g. RSN801 SJTE315 SJTE225)")
    p.add_argument("--name", default=None, help="motion name when --files is used")
    p.add_argument("-n", "--n-synthetic", type=int, default=10, help="synthetic pairs")
    p.add_argument("--seed", type=int, default=2017, help="root seed")
    p.add_argument("--rotation", type=_rotation, default="auto",
                   help="'auto' or the forced offset of the major axis [deg], e.g. 22.33")
    p.add_argument("--highpass", choices=HIGHPASS_KINDS, default="oscillator")
    p.add_argument("--fc-hz", type=float, default=None,
                   help="high-pass corner [Hz] (default: Brune corner of --mw)")
    p.add_argument("--mw", type=float, default=None,
                   help="moment magnitude (default: the named record's)")
    p.add_argument("--stress-bar", type=float, default=50.0, help="Brune stress drop [bar]")
    p.add_argument("--beta-kms", type=float, default=3.5, help="shear-wave velocity [km/s]")
    p.add_argument("--order", type=int, default=4, help="Butterworth order")
    p.add_argument("--method", choices=("time", "spectral"), default="time")
    p.add_argument("--axes", choices=("principal", "record"), default="principal")
    p.add_argument("--max-duration", type=float, default=None,
                   help="keep the first seconds of every motion [s]")
    p.add_argument("-o", "--out", type=Path, required=True, help="ensemble file (.nc)")
    p.add_argument("--params-out", type=Path, default=None,
                   help="JSON of settings and fitted parameters (default: OUT with .json)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=run)


def run(args) -> int:
    """Build the ensemble, write the NetCDF and JSON files; returns 0."""
    from ..motions.ensemble_io import save_ensemble

    if args.out.suffix.lower() != ".nc":
        raise ValueError(f"out must end in .nc, got {str(args.out)!r}")
    record = args.record if (args.record or args.files) else "el-centro-1940"
    paths = args.files or args.paths
    motion = read_motion(record, paths, args.name)
    _progress(f"read {motion.name} ({motion.npts} samples, dt {motion.dt} s, vector PGA "
              f"{motion.pga_g:.4f} g){' [stand-in]' if motion.metadata.get('stand_in') else ''}",
              args.quiet)
    build = build_ensemble(
        motion, args.n_synthetic, args.seed, rotation=args.rotation, highpass=args.highpass,
        fc_hz=args.fc_hz, mw=args.mw, stress_bar=args.stress_bar, beta_kms=args.beta_kms,
        order=args.order, method=args.method, axes=args.axes, max_duration=args.max_duration,
        quiet=args.quiet,
    )
    params = build.parameters()
    save_ensemble(args.out, build.motions, attrs={k: params[k] for k in (
        "record", "label", "stand_in", "stand_in_for", "rotation_deg", "highpass", "seed",
        "n_synthetic")})
    params_out = args.params_out or args.out.with_suffix(".json")
    params_out.parent.mkdir(parents=True, exist_ok=True)
    params_out.write_text(json.dumps(params, indent=2, sort_keys=True, default=str) + "\n")
    _progress(f"wrote {len(build.motions)} motions to {args.out} and parameters to "
              f"{params_out}", args.quiet)
    return 0
