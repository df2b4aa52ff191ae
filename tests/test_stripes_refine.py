"""Stripes beyond the first fit (rocking.fragility.stripes): stripes in another intensity measure
against the engine at the scale an independent Sa gives, refinement of a separated fit against
a dense-stripe reference, and the bootstrap over motions against a resampling written here."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal
from test_stripes import independent_mle

import rocking
from rocking.dynamics.analysis import ground_response
from rocking.fragility.stripes import (
    BOOTSTRAP_SEED,
    bootstrap_interval,
    bootstrap_stripes,
    bracket,
    fit_stripes,
    from_outcomes,
    measure_ratio,
    refine_stripes,
    refinement_point,
    stripe_fragility,
    stripe_intensities,
)

# --------------------------------------------------------------------------------------
# A threshold model: motion m exceeds at every intensity >= its capacity c_m (no dynamics)
# --------------------------------------------------------------------------------------


def threshold_result(x, caps, limit_states=("overturning",)):
    x = np.asarray(x, dtype=float)
    exc = np.repeat((x[:, None] >= caps[None, :])[:, :, None], len(limit_states), axis=2)
    return from_outcomes(x, list(limit_states), [f"m{i}" for i in range(caps.size)], exc,
                         np.zeros((x.size, caps.size), bool), tan_alpha=0.11)


def threshold_analyzer(caps, n_states=1):
    calls = []

    def analyze(x):
        calls.append(float(x))
        e = np.repeat((x >= caps)[:, None], n_states, axis=1)
        return e, np.zeros(caps.size, bool), caps.size

    return analyze, calls


def test_bracket_and_refinement_point():
    x = np.array([1.0, 2.0, 4.0, 8.0])
    n = np.full(4, 5)
    # a step between 2 and 4: the bracket, and the new stripe at their geometric middle
    assert bracket(x, [0, 0, 5, 5], n) == (2.0, 4.0)
    assert refinement_point(x, [0, 0, 5, 5], n) == pytest.approx(math.sqrt(8.0))
    # one mixed stripe at 4: bracket 2-8, the larger gap in ln I is halved (tie: the lower)
    assert bracket(x, [0, 0, 3, 5], n) == (2.0, 8.0)
    assert refinement_point(x, [0, 0, 3, 5], n) == pytest.approx(math.sqrt(8.0))
    assert refinement_point([1.0, 2.0, 2.5, 8.0], [0, 0, 3, 5], n) == pytest.approx(
        math.sqrt(20.0))
    # none exceeding / all exceeding: unbounded on one side, nothing to bisect
    assert bracket(x, [0, 0, 0, 0], n) == (8.0, math.inf)
    assert bracket(x, [5, 5, 5, 5], n) == (0.0, 1.0)
    assert refinement_point(x, [0, 0, 0, 0], n) is None
    assert refinement_point(x, [5, 5, 5, 5], n) is None
    # a defined fit is not separated, and the step at the first stripe cannot be bisected
    assert fit_stripes(x, [0, 2, 3, 5], n).status == "ok"
    assert refinement_point(x, [0, 5, 5, 5], n) == pytest.approx(math.sqrt(2.0))
    # mixed at the first (last) stripe, all (none) beyond: the step is sought beyond it, as
    # far from it in ln I as the next bracketing stripe
    assert fit_stripes(x, [3, 5, 5, 5], n).status == "separated"
    assert bracket(x, [3, 5, 5, 5], n) == (0.0, 2.0)
    assert refinement_point(x, [3, 5, 5, 5], n) == pytest.approx(0.5)
    assert refinement_point(x, [0, 0, 0, 2], n) == pytest.approx(16.0)


def test_refined_stripes_match_a_dense_stripe_reference():
    """Capacities close together (β 0.05): 8 stripes over (1, 20] step from none to all
    between two of them (separated); refined, the fit is defined and its median within
    1 % of the fit on 2000 stripes over the same range (the dense reference)."""
    caps = np.exp(np.random.default_rng(7).normal(math.log(5.3), 0.05, 20))
    coarse = threshold_result(stripe_intensities(8), caps)
    assert coarse.status["overturning"] == "separated"
    lo, hi = bracket(coarse.intensities, coarse.n_exceeding[:, 0], coarse.n_motions)
    assert lo < caps.min() and caps.max() <= hi
    analyze, calls = threshold_analyzer(caps)
    lines = []
    r = refine_stripes(coarse, "overturning", analyze, budget=12, log=lines.append)
    assert r.status["overturning"] in ("ok", "extrapolated") and r.status["overturning"] == "ok"
    assert r.n_refined == len(calls) == len(lines) and 1 <= r.n_refined <= 12
    assert all(lo < c < hi for c in calls)  # every stripe added inside the first bracket
    assert r.intensities.size == 8 + r.n_refined and np.all(np.diff(r.intensities) > 0)
    dense = threshold_result(stripe_intensities(2000), caps)
    assert dense.status["overturning"] == "ok"
    assert r.median["overturning"] == pytest.approx(dense.median["overturning"], rel=0.01)
    # the refined counts are the threshold model's own at each stripe
    want = (r.intensities[:, None] >= caps[None, :]).sum(axis=1)
    assert r.n_exceeding[:, 0].tolist() == want.tolist()


def test_refinement_stops_at_its_budget_and_keeps_the_bracket():
    """One motion is a step at any resolution: the budget is spent, the row stays separated
    with a bracket that has shrunk around the capacity by 2^budget in ln I."""
    caps = np.array([4.2])
    coarse = threshold_result(stripe_intensities(8), caps)
    lo0, hi0 = bracket(coarse.intensities, coarse.n_exceeding[:, 0], coarse.n_motions)
    analyze, calls = threshold_analyzer(caps)
    r = refine_stripes(coarse, "overturning", analyze, budget=5)
    assert r.status["overturning"] == "separated" and r.n_refined == 5 == len(calls)
    lo, hi = bracket(r.intensities, r.n_exceeding[:, 0], r.n_motions)
    assert lo < 4.2 <= hi
    assert math.log(hi / lo) == pytest.approx(math.log(hi0 / lo0) / 2**5, rel=1e-9)
    row = r.summary_frame().iloc[0]
    assert row["bracket_lo"] == pytest.approx(lo * 0.11) and row["n_refined"] == 5
    # nothing to do where the fit is defined or no motion exceeds
    assert refine_stripes(threshold_result(stripe_intensities(8), np.array([50.0])),
                          "overturning", analyze, budget=5).n_refined == 0
    with pytest.raises(ValueError, match="budget"):
        refine_stripes(coarse, "overturning", analyze, budget=-1)


def test_bootstrap_matches_an_independent_resampling():
    """The same resamples drawn here (numpy's generator, the documented seed), each refitted
    by the independent MLE of test_stripes: the 5 and 95 % points agree."""
    rng = np.random.default_rng(3)
    x = stripe_intensities(12, 1.0, 12.0)
    caps = np.exp(rng.normal(math.log(4.0), 0.4, 15))
    # scatter: each motion also survives at one stripe above its capacity (non-monotonic)
    exc = x[:, None] >= caps[None, :]
    for m in range(caps.size):
        above = np.flatnonzero(exc[:, m])
        if above.size > 2:
            exc[above[1], m] = False
    r = from_outcomes(x, ["overturning"], [f"m{i}" for i in range(15)], exc[:, :, None],
                      np.zeros((x.size, 15), bool), tan_alpha=0.11)
    B = 200
    got = bootstrap_stripes(r, B)["overturning"]
    idx = np.random.default_rng(BOOTSTRAP_SEED).integers(0, 15, size=(B, 15))
    ref = []
    for b in range(B):
        k = exc[:, idx[b]].sum(axis=1)
        n = np.full(x.size, 15)
        if fit_stripes(x, k, n).status in ("ok", "extrapolated"):
            ref.append(independent_mle(x, k, n)[0])
        else:
            ref.append(math.nan)
    ref = np.array(ref)
    assert not np.isnan(ref).any()  # every resample has a fit (the scatter sees to it)
    np.testing.assert_allclose(got["median"], ref, rtol=1e-3)
    lo, hi = bootstrap_interval(got["median"])
    # the 5 and 95 % order statistics (inverted CDF: the smallest sample with F >= p)
    srt = np.sort(ref)
    ref_lo, ref_hi = srt[math.ceil(0.05 * B) - 1], srt[math.ceil(0.95 * B) - 1]
    assert (lo, hi) == pytest.approx((ref_lo, ref_hi), rel=1e-3)
    assert lo < r.median["overturning"] < hi
    # the same seed gives the same samples; another seed others
    again = bootstrap_stripes(r, B)["overturning"]["median"]
    np.testing.assert_array_equal(again, got["median"])
    assert not np.array_equal(bootstrap_stripes(r, B, seed=1)["overturning"]["median"],
                              got["median"])
    with pytest.raises(ValueError, match="resamples"):
        bootstrap_stripes(r, 0)


def test_bootstrap_of_separated_resamples_takes_the_bracket_middle():
    x = np.array([1.0, 2.0, 4.0, 8.0])
    exc = np.array([[0, 0], [0, 0], [1, 1], [1, 1]], bool)[:, :, None]
    r = from_outcomes(x, ["overturning"], ["a", "b"], exc, np.zeros((4, 2), bool))
    b = bootstrap_stripes(r, 20)["overturning"]
    assert np.all(b["median"] == pytest.approx(math.sqrt(8.0))) and np.all(b["beta"] == 0.0)


# --------------------------------------------------------------------------------------
# Stripes in Sa(1 s): each motion scaled so that its Sa equals the stripe's
# --------------------------------------------------------------------------------------


def independent_vector_sa(motion, period, damping=0.05):
    """Sa(T) [g] of the pair by scipy's lsim of the oscillator u'' + 2ζωu' + ω²u = −a
    (first-order hold of the input), peak of the vector √(ux² + uy²) times ω²."""
    w = 2 * math.pi / period
    sys = signal.StateSpace([[0, 1], [-w * w, -2 * damping * w]], [[0], [-1]], [[1, 0]], [[0]])
    t = np.arange(motion.npts) * motion.dt
    ux = signal.lsim(sys, motion.ax, t, interp=True)[1]
    uy = signal.lsim(sys, motion.ay, t, interp=True)[1]
    return w * w * np.max(np.hypot(ux, uy)) / rocking.G


def test_sa_stripes_scale_each_motion_to_its_sa_and_match_the_engine():
    motion = rocking.load_motion("el-centro-1940")
    sa = independent_vector_sa(motion, 1.0)
    ratio = measure_ratio(motion, "sa:1.0")
    assert ratio == pytest.approx(motion.pga_g / sa, rel=2e-3)
    assert measure_ratio(motion, "pga") == 1.0
    cyl = rocking.Cylinder(1.5, 0.15)
    x = np.array([2.0, 4.0, 7.0])  # Sa(1 s)/(g tan α)
    r = stripe_fragility(cyl, motion, ["overturning", "tilt:1/3"], intensities=x,
                         measure="sa:1.0")
    assert r.measure == "sa:1.0" and r.scale == pytest.approx(0.15)
    for i, im in enumerate(x):
        scale = im * cyl.tan_alpha / sa  # the motion's Sa(1 s) made im g tan α
        g = ground_response(cyl, motion, model="3d", scale=scale, history=False)
        assert list(r.exceeded[i, 0]) == [g.overturned,
                                          g.overturned or g.theta_max > cyl.alpha / 3], im
    f = r.to_frame()
    assert np.isnan(f["pga_g"]).all() and f["im"].to_numpy()[:3] == pytest.approx(x * 0.15)
    s = r.summary_frame()
    assert (s["measure"] == "sa:1.0").all() and np.isnan(s["median_pga_g"]).all()
    with pytest.raises(ValueError, match="intensity measure"):
        stripe_fragility(cyl, motion, "overturning", intensities=x, measure="sa")
