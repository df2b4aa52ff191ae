"""λ with its uncertainty and in the hazard's measure (issue 29): the bootstrap over the
motions against an independent resampling written here, the SA(1.0) path against an
independent quadrature of the Sa fragility, rows without a fit kept (stripe brackets), the
preset's warning and the small-suite warning."""

from __future__ import annotations

import json
import math
from html import unescape

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from scipy import integrate, optimize, stats

from rocking.cli import main
from rocking.fragility import lognormal as F
from rocking.fragility.bootstrap import bootstrap_path, read_bootstrap
from rocking.fragility.table import read_fragilities
from rocking.report.risk import risk_section_html, small_suite_warnings
from rocking.risk.annual_frequency import annual_frequency_interval, mean_annual_frequencies
from rocking.risk.exports import write_risk_outputs
from rocking.risk.hazard import HazardCurve, parse_hazard
from rocking.risk.risk_table import risk_table

SEED = 3


def closed_form(k0, k, median, beta):
    """λ_LS of a lognormal fragility under λ = k0·im^−k (Cornell et al. 2002)."""
    return k0 * median ** (-k) * math.exp(0.5 * k * k * beta * beta)


def own_censored_fit(x, c):
    """Maximum likelihood of a right-censored lognormal, written here: Nelder–Mead on
    (μ, ln β) of Σ_obs ln φ((ln x − μ)/β)/β + Σ_cens ln(1 − Φ((ln x − μ)/β))."""
    y = np.log(x)

    def nll(p):
        mu, b = p[0], math.exp(p[1])
        z = (y - mu) / b
        return -(np.sum(stats.norm.logpdf(z[~c]) - math.log(b)) + np.sum(stats.norm.logsf(z[c])))

    obs = y[~c]
    res = optimize.minimize(nll, [obs.mean(), math.log(obs.std())], method="Nelder-Mead",
                            options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 20000})
    return math.exp(res.x[0]), math.exp(res.x[1])


def samples(n, censor_above=None, seed=SEED):
    rng = np.random.default_rng(seed)
    x = 2.0 * np.exp(0.35 * rng.standard_normal(n))
    c = np.zeros(n, bool) if censor_above is None else x > censor_above
    return np.where(c, censor_above or 0.0, x), c


# ------------------------------------------------------------------ the bootstrap itself


def test_bootstrap_refits_each_resample_as_an_independent_fit_does():
    x, c = samples(12, censor_above=2.6)
    assert c.sum() >= 2
    med, beta = F.bootstrap_lognormal(x, c, n_resamples=200, seed=11)
    # the resampling written here: the same generator, 200 × 12 draws with replacement
    idx = np.random.default_rng(11).integers(0, 12, size=(200, 12))
    checked = 0
    for i in range(0, 200, 7):
        xi, ci = x[idx[i]], c[idx[i]]
        if (~ci).sum() < 2 or np.ptp(np.log(xi[~ci])) == 0:
            assert math.isnan(med[i])
            continue
        if ci.any():
            m, b = own_censored_fit(xi, ci)
        else:
            m, b = math.exp(np.log(xi).mean()), np.log(xi).std()
        assert med[i] == pytest.approx(m, rel=1e-5) and beta[i] == pytest.approx(b, rel=1e-5)
        checked += 1
    assert checked >= 20


def test_bootstrap_interval_matches_an_independent_resampling_and_the_asymptotics():
    """Another seed, resampled and fitted here (closed form): the 90 % intervals of the
    median agree within the Monte Carlo error, and with θ·exp(±1.645 β/√n)."""
    n = 25
    x, c = samples(n)
    lo, hi = F.percentile_interval(F.bootstrap_lognormal(x, c)[0])
    rng = np.random.default_rng(12345)
    own = np.exp(np.log(x)[rng.integers(0, n, size=(4000, n))].mean(axis=1))
    own_lo, own_hi = np.percentile(own, [5, 95])
    assert lo == pytest.approx(own_lo, rel=0.02) and hi == pytest.approx(own_hi, rel=0.02)
    theta, beta = math.exp(np.log(x).mean()), np.log(x).std()
    half = 1.645 * beta / math.sqrt(n)
    assert math.log(hi / lo) == pytest.approx(2 * half, rel=0.15)
    assert math.sqrt(lo * hi) == pytest.approx(theta, rel=0.02)


