"""The critical-intensity search on constructed responses with known answers.

A fake analysis maps the normalized intensity I to a peak tilt θ_max(I)/α given piecewise,
honours ``stop_at`` like the engine (ends with θ = stop_at, status STOPPED_AT_LIMIT) and
reports overturning, so P(s) and I_p = inf{s : P(s) >= p} of every goal follow from their
definitions (rocking.spectra.quantity): a goal first exceeded for good at s* (a clean step)
has I_p = s*·exp(−w(1 − 2p)).
"""

import math

import numpy as np
import pytest

from rocking.dynamics.result import Status
from rocking.spectra.accuracy import PRESETS, Accuracy
from rocking.spectra.limit_states import parse_limit_states
from rocking.spectra.quantity import Quantity
from rocking.spectra.search import MAX_ANALYSES, Outcome, search_critical

ALPHA = math.atan(0.2)
W, P = Quantity().w, Quantity().p
STEP_FACTOR = math.exp(-W * (1 - 2 * P))
"""I10 of a clean step at s* is s*·STEP_FACTOR."""
DEFAULT = PRESETS["default"]
STATES = ["tilt:0.1", "tilt:0.2", "tilt:0.5", "tilt:0.75", "overturning"]


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


def smooth_response(I):
    """Monotonic: θ/α = 2 (I − 1)², overturning once it would pass 1."""
    ratio = 2.0 * (I - 1.0) ** 2
    return None if ratio >= 1.0 else ratio


SMOOTH_FIRST = {"tilt:0.1": 1.0 + math.sqrt(0.05), "tilt:0.2": 1.0 + math.sqrt(0.1),
                "tilt:1/3": 1.0 + math.sqrt(1.0 / 6.0), "tilt:0.5": 1.5,
                "tilt:0.75": 1.0 + math.sqrt(0.375), "overturning": 1.0 + math.sqrt(0.5)}
"""Where each goal is first exceeded by smooth_response (a clean step)."""


def windows_response(I):
    """θ_max/α, or None for overturning: a non-monotonic staircase.

    tilt:0.5 is exceeded on [1.5, 1.8) and again from 2.5; overturning from 3.0."""
    if I >= 3.0:
        return None
    if I >= 2.5:
        return 0.8
    if I >= 1.8:
        return 0.3
    if I >= 1.5:
        return 0.6
    return 0.3 * (I - 1.0)


WINDOWS_FIRST = {"tilt:0.1": 1.0 + 0.1 / 0.3, "tilt:0.2": 1.5, "tilt:0.5": 1.5,
                 "tilt:0.75": 2.5, "overturning": 3.0}
"""Every goal of windows_response is a clean step at these intensities (the window of
tilt:0.5 on [1.5, 1.8) is 18 % wide: a step, whatever comes after)."""


def _tol(acc: Accuracy) -> float:
    """How far an I_p read off a local sample may sit from the closed form: a stratum and a
    half (the first judged s with P̂ >= p lies within a stratum of the exact crossing)."""
    return 1.5 * acc.local_step


@pytest.mark.parametrize("preset", ["fast", "default", "precise"])
@pytest.mark.parametrize(("response", "first"), [(smooth_response, SMOOTH_FIRST),
                                                 (windows_response, WINDOWS_FIRST)],
                         ids=["smooth", "windows"])
def test_steps_give_their_closed_form(preset, response, first):
    acc = Accuracy.of(preset)
    names = [s for s in STATES if s in first]
    for seed in range(3):
        res = search_critical(fake_analysis(response, []), names, ALPHA, lower=1.0,
                              upper=10.0, accuracy=acc, seed=seed)
        for k, name in enumerate(res.limit_states):
            exact = first[name] * STEP_FACTOR
            assert res.intensity[k] == pytest.approx(exact, rel=_tol(acc)), (preset, name)
            # I50 of a step is the step itself; the grid's first exceedance lies at or above
            assert res.i50[k] == pytest.approx(first[name], rel=_tol(acc)), (preset, name)
            assert first[name] <= res.first_exceedance[k] \
                < first[name] * (1 + acc.scan_step) + 1e-12
        assert not res.not_reached.any() and not res.failed.any()
        assert not res.plateau.any()
        assert res.n_analyses == len(res.evaluations)


def test_answers_ordered_by_goal():
    res = search_critical(fake_analysis(windows_response, []), STATES, ALPHA, lower=1.0,
                          upper=10.0)
    assert np.all(np.diff(res.intensity) >= 0.0)


