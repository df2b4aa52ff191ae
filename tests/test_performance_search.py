"""The critical-intensity search on synthetic responses with known answers.

A fake analysis maps the normalized intensity I to a peak tilt θ_max(I)/α given piecewise,
honours ``stop_at`` like the engine (ends with θ = stop_at, status STOPPED_AT_LIMIT) and
reports overturning, so every answer is known exactly from the definition.
"""

import math

import numpy as np
import pytest

from rocking.dynamics.result import Status
from rocking.spectra.accuracy import PRESETS, Accuracy
from rocking.spectra.limit_states import parse_limit_states
from rocking.spectra.search import Outcome, search_critical

ALPHA = math.atan(0.2)
STATES = ["tilt:0.1", "tilt:0.2", "tilt:0.5", "tilt:0.75", "overturning"]
FIXED = PRESETS["default"].with_(name="fixed 1 %", scan_step=0.01, refine_budget=0)
"""The default tolerances with a fixed 1 % scan and no refinement (the default until the
refinement of near misses: tests/test_search_refine.py covers that)."""
ADAPTIVE = PRESETS["default"].with_(name="adaptive", scan="adaptive", scan_step=0.005,
                                    scan_step_max=0.05, tilt_growth=60.0)
"""The adaptive scan measured against it (benchmarks.spectra.ADAPTIVE)."""
SCANS = [FIXED, ADAPTIVE]


def windows_response(I):
    """θ_max/α, or None for overturning: a non-monotonic staircase.

    tilt:0.5 is exceeded on [1.5, 1.8) and again from 2.5; overturning from 3.0.
    """
    if I >= 3.0:
        return None
    if I >= 2.5:
        return 0.8
    if I >= 1.8:
        return 0.3
    if I >= 1.5:
        return 0.6
    return 0.3 * (I - 1.0)


# Smallest I exceeding each of STATES for windows_response (θ/α > r):
EXACT = {"tilt:0.1": 1.0 + 0.1 / 0.3, "tilt:0.2": 1.5, "tilt:0.5": 1.5, "tilt:0.75": 2.5,
         "overturning": 3.0}


def fake_analysis(response, calls, fail=lambda I, rtol: False, nan_at=()):
    def analyze(I, stop_at, rtol):
        calls.append((I, stop_at, rtol))
        if fail(I, rtol):
            return Outcome(float("nan"), False, Status.FAILED, "fake failure")
        if I in nan_at:
            return Outcome(float("nan"), False, Status.OK)
        ratio = response(I)
        theta = math.pi / 2 if ratio is None else ratio * ALPHA
        if stop_at is not None and theta > stop_at:
            return Outcome(stop_at, False, Status.STOPPED_AT_LIMIT)  # θ exactly on the goal
        if ratio is None:
            return Outcome(math.pi / 2, True, Status.OVERTURNED)
        return Outcome(theta, False, Status.OK)

    return analyze


@pytest.mark.parametrize("preset", ["fast", "default", "precise", FIXED], ids=str)
def test_exact_on_non_monotonic_windows(preset):
    calls = []
    res = search_critical(fake_analysis(windows_response, calls), STATES, ALPHA, lower=1.0,
                          upper=10.0, accuracy=preset)
    tol = res.accuracy.bisection_tol
    for k, name in enumerate(res.limit_states):
        truth = EXACT[name]
        # The answer is an intensity seen exceeding, the bracket holds the true boundary and
        # is as narrow as the preset asks.
        assert res.bracket_lo[k] < truth <= res.intensity[k], name
        assert res.intensity[k] - res.bracket_lo[k] <= tol * res.intensity[k] + 1e-15, name
        assert res.intensity[k] - truth <= tol * truth, name
    assert not res.not_reached.any() and not res.failed.any()
    flagged = dict(zip(res.limit_states, res.non_monotonic, strict=True))
    # tilt:0.5 was seen exceeded at I ∈ [1.5, 1.8) and not at the next scan points.
    assert flagged == {"tilt:0.1": False, "tilt:0.2": False, "tilt:0.5": True,
                       "tilt:0.75": False, "overturning": False}
    assert res.n_analyses == len(calls) == len(res.evaluations)


def test_answers_ordered_by_goal():
    res = search_critical(fake_analysis(windows_response, []), STATES, ALPHA, lower=1.0,
                          upper=10.0)
    assert np.all(np.diff(res.intensity) >= 0.0)


