"""A ground-motion ensemble built from a recorded pair: the processed record, then its
synthetic Rezaeian–Der Kiureghian pairs.

Pipeline: read the pair (named record or two files) → rotate to its principal axes
(x = major; ``rotation="auto"`` or a forced offset such as the paper's 22.33°) → high-pass
(critically damped oscillator at the Brune corner of the event, "baseline corrected via a
high-pass filter based on Brune's source model") → fit the RDK model to both principal
components → simulate N pairs with independent seeded noise and the same high-pass. The
command line (``rocking motions``) and the workflow's ``motions`` rule both call
:func:`build_ensemble`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .._validate import positive_finite
from .highpass import brune_corner, highpass_motion
from .motion import GroundMotion
from .principal import to_principal_axes
from .records import load_record, loma_prieta_pair
from .stochastic import fit_rdk, synthesize

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


def read_motion(
    record: str | None = None, paths: list[str | Path] | None = None, name: str | None = None
) -> GroundMotion:
    """The recorded pair: a named record, or two files (x, y).

    ``"loma-prieta-sjte"`` without ``paths`` gives the labelled Corralitos stand-in
    (:func:`rocking.motions.records.loma_prieta_pair`).
    """
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
    progress: Callable[[str], None] | None = None,
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
    progress : callable, optional
        Called with one line of text after each stage (None: silent).

    Returns
    -------
    EnsembleBuild
    """
    say = progress or (lambda message: None)
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
    say(
        f"{motion.name}: principal angle {meta['principal_angle_deg']:.3f} deg "
        f"({meta['principal_offset_deg']:.3f} deg from axis {meta['principal_reference_axis']}),"
        f" rotated by {angle:.3f} deg",
    )
    record = rotated
    if highpass != "none":
        record = highpass_motion(rotated, highpass, fc_hz, order)
        say(f"high-pass {highpass} at {fc_hz:.4f} Hz")
    timings["process_s"] = time.perf_counter() - t0
    motions = [record]
    fit = None
    if n > 0:
        t1 = time.perf_counter()
        # Fit the rotated record before its high-pass (spec §5: the high-pass post-processes
        # simulations; a Butterworth's padding would shift the envelope). It is on its
        # principal axes already: a forced 0 keeps it there.
        fit = fit_rdk(rotated, 0.0, seed=seed)
        timings["fit_s"] = time.perf_counter() - t1
        say(
            f"RDK fit in {timings['fit_s']:.1f} s: zeta_f major {fit.major.zeta_f:.3f}, "
            f"minor {fit.minor.zeta_f:.3f}",
        )
        t2 = time.perf_counter()
        kw: dict[str, Any] = {"method": method, "axes": axes, "order": order}
        if highpass == "none":
            kw["highpass"] = False
        else:
            kw.update(highpass=highpass, fc_hz=fc_hz)
        motions += synthesize(fit, n, seed, **kw)
        timings["synthesize_s"] = time.perf_counter() - t2
        say(f"{n} synthetic pairs in {timings['synthesize_s']:.1f} s")
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
    keep = int(round(positive_finite("max_duration", max_duration) / motion.dt)) + 1
    if keep >= motion.npts:
        return motion
    meta = dict(motion.metadata)
    meta["processing"] = [*meta.get("processing", []),
                          {"step": "truncate", "max_duration": max_duration, "npts": keep}]
    return GroundMotion(motion.ax[:keep], motion.ay[:keep], motion.dt, motion.name, meta)
