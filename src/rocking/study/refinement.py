"""How far a study's answers move under refinement, measured on a sample of its own cells.

A stated sample of the study's answered cells is searched again with a converged setting: a
fixed scan of :data:`REFINED_STEP` (0.05 %) of the intensity from uplift up to the answer,
with the study's own ODE tolerance, bisection and rest criterion, so the only change is the
scan (resolution benchmark, docs/performance.md: windows of exceedance are 0.02–0.25 % wide;
a 0.05 % scan finds nearly all of them). The refined answer is the lower of the two (the
run's answer is an exceedance already found); the shift (refined − answer)/answer is ≤ 0.

The sample (:func:`choose_cells`): per (mode, limit state) ``k`` reached cells drawn with a
seeded generator, and every cell of the headline mean (the primary mode's overturning at the
largest size R, at the study's main slenderness). Each point (mode, motion, tan α, R) is
searched once for all its sampled limit states. The cost is capped per point
(``max_analyses``): a point whose scan needs more (ln(answer/uplift)/ln(1.0005) points:
about 3100 for an answer 4.75 above uplift at 1, 6100 for 21) is not run and is recorded
``truncated`` with no refined answer. One analysis of a 10 m cylinder under El Centro costs
about 7 ms of CPU (the record at R = 10 m: 3126 analyses in 23 s, its answer 5.428 refined to
4.771, where the resolution benchmark's converged reference is 4.774), so a point costs up to
``max_analyses`` × 7 ms.

``refinement_sample.csv`` (:func:`write_refinement_sample`) has one row per sampled cell:
mode, limit_state, motion, tan_alpha, R, why ("sample" or "headline"), answer, refined,
shift, analyses, truncated, and the draw's k and seed (the same on every row, so the table
states its sample). The report reads it through :mod:`rocking.plot.refined`.

λ under refinement (:func:`write_refinement_risk`, ``refinement_risk.csv``): at every point
(mode, limit state, tan α, R) holding a refined cell, the lognormal fragility is fitted again
with the refined answers substituted (the study's own fit,
:func:`rocking.fragility.lognormal.fit_lognormal`, censoring included) and integrated with the
study's hazard curve (:func:`rocking.risk.annual_frequency.mean_annual_frequency`, the
function of ``risk.csv``); exact where every cell of the point was refined (the headline
point), a part of the move elsewhere.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

REFINED_STEP = 0.0005
"""Relative step of the refining scan [-] (0.05 %)."""
COLUMNS = ("mode", "limit_state", "motion", "tan_alpha", "R", "why", "answer", "refined",
           "shift", "analyses", "truncated")
"""Columns of ``refinement_sample.csv`` (intensities in PGA/(g tan α), R in m), before the
draw's ``k`` and ``seed``."""