def test_one_search_serves_all_limit_states():
    """One search of every goal costs less than one search per goal and answers the same
    (the same cell: the same grid and strata); a local sample serving one tilt goal alone
    stops its analyses at that goal."""
    calls = []
    together = search_critical(fake_analysis(smooth_response, calls), STATES, ALPHA,
                               lower=1.0, upper=10.0, seed=5)
    separate_cost = 0
    for k, name in enumerate(STATES):
        one = search_critical(fake_analysis(smooth_response, []), [name], ALPHA, lower=1.0,
                              upper=10.0, seed=5)
        separate_cost += one.n_analyses
        assert one.intensity[0] == pytest.approx(together.intensity[k], rel=1e-12)
    assert together.n_analyses < 0.85 * separate_cost
    # while overturning is open the scan runs to the end (stop_at None)
    assert calls[0][1] is None
    # the local sample around tilt:0.1's step (1.22) serves it alone: stopped at its goal
    near = [c for c in calls if 1.20 < c[0] < 1.23 and c[1] is not None]
    assert near and all(c[1] == pytest.approx(0.1 * ALPHA, rel=1e-15) for c in near)


def test_a_window_far_below_the_rise_is_dismissed():
    """tilt:0.5 exceeded only on a 0.1 % window at 1.5 and from 2.0 on: where the grid
    first lands in the window, I10 is still the rise's."""
    def response(I):
        return 0.6 if I >= 2.0 or 1.5 <= I < 1.5015 else 0.3

    seen_window = 0
    for seed in range(300):
        res = search_critical(fake_analysis(response, []), ["tilt:0.5"], ALPHA, lower=1.0,
                              upper=10.0, seed=seed)
        if res.first_exceedance[0] > 1.6:
            continue
        seen_window += 1
        assert res.intensity[0] == pytest.approx(2.0 * STEP_FACTOR, rel=_tol(DEFAULT))
    assert seen_window >= 3  # the grid lands in the window for about 1 offset in 20


def test_the_local_sample_extends_down_to_where_P_crosses_p():
    """A comb exceeding on 30 % of every 0.05 % from 1.5 on (P = 0.3 there) and everywhere
    from 3: I10 is where the window holds a third of the comb, 1.5·exp(−w/3), however far
    above 1.5 the 5 % grid first lands in a tooth."""
    def response(I):
        if I >= 3.0:
            return 0.6
        return 0.6 if I >= 1.5 and (math.log(I / 1.5) / 0.0005) % 1.0 < 0.3 else 0.3

    # strata of 0.25 %: ~16 analyses per window tell P = 0.3 from p (the default's 0.8 %
    # leaves ~5, and P̂ of a comb is then noisy by ±0.2)
    acc = DEFAULT.with_(scan_step=0.05, local_step=0.0025, local_below=0.05, local_above=0.02)
    exact = 1.5 * math.exp(-W / 3)
    for seed in range(5):
        res = search_critical(fake_analysis(response, []), ["tilt:0.5"], ALPHA, lower=1.0,
                              upper=10.0, accuracy=acc, seed=seed)
        # the comb's share in a window of ~16 strata is 0.3 give or take a tooth
        assert res.intensity[0] == pytest.approx(exact, rel=0.02), seed
        assert res.first_exceedance[0] >= 1.5


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


def test_failure_retried_with_tighter_rtol():
    rtol = DEFAULT.rtol
    calls = []
    fake = fake_analysis(windows_response, calls, fail=lambda I, r: I > 2.0 and r == rtol)
    res = search_critical(fake, STATES, ALPHA, lower=1.0, upper=10.0)
    assert not res.failed.any()
    assert res.intensity[-1] == pytest.approx(3.0 * STEP_FACTOR, rel=_tol(DEFAULT))
    retried = [c for c in calls if c[2] != rtol]
    assert retried and all(r == pytest.approx(rtol * 0.1) for _, _, r in retried)
    assert res.n_analyses == len(calls)


def test_persistent_failure_is_flagged_not_survival():
    # Analyses fail on [2.0, 2.7): overturning (3.0) and tilt:0.75 (2.5) could hide there.
    fake = fake_analysis(windows_response, [], fail=lambda I, r: 2.0 <= I < 2.7)
    res = search_critical(fake, STATES, ALPHA, lower=1.0, upper=10.0)
    flags = dict(zip(res.limit_states, res.failed, strict=True))
    assert flags == {"tilt:0.1": False, "tilt:0.2": False, "tilt:0.5": False,
                     "tilt:0.75": True, "overturning": True}
    assert res.intensity[-1] == pytest.approx(3.0 * STEP_FACTOR, rel=_tol(DEFAULT))
    # Everything failing: nothing is reported as survived.
    res = search_critical(fake_analysis(windows_response, [], fail=lambda I, r: True), STATES,
                          ALPHA, lower=1.0, upper=3.0)
    assert res.not_reached.all() and res.failed.all()


