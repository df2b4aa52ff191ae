"""A fragility surface: a study's lognormal fragility as a function of size R and slenderness tan α.

A study whose runs cover a grid of R and tan α (the El Centro gallery: 20 R from 0.5 to 10 m ×
tan α 0.1, 0.2, 0.3 in 3D for overturning and θ > α/3) fits one lognormal per grid node
(``fragility.csv``). :class:`FragilitySurface` makes each limit state's ln median and β
functions of (R, tan α) between the nodes:

- **Bilinear in (ln R, tan α) of the normalized capacity.** What is interpolated is
  ln(θ/tan α), the log of the normalized capacity PGA/(g tan α) of the paper's spectra, which
  changes little with slenderness, while θ itself is near-proportional to tan α (a line in
  tan α through ln θ bends ln tan α: 13 % low at tan α 0.15 between 0.1 and 0.3; on the
  El Centro grid leaving the tan α 0.2 row out gave an RMS error of 15 % that way, 2–3.5 %
  this way). Along ln R (the medians grow near-linearly with R over a 20× range) a straight
  line between neighbours gave a smaller leave-one-out error than PCHIP or a cubic spline
  (RMS 2.2/3.1 % against 2.6/3.2 % and 3.3/3.6 % for θ > α/3 / overturning): each node
  carries the sampling noise of 11 motions, which a curve through the nodes follows and a
  line does not amplify. β is interpolated the same way, not pooled: it changes by a factor
  2–4 across R, and at a node the surface must return the study's own β. At a grid node the
  surface returns the study's median and β themselves (to rounding).
- **Bootstrap carried through.** The motions are resampled with replacement as the study
  does (:func:`rocking.fragility.lognormal.bootstrap_lognormal`, same seed: resample r draws
  the same motions at every node), every node refitted from ``critical.csv``, and each
  resample interpolated like the central fit: the spread of the interpolated θ and β over
  the resamples is their interval, and :mod:`rocking.risk.portfolio` integrates each for the
  interval of λ.
- **Error stated.** :meth:`FragilitySurface.leave_one_out` predicts every node from the grid
  without it (interior R nodes, and the middle tan α row from its neighbours): the error of
  ln θ and of β. Leaving a node out doubles the local spacing, so the error is an upper
  estimate of the error between nodes at the full spacing; docs/risk.md compares it with
  direct studies at hold-out columns (``python -m benchmarks surface_holdout``).
- **Outside the grid: refused.** A column with R or tan α beyond the grid's range is refused
  in one line (:class:`OutsideGrid`, a ValueError), unless ``extrapolate=True`` is asked for:
  then the end segments are continued and every such answer is marked ``extrapolated``.

A study without at least two R and two tan α in some (mode, limit state) with a fit at
every node is refused in one line: it has no surface.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from rocking._validate import positive_finite_array
from rocking.fragility.lognormal import BOOTSTRAP_RESAMPLES, BOOTSTRAP_SEED
from rocking.fragility.table import Fragilities
from rocking.motions.measures import DEFAULT_COMPONENT
from rocking.spectra.limit_states import sort_limit_states

RTOL = 1e-9
"""Relative distance [-] within which a column's R or tan α counts as on the grid's edge."""

CI = 0.90
"""Central probability of the intervals over the resamples (5th to 95th percentile)."""


def interval(samples: np.ndarray, ci: float = CI) -> tuple[np.ndarray, np.ndarray]:
    """The central ``ci`` interval along the last axis, over the finite values (NaN where
    none); the plain percentile where every value is finite (several times faster)."""
    import warnings

    q = 100.0 * (1.0 - ci) / 2.0
    samples = np.asarray(samples, float)
    if np.isfinite(samples).all():
        lo, hi = np.percentile(samples, [q, 100.0 - q], axis=-1)
        return lo, hi
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a row without any fit: NaN
        lo, hi = np.nanpercentile(samples, [q, 100.0 - q], axis=-1)
    return lo, hi


class OutsideGrid(ValueError):
    """A column beyond the surface's grid (and extrapolation not asked for)."""


