"""A study's fragility in any intensity measure and horizontal component, from its motions.

The critical-intensity search scales each motion: its answer is a critical scale factor s_m,
and the study stores s_m times the motion's vector-peak PGA (``pga_crit`` of ``critical.csv``,
over g tan α). Every intensity measure of :mod:`rocking.motions.measures` is linear in the
scale of a record, so the motion's critical measure in another (measure, component) is
exactly

    IM_m,crit = s_m · IM_m = pga_crit_m · g tan α · r_m,    r_m = IM_m / PGA_vp,m,

with r_m the motion's own ratio of that measure to its vector-peak PGA (``motion_measures.csv``,
:func:`motion_measures`); a motion not reached up to the search bound u [PGA/(g tan α)] is
censored at u · tan α · r_m. The lognormal is then fitted as ``fragility.csv`` is
(:func:`rocking.fragility.lognormal.fit_lognormal`, right-censored), with the same bootstrap
over the motions (:func:`rocking.fragility.lognormal.bootstrap_lognormal`, same seed, so
resample r draws the same motions in every cell and every component). In the vector-peak PGA
(r_m = 1) the refit is ``fragility.csv``'s own fit (to the 10 digits ``critical.csv`` keeps).

The median in another component is therefore the vector-peak one times the geometric mean
of the motions' ratios where no motion is censored (ln θ = mean ln x), and β changes by the
spread of the ratios: what "the records' ratio" means for a fragility.

``motion_measures.csv`` (long: one row per motion, measure and component): ``motion``,
``kind`` (record, synthetic), ``pga_g`` [g] (the vector-peak PGA, the spectra's intensity),
``measure``, ``component``, ``unit``, ``value`` [unit]. The workflow writes it beside a study's
tables (rule ``motion_measures``) in every component of
:data:`rocking.motions.measures.COMPONENTS` and every measure of the study.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from rocking.fragility.bootstrap import BootstrapSamples
from rocking.fragility.lognormal import (
    AT_BOUND,
    BOOTSTRAP_RESAMPLES,
    BOOTSTRAP_SEED,
    bootstrap_lognormal,
    fit_lognormal,
)
from rocking.motions.measures import COMPONENTS, DEFAULT_COMPONENT, Measure, parse_component

MOTION_MEASURES = "motion_measures.csv"
"""The file of every motion's measures beside a study's tables."""

MEASURE_COLUMNS = ("motion", "kind", "pga_g", "measure", "component", "unit", "value")
"""Columns of ``motion_measures.csv``."""

CELL = ("mode", "limit_state", "tan_alpha", "R")
"""What identifies a cell of the study (a body in a mode, one limit state)."""


def motion_measures(motions, measures: Sequence[str],
                    components: Sequence[str] = tuple(COMPONENTS)) -> pd.DataFrame:
    """Every motion's ``measures`` in every one of ``components`` (:data:`MEASURE_COLUMNS`).

    Parameters
    ----------
    motions : sequence of GroundMotion
        The study's motions (its ensemble file).
    measures : sequence of str
        Intensity measures; ``pga`` is always given.
    components : sequence of str
        Horizontal components (default: every one the project knows).
    """
    from rocking.motions.identity import identity

    wanted = list(dict.fromkeys([Measure("pga"), *(Measure.of(m) for m in measures)]))
    rows = []
    for motion in motions:
        kind = identity(motion)["kind"]
        for measure in wanted:
            for component in components:
                rows.append({"motion": motion.name, "kind": kind, "pga_g": motion.pga_g,
                             "measure": measure.name, "component": parse_component(component),
                             "unit": measure.unit,
                             "value": measure.of_motion(motion, component)})
    return pd.DataFrame(rows, columns=list(MEASURE_COLUMNS))


def write_motion_measures(motions_path: str | Path, measures: Sequence[str],
                          csv: str | Path) -> Path:
    """``motion_measures.csv`` of an ensemble file (written under a temporary name)."""
    from rocking.motions.ensemble_io import load_ensemble
    from rocking.provenance import write_atomic
    from rocking.units import CSV_FLOAT_FORMAT

    frame = motion_measures(load_ensemble(motions_path), measures)
    return write_atomic(csv, lambda tmp: frame.to_csv(tmp, index=False,
                                                      float_format=CSV_FLOAT_FORMAT))


def read_motion_measures(path: str | Path) -> pd.DataFrame:
    """``motion_measures.csv``, its measures in their canonical names."""
    frame = pd.read_csv(path)
    missing = sorted(set(MEASURE_COLUMNS) - set(frame.columns))
    if missing:
        raise ValueError(f"{path}: lacks the columns {missing} (a motion_measures.csv has "
                         f"{', '.join(MEASURE_COLUMNS)})")
    frame["measure"] = [Measure.of(str(m)).name for m in frame["measure"]]
    return frame


def available(table: pd.DataFrame | None) -> set[tuple[str, str]]:
    """The (measure, component) pairs a motion-measures table can refit in; the vector-peak
    PGA always (its ratio is 1)."""
    out = {("pga", DEFAULT_COMPONENT)}
    if table is not None:
        out |= set(zip(table["measure"], table["component"], strict=True))
    return out


def motion_ratios(table: pd.DataFrame | None, measure, component: str) -> dict[str, float] | None:
    """Each motion's ratio r = IM/PGA_vp in ``measure`` and ``component`` [unit per g]; None
    for the vector-peak PGA (1 for every motion, nothing to look up)."""
    measure, component = Measure.of(measure), parse_component(component)
    if measure == Measure("pga") and component == DEFAULT_COMPONENT:
        return None
    if table is None:
        raise ValueError(f"no motion measures to refit the fragility in {measure} "
                         f"{component}")
    part = table[(table["measure"] == measure.name) & (table["component"] == component)]
    if part.empty:
        raise ValueError(f"the motion measures have no {measure} in {component} (they have "
                         f"{sorted(available(table))})")
    ratio = part["value"].to_numpy(float) / part["pga_g"].to_numpy(float)
    bad = ~np.isfinite(ratio) | (ratio <= 0)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"motion {part['motion'].iloc[i]!r} has {measure} {component} = "
                         f"{part['value'].iloc[i]!r}: no ratio to its PGA")
    return dict(zip(part["motion"].astype(str), ratio, strict=True))


def cell_samples(critical: pd.DataFrame, bound: float | None, ratios: dict | None = None):
    """``(cell, values, censored)`` per cell of ``critical`` (``mode, limit_state, motion,
    tan_alpha, R, pga_crit, not_reached[, failed]``; titles without units), in its order:
    the critical measures in the measure's unit (PGA in g times each motion's ratio), not
    reached ones censored at the bound, failed analyses left out (they say nothing of the
    intensity)."""
    frame = critical
    failed = frame["failed"].astype(bool).to_numpy() if "failed" in frame else \
        np.zeros(len(frame), bool)
    for key, idx in frame.groupby(list(CELL), sort=False).indices.items():
        cell = frame.iloc[idx]
        ok = ~failed[idx]
        tan_alpha = float(key[2])
        x = cell["pga_crit"].to_numpy(float)[ok] * tan_alpha
        c = cell["not_reached"].astype(bool).to_numpy()[ok]
        unbounded = c & ~np.isfinite(x)
        if unbounded.any():
            if bound is None:
                raise ValueError(f"not-reached motions at {dict(zip(CELL, key, strict=True))} "
                                 "and no search bound to censor them at")
            x[unbounded] = bound * tan_alpha
        if ratios is not None:
            motions = cell["motion"].astype(str).to_numpy()[ok]
            try:
                x = x * np.array([ratios[m] for m in motions])
            except KeyError as exc:
                raise ValueError(f"motion {exc.args[0]!r} of the study has no measures in "
                                 "the motion-measures table") from None
        keep = np.isfinite(x)
        yield key, x[keep], c[keep]


def fit_cells(critical: pd.DataFrame, measure="pga", component: str = DEFAULT_COMPONENT, *,
              ratios: dict | None = None, bound: float | None = None,
              n_resamples: int = BOOTSTRAP_RESAMPLES, seed: int = BOOTSTRAP_SEED,
              ) -> tuple[pd.DataFrame, BootstrapSamples]:
    """The censored lognormal of every cell of ``critical`` in ``measure`` and ``component``
    (module docstring), with its bootstrap over the motions.

    Returns
    -------
    (pandas.DataFrame, BootstrapSamples)
        One row per cell: ``mode, limit_state, tan_alpha, R, median`` [the measure's unit],
        ``beta``, ``n``, ``n_censored``, ``status`` (``median-at-bound`` where the median is
        at or above the censoring bound in the measure), ``median_p05``, ``median_p95``
        (the 90 % interval over the resamples), ``bootstrap_fitted``; and the resamples'
        θ and β, one row per row of the table.
    """
    from rocking.fragility.lognormal import percentile_interval

    measure = Measure.of(measure)
    rows, med_s, beta_s = [], [], []
    for key, x, c in cell_samples(critical, bound, ratios):
        fit = fit_lognormal(x, c) if x.size else None
        if fit is None or not math.isfinite(fit.median) or n_resamples == 0:
            med = beta = np.full(n_resamples, np.nan)
        else:
            med, beta = bootstrap_lognormal(x, c, n_resamples=n_resamples, seed=seed)
        lo, hi = percentile_interval(med) if n_resamples else (math.nan, math.nan)
        status = "too-few-observed" if fit is None else fit.status
        if fit is not None and status == "ok" and c.any() and \
                fit.median >= np.min(x[c]) * (1.0 - 1e-9):
            status = AT_BOUND  # the median is at or beyond where the search stopped
        rows.append({**dict(zip(CELL, key, strict=True)),
                     "median": math.nan if fit is None else fit.median,
                     "beta": math.nan if fit is None else fit.beta,
                     "n": int(x.size), "n_censored": int(c.sum()), "status": status,
                     "median_p05": float(lo), "median_p95": float(hi),
                     "bootstrap_fitted": int(np.isfinite(med).sum())})
        med_s.append(med)
        beta_s.append(beta)
    frame = pd.DataFrame(rows, columns=[*CELL, "median", "beta", "n", "n_censored", "status",
                                        "median_p05", "median_p95", "bootstrap_fitted"])
    frame.insert(0, "measure", measure.name)
    frame.insert(1, "component", parse_component(component))
    frame.insert(2, "unit", measure.unit)
    shape = (len(rows), n_resamples)
    samples = BootstrapSamples(np.array(med_s).reshape(shape), np.array(beta_s).reshape(shape),
                               f"refit in {measure} {component}")
    return frame, samples


def read_critical(path: str | Path, *, mode: str | None = None,
                  limit_states: Sequence[str] | None = None) -> pd.DataFrame:
    """``critical.csv`` with titles without units and canonical limit states, optionally only
    one mode and some limit states."""
    from rocking.spectra.limit_states import parse_limit_state
    from rocking.units import read_table

    frame = read_table(path)
    missing = sorted({"mode", "limit_state", "motion", "tan_alpha", "R", "pga_crit",
                      "not_reached"} - set(frame.columns))
    if missing:
        raise ValueError(f"{path}: lacks the columns {missing} (a critical.csv of the "
                         "spectra)")
    frame["limit_state"] = [parse_limit_state(str(s)).name for s in frame["limit_state"]]
    if mode is not None:
        frame = frame[frame["mode"].astype(str) == mode]
    if limit_states is not None:
        names = {parse_limit_state(s).name for s in limit_states}
        frame = frame[frame["limit_state"].isin(names)]
    return frame.reset_index(drop=True)


def study_bound(fragility_csv: str | Path) -> float | None:
    """The search bound [PGA/(g tan α)] a study's ``fragility.csv`` was censored at (its
    ``censoring_bound`` column; None for a table without one)."""
    from rocking.units import read_table

    frame = read_table(fragility_csv)
    if "censoring_bound" not in frame.columns:
        return None
    values = frame["censoring_bound"].dropna().astype(float).unique()
    return float(values[0]) if values.size else None


def study_folder(study: str | Path) -> Path:
    """A study's results folder, given it or one of its tables."""
    study = Path(study)
    return study.parent if study.suffix in (".csv", ".nc") else study


