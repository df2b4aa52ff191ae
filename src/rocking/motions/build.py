"""A ground-motion ensemble built from a recorded pair: the processed record, then its
synthetic Rezaeian–Der Kiureghian pairs.

Pipeline: read the pair (named record or two files) → rotate to its principal axes
(x = major; ``rotation="auto"`` or a forced offset such as the paper's 22.33°) → high-pass
(critically damped oscillator at the Brune corner of the event, "baseline corrected via a
high-pass filter based on Brune's source model") → fit the RDK model to both principal
components (by default matching the record's 5 % response spectrum after the same high-pass;
``fit_method="counts"`` for the RDK 2010 count-based filter) → simulate N pairs with
independent seeded noise and the same high-pass → measure how well the ensemble's median
spectrum matches the record's, per component and period band
(:mod:`rocking.motions.stochastic.quality`). ``compare=True`` also builds the other
method's pairs (same seed), for Fig 8's side-by-side view. The command line
(``rocking motions``) and the workflow's ``motions`` rule both call :func:`build_ensemble`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rocking._validate import positive_finite
from rocking.constants import G
from rocking.motions.catalogue import load_record, loma_prieta_pair
from rocking.motions.highpass import brune_corner, highpass_motion
from rocking.motions.motion import GroundMotion
from rocking.motions.principal import to_principal_axes
from rocking.motions.stochastic import fit_rdk, synthesize
from rocking.motions.stochastic.quality import ensemble_quality, format_quality
from rocking.motions.stochastic.recorded import (
    SIGNIFICANT_DIGITS,
    pairs_match,
    pairs_sha256,
    record_entry,
    recorded_fit,
    rounded_fit,
)

HIGHPASS_KINDS = ("oscillator", "butterworth", "none")
FIT_METHODS = ("spectrum", "counts")

ENSEMBLE_ATTRS = ("record", "label", "stand_in", "stand_in_for", "rotation_deg", "highpass",
                  "seed", "n_synthetic", "fit_method", "fit_quality")
"""Keys of :meth:`EnsembleBuild.parameters` kept in the ensemble file's attributes."""


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
        Settings and derived values (rotation, corner frequency, seed, fit method, fit
        quality, timings [s]).
    comparison : list of GroundMotion
        With ``compare``: the record, then the pairs of the other identification method
        (same seed); else empty.
    """

    motions: list[GroundMotion]
    fit: Any
    info: dict[str, Any] = field(default_factory=dict)
    comparison: list[GroundMotion] = field(default_factory=list)

    def parameters(self) -> dict[str, Any]:
        """JSON-able summary: the settings plus the fitted RDK parameters."""
        out = dict(self.info)
        out["fit"] = None if self.fit is None else self.fit.to_dict()
        return out


def read_motion(
    record: str | None = None, paths: list[str | Path] | None = None, name: str | None = None,
    *, units: str = "g", dt: float | None = None, vertical: bool = False,
) -> GroundMotion:
    """The recorded pair: a named record, or two files (x, y) in ``units`` (one-column
    text files need their time step ``dt`` [s]); with ``vertical``, also its vertical
    component (the named record's ``UP``/``DWN`` file, or the third of three ``paths``).

    ``"loma-prieta-sjte"`` without ``paths`` gives the labelled Corralitos stand-in
    (:func:`rocking.motions.catalogue.loma_prieta_pair`), which has no vertical.
    """
    if paths is not None and len(paths) == 3 and not vertical:
        raise ValueError(f"three files {list(paths)!r}: the third is the vertical component; "
                         "give vertical=True, or two files")
    if vertical and paths is not None and len(paths) != 3:
        raise ValueError(f"vertical=True needs three files (x, y, z), got {list(paths)!r}")
    if record == "loma-prieta-sjte":
        if vertical and paths is None:
            raise ValueError("vertical=True: record 'loma-prieta-sjte' ships no files (its "
                             "stand-in is horizontal); give its three files x, y, z")
        return loma_prieta_pair(paths)
    if record is None:
        if not paths:
            raise ValueError("give a record name or two component files")
        return load_record(name or Path(paths[0]).stem, paths, units=units, dt=dt,
                           vertical=vertical)
    return load_record(record, paths, units=units, dt=dt, vertical=vertical)


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
    fit_method: str = "spectrum",
    compare: bool = False,
    recorded: dict[str, Any] | None = None,
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
    rotation : "auto", None, "none" or float
        Principal-axis rotation (see :func:`rocking.motions.principal.to_principal_axes`)
        [deg]; ``"none"`` keeps the recorded axes (only with ``n = 0``: the synthetic pairs
        are fitted on principal axes).
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
    fit_method : {"spectrum", "counts"}
        Identification of the RDK parameters (:func:`rocking.motions.stochastic.fit_rdk`).
    compare : bool
        Also fit and simulate with the other method (same seed and settings): its pairs go
        to ``comparison`` and its fit and quality to ``info["comparison"]``.
    recorded : dict, optional
        The record's entry of a parameters file
        (:func:`rocking.motions.stochastic.recorded.read_params_file`): its rounded fit is
        used instead of fitting, and the pairs made from it are checked against its
        ``pairs_sha256`` (``info["motions_match"]``). Without it the fit is rounded to
        :data:`~rocking.motions.stochastic.recorded.SIGNIFICANT_DIGITS` digits before the
        simulation, so the entry written from the build (:func:`recorded_entries`) makes the
        same pairs.
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
    if fit_method not in FIT_METHODS:
        raise ValueError(f"fit_method must be one of {FIT_METHODS}, got {fit_method!r}")
    keep_axes = isinstance(rotation, str) and rotation.strip().lower() == "none"
    if keep_axes and n > 0:
        raise ValueError(f"rotation='none' with n={n} synthetic pairs: the pairs are fitted on "
                         "the record's principal axes; rotate (auto or an angle) or give n=0")
    if highpass != "none" and fc_hz is None:
        mw = mw if mw is not None else motion.metadata.get("mw")
        if mw is None:
            raise ValueError(f"mw (or fc_hz) is needed for the high-pass of {motion.name!r}")
        fc_hz = brune_corner(mw, stress_bar, beta_kms)
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    if keep_axes:
        rotated, angle = motion, None
        meta = {"principal_angle_deg": None, "principal_offset_deg": None,
                "forced_angle_deg": None}
        say(f"{motion.name}: recorded axes kept (no rotation)")
    else:
        rotated, angle = to_principal_axes(motion, rotation)
        meta = rotated.metadata
        say(
            f"{motion.name}: principal angle {meta['principal_angle_deg']:.3f} deg "
            f"({meta['principal_offset_deg']:.3f} deg from axis "
            f"{meta['principal_reference_axis']}), rotated by {angle:.3f} deg",
        )
    # the record's own PGA before any processing: the per-record table's "as recorded"
    rotated = GroundMotion(rotated.ax, rotated.ay, rotated.dt, rotated.name,
                           {**rotated.metadata, "recorded_pga_g": motion.pga_g}, rotated.az)
    if rotated.az is not None:
        say(f"{motion.name}: with its vertical component (peak {motion.pga_vertical / G:.3f} g)"
            + ("; its synthetic pairs are horizontal" if n > 0 else ""))
    record = rotated
    if highpass != "none":
        record = highpass_motion(rotated, highpass, fc_hz, order)
        say(f"high-pass {highpass} at {fc_hz:.4f} Hz")
    timings["process_s"] = time.perf_counter() - t0
    sim = {"method": method, "axes": axes, "order": order, "highpass": highpass,
           "fc_hz": fc_hz, "max_duration": max_duration}
    motions, fit, quality, pairs_sha = _synthetic_pairs(rotated, record, n, seed, fit_method,
                                                        sim, timings, say, recorded)
    comparison, other = [], None
    if compare and n > 0:
        other_method = next(m for m in FIT_METHODS if m != fit_method)
        comparison, other_fit, other_quality, _ = _synthetic_pairs(
            rotated, record, n, seed, other_method, sim, {}, say)
        other = {"fit_method": other_method, "fit_quality": other_quality,
                 "fit": other_fit.to_dict()}
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
        "recorded_pga_g": motion.pga_g,
        "highpass": {"kind": highpass, "fc_hz": fc_hz, "order": order, "mw": mw,
                     "stress_bar": stress_bar, "beta_kms": beta_kms},
        "n_synthetic": int(n),
        "seed": int(seed),
        "method": method,
        "fit_method": fit_method,
        "fit_quality": quality,
        "comparison": other,
        "axes": axes,
        "max_duration": max_duration,
        "timings": timings,
        "fit_source": None if fit is None else ("recorded" if recorded else "fitted"),
        "pairs_sha256": pairs_sha,
        "motions_match": _motions_match(recorded, n, seed, pairs_sha, motion.name, say),
    }
    return EnsembleBuild(motions, fit, info, comparison)


def recorded_entries(build: EnsembleBuild,
                     settings: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Entries of a parameters file (:mod:`rocking.motions.stochastic.recorded`) by record
    name, for every record of ``build`` (one record or a suite) that has synthetic pairs.

    ``settings`` holds each record's settings in the build's order (keys
    :data:`~rocking.motions.stochastic.recorded.FIT_SETTINGS`; a suite's ``fit_method`` is
    the build's).
    """
    per_record = build.info["records"] if build.info.get("suite") else [build.parameters()]
    if len(per_record) != len(settings):
        raise ValueError(f"{len(settings)} settings for {len(per_record)} records")
    out = {}
    for p, given in zip(per_record, settings, strict=True):
        if p["fit"] is None:
            continue
        given = {**given, "fit_method": p["fit_method"]}
        out[p["fit"]["name"]] = record_entry(p["fit"], given, p["pairs_sha256"], p["seed"])
    return out


def _motions_match(recorded: dict[str, Any] | None, n: int, seed: int,
                   sha: list[str] | None, name: str, say: Callable[[str], None]) -> bool | None:
    """Whether the pairs made from a recorded fit are the recorded ones to the bit (None
    where the file recorded another seed, or no fit was recorded)."""
    match = None if not recorded or sha is None else pairs_match(recorded, seed, sha)
    if match:
        say(f"{name}: the {n} pairs made from the recorded parameters are the recorded ones "
            "to the bit")
    elif match is False:
        say(f"WARNING {name}: the {n} pairs made from the recorded parameters differ from the "
            "recorded ones in their bits (this machine's exp/sin or library versions differ "
            "from the one that wrote the file): answers may differ from the gallery's; "
            "`rocking verify` tells by how much")
    return match


SUITE_RECORD_KEYS = ("n_synthetic", "seed", "mw", "rotation_deg", "highpass", "fc_hz")
"""Settings of one record of a suite (:func:`build_suite`)."""


def build_suite(
    records: list[tuple[GroundMotion, dict[str, Any]]],
    *,
    fit_method: str = "spectrum",
    max_duration: float | None = None,
    recorded: dict[str, dict[str, Any]] | None = None,
    progress: Callable[[str], None] | None = None,
) -> EnsembleBuild:
    """Process every record of a suite with its own settings and synthesize its pairs.

    Parameters
    ----------
    records : list of (GroundMotion, dict)
        Each recorded pair [m/s²] and its settings: ``n_synthetic``, ``seed``, ``mw``,
        ``rotation_deg``, ``highpass``, ``fc_hz`` (:data:`SUITE_RECORD_KEYS`).
    fit_method : {"spectrum", "counts"}
        Identification of the RDK parameters of every record with synthetic pairs.
    max_duration : float, optional
        Keep only the first ``max_duration`` seconds of every motion [s].
    recorded : dict, optional
        Entries of a parameters file by record name (``recorded`` of :func:`build_ensemble`);
        a record without one is fitted.
    progress : callable, optional
        Called with one line of text after each stage.

    Returns
    -------
    EnsembleBuild
        ``motions``: the processed records in the order given, then each record's
        synthetic pairs (so the recorded motions come first, as in one record's ensemble);
        ``fit`` None; ``info["records"]``: each record's :meth:`EnsembleBuild.parameters`.

    Raises
    ------
    ValueError
        No records, a record without its settings, or two records of the same name.
    """
    if not records:
        raise ValueError("records must hold at least one (motion, settings) pair")
    names = [m.name for m, _ in records]
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ValueError(f"record names must be unique in a suite, repeated: {repeated}")
    builds = []
    for motion, settings in records:
        missing = [k for k in SUITE_RECORD_KEYS if k not in settings]
        if missing:
            raise ValueError(f"settings of record {motion.name!r} lack {missing}")
        builds.append(build_ensemble(
            motion, settings["n_synthetic"], settings["seed"],
            rotation=settings["rotation_deg"], highpass=settings["highpass"],
            fc_hz=settings["fc_hz"], mw=settings["mw"], max_duration=max_duration,
            fit_method=fit_method, recorded=(recorded or {}).get(motion.name),
            progress=progress))
    motions = [b.motions[0] for b in builds] + [m for b in builds for m in b.motions[1:]]
    per_record = [b.parameters() for b in builds]
    timings: dict[str, float] = {}
    for p in per_record:
        for k, v in p["timings"].items():
            timings[k] = timings.get(k, 0.0) + v
    info = {
        "suite": True,
        "record": ", ".join(names),
        "label": f"suite of {len(names)} records: {', '.join(names)}",
        "stand_in": any(p["stand_in"] for p in per_record),
        "stand_in_for": next((p["stand_in_for"] for p in per_record if p["stand_in"]), None),
        "rotation_deg": None,  # per record, in "records"
        "highpass": None,
        "n_synthetic": sum(p["n_synthetic"] for p in per_record),
        "seed": None,
        "fit_method": fit_method,
        "fit_quality": None,
        "comparison": None,
        "max_duration": max_duration,
        "timings": timings,
        "records": per_record,
    }
    return EnsembleBuild(motions, None, info)


def _synthetic_pairs(
    rotated: GroundMotion,
    record: GroundMotion,
    n: int,
    seed: int,
    fit_method: str,
    sim: dict[str, Any],
    timings: dict[str, float],
    say: Callable[[str], None],
    recorded: dict[str, Any] | None = None,
) -> tuple[list[GroundMotion], Any, dict[str, Any] | None, list[str] | None]:
    """[record, pairs…], the (rounded) RDK fit, the fit quality (None below 2 pairs) of one
    method and the digests of the pairs before any cut (None without pairs)."""
    motions, fit, quality, sha = [record], None, None, None
    if n > 0:
        hp: dict[str, Any] = {"highpass": False}
        if sim["highpass"] != "none":
            hp = {"highpass": sim["highpass"], "fc_hz": sim["fc_hz"]}
        t1 = time.perf_counter()
        if recorded:
            fit = recorded_fit(recorded)
            say(f"RDK fit recorded ({SIGNIFICANT_DIGITS} significant digits, fit_sha256 "
                f"{recorded['fit_sha256'][:12]}): {_describe(fit)}")
        else:
            # Fit the rotated record before its high-pass (a Butterworth's padding would
            # shift the envelope); the spectrum match compares both after the same
            # high-pass. It is on its principal axes already: a forced 0 keeps it there.
            # Rounded: the optimiser's last digits differ between machines, the rounded
            # parameters (written to the build's recorded_params) do not.
            fit = rounded_fit(fit_rdk(rotated, 0.0, method=fit_method, seed=seed,
                                      order=sim["order"], **hp))
            timings["fit_s"] = time.perf_counter() - t1
            say(f"RDK fit ({fit_method}) in {timings['fit_s']:.1f} s, rounded to "
                f"{SIGNIFICANT_DIGITS} significant digits: {_describe(fit)}")
        t2 = time.perf_counter()
        pairs = synthesize(fit, n, seed, method=sim["method"], axes=sim["axes"],
                           order=sim["order"], **hp)
        sha = pairs_sha256(pairs)
        motions += pairs
        timings["synthesize_s"] = time.perf_counter() - t2
        say(f"{n} synthetic pairs in {timings['synthesize_s']:.1f} s")
    if sim["max_duration"] is not None:
        motions = [cut(m, sim["max_duration"]) for m in motions]
    if n >= 2 and sim["axes"] == "principal":
        quality = ensemble_quality(motions)
    return motions, fit, quality, sha


def _describe(fit: Any) -> str:
    """One line of the fitted spectral parameters of both components."""
    parts = []
    for name, p in (("major", fit.major), ("minor", fit.minor)):
        text = f"{name} f_mid {p.f_mid:.2f} Hz, zeta_f {p.zeta_f:.3f}"
        if p.f_mid2 is not None:
            text += f"; f_mid2 {p.f_mid2:.2f} Hz, zeta_f2 {p.zeta_f2:.3f}, share2 {p.share2:.2f}"
        if p.f_low is not None:
            text += f"; f_low {p.f_low:.2f} Hz, zeta_low {p.zeta_low:.2f}"
        parts.append(text)
    return " | ".join(parts)


def comparison_path(out: str | Path) -> Path:
    """File of the other identification's ensemble: ``<out stem>.compare.nc``."""
    out = Path(out)
    return out.with_name(f"{out.stem}.compare.nc")


def quality_lines(params: dict[str, Any]) -> list[str]:
    """Fit-quality summary of an ensemble (and of its comparison) as text lines; of each
    record of a suite."""
    if params.get("records"):
        return [line for p in params["records"] for line in quality_lines(p)]
    lines = []
    runs = [(params.get("fit_method"), params.get("fit_quality"))]
    if params.get("comparison"):
        runs.append((params["comparison"]["fit_method"], params["comparison"]["fit_quality"]))
    for method, quality in runs:
        if quality is None:
            lines.append(f"{params['record']}: no fit quality ({method}; needs >= 2 pairs "
                         "on principal axes)")
        else:
            lines += format_quality(quality, f"{params['record']}, {method} fit: 5 % PSA of "
                                    f"the ensemble (geometric mean) / record")
    return lines


def cut(motion: GroundMotion, max_duration: float) -> GroundMotion:
    """The first ``max_duration`` [s] of a motion (the motion itself if it is not longer).

    Counted from the start of the record: the zeros an acausal (Butterworth) high-pass put
    in front are kept besides, else a short cut would keep only padding.
    """
    front = sum(int(s.get("pad_front", 0)) for s in motion.metadata.get("processing", [])
                if isinstance(s, dict) and s.get("step") == "highpass")
    keep = front + int(round(positive_finite("max_duration", max_duration) / motion.dt)) + 1
    if keep >= motion.npts:
        return motion
    meta = dict(motion.metadata)
    meta["processing"] = [*meta.get("processing", []),
                          {"step": "truncate", "max_duration": max_duration, "npts": keep}]
    return GroundMotion(motion.ax[:keep], motion.ay[:keep], motion.dt, motion.name, meta,
                        None if motion.az is None else motion.az[:keep])
