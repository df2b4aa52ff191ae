"""Multiple-stripe fragility (rocking.fragility.stripes): the binomial fit against an independent
maximum-likelihood fit and against counts drawn from a known lognormal, its undefined cases,
the analyses against the engine, bad input, and the ``rocking stripes`` command."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize, stats

import rocking
from rocking.dynamics.analysis import ground_response
from rocking.fragility.stripes import (
    BETA_MAX,
    fit_stripes,
    from_outcomes,
    stripe_fragility,
    stripe_intensities,
)


def independent_mle(x, k, n):
    """Binomial MLE written separately: (θ, β) directly, bounded L-BFGS-B on binom.logpmf,
    started from a grid (no shared code with the library)."""
    x, k, n = (np.asarray(a, float) for a in (x, k, n))

    def nll(p):
        theta, beta = p
        prob = np.clip(stats.norm.cdf(np.log(x / theta) / beta), 1e-15, 1 - 1e-15)
        return -np.sum(stats.binom.logpmf(k, n, prob))

    grid = [(t, b) for t in np.geomspace(x[0], x[-1], 25) for b in (0.1, 0.3, 0.6, 1.0)]
    start = min(grid, key=nll)
    res = optimize.minimize(nll, start, method="L-BFGS-B",
                            bounds=[(x[0] / 10, x[-1] * 10), (1e-3, 5.0)],
                            options={"ftol": 1e-15, "gtol": 1e-12, "maxiter": 10000})
    return res.x


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_fit_matches_independent_mle(seed):
    rng = np.random.default_rng(seed)
    x = np.geomspace(1.2, 12.0, 15)
    n = rng.integers(5, 30, x.size)
    theta, beta = rng.uniform(2.5, 6.0), rng.uniform(0.2, 0.7)
    k = rng.binomial(n, stats.norm.cdf(np.log(x / theta) / beta))
    fit = fit_stripes(x, k, n)
    ref_theta, ref_beta = independent_mle(x, k, n)
    assert fit.status == "ok"
    assert fit.median == pytest.approx(ref_theta, rel=1e-4)
    assert fit.beta == pytest.approx(ref_beta, rel=1e-4)


def test_known_lognormal_recovered_within_its_interval():
    """Counts drawn from Φ(ln(x/θ)/β): the 95 % Wald intervals hold the truth for one draw,
    and over 200 draws they cover it about 95 % of the time."""
    theta, beta = 3.0, 0.4
    x = stripe_intensities(20, 1.0, 10.0)
    p = stats.norm.cdf(np.log(x / theta) / beta)
    n = np.full(x.size, 40)
    rng = np.random.default_rng(2017)
    cover_m = cover_b = 0
    draws = 200
    for i in range(draws):
        fit = fit_stripes(x, rng.binomial(n, p), n)
        assert fit.status == "ok"
        in_m = fit.median_ci[0] <= theta <= fit.median_ci[1]
        in_b = fit.beta_ci[0] <= beta <= fit.beta_ci[1]
        if i == 0:
            assert in_m and in_b
            assert fit.median_ci[1] / fit.median_ci[0] < 1.2  # 800 analyses pin θ to ±10 %
        cover_m += in_m
        cover_b += in_b
    # binomial(200, 0.95): 2.5 sd is ±3.9 %
    assert 0.91 <= cover_m / draws <= 0.99
    assert 0.91 <= cover_b / draws <= 0.99


def test_undefined_fits_say_why():
    x = np.array([1.5, 2.0, 3.0, 4.0])
    n = np.array([10, 10, 10, 10])
    cases = {
        "none-exceeded": [0, 0, 0, 0],
        "all-exceeded": [10, 10, 10, 10],
        "separated": [0, 0, 10, 10],
    }
    for status, k in cases.items():
        fit = fit_stripes(x, k, n)
        assert fit.status == status
        assert math.isnan(fit.median) and math.isnan(fit.beta)
        assert fit.reason
    # one mixed stripe between none and all still separates: β → 0 at that stripe
    assert fit_stripes(x, [0, 4, 10, 10], n).status == "separated"
    assert "2 and 3" in fit_stripes(x, [0, 0, 10, 10], n).reason
    assert "only the stripe at 2 " in fit_stripes(x, [0, 4, 10, 10], n).reason
    # no trend: the same share everywhere over a wide span, β beyond BETA_MAX
    flat = fit_stripes(np.geomspace(1, 20, 8), [5] * 8, [10] * 8)
    assert flat.status == "no-trend" and math.isnan(flat.median)
    assert BETA_MAX < 10
    # nothing analysed
    assert fit_stripes(x, [0] * 4, [0] * 4).status == "no-analyses"


def test_extrapolated_median_is_flagged():
    x = np.geomspace(1.0, 4.0, 6)
    fit = fit_stripes(x, [0, 0, 1, 1, 2, 3], [20] * 6)
    assert fit.status == "extrapolated"
    assert fit.median > x[-1] and "outside" in fit.reason


def test_stripes_with_no_motion_are_left_out():
    x = np.geomspace(1.2, 12.0, 10)
    k = np.array([0, 0, 1, 3, 5, 0, 12, 14, 15, 15])
    n = np.array([15, 15, 15, 15, 15, 0, 15, 15, 15, 15])
    fit = fit_stripes(x, k, n)
    keep = n > 0
    ref = independent_mle(x[keep], k[keep], n[keep])
    assert fit.median == pytest.approx(ref[0], rel=1e-4)


@pytest.mark.parametrize("args, match", [
    (([1.0, 2.0], [0, 1], [1]), "n_total"),
    (([1.0, 2.0], [0, 3], [2, 2]), "exceeds n_total"),
    (([1.0, 2.0], [0, -1], [2, 2]), "n_exceeding"),
    (([1.0, 2.0], [0, 0.5], [2, 2]), "n_exceeding"),
    (([2.0, 1.0], [0, 1], [2, 2]), "strictly increasing"),
    (([0.0, 1.0], [0, 1], [2, 2]), "finite numbers > 0, got 0.0 at sample 0"),
    (([np.nan, 1.0], [0, 1], [2, 2]), "finite numbers > 0, got nan at sample 0"),
])
def test_fit_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        fit_stripes(*args)


def test_stripe_intensities_bad_input():
    assert stripe_intensities(5, 1.0, 16.0).tolist() == [1.0, 2.0, 4.0, 8.0, 16.0]  # both ends
    for bad in (0, -3, 2.5, True):
        with pytest.raises(ValueError, match="number of stripes"):
            stripe_intensities(bad)
    with pytest.raises(ValueError, match="lower < upper"):
        stripe_intensities(5, 3.0, 2.0)


@pytest.fixture(scope="module")
def elcentro():
    return rocking.load_motion("el-centro-1940")


def test_stripe_fragility_bad_input(elcentro):
    cyl = rocking.Cylinder(2.0, 0.2)
    with pytest.raises(ValueError, match="mode"):
        stripe_fragility(cyl, [elcentro], "overturning", mode="4d", intensities=[2.0])
    with pytest.raises(ValueError, match="at least one"):
        stripe_fragility(cyl, [], "overturning", intensities=[2.0])
    with pytest.raises(ValueError, match="GroundMotion"):
        stripe_fragility(cyl, [elcentro, "x"], "overturning", intensities=[2.0])
    with pytest.raises(ValueError, match="unique"):
        stripe_fragility(cyl, [elcentro, elcentro], "overturning", intensities=[2.0])
    with pytest.raises(ValueError, match="strictly increasing"):
        stripe_fragility(cyl, [elcentro], "overturning", intensities=[2.0, 2.0])
    with pytest.raises(ValueError, match="limit state"):
        stripe_fragility(cyl, [elcentro], "tilt:20", intensities=[2.0])


def test_one_analysis_per_stripe_and_motion_matches_the_engine(elcentro):
    """Each flag equals the engine's own verdict at that scale (run to the end, no stop),
    stripes at or below uplift run nothing, and every limit state shares one analysis."""
    cyl = rocking.Cylinder(2.0, 0.2)
    x = np.array([0.8, 1.0, 1.5, 2.5, 4.0])
    states = ["overturning", "tilt:1/3", "tilt:0.1"]
    r = stripe_fragility(cyl, elcentro, states, intensities=x, jitter=0.0)  # the stripes exactly
    assert r.n_analyses == 3  # 0.8 and 1.0 are at or below uplift (3D: 1)
    assert r.limit_states == ("overturning", "tilt:1/3", "tilt:0.1")
    scale = rocking.G * cyl.tan_alpha / elcentro.pga
    for i, im in enumerate(x):
        g = ground_response(cyl, elcentro, model="3d", scale=im * scale, history=False)
        want = [g.overturned, g.overturned or g.theta_max > cyl.alpha / 3,
                g.overturned or g.theta_max > 0.1 * cyl.alpha]
        assert list(r.exceeded[i, 0]) == want, im
    assert r.n_motions.tolist() == [1] * x.size
    assert r.fraction.shape == (x.size, 3)
    assert r.fraction[:2].sum() == 0.0
    # a single motion is a step: no spread is seen, so no finite median
    for name in r.limit_states:
        assert r.status[name] in {"separated", "none-exceeded", "all-exceeded"}
        assert math.isnan(r.median[name])
    assert "tilt:1/3" in repr(r)
    assert r["excessive-tilt"].status == r.status["tilt:1/3"]
    frame = r.to_frame()
    assert len(frame) == 3 * x.size and set(frame["n_motions"]) == {1}


def test_from_outcomes_counts_and_failures():
    x = np.geomspace(1.5, 10, 6)
    rng = np.random.default_rng(4)
    caps = np.exp(rng.normal(math.log(4.0), 0.5, 12))  # each motion exceeds above its capacity
    exc = (x[:, None] >= caps[None, :])[:, :, None]
    failed = np.zeros((x.size, 12), bool)
    failed[2, 3] = True
    r = from_outcomes(x, ["overturning"], [f"m{i}" for i in range(12)], exc, failed)
    assert r.n_motions[2] == 11 and r.n_motions[0] == 12
    assert r.n_exceeding[2, 0] == exc[2, :, 0].sum() - exc[2, 3, 0]
    k = r.n_exceeding[:, 0]
    ref = independent_mle(x, k, r.n_motions)
    assert r.median["overturning"] == pytest.approx(ref[0], rel=1e-4)
    assert r.beta["overturning"] == pytest.approx(ref[1], rel=1e-4)
    with pytest.raises(ValueError, match="shape"):
        from_outcomes(x, ["overturning"], ["a"], exc, failed)


def test_cli_stripes_table_with_units(capsys):
    from rocking.cli import main

    code = main(["stripes", "--R", "2", "--tan-alpha", "0.2", "--record", "el-centro-1940",
                 "--intensities", "1.5,2.5,4", "--limit-states", "overturning,tilt:1/3", "-q"])
    out = capsys.readouterr().out
    assert code == 0
    assert "median PGA/(g tan α) [-]" in out and "median PGA [g]" in out and "β [-]" in out
    assert "fraction [-]" in out and "separated" in out


def test_cli_stripes_bad_input(capsys):
    from rocking.cli import main

    assert main(["stripes", "--R", "2", "--tan-alpha", "0.2", "--record", "el-centro-1940",
                 "--intensities", "3,2"]) == 2
    assert "strictly increasing" in capsys.readouterr().err


def test_cli_default_matches_library():
    from rocking.cli import stripes as cli
    from rocking.fragility import stripes as lib

    assert cli.DEFAULT_STRIPES == lib.DEFAULT_STRIPES
    assert cli.DEFAULT_REFINE == lib.DEFAULT_REFINE
    assert (1.0, 20.0) == lib.STRIPE_RANGE


def test_cli_stripes_csv_and_strict_json(tmp_path):
    import json

    from rocking.cli import main

    args = ["stripes", "--R", "2", "--tan-alpha", "0.2", "--record", "el-centro-1940",
            "--intensities", "1.5,2.5", "--limit-states", "overturning", "--refine", "0", "-q"]
    assert main([*args, "-o", str(tmp_path / "s.csv")]) == 0
    import pandas as pd

    fits = pd.read_csv(tmp_path / "s.csv")
    stripes = pd.read_csv(tmp_path / "s_stripes.csv")
    assert "median [g tan(alpha)]" in fits.columns and len(stripes) == 2
    assert main([*args, "-o", str(tmp_path / "s.json")]) == 0

    def no_nan(token):
        raise ValueError(token)

    doc = json.loads((tmp_path / "s.json").read_text(), parse_constant=no_nan)
    assert doc["intensities"] == [1.5, 2.5] and doc["units"]["median"] == "g tan(alpha)"
    assert doc["fits"][0]["status"] != "ok" and doc["fits"][0]["median"] is None


def test_cli_stripes_in_sa_refined_and_bootstrapped(tmp_path, capsys):
    """--measure sa:1.0: the stripes in Sa(1 s) as the library gives them; --refine adds
    stripes to a separated fit (one motion: it stays separated, with its bracket in g);
    --bootstrap fills the interval columns."""
    import json

    from rocking.cli import main
    from rocking.fragility.stripes import refine_stripes, stripe_analyzer

    args = ["stripes", "--R", "2", "--tan-alpha", "0.15", "--record", "el-centro-1940",
            "--intensities", "2,4,8", "--limit-states", "overturning", "--measure", "sa:1.0",
            "--refine", "2", "--bootstrap", "20", "-q", "-o", str(tmp_path / "s.json")]
    assert main(args) == 0
    assert "median Sa(1 s) [g]" in capsys.readouterr().out
    doc = json.loads((tmp_path / "s.json").read_text())
    assert doc["measure"] == "sa:1.0" and doc["units"]["median_im"] == "g"
    motion = rocking.load_motion("el-centro-1940")
    cyl = rocking.Cylinder(2.0, 0.15)
    base = stripe_fragility(cyl, motion, "overturning", intensities=[2, 4, 8], measure="sa:1.0")
    want = refine_stripes(base, "overturning",
                          stripe_analyzer(cyl, [motion], ["overturning"], measure="sa:1.0"), 2)
    (fit,) = doc["fits"]
    assert fit["status"] == want.status["overturning"] and fit["n_refined"] == want.n_refined
    assert [s["intensity"] for s in doc["stripes"]] == want.intensities.tolist()
    if fit["status"] == "separated":
        assert 0 < fit["bracket_lo"] < fit["bracket_hi"]


# ------------------------------------------------------------------ jitter: the mean of P(s)
def test_the_jittered_share_estimates_the_mean_local_exceedance_probability():
    """A motion that exceeds above c: averaged over the jitter its exceedance at s is
    P(s) = clip((ln(s/c) + w) / 2w, 0, 1), the share of intensities within ±w of s (in ln s)
    that exceed; the share over many motions (their own draws) converges to it."""
    from rocking.fragility.stripes import jittered

    w, c, n = 0.02, 2.0, 4000
    s = c * np.exp([-0.03, -0.01, 0.0, 0.015, 0.03])
    want = np.clip((np.log(s / c) + w) / (2 * w), 0.0, 1.0)
    assert want.tolist() == pytest.approx([0.0, 0.25, 0.5, 0.875, 1.0])
    draws = np.array([jittered(s, w, motion=f"m{k}", mode="3d", R=2.0, tan_alpha=0.2)
                      for k in range(n)])
    assert np.all(np.abs(np.log(draws / s)) <= w)
    share = (draws > c).mean(axis=0)
    sigma = np.sqrt(want * (1 - want) / n)
    assert np.all(np.abs(share - want) <= 4 * sigma + 1e-12), (share, want)


def test_the_jitter_is_drawn_from_the_analysis_identity():
    from rocking.fragility.stripes import jittered

    s = np.array([1.5, 2.0, 3.0])
    one = dict(motion="el-centro-1940", mode="3d", R=2.0, tan_alpha=0.2)
    a, b = jittered(s, 0.02, **one), jittered(s, 0.02, **one)
    assert a.tobytes() == b.tobytes()  # the same analysis, the same bits
    # a stripe's draw does not depend on the other stripes (a refined stripe is analysed at
    # the same intensity whatever was added around it)
    assert jittered(s[1:2], 0.02, **one)[0] == a[1]
    for key, value in (("motion", "other"), ("mode", "2d-x"), ("R", 2.5), ("tan_alpha", 0.3)):
        assert jittered(s, 0.02, **{**one, key: value}).tobytes() != a.tobytes(), key
    assert jittered(s, 0.0, **one).tobytes() == s.tobytes()
    with pytest.raises(ValueError, match=r"jitter must be in \[0, 0.5\)"):
        jittered(s, 0.5, **one)


def test_the_exceedance_table_is_the_share_with_its_bootstrap_interval():
    from rocking.fragility.stripes import exceedance_table

    x = np.array([1.0, 2.0, 4.0])
    exceeded = np.zeros((3, 5, 1), bool)
    exceeded[1, :2, 0] = True
    exceeded[2, :4, 0] = True
    failed = np.zeros((3, 5), bool)
    failed[2, 4] = True  # left out of the count at that stripe
    r = from_outcomes(x, ["overturning"], [f"m{k}" for k in range(5)], exceeded, failed,
                      R=2.0, tan_alpha=0.2, jitter=0.02)
    t = exceedance_table(r, resamples=400)
    assert t["share"].tolist() == [0.0, 0.4, 1.0]
    assert t["n_motions"].tolist() == [5, 5, 4] and set(t["jitter"]) == {0.02}
    assert t["im"].tolist() == pytest.approx((x * 0.2).tolist())
    assert (t["share_p05"] <= t["share"]).all() and (t["share"] <= t["share_p95"]).all()
    assert t.loc[1, "share_p05"] < 0.4 < t.loc[1, "share_p95"]  # two of five: uncertain