def test_lambda_interval_is_the_percentiles_of_each_resample_integrated():
    x, c = samples(15, censor_above=2.8)
    med, beta = F.bootstrap_lognormal(x, c)
    h = HazardCurve.from_power_law(1e-4, 2.5)
    lo, hi, lam = annual_frequency_interval(med, beta, h)
    own = np.array([closed_form(1e-4, 2.5, m, b) if np.isfinite(m) else np.nan
                    for m, b in zip(med, beta, strict=True)])
    np.testing.assert_allclose(lam, own, rtol=2e-3)
    own_lo, own_hi = np.nanpercentile(own, [5, 95])
    assert lo == pytest.approx(own_lo, rel=2e-3) and hi == pytest.approx(own_hi, rel=2e-3)
    fit = F.fit_lognormal(x, c)
    assert lo < closed_form(1e-4, 2.5, fit.median, fit.beta) < hi


def test_vectorized_lambda_agrees_with_the_single_integral_on_a_curved_hazard():
    from rocking.risk.annual_frequency import mean_annual_frequency

    im = np.geomspace(0.005, 4.0, 24)
    L = np.log(im / 0.25)
    h = HazardCurve(im, np.exp(-2.2 * L - 0.262 * L * L) / 475.0)
    rng = np.random.default_rng(1)
    m, b = np.exp(rng.normal(-0.5, 0.8, 40)), rng.uniform(0.05, 1.0, 40)
    got = mean_annual_frequencies(m, b, h)
    want = [mean_annual_frequency(mi, bi, h) for mi, bi in zip(m, b, strict=True)]
    np.testing.assert_allclose(got, want, rtol=2e-3)


# ------------------------------------------------------------------ fragility.csv and its samples


def store(n=14, seed=SEED):
    """A spectra store stand-in: one mode, two limit states, two sizes; critical intensities
    lognormal, those above 12 not reached (censored at the bound 12)."""
    rng = np.random.default_rng(seed)
    x = np.exp(0.4 * rng.standard_normal((1, 2, n, 1, 2)))
    x = x * np.array([3.0, 6.0])[None, None, None, None, :] \
        * np.array([1.0, 0.6])[None, :, None, None, None]
    nr = x > 12.0
    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    ds = xr.Dataset({"pga_crit": (dims, np.where(nr, np.nan, x)), "not_reached": (dims, nr)},
                    coords={"mode": ["3d"], "limit_state": ["overturning", "tilt:1/3"],
                            "motion": [f"m{i}" for i in range(n)], "tan_alpha": [0.11],
                            "R": [2.0, 6.0]})
    ds.attrs["config"] = json.dumps({"spectra": {"upper": 12.0}})
    return ds


@pytest.fixture()
def fragility_csv(tmp_path):
    """fragility.csv and fragility_bootstrap.nc as the fragility rule writes them."""
    from rocking.fragility.bootstrap import write_bootstrap

    s = store()
    table = F.fragility_table(s, upper=12.0)
    boot = F.fragility_bootstrap(s, table, upper=12.0, n_resamples=300)
    path = tmp_path / "fragility.csv"
    F.to_frame(F.with_interval(table, boot)).to_csv(path, index=False, float_format="%.10g")
    write_bootstrap(boot, bootstrap_path(path), table=path)  # after its table, as the rule
    return path


