"""Fragility curves from the performance spectra, and linear fits of the mean spectra.

For one cylinder (R, tan α), limit state and analysis mode, each motion of the ensemble gives
a critical intensity x_i = PGA/(g tan α) at which the limit state is first exceeded. Treating
the motions as samples of the record-to-record variability, the fragility is the probability
that the critical intensity is below the intensity IM:

    P(exceed | IM) = Φ( ln(IM/θ) / β ),

a lognormal distribution with median θ and dispersion β, fitted by maximum likelihood. Motions
for which the limit state was not reached up to the search bound c_i are right-censored: they
only tell that x_i > c_i, and enter the likelihood through the survival function,

    ln L = Σ_observed [ln φ(z_i) − ln β − ln x_i] + Σ_censored ln[1 − Φ(z_i)],
    z_i = (ln x_i − ln θ)/β.

The mean spectra are also fitted by a straight line in R (paper §5.2: "almost straight lines").
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr
from scipy import optimize, special, stats

from rocking._validate import positive_finite_array
from rocking.fragility.table import CRITICAL_INTENSITY, quantity_of
from rocking.motions.measures import DEFAULT_COMPONENT
from rocking.units import header, set_attrs

MIN_OBSERVED = 2
"""Fewest uncensored samples that identify both θ and β."""


@dataclass(frozen=True)
class LognormalFit:
    """Maximum-likelihood lognormal fragility.

    Attributes
    ----------
    median : float
        θ, the intensity with 50 % probability of exceedance [same unit as the samples].
    beta : float
        Dispersion, the standard deviation of ln x [-].
    n : int
        Samples used (observed + censored).
    n_censored : int
        Right-censored samples (limit state not reached).
    log_likelihood : float
        Maximized log-likelihood.
    status : str
        ``"ok"``, or why no fit exists (``"too-few-observed"``, ``"no-spread"``); median
        and beta are NaN then, stated by this flag rather than silently.
    """

    median: float
    beta: float
    n: int
    n_censored: int
    log_likelihood: float
    status: str = "ok"

    def probability(self, intensity) -> np.ndarray:
        """P(exceed | IM) = Φ(ln(IM/θ)/β) at ``intensity`` (> 0)."""
        im = positive_finite_array("intensity", intensity)
        return stats.norm.cdf(np.log(im / self.median) / self.beta)


def _check_samples(values, censored) -> tuple[np.ndarray, np.ndarray]:
    x = np.asarray(values, dtype=float).ravel()
    c = np.zeros(x.shape, bool) if censored is None else np.asarray(censored, bool).ravel()
    if c.shape != x.shape:
        raise ValueError(f"censored must match values in shape, got {c.shape} and {x.shape}")
    positive_finite_array("values", x)
    return x, c


def neg_log_likelihood(params, log_x: np.ndarray, censored: np.ndarray) -> float:
    """−ln L of (ln θ, ln β) for log-samples with right-censoring flags."""
    log_median, log_beta = params
    beta = math.exp(log_beta)
    z = (log_x - log_median) / beta
    obs = ~censored
    ll = np.sum(stats.norm.logpdf(z[obs]) - log_beta - log_x[obs])
    ll += np.sum(stats.norm.logsf(z[censored]))
    return float(-ll)


def fit_lognormal(values, censored=None) -> LognormalFit:
    """Maximum-likelihood lognormal (θ, β) of positive samples, right-censored where flagged.

    Parameters
    ----------
    values : array_like
        Critical intensities, or for censored samples the bound up to which the limit state
        was not reached; all finite and > 0.
    censored : array_like of bool, optional
        True where the sample is right-censored.

    Returns
    -------
    LognormalFit

    Notes
    -----
    Without censoring the maximum is closed-form: ln θ = mean(ln x), β = std(ln x) (ddof 0),
    which is returned exactly. With censoring it is found numerically (BFGS on (ln θ, ln β)),
    started from the observed samples' closed form.
    """
    x, c = _check_samples(values, censored)
    log_x = np.log(x)
    n_obs = int(np.count_nonzero(~c))
    if n_obs < MIN_OBSERVED:
        return LognormalFit(math.nan, math.nan, x.size, int(c.sum()), math.nan,
                            "too-few-observed")
    obs = log_x[~c]
    if np.ptp(obs) == 0.0:
        return LognormalFit(math.nan, math.nan, x.size, int(c.sum()), math.nan, "no-spread")
    mu0, beta0 = float(np.mean(obs)), float(np.std(obs))
    if not c.any():
        start = np.array([mu0, math.log(beta0)])
        return LognormalFit(math.exp(mu0), beta0, x.size, 0,
                            -neg_log_likelihood(start, log_x, c))
    res = optimize.minimize(neg_log_likelihood, np.array([mu0, math.log(beta0)]),
                            args=(log_x, c), method="BFGS", options={"gtol": 1e-9})
    if not np.all(np.isfinite(res.x)):
        raise ValueError(f"lognormal fit diverged: {res.message}")
    return LognormalFit(math.exp(res.x[0]), math.exp(res.x[1]), x.size, int(c.sum()),
                        -float(res.fun))


BOOTSTRAP_RESAMPLES = 1000
"""Resamples of the motions behind each interval (:func:`bootstrap_lognormal`)."""

BOOTSTRAP_SEED = 29
"""Seed of the resampling: the same motions are drawn for every cell of a table, so the
intervals of one study are reproducible and consistent between cells."""


def bootstrap_indices(n: int, n_resamples: int = BOOTSTRAP_RESAMPLES,
                      seed: int = BOOTSTRAP_SEED) -> np.ndarray:
    """Which of ``n`` motions each resample draws (with replacement), shape (resamples, n)."""
    if n_resamples < 1:
        raise ValueError(f"n_resamples must be >= 1, got {n_resamples!r}")
    return np.random.default_rng(seed).integers(0, n, size=(n_resamples, n))


def bootstrap_lognormal(values, censored=None, *, n_resamples: int = BOOTSTRAP_RESAMPLES,
                        seed: int = BOOTSTRAP_SEED) -> tuple[np.ndarray, np.ndarray]:
    """Lognormal (θ, β) refitted to resamples of the motions drawn with replacement.

    Each resample draws as many motions as there are (:func:`bootstrap_indices`), keeps
    their censoring flags, and is fitted by the maximum likelihood of :func:`fit_lognormal`:
    the closed form without censored motions, else Newton's method on the censored
    likelihood (vectorized over the resamples; a resample that does not converge is fitted
    by :func:`fit_lognormal` itself).

    Parameters
    ----------
    values, censored : array_like
        As for :func:`fit_lognormal`.
    n_resamples : int
        Resamples (default :data:`BOOTSTRAP_RESAMPLES`).
    seed : int
        Seed of the draws (default :data:`BOOTSTRAP_SEED`).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        θ [unit of ``values``] and β [-] of each resample; NaN where the resample has no fit
        (fewer than :data:`MIN_OBSERVED` motions exceeding, or no spread), as
        :func:`fit_lognormal` says.
    """
    x, c = _check_samples(values, censored)
    idx = bootstrap_indices(x.size, n_resamples, seed)
    y, cens = np.log(x)[idx], c[idx]
    obs = ~cens
    n_obs = obs.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mu = np.where(obs, y, 0.0).sum(axis=1) / n_obs
        var = np.where(obs, (y - mu[:, None]) ** 2, 0.0).sum(axis=1) / n_obs
    spread = np.where(obs, y, -np.inf).max(axis=1) > np.where(obs, y, np.inf).min(axis=1)
    ok = (n_obs >= MIN_OBSERVED) & spread
    beta = np.sqrt(var)
    todo = ok & cens.any(axis=1)
    if todo.any():
        mu_c, beta_c, conv = _censored_newton(y[todo], cens[todo], mu[todo], beta[todo])
        mu[todo], beta[todo] = mu_c, beta_c
        for i in np.flatnonzero(todo)[~conv]:  # rare: the general fit decides
            f = fit_lognormal(x[idx[i]], c[idx[i]])
            mu[i], beta[i] = math.log(f.median), f.beta
    median = np.where(ok, np.exp(mu), np.nan)
    return median, np.where(ok, beta, np.nan)


def _censored_loglik(y, cens, mu, beta):
    """ln L of (μ, β) per resample (row) of log-samples ``y`` with censoring flags."""
    z = (y - mu[:, None]) / beta[:, None]
    obs = np.where(cens, 0.0, -np.log(beta)[:, None] - 0.5 * z * z)
    return obs.sum(axis=1) + np.where(cens, special.log_ndtr(-z), 0.0).sum(axis=1)


def _censored_newton(y, cens, mu, beta, iterations: int = 100):
    """Newton's method on the right-censored normal likelihood of ln x, one problem per row,
    with the analytic gradient and Hessian in (μ, β) and step halving; returns μ, β and
    which rows converged (step below 1e-12 relative)."""
    mu, beta = mu.copy(), beta.copy()
    conv = np.zeros(mu.shape, bool)
    act = np.arange(mu.size)
    for _ in range(iterations):
        if act.size == 0:
            break
        ya, ca, m, bt = y[act], cens[act], mu[act], beta[act]
        ll = _censored_loglik(ya, ca, m, bt)
        d_mu, d_b = _newton_step(ya, ca, m, bt)
        # keep β > 0 and the likelihood from falling: halve the step where needed
        step = np.ones_like(m)
        for _ in range(40):
            new_b = bt + step * d_b
            trial = np.where(new_b > 0, _censored_loglik(ya, ca, m + step * d_mu,
                                                         np.where(new_b > 0, new_b, 1.0)),
                             -np.inf)
            bad = ~(trial >= ll - 1e-12 * np.abs(ll))
            if not bad.any():
                break
            step = np.where(bad, 0.5 * step, step)
        mu[act], beta[act] = m + step * d_mu, bt + step * d_b
        done = (np.abs(step * d_mu) < 1e-12 * (1 + np.abs(m))) & (np.abs(step * d_b) < 1e-12 * bt)
        conv[act[done]] = True
        act = act[~done]
    return mu, beta, conv & np.isfinite(mu) & np.isfinite(beta) & (beta > 0)


def _newton_step(y, cens, mu, beta):
    """Newton step (Δμ, Δβ) of the censored likelihood per row (a gradient step where the
    Hessian is not negative definite)."""
    b = beta[:, None]
    z = (y - mu[:, None]) / b
    h = np.exp(-0.5 * z * z - 0.5 * math.log(2 * math.pi) - special.log_ndtr(-z))  # φ/(1−Φ)
    g_mu = np.where(cens, h / b, z / b).sum(axis=1)
    g_b = np.where(cens, h * z / b, (z * z - 1.0) / b).sum(axis=1)
    hz = h * (h - z)
    b2 = beta**2
    h_mm = np.where(cens, -hz, -1.0).sum(axis=1) / b2
    h_mb = np.where(cens, -hz * z - h, -2.0 * z).sum(axis=1) / b2
    h_bb = np.where(cens, -z * h * ((h - z) * z + 2.0), 1.0 - 3.0 * z * z).sum(axis=1) / b2
    det = h_mm * h_bb - h_mb**2
    newton = (h_mm < 0) & (det > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        d_mu = np.where(newton, -(h_bb * g_mu - h_mb * g_b) / det, 0.1 * beta * g_mu)
        d_b = np.where(newton, -(h_mm * g_b - h_mb * g_mu) / det, 0.1 * beta * g_b)
    return d_mu, d_b


@dataclass(frozen=True)
class LineFit:
    """Least-squares line y = slope·x + intercept with its coefficient of determination."""

    slope: float
    intercept: float
    r_squared: float
    n: int


def fit_line(x, y) -> LineFit:
    """Least-squares straight line through the finite (x, y) pairs.

    NaN entries (not computed or not aggregated) are dropped; fewer than 3 finite pairs
    return NaN parameters (a line through two points says nothing about linearity).
    """
    x = np.asarray(x, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    if x.shape != y.shape:
        raise ValueError(f"x and y must have the same length, got {x.size} and {y.size}")
    ok = np.isfinite(x) & np.isfinite(y)
    if np.count_nonzero(ok) < 3:
        return LineFit(math.nan, math.nan, math.nan, int(ok.sum()))
    res = stats.linregress(x[ok], y[ok])
    return LineFit(float(res.slope), float(res.intercept), float(res.rvalue**2), int(ok.sum()))


def censoring_bound(store: xr.Dataset, upper: float | None = None) -> float | None:
    """Search bound used for not-reached points: ``upper`` or the store's config/tolerances."""
    if upper is not None:
        return float(upper)
    for key in ("tolerances", "config"):
        raw = store.attrs.get(key)
        try:
            found = _find_key(json.loads(raw) if isinstance(raw, str) else raw, "upper")
        except json.JSONDecodeError:
            found = None
        if found is not None:
            return float(found)
    return None


