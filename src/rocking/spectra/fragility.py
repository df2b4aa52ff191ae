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
import xarray as xr
from scipy import optimize, stats

from ..units import header, set_attrs

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
        im = np.asarray(intensity, dtype=float)
        if np.any(~np.isfinite(im) | (im <= 0.0)):
            raise ValueError(f"intensity must be finite and > 0, got {intensity!r}")
        return stats.norm.cdf(np.log(im / self.median) / self.beta)


def _check_samples(values, censored) -> tuple[np.ndarray, np.ndarray]:
    x = np.asarray(values, dtype=float).ravel()
    c = np.zeros(x.shape, bool) if censored is None else np.asarray(censored, bool).ravel()
    if c.shape != x.shape:
        raise ValueError(f"censored must match values in shape, got {c.shape} and {x.shape}")
    bad = np.flatnonzero(~np.isfinite(x) | (x <= 0.0))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"values must be finite and > 0, got {float(x[i])!r} at index {i}")
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
    pga = store["pga_crit"].transpose("mode", "limit_state", "tan_alpha", "R", "motion")
    nr = store["not_reached"].transpose(*pga.dims).values.astype(bool)
    vals = pga.values.astype(float)
    bound = censoring_bound(store, upper)
    shape = vals.shape[:-1]
    out = {k: np.full(shape, np.nan) for k in ("median", "beta", "log_likelihood")}
    n = np.zeros(shape, np.int32)
    n_cens = np.zeros(shape, np.int32)
    status = np.full(shape, "", dtype=object)
    for idx in np.ndindex(shape):
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
        if not keep.any():
            status[idx] = "not-computed"
            continue
        fit = fit_lognormal(x[keep], c[keep])
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
    set_attrs(ds)
    ds["median"].attrs["long_name"] = "median PGA/(g tan(alpha)) of the lognormal fragility"
    ds.attrs["censoring_bound"] = "none" if bound is None else bound
    return ds


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
    "fit_line",
    "fit_lognormal",
    "fragility_table",
    "linear_fit_table",
    "to_frame",
]
