"""Limit-state parsing and accuracy presets."""

import math

import pytest

from rocking.dynamics.result import Status
from rocking.spectra.accuracy import PRESETS, Accuracy
from rocking.spectra.limit_states import (
    DEFAULT_LIMIT_STATES,
    Overturning,
    TiltGoal,
    classify,
    limit_state_title,
    match_limit_state,
    parse_limit_state,
    parse_limit_states,
    severity,
    stop_for,
)
from rocking.spectra.search import Outcome


def peaks(theta_max: float, overturned: bool) -> dict:
    return {"theta_max": theta_max, "overturned": overturned}


def test_parse_names_and_ratios():
    assert parse_limit_state("overturning") == Overturning()
    assert parse_limit_state(" Tilt:0.5 ") == TiltGoal("tilt:0.5", 0.5)
    assert parse_limit_state("tilt:1") == TiltGoal("tilt:1", 1.0)
    third = parse_limit_state("tilt:1/3")
    assert third.name == "tilt:1/3" and third.ratio == 1.0 / 3.0
    assert parse_limit_state("excessive-tilt") == third
    assert parse_limit_state("tilt:0.3333").ratio == 0.3333


@pytest.mark.parametrize(
    "bad", ["", "collapse", "tilt", "tilt:", "tilt:abc", "tilt:-0.2", "tilt:0", "tilt:nan",
            "tilt:inf", "tilt:1/0", "tilt=0.5", 0.5]
)
def test_parse_rejects_with_the_text(bad):
    with pytest.raises(ValueError, match="limit_state"):
        parse_limit_state(bad)


def test_default_set_sorted_and_complete():
    states = parse_limit_states(None)
    assert [s.name for s in states] == list(DEFAULT_LIMIT_STATES)
    keys = [s.severity for s in states]
    assert keys == sorted(keys) and keys[-1] == (0, math.inf)
    assert [r for _, r in keys[:-1]] == [0.1, 0.2, 1 / 3, 0.5, 0.75, 1.0]


def test_set_from_string_sorts_and_dedups():
    states = parse_limit_states("overturning, tilt:0.5,tilt:1/2, tilt:0.1")
    assert [s.name for s in states] == ["tilt:0.1", "tilt:0.5", "overturning"]
    with pytest.raises(ValueError, match="at least one"):
        parse_limit_states([])


def test_thresholds_and_exceedance():
    alpha = math.atan(0.2)
    tilt = parse_limit_state("tilt:1/3")
    assert tilt.threshold(alpha) == pytest.approx(alpha / 3, rel=1e-15)
    assert parse_limit_state("overturning").threshold(alpha) == math.pi / 2
    assert tilt.exceeded(peaks(alpha / 3 * 1.0001, False), alpha)
    assert not tilt.exceeded(peaks(alpha / 3 * 0.9999, False), alpha)
    assert tilt.exceeded(peaks(0.0, True), alpha)  # overturning passes every tilt goal
    over = parse_limit_state("overturning")
    assert not over.exceeded(peaks(1.5, False), alpha) and over.exceeded(peaks(1.5, True), alpha)
    # A goal beyond π/2 can only be met by overturning: refused, naming the limit state.
    with pytest.raises(ValueError, match="tilt:9"):
        parse_limit_state("tilt:9").threshold(alpha)


def test_an_outcome_is_read_through_its_named_peaks():
    alpha = math.atan(0.2)
    tilt, over = parse_limit_state("tilt:1/3"), parse_limit_state("overturning")
    out = Outcome(alpha / 2, False, Status.OK, other_peaks={"mu_required_max": 0.3})
    assert out.peaks == {"theta_max": alpha / 2, "overturned": False, "mu_required_max": 0.3}
    assert tilt.exceeded(out, alpha) and not over.exceeded(out, alpha)
    assert (tilt.quantity, over.quantity) == ("theta_max", "overturned")
    with pytest.raises(ValueError, match="unknown quantity name.*'sliding'"):
        Outcome(0.0, False, Status.OK, other_peaks={"sliding": 1.0})


def test_severity_title_and_stops_belong_to_the_limit_state():
    alpha = math.atan(0.2)
    names = ["overturning", "tilt:0.5", "tilt:1/3", "tilt:0.1"]
    assert sorted(names, key=severity) == ["tilt:0.1", "tilt:1/3", "tilt:0.5", "overturning"]
    assert limit_state_title("tilt:2/6") == "Tilt θ > α/3 (excessive tilt)"
    assert limit_state_title("overturning") == "Overturning"
    states = parse_limit_states(["tilt:0.1", "tilt:0.5"])
    assert stop_for(states, alpha) == 0.5 * alpha  # the largest goal decides them all
    assert stop_for(parse_limit_states(["tilt:0.1", "overturning"]), alpha) is None
    assert match_limit_state("tilt:0.3333", ["tilt:1/3", "overturning"]) == "tilt:1/3"
    assert match_limit_state("tilt:0.75", ["tilt:1/3"], missing_ok=True) is None
    with pytest.raises(KeyError, match="tilt:0.75"):
        match_limit_state("tilt:0.75", ["tilt:1/3"])