@dataclass(frozen=True)
class SampleSpec:
    """What is refined.

    Parameters
    ----------
    k : int
        Cells drawn per (mode, limit state) [-], >= 0.
    seed : int
        Seed of the draw.
    max_analyses : int
        Analyses allowed per point (mode, motion, tan α, R) [-], > 0.
    headline : bool
        Add every cell of the headline mean (primary mode, overturning, largest R).
    """

    k: int = 2
    seed: int = 0
    max_analyses: int = 5000
    headline: bool = True

    def __post_init__(self) -> None:
        for name, low in (("k", 0), ("max_analyses", 1)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < low:
                raise ValueError(f"refinement.{name} must be an integer >= {low}, got {v!r}")

    @classmethod
    def from_config(cls, cfg: Mapping | None) -> SampleSpec:
        """From the configuration's ``refinement:`` mapping (absent keys: the defaults)."""
        cfg = dict(cfg or {})
        unknown = set(cfg) - {"k", "seed", "max_analyses", "headline"}
        if unknown:
            raise ValueError(f"refinement: unknown key(s) {sorted(unknown)}")
        return cls(**cfg)


def answered_cells(store) -> pd.DataFrame:
    """Cells of a spectra store with an answer (reached, finite): mode, limit_state, motion,
    tan_alpha, R, answer [PGA/(g tan α)]."""

    ds = store
    crit = ds["pga_crit"].transpose("mode", "limit_state", "motion", "tan_alpha", "R")
    reached = ~ds["not_reached"].transpose(*crit.dims).values.astype(bool)
    values = crit.values.astype(float)
    return _cell_frame(ds, crit.dims, values, np.isfinite(values) & reached)


def _cell_frame(ds, dims, values: np.ndarray, keep: np.ndarray, **extra) -> pd.DataFrame:
    """One row per kept cell of a (mode, limit_state, motion, tan_alpha, R) array: its
    labels, ``answer`` and each of ``extra`` (arrays of the same shape)."""
    from rocking.spectra.limit_states import parse_limit_state

    idx = np.argwhere(keep)
    coords = [np.asarray(ds[d].values) for d in dims]
    at = tuple(idx.T)
    return pd.DataFrame({
        "mode": [_text(coords[0][i]) for i in idx[:, 0]],
        "limit_state": [parse_limit_state(_text(coords[1][i])).name for i in idx[:, 1]],
        "motion": [_text(coords[2][i]) for i in idx[:, 2]],
        "tan_alpha": coords[3][idx[:, 3]].astype(float),
        "R": coords[4][idx[:, 4]].astype(float),
        "answer": values[at], **{k: v[at] for k, v in extra.items()},
    })


def cells_from_table(path: str | Path) -> pd.DataFrame:
    """:func:`answered_cells` of a ``critical.csv`` (the table a study writes beside its
    store): the reached rows with a finite answer."""
    from rocking.spectra.limit_states import parse_limit_state

    df = pd.read_csv(path)
    col = {c.split(" [")[0]: c for c in df.columns}
    answer = pd.to_numeric(df[col["pga_crit"]], errors="coerce").astype(float)
    reached = ~df[col["not_reached"]].astype(str).str.lower().isin(["true", "1"])
    df = df[reached & np.isfinite(answer)]
    return pd.DataFrame({
        "mode": df["mode"].astype(str).to_numpy(),
        "limit_state": [parse_limit_state(str(x)).name for x in df["limit_state"]],
        "motion": df["motion"].astype(str).to_numpy(),
        "tan_alpha": df[col["tan_alpha"]].astype(float).to_numpy(),
        "R": df[col["R"]].astype(float).to_numpy(),
        "answer": answer[df.index].to_numpy(),
    })


def _text(v) -> str:
    """A coordinate label as text (zarr may hand back bytes)."""
    return v.decode() if isinstance(v, bytes) else str(v)


def choose_cells(cells: pd.DataFrame, spec: SampleSpec) -> pd.DataFrame:
    """The sample: ``k`` cells per (mode, limit state) drawn with ``seed`` (groups in sorted
    order, so the draw does not depend on the table's order), plus the headline cells."""
    rng = np.random.default_rng(spec.seed)
    cells = cells.sort_values(["mode", "limit_state", "motion", "tan_alpha", "R"]).reset_index(
        drop=True)
    picked: dict[int, str] = {}
    if spec.headline and len(cells):
        for i in headline_cells(cells).index:
            picked[int(i)] = "headline"
    if spec.k:
        for _, group in cells.groupby(["mode", "limit_state"], sort=True):
            take = rng.choice(group.index.to_numpy(), size=min(spec.k, len(group)),
                              replace=False)
            for i in sorted(int(x) for x in take):
                picked.setdefault(i, "sample")
    out = cells.loc[sorted(picked)].copy()
    out.insert(5, "why", [picked[i] for i in out.index])
    return out.reset_index(drop=True)


def headline_cells(cells: pd.DataFrame) -> pd.DataFrame:
    """Cells of the headline mean: mode "3d" (else the first mode), overturning (else the
    most severe limit state), tan α 0.2 (else the most frequent), the largest R."""
    from rocking.spectra.limit_states import severity
    from rocking.spectra.modes import MODE_3D

    modes = list(dict.fromkeys(cells["mode"]))
    mode = MODE_3D if MODE_3D in modes else modes[0]
    sub = cells[cells["mode"] == mode]
    states = list(dict.fromkeys(sub["limit_state"]))
    ls = "overturning" if "overturning" in states else max(states, key=severity)
    sub = sub[sub["limit_state"] == ls]
    tans = sub["tan_alpha"]
    t = 0.2 if np.isclose(tans, 0.2).any() else float(tans.mode().iloc[0])
    sub = sub[np.isclose(sub["tan_alpha"], t)]
    return sub[sub["R"] == sub["R"].max()]


def refine_point(motion, mode: str, R: float, tan_alpha: float, answers: Mapping[str, float],
                 accuracy, *, upper: float, max_analyses: int,
                 omega_n: float | None = None, zeta: float | None = None) -> dict:
    """Scan one point again from uplift up to its answers in steps of :data:`REFINED_STEP`.

    Each analysis runs with the study's ODE tolerance and rest criterion (a failed one is
    retried at a tenth of it, as the search does) until the largest goal still open, and
    decides every goal as the search does
    (:func:`rocking.spectra.limit_states.classify`). A goal's refined answer is the first
    exceeding scan point, or the run's answer when none lies below it (it was an exceedance
    already); the scan point is within 0.05 % above the boundary of its window, finer than
    any bisection of the presets.

    Parameters
    ----------
    motion : GroundMotion
    mode : str
    R, tan_alpha : float
        Size [m] and slenderness [-].
    answers : mapping of str to float
        The run's answer per limit state [PGA/(g tan α)].
    accuracy : str, dict or Accuracy
        The study's tolerances (``tolerances`` of its store).
    upper : float
        The study's search bound [-].
    max_analyses : int
        Analyses allowed. A scan that needs more points than this (known beforehand from
        ln(answer/uplift)/ln(1.0005)) is not started; one that runs out (retried failures)
        stops: either way the point is ``truncated`` and its refined answers NaN.

    Returns
    -------
    dict
        ``refined``: {limit state: refined answer}, ``analyses``, ``truncated``.
    """
    from rocking.dynamics.bodies import Cylinder
    from rocking.dynamics.result import Status
    from rocking.spectra.accuracy import get_accuracy
    from rocking.spectra.critical import MODES, make_analysis, uplift_intensity
    from rocking.spectra.limit_states import classify, parse_limit_states, stop_for
    from rocking.spectra.search import RETRY_RTOL_FACTOR

    acc = get_accuracy(accuracy)
    body = Cylinder(float(R), float(tan_alpha))
    names = list(answers)
    states = parse_limit_states(names, sort=False)
    goal = np.array([float(answers[n]) for n in names])
    analyze = make_analysis(body, motion, mode, omega_n=omega_n, zeta=zeta,
                            rest_tilt=acc.rest_tilt)
    rtol = acc.rtol_for(MODES[mode][0])
    lower = uplift_intensity(motion, mode)
    first = np.full(len(states), np.nan)
    top = min(float(goal.max()), upper)
    if not math.isfinite(lower):  # the component is zero: nothing to refine (never reached)
        return {"refined": dict(answers), "analyses": 0, "truncated": False}
    needed = math.ceil(math.log(top / lower) / math.log1p(REFINED_STEP)) if top > lower else 0
    if needed > max_analyses:  # known before any analysis: no CPU spent on a cut scan
        return {"refined": {ls: float("nan") for ls in names}, "analyses": 0,
                "truncated": True}
    n, analyses = 0, 0
    while True:
        n += 1
        intensity = lower * (1.0 + REFINED_STEP) ** n
        open_ = np.isnan(first) & (intensity < goal)
        if intensity >= top or not open_.any():
            break
        if analyses >= max_analyses:
            return {"refined": {ls: float("nan") for ls in names}, "analyses": analyses,
                    "truncated": True}
        stop_at = stop_for([ls for ls, o in zip(states, open_, strict=True) if o], body.alpha)
        out = analyze(intensity, stop_at, rtol)
        analyses += 1
        if out.status is Status.FAILED:
            out = analyze(intensity, stop_at, rtol * RETRY_RTOL_FACTOR)
            analyses += 1
        if out.status is Status.FAILED:
            continue  # nothing learnt here
        known, exceeded = classify(out, states, body.alpha, stop_at,
                                   stopped=out.status is Status.STOPPED_AT_LIMIT)
        first[open_ & known & exceeded] = intensity
    refined = {ls: float(min(f, a)) if np.isfinite(f) else float(a)
               for ls, f, a in zip(names, first, goal, strict=True)}
    return {"refined": refined, "analyses": analyses, "truncated": False}


def _refine_task(args) -> dict:
    return refine_point(*args[0], **args[1])


def refine_sample(sample: pd.DataFrame, motions: Sequence, accuracy, *, upper: float,
                  max_analyses: int, omega_n: float | None = None, zeta: float | None = None,
                  n_workers: int = 1) -> pd.DataFrame:
    """The sample with its refined answers: one search per point, ``n_workers`` processes."""
    by_name = {m.name: m for m in motions}
    missing = sorted(set(sample["motion"]) - set(by_name))
    if missing:
        raise ValueError(f"motion {missing[0]!r} of the sample is not in the ensemble file "
                         f"(it has {sorted(by_name)})")
    points = list(sample.groupby(["mode", "motion", "tan_alpha", "R"], sort=True))
    tasks = [((by_name[motion], mode, R, t, dict(zip(rows["limit_state"], rows["answer"],
                                                      strict=True)), accuracy),
              {"upper": upper, "max_analyses": max_analyses, "omega_n": omega_n,
               "zeta": zeta})
             for (mode, motion, t, R), rows in points]
    if n_workers > 1 and len(tasks) > 1:
        with ProcessPoolExecutor(n_workers) as pool:
            results = list(pool.map(_refine_task, tasks))
    else:
        results = [_refine_task(t) for t in tasks]
    out = sample.copy()
    out["refined"], out["analyses"], out["truncated"] = np.nan, 0, False
    for ((_, rows), res) in zip(points, results, strict=True):
        for i, ls in zip(rows.index, rows["limit_state"], strict=True):
            out.loc[i, "refined"] = res["refined"][ls]
            out.loc[i, "analyses"] = res["analyses"]
            out.loc[i, "truncated"] = res["truncated"]
    out["shift"] = (out["refined"] - out["answer"]) / out["answer"]
    return out[list(COLUMNS)]


def write_refinement_sample(store_path: str | Path, motions_path: str | Path,
                            out_csv: str | Path, spec: SampleSpec, n_workers: int = 1) -> int:
    """Choose, refine and write ``refinement_sample.csv`` of a finished spectra store.

    Returns
    -------
    int
        Rows written.
    """
    import warnings

    import xarray as xr

    from rocking.motions.ensemble_io import load_ensemble
    from rocking.store import read_attrs
    from rocking.units import CSV_FLOAT_FORMAT

    with warnings.catch_warnings():  # a store written without consolidated metadata is read too
        warnings.simplefilter("ignore", RuntimeWarning)
        with xr.open_zarr(store_path) as store:
            cells = answered_cells(store.load())
    attrs = read_attrs(store_path)
    options = attrs.get("search_options", {})
    sample = choose_cells(cells, spec)
    table = refine_sample(sample, load_ensemble(motions_path), attrs["tolerances"],
                          upper=float(options.get("upper", 20.0)),
                          max_analyses=spec.max_analyses, omega_n=options.get("omega_n"),
                          zeta=options.get("zeta"), n_workers=n_workers)
    table = table.assign(k=spec.k, seed=spec.seed)  # the table states how it was drawn
    table.to_csv(out_csv, index=False, float_format=CSV_FLOAT_FORMAT)
    return len(table)


# ------------------------------------------------------------------ λ under refinement

RISK_COLUMNS = ("mode", "limit_state", "tan_alpha [-]", "R [m]", "n", "n_refined",
                "median [g tan(alpha)]", "beta [-]", "median_refined [g tan(alpha)]",
                "beta_refined [-]", "maf [1/yr]", "maf_refined [1/yr]", "shift [-]")
"""Columns of ``refinement_risk.csv`` (:func:`write_refinement_risk`)."""


def critical_cells(path: str | Path, bound: float | None = None) -> pd.DataFrame:
    """Every computed cell of a ``critical.csv``, as the fragility fit sees it: mode,
    limit_state, motion, tan_alpha, R, answer [PGA/(g tan α)], censored. A not-reached cell
    is right-censored at its stored value, or at ``bound`` (the search bound) where none is
    stored, as :func:`rocking.fragility.lognormal.fragility_table` does; a cell without a value
    that was not censored (never computed, failed) is left out, as there."""
    from rocking.spectra.limit_states import parse_limit_state

    df = pd.read_csv(path)
    col = {c.split(" [")[0]: c for c in df.columns}
    answer = pd.to_numeric(df[col["pga_crit"]], errors="coerce").to_numpy(dtype=float,
                                                                          copy=True)
    censored = df[col["not_reached"]].astype(str).str.lower().isin(["true", "1"]).to_numpy()
    unbounded = censored & ~np.isfinite(answer)
    if unbounded.any():
        if bound is None:
            raise ValueError(f"{path}: not-reached cells without a value and no censoring "
                             "bound: pass bound=<search bound>")
        answer[unbounded] = bound
    keep = np.isfinite(answer)
    return pd.DataFrame({
        "mode": df["mode"].astype(str).to_numpy()[keep],
        "limit_state": [parse_limit_state(str(x)).name for x in df["limit_state"][keep]],
        "motion": df["motion"].astype(str).to_numpy()[keep],
        "tan_alpha": df[col["tan_alpha"]].astype(float).to_numpy()[keep],
        "R": df[col["R"]].astype(float).to_numpy()[keep],
        "answer": answer[keep],
        "censored": censored[keep],
    })


def refit_points(cells: pd.DataFrame, sample: pd.DataFrame) -> pd.DataFrame:
    """The lognormal fragility of every point (mode, limit state, tan α, R) holding a refined
    cell of ``sample``, fitted as the study fits it
    (:func:`rocking.fragility.lognormal.fit_lognormal`) from ``cells``
    (:func:`critical_cells`) as they are and with the sample's refined answers substituted.

    Returns
    -------
    pandas.DataFrame
        mode, limit_state, tan_alpha, R, n (motions behind the fit), n_refined (of them
        refined), median, beta, median_refined, beta_refined (medians in PGA/(g tan α); NaN
        where the fit has none).
    """
    from rocking.fragility.lognormal import fit_lognormal

    ok = sample[~sample["truncated"].astype(bool)
                & np.isfinite(sample["refined"].astype(float))]
    rows = []
    for (mode, ls, t, R), s in ok.groupby(["mode", "limit_state", "tan_alpha", "R"],
                                          sort=True):
        at = cells[(cells["mode"] == mode) & (cells["limit_state"] == ls)
                   & np.isclose(cells["tan_alpha"], t) & np.isclose(cells["R"], R)]
        if at.empty:
            continue
        x, c = at["answer"].to_numpy(float), at["censored"].to_numpy(bool)
        new = dict(zip(s["motion"], s["refined"].astype(float), strict=True))
        hit = at["motion"].isin(list(new)).to_numpy() & ~c  # a sampled cell is answered
        x_ref = x.copy()
        x_ref[hit] = [new[m] for m in at["motion"].to_numpy()[hit]]
        f0, f1 = fit_lognormal(x, c), fit_lognormal(x_ref, c)
        rows.append({"mode": mode, "limit_state": ls, "tan_alpha": float(t), "R": float(R),
                     "n": int(x.size), "n_refined": int(hit.sum()), "median": f0.median,
                     "beta": f0.beta, "median_refined": f1.median, "beta_refined": f1.beta})
    return pd.DataFrame(rows, columns=["mode", "limit_state", "tan_alpha", "R", "n",
                                       "n_refined", "median", "beta", "median_refined",
                                       "beta_refined"])


def lambda_shifts(points: pd.DataFrame, hazard) -> pd.DataFrame:
    """λ of each refitted point (:func:`refit_points`) before and after refinement, with the
    function of ``risk.csv`` (:func:`rocking.risk.annual_frequency.mean_annual_frequency`,
    the median in g = PGA/(g tan α) · tan α), and ``shift`` = λ_refined/λ − 1 [-] (> 0
    where the refined medians fall). NaN where a fit is missing.

    Parameters
    ----------
    points : pandas.DataFrame
        :func:`refit_points`.
    hazard : HazardCurve
        The study's hazard curve, of PGA [g].
    """
    from rocking.risk.annual_frequency import mean_annual_frequency

    def lam(median, beta, t) -> float:
        if not (np.isfinite(median) and np.isfinite(beta) and beta > 0):
            return math.nan
        return mean_annual_frequency(float(median) * float(t), float(beta), hazard)

    out = points.copy()
    out["maf"] = [lam(m, b, t) for m, b, t in
                  zip(out["median"], out["beta"], out["tan_alpha"], strict=True)]
    out["maf_refined"] = [lam(m, b, t) for m, b, t in
                          zip(out["median_refined"], out["beta_refined"], out["tan_alpha"],
                              strict=True)]
    out["shift"] = out["maf_refined"] / out["maf"] - 1.0
    return out


def store_cells(store, bound: float | None = None) -> pd.DataFrame:
    """:func:`critical_cells` of a spectra store (an xarray Dataset): what
    :func:`rocking.fragility.lognormal.fragility_table` fits, cell by cell."""

    crit = store["pga_crit"].transpose("mode", "limit_state", "motion", "tan_alpha", "R")
    values = crit.values.astype(float).copy()
    censored = store["not_reached"].transpose(*crit.dims).values.astype(bool)
    unbounded = censored & ~np.isfinite(values)
    if unbounded.any():
        if bound is None:
            raise ValueError("not-reached cells without a value and no censoring bound: "
                             "pass bound=<search bound>")
        values[unbounded] = bound
    return _cell_frame(store, crit.dims, values, np.isfinite(values), censored=censored)


def write_refinement_risk(cells: pd.DataFrame, sample_csv: str | Path, hazard,
                          out_csv: str | Path, *, applies: bool = True) -> int:
    """``refinement_risk.csv``: λ of every point with a refined cell, before and after
    refinement (:func:`refit_points`, :func:`lambda_shifts`); columns :data:`RISK_COLUMNS`.

    Parameters
    ----------
    cells : pandas.DataFrame
        The study's cells (:func:`store_cells` or :func:`critical_cells`).
    sample_csv : path
        ``refinement_sample.csv``.
    hazard : HazardCurve
        The study's hazard curve.
    out_csv : path
        The table to write.
    applies : bool
        False for a hazard that is not of PGA in the study's component (``risk.csv`` then
        takes its fits from the suite, not from these cells): the header only is written.

    Returns
    -------
    int
        Rows written.
    """
    from rocking.units import CSV_FLOAT_FORMAT

    sample = pd.read_csv(sample_csv)
    if applies and len(sample):
        table = lambda_shifts(refit_points(cells, sample), hazard)
    else:
        table = pd.DataFrame(columns=["mode", "limit_state", "tan_alpha", "R", "n",
                                      "n_refined", "median", "beta", "median_refined",
                                      "beta_refined", "maf", "maf_refined", "shift"])
    table.columns = list(RISK_COLUMNS)
    table.to_csv(out_csv, index=False, float_format=CSV_FLOAT_FORMAT)
    return len(table)