def test_fragility_table_rows_and_samples_line_up(fragility_csv):
    frame = pd.read_csv(fragility_csv)
    assert {"median_p05 [g]", "median_p95 [g]", "bootstrap_fitted"} <= set(frame.columns)
    boot = read_bootstrap(bootstrap_path(fragility_csv), n_rows=len(frame))
    s = store()
    idx = np.random.default_rng(F.BOOTSTRAP_SEED).integers(0, 14, size=(300, 14))
    for i, r in frame.iterrows():
        # the row's own motions, resampled here and fitted here (independent of the table)
        cell = s.sel(mode=r["mode"], limit_state=r["limit_state"], tan_alpha=r["tan_alpha [-]"],
                     R=r["R [m]"])
        x = np.where(cell["not_reached"], 12.0, cell["pga_crit"]).astype(float)
        c = cell["not_reached"].values.astype(bool)
        j = 5
        if c[idx[j]].any():
            m, _ = own_censored_fit(x[idx[j]], c[idx[j]])
        else:
            m = math.exp(np.log(x[idx[j]]).mean())
        assert boot.median[i, j] == pytest.approx(m * 0.11, rel=1e-5)  # in g
        lo, hi = np.nanpercentile(boot.median[i], [5, 95])
        assert r["median_p05 [g]"] == pytest.approx(lo, rel=1e-9)
        assert r["median_p95 [g]"] == pytest.approx(hi, rel=1e-9)
        assert lo < r["median_pga_g [g]"] < hi
    with pytest.raises(ValueError, match="rows, its table has"):
        read_bootstrap(bootstrap_path(fragility_csv), n_rows=len(frame) + 1)


def test_risk_csv_interval_from_the_samples_beside_the_table(fragility_csv, capsys):
    h = HazardCurve.from_power_law(2e-4, 2.2)
    t = risk_table(read_fragilities(fragility_csv), h)
    boot = read_bootstrap(bootstrap_path(fragility_csv))
    frame = pd.read_csv(fragility_csv)
    for r in t.to_dict(orient="records"):
        i = int(np.flatnonzero((frame["R [m]"] == r["R [m]"])
                               & (frame["limit_state"] == r["limit_state"]))[0])
        own = [closed_form(2e-4, 2.2, m, b) for m, b in zip(boot.median[i], boot.beta[i],
                                                              strict=True) if np.isfinite(m)]
        lo, hi = np.percentile(own, [5, 95])
        assert r["lambda_p05 [1/yr]"] == pytest.approx(lo, rel=3e-3)
        assert r["lambda_p95 [1/yr]"] == pytest.approx(hi, rel=3e-3)
        assert r["lambda_p05 [1/yr]"] < r["maf [1/yr]"] < r["lambda_p95 [1/yr]"]
        assert r["n"] == 14
    # the command line prints the interval
    assert main(["risk", "--fragility", str(fragility_csv), "--hazard", "2e-4,2.2"]) == 0
    out = capsys.readouterr().out
    assert "90 % interval of λ over 300 resamples" in out
    assert f"{t['lambda_p05 [1/yr]'].iloc[0]:.3g}" in out


# ------------------------------------------------------------------ SA(1.0)


def sa_hazard(im):
    """An analytic Sa(1 s) hazard: λ = (1/475)·exp(−1.9 L − 0.2 L²), L = ln(Sa/0.2 g), and
    |dλ/d im|."""
    L = np.log(np.asarray(im, float) / 0.2)
    lam = np.exp(-1.9 * L - 0.2 * L * L) / 475.0
    return lam, lam * (1.9 + 0.4 * L) / np.asarray(im, float)


def quad_maf(median, beta):
    """∫ Φ(ln(im/θ)/β) |dλ/d im| d im by adaptive quadrature on the analytic curve."""
    def f(u):
        im = math.exp(u)
        return stats.norm.cdf((u - math.log(median)) / beta) * sa_hazard(im)[1] * im

    lo, hi, c = math.log(0.01), math.log(200.0), math.log(median)
    pts = sorted({max(lo, c - 3 * beta), c, min(hi, c + 3 * beta)})
    return integrate.quad(f, lo, hi, points=pts, limit=500, epsabs=0, epsrel=1e-10)[0]


def suite_table(path):
    """suite_fragility.csv as records.py writes it: per motions group, cell and measure."""
    rows = []
    for motions, scale in (("records", 1.0), ("synthetic", 1.3)):
        for R, (m_pga, m_sa, b) in ((2.0, (0.35, 0.42, 0.3)), (6.0, (0.7, 0.9, 0.45))):
            rows.append((motions, "3d", 0.11, "overturning", R, "pga", "g", m_pga * scale, b))
            rows.append((motions, "3d", 0.11, "overturning", R, "sa:1.0", "g", m_sa * scale,
                         b * 1.1))
            rows.append((motions, "3d", 0.11, "overturning", R, "pgv", "m/s", 0.5, 0.4))
    frame = pd.DataFrame(rows, columns=["motions", "mode", "tan_alpha", "limit_state", "R",
                                        "measure", "unit", "median", "beta"])
    frame["n"], frame["n_censored"], frame["status"] = 4, 0, "ok"
    frame.to_csv(path, index=False)
    return frame