def test_a_run_stopped_past_a_goal_decides_the_goals_up_to_it():
    alpha = math.atan(0.2)
    states = parse_limit_states(["tilt:0.1", "tilt:0.5", "tilt:1", "overturning"])
    # stopped exactly on 0.5·α: 0.1 and 0.5 passed, 1 and overturning unknown
    known, exc = classify(peaks(0.5 * alpha, False), states, alpha, 0.5 * alpha, stopped=True)
    assert known.tolist() == [True, True, False, False]
    assert exc.tolist() == [True, True, False, False]
    # ran to its end below 0.5·α: everything known, only 0.1 exceeded
    known, exc = classify(peaks(0.3 * alpha, False), states, alpha, None, stopped=False)
    assert known.all() and exc.tolist() == [True, False, False, False]


def test_presets_ordered_by_cost_and_accuracy():
    fast, default, precise = (PRESETS[k] for k in ("fast", "default", "precise"))
    assert fast.rtol >= default.rtol >= precise.rtol
    assert fast.scan_step >= default.scan_step >= precise.scan_step
    assert fast.local_step >= default.local_step > precise.local_step
    assert Accuracy.of("Default") is default


def test_accuracy_overrides_and_errors():
    acc = Accuracy.of({"preset": "fast", "rtol": 1e-9})
    assert acc.rtol == 1e-9 and acc.scan_step == PRESETS["fast"].scan_step
    assert acc.name == "custom"
    with pytest.raises(ValueError, match="accuracy must be one of"):
        Accuracy.of("sloppy")
    with pytest.raises(ValueError, match="unknown field"):
        Accuracy.of({"rtoll": 1e-9})
    with pytest.raises(ValueError, match="rtol"):
        Accuracy("x", rtol=float("nan"), scan_step=0.1, local_step=0.002, local_below=0.1)
    with pytest.raises(ValueError, match="local_step"):
        Accuracy("x", rtol=1e-8, scan_step=0.01, local_step=1.0)
    with pytest.raises(ValueError, match="scan_step"):
        Accuracy("x", rtol=1e-8, scan_step=-0.1, local_step=0.002)


def test_accuracy_round_trips_through_its_dict():
    # The study store keeps tolerances as JSON and workers rebuild them with Accuracy.of.
    for acc in PRESETS.values():
        assert Accuracy.of(acc.to_dict()) == acc
        # a record that names its preset and nothing else is that preset, not the default
        # under its name (a store with tolerances {"name": "fast"} searched at default's)
        assert Accuracy.of({"name": acc.name}) == acc


# --- one spelling per limit state, every spelling accepted -------------------------------

SPELLINGS_OF_A_THIRD = ["tilt:1/3", "tilt:2/6", "TILT:1/3", " tilt:1/3 ", "excessive-tilt",
                        "tilt:0.333333333333333", "tilt:0.3333"]


def test_canonical_names_are_unique_per_ratio():
    from rocking.spectra.limit_states import parse_limit_state

    assert parse_limit_state("tilt:1/2").name == parse_limit_state("tilt:0.5").name == \
        "tilt:0.5"
    assert parse_limit_state("tilt:3/3").name == "tilt:1"
    assert parse_limit_state("tilt:2/6").name == "tilt:1/3"
    assert parse_limit_state("tilt:0.333333333333333").name == "tilt:1/3"
    assert parse_limit_state("tilt:0.3333").name == "tilt:0.3333"  # a different goal


def test_every_spelling_selects_the_same_store_entry():
    import numpy as np
    import xarray as xr

    from rocking.store.select import select

    for stored in ("tilt:0.3333", "tilt:1/3"):
        ds = xr.Dataset({"pga_crit": (("limit_state", "R"), np.array([[1.0, 2.0], [3.0, 4.0]]))},
                        coords={"limit_state": ["overturning", stored], "R": [1.0, 6.0]})
        for spelling in SPELLINGS_OF_A_THIRD:
            got = select(ds.pga_crit, limit_state=spelling, R=6)
            assert float(got) == 4.0, (stored, spelling)
        assert float(select(ds.pga_crit, limit_state="OVERTURNING", R=1.0)) == 1.0
    with pytest.raises(KeyError, match="tilt:0.5"):
        select(ds.pga_crit, limit_state="tilt:0.5")


def test_result_comes_back_in_the_order_asked():
    import numpy as np

    from rocking import Cylinder, GroundMotion, critical_intensity

    t = np.arange(0, 3.0, 0.01)
    a = np.where(t < 1.0, 4.0 * np.sin(2 * np.pi * t), 0.0)
    m = GroundMotion(a, 0.5 * a, 0.01, "pulse")
    asked = ["overturning", "tilt:1/3", "tilt:0.1"]
    res = critical_intensity(Cylinder(1.0, 0.2), m, asked, "3d", accuracy="fast", upper=5.0)
    assert res.limit_states == ("overturning", "tilt:1/3", "tilt:0.1")
    ref = critical_intensity(Cylinder(1.0, 0.2), m, list(reversed(asked)), "3d",
                             accuracy="fast", upper=5.0)
    assert res.limit_states == tuple(reversed(ref.limit_states))
    np.testing.assert_array_equal(res.intensity, ref.intensity[::-1])
    assert res.intensity[0] == res["overturning"]["intensity"]
    assert res["excessive-tilt"]["intensity"] == res.intensity[1]
    np.testing.assert_array_equal(res.pga_g, res.intensity * 0.2)
    text = repr(res)
    assert len(text) < 500 and text.count("\n") == 3 and "PGA = " in text