def _find_key(obj, key: str):
    # The bound may sit at any depth of the config JSON (e.g. spectra.upper).
    if isinstance(obj, dict):
        if key in obj and isinstance(obj[key], int | float):
            return obj[key]
        for v in obj.values():
            hit = _find_key(v, key)
            if hit is not None:
                return hit
    return None


def fragility_table(store: xr.Dataset, *, upper: float | None = None) -> xr.Dataset:
    """Lognormal fragility parameters for every (mode, limit_state, tan_alpha, R) of a store.

    Parameters
    ----------
    store : xarray.Dataset
        The study store (``pga_crit``, ``not_reached``; dims of docs/design.md).
    upper : float, optional
        Censoring bound for not-reached points whose ``pga_crit`` is NaN [PGA/(g tan α)];
        default: the store's ``upper`` setting, else the point's stored value.

    Returns
    -------
    xarray.Dataset
        ``median`` [PGA/(g tan α)], ``median_pga_g`` [g] (= median · tan α), ``beta``,
        ``n``, ``n_censored``, ``status`` over (mode, limit_state, tan_alpha, R); status
        ``"median-at-bound"`` (:data:`AT_BOUND`) where the median is at or above the
        censoring bound.
    """
    pga, bound = _critical(store), censoring_bound(store, upper)
    shape = pga.shape[:-1]
    out = {k: np.full(shape, np.nan) for k in ("median", "beta", "log_likelihood")}
    n = np.zeros(shape, np.int32)
    n_cens = np.zeros(shape, np.int32)
    status = np.full(shape, "", dtype=object)
    for idx, x, c in _cell_samples(store, bound):
        if x.size == 0:
            status[idx] = "not-computed"
            continue
        fit = fit_lognormal(x, c)
        out["median"][idx], out["beta"][idx] = fit.median, fit.beta
        out["log_likelihood"][idx] = fit.log_likelihood
        n[idx], n_cens[idx], status[idx] = fit.n, fit.n_censored, _status(fit, bound)
    dims = pga.dims[:-1]
    coords = {d: _plain(pga[d].values) for d in dims}
    ds = xr.Dataset(
        {
            "median": (dims, out["median"]),
            "beta": (dims, out["beta"]),
            "log_likelihood": (dims, out["log_likelihood"]),
            "n": (dims, n),
            "n_censored": (dims, n_cens),
            "status": (dims, status.astype(str)),
        },
        coords=coords,
    )
    ds["median_pga_g"] = ds["median"] * ds["tan_alpha"]
    # the bound in every row: a refit in another measure or component censors there too
    ds["censoring_bound"] = xr.full_like(ds["median"], np.nan if bound is None else bound)
    set_attrs(ds)
    ds["median"].attrs["long_name"] = "median PGA/(g tan(alpha)) of the lognormal fragility"
    ds.attrs.update(censoring_bound="none" if bound is None else bound,
                    estimator=CRITICAL_INTENSITY, measure="pga", component=DEFAULT_COMPONENT,
                    unit="g", **{k: (str(v) if isinstance(v, str) else v)
                                 for k, v in quantity_of(store.attrs).items()})
    return ds