def write_sa_csv(path):
    im = np.geomspace(0.005, 6.0, 60)
    poe = -np.expm1(-50.0 * sa_hazard(im)[0])
    # the engine's lowest levels (below the analytic curve's range): PoE = 1 to six digits
    im, poe = np.concatenate([[0.002, 0.003], im]), np.concatenate([[1.0, 1.0], poe])
    path.write_text("#,,,,,\"generated_by='OpenQuake engine 3.23', kind='mean', "
                    "investigation_time=50.0, imt='SA(1.0)'\"\n"
                    "lon,lat,depth," + ",".join(f"poe-{x:.7f}" for x in im) + "\n"
                    "0.0,0.0,0.0," + ",".join(f"{p:.6E}" for p in poe) + "\n")
    return path


def test_sa_path_against_an_independent_quadrature(tmp_path, capsys):
    suite = tmp_path / "suite_fragility.csv"
    frame = suite_table(suite)
    hazard_file = write_sa_csv(tmp_path / "hazard_curve-mean-SA(1.0).csv")
    h = parse_hazard({"file": str(hazard_file), "component": "vector_peak"})
    assert h.measure == "sa:1.0" and h.n_dropped > 0  # its lowest levels read PoE = 1
    t = risk_table(suite, h)
    assert set(t["measure"]) == {"sa:1.0"} and len(t) == 2
    want = frame[(frame["motions"] == "records") & (frame["measure"] == "sa:1.0")]
    for r, w in zip(t.to_dict(orient="records"), want.itertuples(), strict=True):
        assert r["median_im [g]"] == w.median and math.isnan(r["median_pga_g [g]"])
        assert r["maf [1/yr]"] == pytest.approx(quad_maf(w.median, w.beta), rel=3e-3)
    # a PGA fragility with no motions to refit it in Sa is refused in one line
    pga = tmp_path / "fragility.csv"
    pd.DataFrame({"mode": ["3d"], "limit_state": ["overturning"], "tan_alpha [-]": [0.11],
                  "R [m]": [2.0], "median_pga_g [g]": [0.35], "beta [-]": [0.3],
                  "status": ["ok"]}).to_csv(pga, index=False)
    with pytest.raises(ValueError, match=r"is of SA\(1.0\), .* of pga only: add sa:1.0"):
        risk_table(pga, h)
    # the command line, with the measure named
    base = ["risk", "--fragility", str(suite), "--hazard", str(hazard_file), "--component",
            "vector_peak"]
    assert main([*base, "--measure", "sa:1.0"]) == 0
    text = capsys.readouterr().out
    assert "SA(1.0)" in text and "dropped" in text
    assert main([*base, "--measure", "pga"]) == 2
    assert "does not match" in capsys.readouterr().err


# ------------------------------------------------------------------ rows without a fit


def stripe_table_new(path):
    """A stripe table with the columns the stripes branch adds (measure, median_im,
    bracket_lo/hi [g], status): one fit, one separated row, one none-exceeded row."""
    frame = pd.DataFrame({
        "mode": ["3d"] * 3, "limit_state": ["overturning"] * 3, "tan_alpha [-]": [0.11] * 3,
        "R [m]": [2.0, 3.02, 6.0], "median [g tan(alpha)]": [3.0, np.nan, np.nan],
        "median_pga_g [g]": [0.33, np.nan, np.nan], "beta [-]": [0.3, np.nan, np.nan],
        "status": ["ok", "separated", "none-exceeded"], "n_motions": [4, 4, 4],
        "stripes": [8, 8, 8], "measure": ["pga"] * 3, "median_im [g]": [0.33, np.nan, np.nan],
        "bracket_lo [g]": [np.nan, 0.30, 0.9], "bracket_hi [g]": [np.nan, 0.45, np.nan]})
    frame.to_csv(path, index=False)
    return path