@dataclass(frozen=True)
class LimitStateGrid:
    """One (mode, limit state) of a study on its (tan α × R) grid.

    Attributes
    ----------
    tan_alpha : numpy.ndarray
        Grid slendernesses [-], increasing (≥ 2).
    R : numpy.ndarray
        Grid sizes [m], increasing (≥ 2).
    median : numpy.ndarray
        (tan α, R): the study's median PGA capacity [g].
    beta : numpy.ndarray
        (tan α, R): its dispersion [-].
    median_resamples, beta_resamples : numpy.ndarray
        (tan α, R, resample): the refits of the bootstrap resamples (NaN: no fit); empty
        (resample axis of length 0) without ``critical.csv``.
    """

    tan_alpha: np.ndarray
    R: np.ndarray
    median: np.ndarray
    beta: np.ndarray
    median_resamples: np.ndarray
    beta_resamples: np.ndarray


def _weights(grid: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Left node index and the weight of the right node for linear interpolation (the end
    segments continued beyond the grid)."""
    j = np.clip(np.searchsorted(grid, x, side="right") - 1, 0, grid.size - 2)
    w = (x - grid[j]) / (grid[j + 1] - grid[j])
    return j, w


def _blend(lo: np.ndarray, hi: np.ndarray, w: np.ndarray) -> np.ndarray:
    """lo + w·(hi − lo), with the node values themselves at w = 0 and w = 1 (no rounding)."""
    out = lo + w * (hi - lo)
    if np.any((w == 0.0) | (w == 1.0)):  # columns at a node (the rest: no copy made)
        out = np.where(w == 0.0, lo, np.where(w == 1.0, hi, out))
    return out


def _interpolate(grid: LimitStateGrid, values: np.ndarray, R: np.ndarray,
                 tan_alpha: np.ndarray) -> np.ndarray:
    """``values`` (tan α, R, ...) interpolated at the columns, bilinearly in (ln R, tan α)
    (the end segments continued beyond the grid). Returns (columns, ...)."""
    extra = (1,) * (values.ndim - 2)
    k, u = _weights(np.log(grid.R), np.log(R))
    j, w = _weights(grid.tan_alpha, tan_alpha)
    u, w = u.reshape((-1,) + extra), w.reshape((-1,) + extra)
    lower = _blend(values[j, k], values[j, k + 1], u)  # the row below the column's tan α
    upper = _blend(values[j + 1, k], values[j + 1, k + 1], u)
    return _blend(lower, upper, w)


@dataclass
class FragilitySurface:
    """Lognormal fragilities of a study over (R, tan α), per (mode, limit state).

    Build it with :meth:`from_study`; evaluate with :meth:`evaluate`.
    """

    grids: dict[tuple[str, str], LimitStateGrid]
    source: str = ""
    n_resamples: int = 0
    skipped: list[str] = field(default_factory=list)
    component: str = DEFAULT_COMPONENT
    """Horizontal component of the medians."""
    measure: str = "pga"
    """Intensity measure of the medians (g)."""
    note: str = ""
    """How the study's fragility was brought into this measure and component ('' for the
    spectra's own vector-peak PGA)."""

    # ----------------------------------------------------------------------------- building
    @classmethod
    def from_study(cls, study: str | Path, *, mode: str = "3d", limit_states=None,
                   n_resamples: int = BOOTSTRAP_RESAMPLES, seed: int = BOOTSTRAP_SEED,
                   measure="pga", component: str = DEFAULT_COMPONENT) -> FragilitySurface:
        """The surface of a study's results folder, in an intensity measure and component.

        Every node is the study's censored lognormal refitted from ``critical.csv`` (each
        motion's critical PGA) in ``measure`` and ``component``
        (:mod:`rocking.fragility.refit`, through each motion's ratio of the two in
        ``motion_measures.csv``; none needed for the vector-peak PGA, where the refit is
        ``fragility.csv``'s own fit), with the bootstrap over the motions.

        Parameters
        ----------
        study : path
            ``results/<study>/`` (``critical.csv``; ``fragility.csv`` for the search bound
            the motions not reached are censored at; ``motion_measures.csv`` for another
            measure or component), or its ``fragility.csv``.
        mode : str
            The analysis mode (``3d`` default).
        limit_states : sequence of str, optional
            Default: every limit state of the mode with a full grid.
        n_resamples, seed : int
            Bootstrap resamples of the motions (0: none) and their seed (the study's own
            by default, so the resamples are the study's).
        measure, component : str
            What the medians are in (the hazard's: :func:`rocking.risk.reconcile.reconcile`).

        Raises
        ------
        ValueError
            One line: no critical.csv, the mode not in it, no (mode, limit state) with a
            grid of ≥ 2 R and ≥ 2 tan α fitted at every node, a limit state asked for
            without one, no motion measures for another measure or component.
        """
        from rocking.fragility.refit import refit_study

        frag = refit_study(study, measure, component, mode=mode, limit_states=limit_states,
                           n_resamples=n_resamples, seed=seed)
        return cls.from_fragilities(frag, mode=mode, limit_states=limit_states)

    @classmethod
    def from_fragilities(cls, frag: Fragilities, *, mode: str = "3d",
                         limit_states=None) -> FragilitySurface:
        """The surface of a study's fragilities of one mode (:class:`Fragilities` with its
        bootstrap resamples, or none: a surface without intervals)."""
        where = frag.source or "the fragility table"
        rows = frag.rows[frag.rows["mode"] == mode]
        if rows.empty:
            raise ValueError(f"{where}: no fitted fragility in mode {mode!r} (its modes: "
                             f"{sorted(set(frag.rows['mode']))})")
        wanted = (sort_limit_states(rows["limit_state"].unique()) if limit_states is None
                  else list(limit_states))
        grids, why = {}, []
        n = frag.samples.n_resamples if frag.samples is not None else 0
        for ls in wanted:
            part = rows[rows["limit_state"] == ls]
            gaps = frag.skipped[(frag.skipped["mode"] == mode)
                                & (frag.skipped["limit_state"] == ls)]
            ta = np.unique(np.concatenate([part["tan_alpha"], gaps["tan_alpha"]]))
            R = np.unique(np.concatenate([part["R"], gaps["R"]]))
            if ta.size < 2 or R.size < 2:
                why.append(f"{ls}: tan α {_list(ta)}, R {_list(R)} [m]")
                continue
            if len(part) != ta.size * R.size:
                miss = ta.size * R.size - len(part)
                why.append(f"{ls}: {miss} node(s) of its {ta.size}×{R.size} grid without a "
                           "fit")
                continue
            cube = part.set_index(["tan_alpha", "R"]).sort_index()
            median = cube["median_g"].to_numpy().reshape(ta.size, R.size)
            beta = cube["beta"].to_numpy().reshape(ta.size, R.size)
            med_r = np.empty((ta.size, R.size, n))
            beta_r = np.empty((ta.size, R.size, n))
            if n:
                idx = cube["row"].to_numpy(int)
                med_r = frag.samples.median[idx].reshape(ta.size, R.size, n)
                beta_r = frag.samples.beta[idx].reshape(ta.size, R.size, n)
            grids[(mode, ls)] = LimitStateGrid(ta, R, median, beta, med_r, beta_r)
        if limit_states is not None and why:
            raise ValueError(f"{where}: no surface for {why[0]} (a surface needs ≥ 2 R and "
                             "≥ 2 tan α, fitted at every node)")
        if not grids:
            raise ValueError(f"{where}: no grid in R and tan α in mode {mode} (a surface "
                             f"needs ≥ 2 R and ≥ 2 tan α, fitted at every node): "
                             + "; ".join(why))
        return cls(grids, where, n, why, frag.component, frag.measure, frag.note)

    # ---------------------------------------------------------------------------- queries
    def limit_states(self, mode: str = "3d") -> list[str]:
        """Limit states with a surface in ``mode``, in increasing severity."""
        return sort_limit_states([ls for m, ls in self.grids if m == mode])

    def modes(self) -> list[str]:
        return list(dict.fromkeys(m for m, _ in self.grids))

    def bounds(self) -> tuple[float, float, float, float]:
        """R_min, R_max [m], tan α_min, tan α_max [-] common to every limit state."""
        gs = list(self.grids.values())
        return (max(g.R[0] for g in gs), min(g.R[-1] for g in gs),
                max(g.tan_alpha[0] for g in gs), min(g.tan_alpha[-1] for g in gs))

    def outside(self, R, tan_alpha) -> np.ndarray:
        """True where a column lies beyond the grid (beyond :data:`RTOL`)."""
        R, ta = np.asarray(R, float), np.asarray(tan_alpha, float)
        r0, r1, t0, t1 = self.bounds()
        return ((R < r0 * (1 - RTOL)) | (R > r1 * (1 + RTOL))
                | (ta < t0 * (1 - RTOL)) | (ta > t1 * (1 + RTOL)))

    def check_inside(self, R, tan_alpha, names=None) -> None:
        """Refuse, in one line naming the first column outside, columns beyond the grid."""
        R, ta = np.atleast_1d(np.asarray(R, float)), np.atleast_1d(np.asarray(tan_alpha, float))
        out = np.flatnonzero(self.outside(R, ta))
        if out.size:
            i = int(out[0])
            r0, r1, t0, t1 = self.bounds()
            name = f"row {i}" if names is None else str(names[i])
            col = "R" if not r0 * (1 - RTOL) <= R[i] <= r1 * (1 + RTOL) else "tan_alpha"
            raise OutsideGrid(f"{name}: {col} outside the surface's grid (R {R[i]:.4g} m, "
                              f"tan α {ta[i]:.4g}; the grid spans R {r0:g}–{r1:g} m, tan α "
                              f"{t0:g}–{t1:g}): {out.size} column(s) outside; allow "
                              "extrapolation explicitly to have them marked extrapolated")

    def evaluate(self, R, tan_alpha, mode: str = "3d", limit_state: str = "overturning", *,
                 extrapolate: bool = False, resamples: bool = True) -> dict:
        """The lognormal fragility at columns (R, tan α).

        Parameters
        ----------
        R, tan_alpha : array_like
            The columns' semi-diagonal [m] and slenderness [-] (same shape).
        mode, limit_state : str
            Which surface.
        extrapolate : bool
            Answer columns beyond the grid too (marked ``extrapolated``); False: refuse them.
        resamples : bool
            Also interpolate every bootstrap resample.

        Returns
        -------
        dict
            ``median`` [g], ``beta`` [-], ``extrapolated`` (bool) per column; with resamples
            ``median_resamples``, ``beta_resamples`` (columns, resamples) and the 90 %
            intervals ``median_p05``, ``median_p95``, ``beta_p05``, ``beta_p95``.
        """
        key = (mode, limit_state)
        if key not in self.grids:
            raise ValueError(f"{self.source}: no surface for {mode} {limit_state} (it has "
                             f"{', '.join(f'{m} {s}' for m, s in self.grids)})")
        g = self.grids[key]
        R = np.atleast_1d(np.asarray(R, float))
        ta = np.atleast_1d(np.asarray(tan_alpha, float))
        if R.shape != ta.shape:
            raise ValueError(f"R and tan_alpha must have the same shape, got {R.shape} and "
                             f"{ta.shape}")
        positive_finite_array("R", R)
        positive_finite_array("tan_alpha", ta)
        outside = self.outside(R, ta)
        if not extrapolate:
            self.check_inside(R, ta)
        # clip onto the grid where within RTOL of an edge: the edge node's own value
        r0, r1, t0, t1 = g.R[0], g.R[-1], g.tan_alpha[0], g.tan_alpha[-1]
        R = np.where(~outside, np.clip(R, r0, r1), R)
        ta = np.where(~outside, np.clip(ta, t0, t1), ta)
        out = {"median": np.exp(_interpolate(g, _normalized(g, g.median), R, ta)) * ta,
               "beta": _interpolate(g, g.beta, R, ta), "extrapolated": outside}
        if resamples and g.median_resamples.shape[-1]:
            with np.errstate(invalid="ignore", divide="ignore"):
                med = np.exp(_interpolate(g, _normalized(g, g.median_resamples), R, ta)) \
                    * ta[:, None]
            bet = _interpolate(g, g.beta_resamples, R, ta)
            out["median_resamples"], out["beta_resamples"] = med, bet
            out["median_p05"], out["median_p95"] = interval(med)
            out["beta_p05"], out["beta_p95"] = interval(bet)
        return out

    def resample_range(self, mode: str, limit_state: str) -> tuple[float, float, float, float]:
        """Smallest and largest median [g] and β [-] any resample takes between the nodes:
        bilinear interpolation does not overshoot its nodes, so the range of the nodes'
        resamples (the normalized median's, times the grid's tan α range) bounds them."""
        g = self.grids[(mode, limit_state)]
        norm = np.exp(_normalized(g, g.median_resamples))
        with np.errstate(invalid="ignore"):
            return (float(np.nanmin(norm)) * g.tan_alpha[0],
                    float(np.nanmax(norm)) * g.tan_alpha[-1],
                    float(np.nanmin(g.beta_resamples)), float(np.nanmax(g.beta_resamples)))

    # ------------------------------------------------------------------------------- error
    def leave_one_out(self) -> pd.DataFrame:
        """Every node predicted from the grid without it: interior R nodes along ln R, interior
        tan α nodes along tan α (the line between its two neighbours).

        Returns
        -------
        pandas.DataFrame
            mode, limit_state, left_out (``R`` or ``tan_alpha``), tan_alpha, R [m], median
            [g] (the study's), median_loo [g], beta, beta_loo, err_ln_median (ln of
            loo/study), err_beta (loo − study).
        """
        rows = []
        for (mode, ls), g in self.grids.items():
            lnR, lnm = np.log(g.R), _normalized(g, g.median)
            for i, ta in enumerate(g.tan_alpha):
                for k in range(1, g.R.size - 1):
                    u = (lnR[k] - lnR[k - 1]) / (lnR[k + 1] - lnR[k - 1])
                    m = float(np.exp(lnm[i, k - 1] + u * (lnm[i, k + 1] - lnm[i, k - 1]))) * ta
                    b = float(g.beta[i, k - 1] + u * (g.beta[i, k + 1] - g.beta[i, k - 1]))
                    rows.append(_loo_row(mode, ls, "R", ta, g.R[k], g.median[i, k], m,
                                         g.beta[i, k], b))
            for i in range(1, g.tan_alpha.size - 1):
                w = (g.tan_alpha[i] - g.tan_alpha[i - 1]) / (g.tan_alpha[i + 1]
                                                             - g.tan_alpha[i - 1])
                for k, R in enumerate(g.R):
                    m = float(np.exp(lnm[i - 1, k] + w * (lnm[i + 1, k] - lnm[i - 1, k]))
                              * g.tan_alpha[i])
                    b = float(g.beta[i - 1, k] + w * (g.beta[i + 1, k] - g.beta[i - 1, k]))
                    rows.append(_loo_row(mode, ls, "tan_alpha", g.tan_alpha[i], R,
                                         g.median[i, k], m, g.beta[i, k], b))
        return pd.DataFrame(rows, columns=LOO_COLUMNS)

    def loo_summary(self) -> pd.DataFrame:
        """Per (mode, limit state) and direction left out: the nodes, the RMS and the
        largest |error| of ln θ (×100 ≈ %) and of β."""
        loo = self.leave_one_out()
        return (loo.assign(abs_ln=loo["err_ln_median"].abs(), abs_b=loo["err_beta"].abs())
                .groupby(["mode", "limit_state", "left_out"], sort=False)
                .agg(nodes=("abs_ln", "size"),
                     rms_ln_median=("err_ln_median", lambda s: float(np.sqrt(np.mean(s**2)))),
                     max_ln_median=("abs_ln", "max"),
                     rms_beta=("err_beta", lambda s: float(np.sqrt(np.mean(s**2)))),
                     max_beta=("abs_b", "max"))
                .reset_index())

    def interpolation_error(self) -> dict[tuple[str, str], float]:
        """Per (mode, limit state): the largest leave-one-out |error| of ln θ [-] (either
        direction), the error quoted with every interpolated median; NaN for a grid without
        an interior node (2 R × 2 tan α: nothing to leave out, the error is not measured)."""
        s = self.loo_summary()
        found = {(m, ls): float(part["max_ln_median"].max())
                 for (m, ls), part in s.groupby(["mode", "limit_state"], sort=False)}
        return {key: found.get(key, float("nan")) for key in self.grids}


LOO_COLUMNS = ("mode", "limit_state", "left_out", "tan_alpha", "R", "median", "median_loo",
               "beta", "beta_loo", "err_ln_median", "err_beta")
"""Columns of :meth:`FragilitySurface.leave_one_out`."""


def _normalized(g: LimitStateGrid, median: np.ndarray) -> np.ndarray:
    """ln of the normalized capacity θ/(g tan α) [-] at the nodes (tan α along axis 0), the
    quantity interpolated: the paper's spectra are near-independent of tan α in it, while
    θ itself is near-proportional to tan α (a line in tan α through ln θ would bend
    ln tan α: 13 % low at tan α 0.15 between 0.1 and 0.3)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.log(median) - np.log(g.tan_alpha).reshape((-1,) + (1,) * (median.ndim - 1))


def _loo_row(mode, ls, left_out, ta, R, m, m_loo, b, b_loo) -> dict:
    return {"mode": mode, "limit_state": ls, "left_out": left_out, "tan_alpha": float(ta),
            "R": float(R), "median": float(m), "median_loo": m_loo, "beta": float(b),
            "beta_loo": b_loo, "err_ln_median": float(np.log(m_loo / m)),
            "err_beta": b_loo - float(b)}


def _list(values) -> str:
    values = [f"{v:g}" for v in values]
    return "[" + ", ".join(values[:4]) + (", ..." if len(values) > 4 else "") + "]"


__all__ = ["CI", "RTOL", "FragilitySurface", "LimitStateGrid", "OutsideGrid", "interval"]