def test_nan_theta_is_a_failure():
    calls = []
    probe = search_critical(fake_analysis(windows_response, calls), ["tilt:0.1"], ALPHA,
                            lower=1.0, upper=3.0, seed=1)
    first = probe.evaluations[0].intensity
    res = search_critical(fake_analysis(windows_response, [], nan_at=(first,)),
                          ["tilt:0.1"], ALPHA, lower=1.0, upper=3.0, seed=1)
    assert res.evaluations[0].status == Status.FAILED.value
    assert res.failed[0]  # the failed point lies below the answer


def test_the_result_says_what_it_answers_and_keeps_its_samples():
    res = search_critical(fake_analysis(smooth_response, []), ["tilt:0.5"], ALPHA,
                          lower=1.0, upper=10.0, seed=2)
    assert res.answer == "I10 (P >= 0.1 within ±2 % in ln s)"
    assert "tilt:0.5: I10 = " in repr(res)
    rec = res.to_records()[0]
    assert (rec["quantity"], rec["quantity_p"], rec["quantity_w"]) == \
        ("exceedance_quantile", 0.1, 0.02)
    assert rec["i50"] == res.i50[0] and rec["first_exceedance"] == res.first_exceedance[0]
    # P̂ from the search's own local samples: a step at 1.5 seen through a ±2 % window
    s = np.array([1.45, 1.5 * STEP_FACTOR, 1.5, 1.55])
    P_hat = res.local_exceedance("tilt:0.5", s)
    np.testing.assert_allclose(P_hat, [0.0, 0.1, 0.5, 1.0], atol=0.08)
    assert res.samples.intensity.size == res.n_analyses


def test_bad_arguments():
    fake = fake_analysis(windows_response, [])
    with pytest.raises(ValueError, match="upper"):
        search_critical(fake, STATES, ALPHA, lower=1.0, upper=float("nan"))
    with pytest.raises(ValueError, match="lower"):
        search_critical(fake, STATES, ALPHA, lower=-1.0)
    with pytest.raises(ValueError, match="limit_state"):
        search_critical(fake, ["collapse"], ALPHA, lower=1.0)
    assert [s.name for s in parse_limit_states(STATES)] == STATES
    assert MAX_ANALYSES >= 1000


# ------------------------------------------------------------------ the accuracy presets
@pytest.mark.parametrize(
    ("fields", "message"),
    [({"scan_step": 0.0}, r"^scan_step must be > 0.0 and <= 1.0, got 0.0$"),
     ({"local_step": 0.5}, r"^local_step must be > 0.0 and <= 0.1, got 0.5$"),
     ({"local_below": -1}, r"^local_below must be"),
     ({"local_above": "x"}, r"^local_above must be a number, got 'x'$"),
     ({"rtol": 0.1}, r"^rtol must be"),
     ({"scan_step": 0.1, "local_below": 0.05}, r"^local_below must be >= ln\(1 \+ scan_step\)"),
     ({"rest_tilt": 1.0}, r"^rest_tilt must be"),
     ({"confirm": "yes"}, r"^confirm must be true or false, got 'yes'$")],
)
def test_bad_settings_name_the_field(fields, message):
    with pytest.raises(ValueError, match=message):
        DEFAULT.with_(**fields)
    with pytest.raises(ValueError, match=message.lstrip("^")):
        Accuracy.of({"preset": "default", **fields})


def test_retired_settings_are_refused_by_name():
    with pytest.raises(ValueError, match=r"unknown field\(s\) \['refine_budget'\]"):
        Accuracy.of({"preset": "default", "refine_budget": 20})


def test_a_sample_narrower_than_the_window_is_refused_before_any_analysis():
    calls = []
    acc = DEFAULT.with_(local_below=0.03, local_above=0.005)
    with pytest.raises(ValueError, match="local_below \\+ local_above"):
        search_critical(fake_analysis(smooth_response, calls), ["tilt:0.5"], ALPHA,
                        lower=1.0, accuracy=acc)
    assert not calls


def test_presets_round_trip_through_their_record():
    for acc in (*PRESETS.values(), DEFAULT.with_(confirm=False)):
        # workers rebuild the settings from the store's record
        assert Accuracy.of(acc.to_dict()) == acc
    assert Accuracy.of({"rtol": 1e-9}) == DEFAULT.with_(rtol=1e-9)
    costs = [PRESETS[p].local_step for p in ("fast", "default", "precise")]
    assert costs == sorted(costs, reverse=True)  # from cheapest to most accurate