def test_one_search_serves_all_limit_states():
    """Stopping each analysis at the largest undecided goal costs less than separate searches,
    and the answers are the same (fixed scan: its bracket of tilt:0.1 needs a bisection)."""
    calls = []
    together = search_critical(fake_analysis(windows_response, calls), STATES, ALPHA,
                               lower=1.0, upper=10.0, accuracy=FIXED)
    separate_cost = 0
    for k, name in enumerate(STATES):
        one = search_critical(fake_analysis(windows_response, []), [name], ALPHA, lower=1.0,
                              upper=10.0, accuracy=FIXED)
        separate_cost += one.n_analyses
        assert one.intensity[0] == pytest.approx(together.intensity[k], rel=0.006)
    assert together.n_analyses < 0.6 * separate_cost
    # While overturning is undecided the scan runs to the end (stop_at None); a bisection
    # inside the tilt:0.1 bracket alone stops at that goal.
    assert calls[0][1] is None
    lo, hi = together.bracket_lo[0], together.bracket_hi[0]
    inside = [c for c in calls if lo <= c[0] <= hi and c[0] < 1.5]
    assert inside and all(c[1] == pytest.approx(0.1 * ALPHA, rel=1e-15) for c in inside[1:])


def test_not_reached_is_a_value():
    res = search_critical(fake_analysis(windows_response, []), STATES, ALPHA, lower=1.0,
                          upper=2.0)
    reached = dict(zip(res.limit_states, ~res.not_reached, strict=True))
    assert reached == {"tilt:0.1": True, "tilt:0.2": True, "tilt:0.5": True,
                       "tilt:0.75": False, "overturning": False}
    assert np.isnan(res.intensity[res.not_reached]).all()
    # The scan ends exactly on upper, where those two were seen not exceeded.
    top = [e for e in res.evaluations if e.intensity == 2.0]
    assert len(top) == 1 and top[0].theta_max == pytest.approx(0.3 * ALPHA, rel=1e-12)


def test_lower_at_or_above_upper_runs_nothing():
    calls = []
    res = search_critical(fake_analysis(windows_response, calls), STATES, ALPHA,
                          lower=math.inf, upper=10.0)
    assert res.not_reached.all() and res.n_analyses == 0 and not calls


@pytest.mark.parametrize("acc", SCANS, ids=lambda a: a.scan)
def test_failure_retried_with_tighter_rtol(acc):
    rtol = PRESETS["default"].rtol
    calls = []
    fake = fake_analysis(windows_response, calls, fail=lambda I, r: I > 2.0 and r == rtol)
    res = search_critical(fake, STATES, ALPHA, lower=1.0, upper=10.0, accuracy=acc)
    assert not res.failed.any()
    assert res.intensity[-1] == pytest.approx(3.0, rel=0.006)
    retried = [c for c in calls if c[2] != rtol]
    assert retried and all(r == pytest.approx(rtol * 0.1) for _, _, r in retried)
    assert res.n_analyses == len(calls)


@pytest.mark.parametrize("acc", SCANS, ids=lambda a: a.scan)
def test_persistent_failure_is_flagged_not_survival(acc):
    # Analyses fail on [2.0, 2.7): overturning (3.0) and tilt:0.75 (2.5) could hide there.
    calls = []
    fake = fake_analysis(windows_response, calls, fail=lambda I, r: 2.0 <= I < 2.7)
    res = search_critical(fake, STATES, ALPHA, lower=1.0, upper=10.0, accuracy=acc)
    flags = dict(zip(res.limit_states, res.failed, strict=True))
    assert flags == {"tilt:0.1": False, "tilt:0.2": False, "tilt:0.5": False,
                     "tilt:0.75": True, "overturning": True}
    assert res.intensity[-1] == pytest.approx(3.0, rel=0.006)
    # Everything failing: nothing is reported as survived.
    res = search_critical(fake_analysis(windows_response, [], fail=lambda I, r: True), STATES,
                          ALPHA, lower=1.0, upper=3.0, accuracy=acc)
    assert res.not_reached.all() and res.failed.all()


def test_nan_theta_is_a_failure():
    calls = []
    scan_point = FIXED.scan_point(1.0, 1)
    res = search_critical(fake_analysis(windows_response, calls, nan_at=(scan_point,)),
                          ["tilt:0.1"], ALPHA, lower=1.0, upper=3.0, accuracy=FIXED)
    assert res.evaluations[0].status == Status.FAILED.value
    assert res.failed[0]  # the failed point lies below the answer


def test_bad_arguments():
    fake = fake_analysis(windows_response, [])
    with pytest.raises(ValueError, match="upper"):
        search_critical(fake, STATES, ALPHA, lower=1.0, upper=float("nan"))
    with pytest.raises(ValueError, match="lower"):
        search_critical(fake, STATES, ALPHA, lower=-1.0)
    with pytest.raises(ValueError, match="limit_state"):
        search_critical(fake, ["collapse"], ALPHA, lower=1.0)
    assert [s.name for s in parse_limit_states(STATES)] == STATES


# --------------------------------------------------------------------- the adaptive scan
GOALS = ["tilt:0.1", "tilt:1/3", "tilt:0.5", "overturning"]


def smooth_response(I):
    """Monotonic: θ/α = 2 (I − 1)², overturning once it would pass 1."""
    ratio = 2.0 * (I - 1.0) ** 2
    return None if ratio >= 1.0 else ratio


