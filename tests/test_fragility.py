"""Lognormal fragility MLE (with right-censoring) and the linear fit of the mean spectra."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr
from scipy import stats

from rocking.fragility.lognormal import fit_line, fit_lognormal, fragility_table, linear_fit_table

THETA, BETA = 3.0, 0.4


def _samples(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.exp(math.log(THETA) + BETA * rng.standard_normal(n))


def test_mle_recovers_known_parameters_within_sampling_spread():
    n = 2000
    fit = fit_lognormal(_samples(n, 1))
    # Asymptotic standard errors of the MLE: sd(ln θ) = β/√n, sd(β) = β/√(2n); 4 sigma.
    assert abs(math.log(fit.median / THETA)) < 4 * BETA / math.sqrt(n)
    assert abs(fit.beta - BETA) < 4 * BETA / math.sqrt(2 * n)
    assert fit.status == "ok" and fit.n == n and fit.n_censored == 0


def test_uncensored_fit_is_the_closed_form():
    x = _samples(50, 2)
    fit = fit_lognormal(x)
    assert fit.median == pytest.approx(math.exp(np.mean(np.log(x))), rel=1e-12)
    assert fit.beta == pytest.approx(np.std(np.log(x)), rel=1e-12)
    # The closed form is a maximum: nearby parameters have a lower likelihood.
    ll = np.sum(stats.lognorm.logpdf(x, fit.beta, scale=fit.median))
    assert fit.log_likelihood == pytest.approx(ll, rel=1e-10)
    for dm, db in ((1.02, 1.0), (0.98, 1.0), (1.0, 1.05), (1.0, 0.95)):
        other = np.sum(stats.lognorm.logpdf(x, fit.beta * db, scale=fit.median * dm))
        assert other < ll


def test_right_censoring_recovers_parameters_and_matters():
    n, bound = 2000, 3.5  # about 35 % of the samples lie beyond the bound
    x = _samples(n, 3)
    censored = x > bound
    assert 0.25 < censored.mean() < 0.45
    values = np.where(censored, bound, x)
    fit = fit_lognormal(values, censored)
    assert fit.n_censored == int(censored.sum())
    # Censoring inflates the spread of the estimates; 2x the uncensored 4-sigma band.
    assert abs(math.log(fit.median / THETA)) < 8 * BETA / math.sqrt(n)
    assert abs(fit.beta - BETA) < 8 * BETA / math.sqrt(2 * n)
    # Ignoring the censoring (or dropping the censored points) is badly biased.
    naive = fit_lognormal(x[~censored])
    assert naive.median < 0.85 * THETA


def test_censored_fit_agrees_with_scipy_censored_data():
    x = _samples(40, 4)
    bound = float(np.quantile(x, 0.7))
    censored = x > bound
    values = np.where(censored, bound, x)
    fit = fit_lognormal(values, censored)
    data = stats.CensoredData(uncensored=values[~censored], right=values[censored])
    beta, _, scale = stats.lognorm.fit(data, floc=0.0)
    assert fit.median == pytest.approx(scale, rel=1e-4)
    assert fit.beta == pytest.approx(beta, rel=1e-4)


def test_fragility_probability_is_lognormal_cdf():
    fit = fit_lognormal(_samples(100, 5))
    im = np.array([0.5, fit.median, 10.0])
    p = fit.probability(im)
    assert p[1] == pytest.approx(0.5, abs=1e-12)
    assert p == pytest.approx(stats.lognorm.cdf(im, fit.beta, scale=fit.median), rel=1e-12)
    with pytest.raises(ValueError, match="intensity"):
        fit.probability([-1.0])


def test_degenerate_samples_are_flagged_not_silent():
    all_censored = fit_lognormal([2.0, 2.0, 2.0], [True, True, True])
    assert all_censored.status == "too-few-observed" and math.isnan(all_censored.median)
    assert fit_lognormal([2.0, 2.0, 2.0]).status == "no-spread"
    with pytest.raises(ValueError, match=r"values .* nan"):
        fit_lognormal([1.0, float("nan"), 2.0])
    with pytest.raises(ValueError, match="-1.0"):
        fit_lognormal([1.0, -1.0, 2.0])
    with pytest.raises(ValueError, match="censored"):
        fit_lognormal([1.0, 2.0], [True])


def test_linear_fit_recovers_known_line():
    R = np.linspace(1.0, 10.0, 10)
    exact = fit_line(R, 0.45 * R + 1.3)
    assert exact.slope == pytest.approx(0.45, rel=1e-12)
    assert exact.intercept == pytest.approx(1.3, rel=1e-12)
    assert exact.r_squared == pytest.approx(1.0, abs=1e-12)
    rng = np.random.default_rng(6)
    R = np.linspace(1.0, 10.0, 200)
    sigma = 0.2
    noisy = fit_line(R, 0.45 * R + 1.3 + sigma * rng.standard_normal(R.size))
    se_slope = sigma / math.sqrt(np.sum((R - R.mean()) ** 2))
    assert abs(noisy.slope - 0.45) < 4 * se_slope
    assert 0.95 < noisy.r_squared < 1.0
    y = 0.45 * R + 1.3
    y[3] = np.nan  # a not-aggregated point is dropped, not propagated
    assert fit_line(R, y).n == R.size - 1
    assert math.isnan(fit_line([1.0, 2.0], [1.0, 2.0]).slope)


def _store(values: np.ndarray, not_reached: np.ndarray, upper: float | None) -> xr.Dataset:
    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    ds = xr.Dataset(
        {"pga_crit": (dims, values), "not_reached": (dims, not_reached)},
        coords={"mode": ["3d"], "limit_state": ["overturning"],
                "motion": [f"m{i}" for i in range(values.shape[2])],
                "tan_alpha": [0.2], "R": [2.0, 6.0]},
    )
    if upper is not None:
        ds.attrs["config"] = json.dumps({"spectra": {"upper": upper}})
    return ds


def test_fragility_table_matches_direct_fits_and_uses_censoring_bound():
    x = _samples(24, 7).reshape(1, 1, 24, 1, 1) * np.array([1.0, 2.0])
    nr = x > 4.0
    values = np.where(nr, np.nan, x)  # not-reached values stored as NaN: bound from config
    table = fragility_table(_store(values, nr, upper=4.0))
    for j in range(2):
        direct = fit_lognormal(np.where(nr[0, 0, :, 0, j], 4.0, x[0, 0, :, 0, j]),
                               nr[0, 0, :, 0, j])
        got = table.isel(mode=0, limit_state=0, tan_alpha=0, R=j)
        assert float(got["median"]) == pytest.approx(direct.median, rel=1e-12)
        assert float(got["beta"]) == pytest.approx(direct.beta, rel=1e-12)
        assert int(got["n_censored"]) == int(nr[0, 0, :, 0, j].sum())
        assert float(got["median_pga_g"]) == pytest.approx(direct.median * 0.2, rel=1e-12)
    with pytest.raises(ValueError, match="upper"):
        fragility_table(_store(values, nr, upper=None))


def test_linear_fit_table_per_mode_and_limit_state():
    R = np.array([1.0, 2.0, 4.0, 6.0, 10.0])
    mean = np.stack([0.3 * R + 1.0, 0.5 * R + 2.0]).reshape(2, 1, 1, 5)
    ds = xr.Dataset({"mean": (("mode", "limit_state", "tan_alpha", "R"), mean)},
                    coords={"mode": ["3d", "2d-x"], "limit_state": ["overturning"],
                            "tan_alpha": [0.2], "R": R})
    table = linear_fit_table(ds)
    assert table["slope"].sel(mode="3d").item() == pytest.approx(0.3, rel=1e-12)
    assert table["intercept"].sel(mode="2d-x").item() == pytest.approx(2.0, rel=1e-12)
    assert table["r_squared"].min().item() == pytest.approx(1.0, abs=1e-12)


def test_median_at_or_above_the_search_bound_is_not_ok():
    """A fit whose median lies at or beyond the bound extrapolates past every intensity
    searched: the table keeps the number and says so instead of "ok"."""
    x = _samples(24, 7).reshape(1, 1, 24, 1, 1) * np.array([1.0, 1.6])
    bound = 1.2 * float(np.median(x[..., 0]))  # below the second column's median
    nr = x > bound
    table = fragility_table(_store(np.where(nr, np.nan, x), nr, upper=bound))
    low, high = (table.isel(mode=0, limit_state=0, tan_alpha=0, R=j) for j in range(2))
    assert float(low["median"]) < bound and str(low["status"].values) == "ok"
    assert float(high["median"]) >= bound
    assert str(high["status"].values) == "median-at-bound"
    assert int(high["n_censored"]) > 12  # more than half were not reached