def _critical(store: xr.Dataset) -> xr.DataArray:
    return store["pga_crit"].transpose("mode", "limit_state", "tan_alpha", "R", "motion")


def _cell_samples(store: xr.Dataset, bound: float | None):
    """``(index, values, censored)`` of every (mode, limit_state, tan_alpha, R): the critical
    PGA/(g tan α) of the motions computed there, not-reached ones censored at the bound
    (empty arrays where nothing was computed)."""
    pga = _critical(store)
    nr = store["not_reached"].transpose(*pga.dims).values.astype(bool)
    vals = pga.values.astype(float)
    for idx in np.ndindex(vals.shape[:-1]):
        x, c = vals[idx].copy(), nr[idx]
        unbounded = c & ~np.isfinite(x)
        if unbounded.any():
            if bound is None:
                # Dropping these would bias the median low; the caller must give the bound.
                raise ValueError(
                    f"not_reached points without a value at {_where(pga, idx)} "
                    "and no censoring bound: pass upper=<search bound>"
                )
            x[unbounded] = bound
        keep = np.isfinite(x)  # NaN and not flagged: never computed, left out
        yield idx, x[keep], c[keep]


def fragility_bootstrap(store: xr.Dataset, table: xr.Dataset, *, upper: float | None = None,
                        n_resamples: int = BOOTSTRAP_RESAMPLES,
                        seed: int = BOOTSTRAP_SEED) -> xr.Dataset:
    """Bootstrap of the critical-intensity fragility over the motions, one row per row of
    :func:`to_frame` of ``table``.

    Every cell's motions are resampled with replacement and refitted
    (:func:`bootstrap_lognormal`, the same draws in every cell).

    Parameters
    ----------
    store : xarray.Dataset
        The spectra store :func:`fragility_table` read.
    table : xarray.Dataset
        :func:`fragility_table` of it (sets the row order).
    upper : float, optional
        As for :func:`fragility_table`.
    n_resamples, seed : int
        As for :func:`bootstrap_lognormal`.

    Returns
    -------
    xarray.Dataset
        ``median`` [g] (PGA) and ``beta`` [-] over (``row``, ``resample``), NaN where a
        resample (or the cell) has no fit; ``row`` in the order of ``to_frame(table)``, with
        mode, limit_state, tan_alpha and R as coordinates along it; attrs ``measure``
        (``pga``), ``unit``, ``n_resamples``, ``seed``.
    """
    bound = censoring_bound(store, upper)
    shape = _critical(store).shape[:-1]
    med = np.full((*shape, n_resamples), np.nan)
    beta = np.full((*shape, n_resamples), np.nan)
    for idx, x, c in _cell_samples(store, bound):
        if int(np.count_nonzero(~c)) >= MIN_OBSERVED:
            med[idx], beta[idx] = bootstrap_lognormal(x, c, n_resamples=n_resamples, seed=seed)
    tan_alpha = table["tan_alpha"].values.astype(float)[None, None, :, None, None]
    dims = (*table["median"].dims, "resample")
    cells = xr.Dataset({"median": (dims, med * tan_alpha), "beta": (dims, beta)},
                       coords={d: table[d].values for d in dims[:-1]})
    frame = table[["median"]].to_dataframe().reset_index()
    rows = cells.sel({d: xr.DataArray(frame[d].to_numpy(), dims="row") for d in dims[:-1]})
    rows = rows.assign_coords(row=np.arange(len(frame)))
    rows["median"].attrs.update(units="g", long_name="median PGA of the resample's fit")
    rows["beta"].attrs.update(units="1", long_name="lognormal dispersion of the resample's fit")
    rows.attrs.update(measure="pga", unit="g", n_resamples=n_resamples, seed=seed,
                      fragility=CRITICAL_INTENSITY)
    return rows