SMOOTH_EXACT = {"tilt:0.1": 1.0 + math.sqrt(0.05), "tilt:1/3": 1.0 + math.sqrt(1.0 / 6.0),
                "tilt:0.5": 1.5, "overturning": 1.0 + math.sqrt(0.5)}


def narrow_window_response(I):
    """Micro-rocking up to 1.3, then hovering at 0.45 α (close to tilt:0.5) with a window of
    exceedance only 1.2 % wide at [2.0, 2.024); robustly above from 2.5, overturning from 3."""
    if I >= 3.0:
        return None
    if I >= 2.5 or 2.0 <= I < 2.024:
        return 0.6
    if I >= 1.3:
        return 0.45
    return 1e-6 * I


NARROW_EXACT = {"tilt:0.1": 1.3, "tilt:1/3": 1.3, "tilt:0.5": 2.0, "overturning": 3.0}


@pytest.mark.parametrize(("response", "exact", "saving"),
                         [(smooth_response, SMOOTH_EXACT, 0.8),
                          (narrow_window_response, NARROW_EXACT, 0.4),
                          (windows_response, {**EXACT, "tilt:1/3": 1.5}, 1.0)],
                         ids=["monotonic", "narrow-window", "non-monotonic"])
def test_adaptive_scan_finds_what_the_fixed_scan_finds(response, exact, saving):
    """Both scans bracket the exact first exceedance of every goal, narrow windows near a
    goal included; below the first goal the adaptive scan spends at most ``saving`` times
    the fixed scan's analyses (far less where the body barely lifts)."""
    found = {}
    for acc in SCANS:
        calls = []
        res = search_critical(fake_analysis(response, calls), GOALS, ALPHA, lower=1.0,
                              upper=10.0, accuracy=acc)
        for k, name in enumerate(res.limit_states):
            truth = exact[name]
            assert res.bracket_lo[k] < truth <= res.intensity[k], (acc.scan, name)
            assert res.intensity[k] - truth <= acc.bisection_tol * truth, (acc.scan, name)
        below_first = sum(c[0] < exact["tilt:0.1"] for c in calls)
        found[acc.scan] = (res.intensity, below_first)
    np.testing.assert_allclose(found["adaptive"][0], found["fixed"][0], rtol=0.006)
    assert found["adaptive"][1] <= saving * found["fixed"][1]


def test_adaptive_step_follows_the_distance_to_the_goal():
    acc = ADAPTIVE
    goal = 0.1
    assert acc.adaptive_step(0.0, goal) == acc.scan_step_max  # at rest: the largest step
    assert acc.adaptive_step(goal, goal) == acc.scan_step  # on the goal: the smallest
    assert acc.adaptive_step(float("nan"), goal) == acc.scan_step  # unknown: the smallest
    theta = goal * math.exp(-0.02 * acc.tilt_growth)  # a growth I^κ reaches the goal in 2 %
    assert acc.adaptive_step(theta, goal) == pytest.approx(0.02, rel=1e-12)
    # steps grow as the tilt falls further below the goal
    steps = [acc.adaptive_step(goal * r, goal) for r in (0.9, 0.5, 0.2, 0.05, 1e-6)]
    assert steps == sorted(steps) and steps[-1] == acc.scan_step_max


def test_adaptive_scan_steps_against_the_lowest_open_goal_but_never_above_alpha():
    """After a step from θ the next intensity is I·(1 + h(θ, min(τ_open, α))): once every
    tilt goal is passed, the approach to overturning is judged against α, not π/2."""
    calls = []
    acc = ADAPTIVE.with_(scan_step=0.001, scan_step_max=1.0, tilt_growth=10.0)
    search_critical(fake_analysis(lambda I: 0.5 if I < 4.0 else None, calls),
                    ["tilt:0.1", "overturning"], ALPHA, lower=1.0, upper=10.0, accuracy=acc)
    scan = [c[0] for c in calls[:3]]
    assert scan[0] == pytest.approx(1.0 + acc.scan_step_max)  # from rest
    # θ = 0.5 α: tilt:0.1 is passed; the step aims at α, ln(2)/10, not ln(π/(2·0.5α))/10
    assert scan[1] / scan[0] - 1.0 == pytest.approx(math.log(2.0) / 10.0, rel=1e-12)


@pytest.mark.parametrize(
    ("fields", "message"),
    [({"scan": "zigzag"}, "scan must be one of"),
     ({"scan": "adaptive", "scan_relative": False}, "scan_relative"),
     ({"scan": "adaptive", "scan_step": 0.05, "scan_step_max": 0.01}, "scan_step_max"),
     ({"tilt_growth": 0.0}, "tilt_growth")],
    ids=["unknown", "absolute", "max-below-min", "growth"],
)
def test_bad_scan_settings_name_the_field(fields, message):
    with pytest.raises(ValueError, match=message):
        Accuracy("x", **{"rtol": 1e-7, "scan_step": 0.01, "bisection_tol": 0.005, **fields})