def test_separated_stripe_rows_are_kept_with_the_bracket_bounds(tmp_path):
    h = HazardCurve.from_power_law(1e-4, 2.5)
    t = risk_table(read_fragilities(stripe_table_new(tmp_path / "stripe_fragility.csv")), h)
    assert list(t["status"]) == ["ok", "separated", "none-exceeded"]
    sep, none = t.iloc[1], t.iloc[2]
    assert math.isnan(sep["maf [1/yr]"])
    assert sep["lambda_lo [1/yr]"] == pytest.approx(1e-4 * 0.45 ** -2.5, rel=1e-9)
    assert sep["lambda_hi [1/yr]"] == pytest.approx(1e-4 * 0.30 ** -2.5, rel=1e-9)
    assert none["lambda_lo [1/yr]"] == 0.0
    assert none["lambda_hi [1/yr]"] == pytest.approx(1e-4 * 0.9 ** -2.5, rel=1e-9)
    assert "separated" in t.attrs["skipped"] and "R=3.02 m" in t.attrs["skipped"]
    html = unescape(risk_section_html(t))
    assert "lambda_hi as the conservative value" in html


def test_old_stripe_table_without_brackets_keeps_its_rows(tmp_path):
    path = stripe_table_new(tmp_path / "s.csv")
    pd.read_csv(path).drop(columns=["measure", "median_im [g]", "bracket_lo [g]",
                                    "bracket_hi [g]"]).to_csv(path, index=False)
    t = risk_table(read_fragilities(path), HazardCurve.from_power_law(1e-4, 2.5))
    assert len(t) == 3 and t["lambda_hi [1/yr]"].isna().all()


def test_a_study_without_any_fit_gets_its_statuses_not_an_error(tmp_path):
    path = tmp_path / "fragility.csv"
    pd.DataFrame({"mode": ["3d", "3d"], "limit_state": ["overturning", "tilt:1/3"],
                  "tan_alpha [-]": [0.11, 0.11], "R [m]": [3.02, 3.02],
                  "median_pga_g [g]": [np.nan, np.nan], "beta [-]": [np.nan, np.nan],
                  "status": ["too-few-observed", "no-spread"]}).to_csv(path, index=False)
    out = {k: tmp_path / f"o.{k}" for k in ("xml", "csv", "risk")}
    summary = write_risk_outputs(path, HazardCurve.from_power_law(1e-4, 2.5), nrml=out["xml"],
                                 pelicun=out["csv"], table=out["risk"], study="s")
    written = pd.read_csv(out["risk"])
    assert sorted(written["status"]) == ["no-spread", "too-few-observed"]
    assert written["maf [1/yr]"].isna().all() and summary["risk_rows"] == 2
    assert "2 row(s)" in summary["risk_skipped"]


# ------------------------------------------------------------------ preset and small suites


def test_fast_preset_warns_and_small_suites_are_flagged(fragility_csv):
    from rocking.risk.risk_table import PRESET_ERRORS

    h = HazardCurve.from_power_law(2e-4, 2.2)
    t = risk_table(read_fragilities(fragility_csv), h, preset="fast")
    assert set(t["preset"]) == {"fast"}
    html = unescape(risk_section_html(t))
    assert "WARNING: λ computed from fast-preset answers, unconservative" in html
    assert f"{PRESET_ERRORS['fast'][0]:g} %" in html and "λ is too low" in html
    assert "90 % interval of λ" in html and "resamples of the study's motions" in html
    assert not small_suite_warnings(t)  # 14 motions
    few = t.assign(n=4)
    (text,) = small_suite_warnings(few)
    width = float(np.median(few["lambda_p95 [1/yr]"] / few["lambda_p05 [1/yr]"]))
    assert f"factor {width:.3g}" in text and f"{width ** math.sqrt(0.4):.3g}" in text
    assert "WARNING" not in risk_section_html(risk_table(read_fragilities(fragility_csv), h,
                                                         preset="default"))