def percentile_interval(samples, ci: float = 0.90) -> tuple[np.ndarray, np.ndarray]:
    """The central ``ci`` interval of bootstrap samples along their last axis, over the
    resamples with a fit (NaN where none has one)."""
    import warnings

    q = 100.0 * (1.0 - ci) / 2.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows give NaN, counted
        lo, hi = np.nanpercentile(np.asarray(samples, dtype=float), [q, 100.0 - q], axis=-1)
    return lo, hi


def with_interval(table: xr.Dataset, samples: xr.Dataset, ci: float = 0.90) -> xr.Dataset:
    """``table`` with ``median_p05`` and ``median_p95`` [g]: the ``ci`` interval of the
    median PGA over the bootstrap ``samples`` (:func:`fragility_bootstrap`), and
    ``bootstrap_fitted``, the resamples with a fit."""
    med = samples["median"].values
    fitted = np.isfinite(med).sum(axis=1)
    lo, hi = percentile_interval(med, ci)
    index = table[["median"]].to_dataframe().index  # the rows of to_frame, in order
    out = table.copy()
    for name, values in (("median_p05", lo), ("median_p95", hi), ("bootstrap_fitted", fitted)):
        da = pd.Series(values, index=index).to_xarray()
        out[name] = da.transpose(*table["median"].dims)
    set_attrs(out)
    return out