def refit_study(study: str | Path, measure="pga", component: str = DEFAULT_COMPONENT, *,
                mode: str | None = None, limit_states: Sequence[str] | None = None,
                n_resamples: int = BOOTSTRAP_RESAMPLES, seed: int = BOOTSTRAP_SEED):
    """A study's critical-intensity fragility in ``measure`` and ``component``, refitted from
    its folder: ``critical.csv`` (each motion's critical PGA), ``fragility.csv`` (the search
    bound the motions not reached are censored at) and, for anything but the vector-peak PGA,
    ``motion_measures.csv`` (:func:`fit_cells`).

    Returns
    -------
    rocking.fragility.table.Fragilities
        With its bootstrap resamples in memory and a ``note`` saying where it comes from.

    Raises
    ------
    ValueError
        One line naming the folder and the file that is missing, and how it is made.
    """
    from dataclasses import replace

    from rocking.fragility.table import CRITICAL_INTENSITY, read_fragilities

    folder = study_folder(study)
    measure, component = Measure.of(measure), parse_component(component)
    critical = folder / "critical.csv"
    if not critical.is_file():
        raise ValueError(f"{folder}: no critical.csv there (each motion's critical PGA, "
                         "which the fragility is fitted to: a study's results folder, e.g. "
                         "results/paper/elcentro; the workflow's rule critical_table)")
    vector_pga = measure == Measure("pga") and component == DEFAULT_COMPONENT
    table = None
    if not vector_pga:
        path = folder / MOTION_MEASURES
        if not path.is_file():
            raise ValueError(f"{folder}: no {MOTION_MEASURES} there, so the fragility cannot "
                             f"be refitted in {measure} {component} (each motion's ratio of "
                             "it to the vector-peak PGA): the workflow writes it for a study "
                             "with a hazard: (rule motion_measures)")
        table = read_motion_measures(path)
    frame = read_critical(critical, mode=mode, limit_states=limit_states)
    if frame.empty:
        raise ValueError(f"{critical}: no answer in mode {mode!r}"
                         + (f" for {list(limit_states)}" if limit_states else ""))
    bound = study_bound(folder / "fragility.csv") if (folder / "fragility.csv").is_file() \
        else None
    fits, samples = fit_cells(frame, measure, component,
                              ratios=motion_ratios(table, measure, component), bound=bound,
                              n_resamples=n_resamples, seed=seed)
    frag = read_fragilities(fits, CRITICAL_INTENSITY, bootstrap=False)
    note = "" if vector_pga else (
        f"the fragility refitted in {measure} {component} from each motion's critical PGA "
        f"({critical}) and its ratio of {measure} {component} to the vector-peak PGA "
        f"({folder / MOTION_MEASURES})")
    quantity = _study_quantity(folder)
    return replace(frag, samples=samples if n_resamples else None, source=str(critical),
                   quantity=quantity, note=note, refitted=not vector_pga)


def _study_quantity(folder: Path) -> dict:
    """The quantity of the study's ``fragility.csv`` (:func:`~rocking.fragility.table.
    quantity_of`; the legacy first exceedance without one)."""
    from rocking.fragility.table import LEGACY_QUANTITY, quantity_of
    from rocking.units import read_table

    path = folder / "fragility.csv"
    return quantity_of(read_table(path)) if path.is_file() else dict(LEGACY_QUANTITY)


__all__ = ["CELL", "MEASURE_COLUMNS", "MOTION_MEASURES", "available", "cell_samples",
           "fit_cells", "motion_measures", "motion_ratios", "read_critical",
           "read_motion_measures", "refit_study", "study_bound", "study_folder",
           "write_motion_measures"]