AT_BOUND = "median-at-bound"
"""Status of a fit whose median is at or above the censoring bound: no analysis up to the
bound saw half of the motions exceed, so the median is an extrapolation of the lognormal tail
beyond the intensities searched (the number is kept, the status says so)."""


def _status(fit: LognormalFit, bound: float | None) -> str:
    """The fit's status, ``"median-at-bound"`` for an ok fit whose median is ≥ the bound."""
    if fit.status == "ok" and bound is not None and fit.median >= bound * (1.0 - 1e-9):
        return AT_BOUND
    return fit.status


def _plain(values: np.ndarray) -> np.ndarray:
    # String labels as Python str objects: NetCDF writers reject numpy's StringDType.
    if values.dtype.kind in "fiu":
        return values
    return np.array([str(v) for v in values], dtype=object)


def _where(da: xr.DataArray, idx: tuple[int, ...]) -> dict:
    # Coordinate labels of an index tuple over the leading dims, for error messages.
    return {d: da[d].values[i].item() for d, i in zip(da.dims, idx, strict=False)}


def linear_fit_table(means: xr.Dataset, stat: str = "mean") -> xr.Dataset:
    """Line fits of ``means[stat]`` against R for every (mode, limit_state, tan_alpha).

    Returns ``slope`` [1/m], ``intercept`` [-], ``r_squared`` [-], ``n``.
    """
    da = means[stat].transpose("mode", "limit_state", "tan_alpha", "R")
    R = da["R"].values.astype(float)
    shape = da.shape[:-1]
    res = {k: np.full(shape, np.nan) for k in ("slope", "intercept", "r_squared")}
    n = np.zeros(shape, np.int32)
    for idx in np.ndindex(shape):
        fit = fit_line(R, da.values[idx])
        res["slope"][idx], res["intercept"][idx] = fit.slope, fit.intercept
        res["r_squared"][idx], n[idx] = fit.r_squared, fit.n
    dims = da.dims[:-1]
    ds = xr.Dataset({**{k: (dims, v) for k, v in res.items()}, "n": (dims, n)},
                    coords={d: _plain(da[d].values) for d in dims})
    return set_attrs(ds)


def to_frame(ds: xr.Dataset):
    """Flat pandas table of a parameter dataset (one row per index combination); the
    column titles carry units (``median [g tan(alpha)]``, ``median_pga_g [g]``)."""
    return ds.to_dataframe().reset_index().rename(columns=header)


__all__ = [
    "LineFit",
    "LognormalFit",
    "BOOTSTRAP_RESAMPLES",
    "BOOTSTRAP_SEED",
    "bootstrap_indices",
    "bootstrap_lognormal",
    "fit_line",
    "fit_lognormal",
    "fragility_bootstrap",
    "percentile_interval",
    "with_interval",
    "fragility_table",
    "linear_fit_table",
    "to_frame",
]
