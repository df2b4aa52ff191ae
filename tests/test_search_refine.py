"""Refinement of the near misses below an answer (``refine_budget`` of the accuracy presets).

Constructed responses (the fake analysis of tests/test_performance_search.py: θ_max/α given
piecewise in I, ``stop_at`` honoured like the engine) plant a window of exceedance between
two points of the default's 2 % scan, or a near miss with no window; a real-dynamics check
measures the flag's precision and recall on a small fixed set of points against a 0.05 %
grid computed here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from test_performance_search import ALPHA, fake_analysis

from rocking.spectra.accuracy import PRESETS, get_accuracy
from rocking.spectra.search import search_critical

DEFAULT = PRESETS["default"]
GOALS = ["tilt:0.5", "overturning"]
STEP = 1.0 + DEFAULT.scan_step
P34, P35, P36 = STEP ** 34, STEP ** 35, STEP ** 36
"""Three neighbouring points of the default's scan from I = 1 (P35 ≈ 2.0)."""
WINDOW = (P35 * 1.003, P35 * 1.005)
"""A window of tilt:0.5 0.2 % wide just above the near miss P35."""


def near_miss_response(window: bool):
    """θ/α (None: overturned): the scan sees 0.45 α at P35 (90 % of tilt:0.5) and 0.05 α at
    its neighbours; with ``window``, θ = 0.6 α on WINDOW. Robust exceedance from 2.5,
    overturning from 3."""
    def response(I):
        if I >= 3.0:
            return None
        if I >= 2.5 or (window and WINDOW[0] <= I < WINDOW[1]):
            return 0.6
        if P35 * 0.999 <= I < P35 * 1.006:
            return 0.45
        return 0.05 if I >= 1.3 else 1e-6 * I
    return response


def many_near_misses(I):
    """Near misses at every scan point from 1.3 to 2.5 (0.45 α and 0.3 α alternating), no
    window below the robust exceedance at 2.5."""
    if I >= 3.0:
        return None
    if I >= 2.5:
        return 0.6
    if I < 1.3:
        return 1e-6 * I
    j = round(math.log(I) / math.log(STEP))
    return 0.45 if j % 2 == 0 and abs(I / STEP ** j - 1.0) < 1e-9 else 0.3


def _search(response, accuracy=DEFAULT, calls=None):
    return search_critical(fake_analysis(response, [] if calls is None else calls), GOALS,
                           ALPHA, lower=1.0, upper=10.0, accuracy=accuracy)


def test_refinement_finds_a_window_planted_below_the_coarse_answer():
    coarse = _search(near_miss_response(True), DEFAULT.with_(refine_budget=0))
    k = coarse.limit_states.index("tilt:0.5")
    assert coarse.intensity[k] > 2.49  # the scan stepped over the window
    assert coarse.unresolved[k] and not coarse.budget_spent[k]  # no budget: nothing spent

    res = _search(near_miss_response(True))
    # the answer moved down into the window, bisected to the preset's tolerance
    assert WINDOW[0] <= res.intensity[k] <= WINDOW[0] * (1.0 + DEFAULT.bisection_tol)
    assert res.bracket_lo[k] < WINDOW[0]
    assert not res.unresolved[k] and not res.budget_spent[k]
    assert res.non_monotonic[k]  # exceeded in the window, not above it
    # overturning is untouched: its response never came close to α below 3
    o = res.limit_states.index("overturning")
    assert res.intensity[o] == pytest.approx(3.0, rel=DEFAULT.bisection_tol)
    assert res.n_analyses <= coarse.n_analyses + DEFAULT.refine_budget


def test_a_near_miss_without_a_window_is_cleared():
    calls = []
    res = _search(near_miss_response(False), calls=calls)
    k = res.limit_states.index("tilt:0.5")
    assert res.intensity[k] == pytest.approx(2.5, rel=DEFAULT.bisection_tol)
    assert not res.unresolved[k] and not res.budget_spent[k]
    # the neighbourhood (P34, P36) was scanned, finely where θ came within refine_near of τ
    inside = sorted(c[0] for c in calls if P34 < c[0] < P36 and c[0] not in (P35,))
    assert inside, "no analysis between the near miss's neighbours"
    near = [b / a - 1.0 for a, b in zip(inside, inside[1:], strict=False)
            if P35 * 0.999 <= a < P35 * 1.006]
    assert near and max(near) <= DEFAULT.refine_step * (1 + 1e-9)
    assert max(b / a - 1.0 for a, b in zip(inside, inside[1:], strict=False)) \
        <= DEFAULT.refine_step_max * (1 + 1e-9)
    assert res.to_records()[k]["budget_spent"] is False


def test_refinement_stops_at_the_budget_and_says_so():
    budget = 12
    acc = DEFAULT.with_(refine_budget=budget)
    calls = []
    res = _search(many_near_misses, acc, calls)
    coarse = _search(many_near_misses, acc.with_(refine_budget=0))
    k = res.limit_states.index("tilt:0.5")
    assert res.unresolved[k] and res.budget_spent[k]
    assert res.to_records()[k]["budget_spent"] is True
    assert "budget_spent" in repr(res)
    # exactly the budget was spent below the answer on top of the coarse search's analyses
    assert res.n_analyses == coarse.n_analyses + budget
    assert res.intensity[k] == pytest.approx(coarse.intensity[k])
    # a budget large enough clears every near miss
    big = _search(many_near_misses, acc.with_(refine_budget=1000))
    assert not big.unresolved[k] and not big.budget_spent[k]


@pytest.mark.parametrize("value", [-1, "lots", 2.5, float("nan"), True])
def test_a_bad_budget_is_one_line_naming_the_key(value):
    with pytest.raises(ValueError, match=r"^refine_budget must be a whole number >= 0, got "):
        DEFAULT.with_(refine_budget=value)
    with pytest.raises(ValueError, match="refine_budget"):
        get_accuracy({"preset": "default", "refine_budget": value})


@pytest.mark.parametrize("value", [-1, "lots", 2.5])
def test_the_config_schema_names_the_budget_key(value):
    from pathlib import Path

    from rocking.config.checks import schema_error

    root = Path(__file__).resolve().parents[1]
    schema = yaml.safe_load((root / "workflow/schemas/config.schema.yaml").read_text())
    config = yaml.safe_load((root / "config/config.yaml").read_text())
    config["accuracy"] = {"preset": "default", "refine_budget": value}
    message = schema_error(config, schema)
    assert message is not None and message.startswith(f"config key accuracy.refine_budget="
                                                      f"{value!r}: ")
    assert "\n" not in message


def test_refinement_settings_round_trip_through_a_record():
    assert DEFAULT.to_dict()["refine_budget"] == DEFAULT.refine_budget > 0
    for acc in PRESETS.values():  # workers rebuild the tolerances from the store's record
        assert get_accuracy(acc.to_dict()) == acc
    # a record written before the refinement existed did not refine
    old = {k: v for k, v in DEFAULT.with_(scan_step=0.01, refine_budget=0).to_dict().items()
           if not k.startswith("refine")}
    assert get_accuracy(old).refine_budget == 0
    # a configuration naming no preset starts from the default's
    assert get_accuracy({"rtol": 1e-9}).refine_budget == DEFAULT.refine_budget
    with pytest.raises(ValueError, match="refine_step_max"):
        DEFAULT.with_(refine_step=0.01, refine_step_max=0.001)


def test_budget_spent_is_a_column_of_the_store_the_cli_and_critical_csv():
    from rocking.cli.spectra import COLUMNS
    from rocking.execution import tasks
    from rocking.study.aggregate import CRITICAL_COLUMNS
    from rocking.units import header

    assert "budget_spent" in COLUMNS and "budget_spent" in CRITICAL_COLUMNS
    assert "budget_spent" in tasks.spectra_layout(["3d"], ["overturning"], ["m"], [0.2],
                                                  [1.0], 1).variables
    assert header("budget_spent") == "budget_spent"
    res = _search(many_near_misses, DEFAULT.with_(refine_budget=5))
    values = tasks.spectra_values([res], list(res.limit_states))
    np.testing.assert_array_equal(values["budget_spent"][:, 0], res.budget_spent)


# ------------------------------------------------------------------- real dynamics, small set
FLAG_POINTS = (("2d-x", 1.0), ("2d-y", 1.0), ("2d-y", 2.0))
"""El Centro (the study's processing), tan α = 0.2: cheap 2D points whose default answers
are within 3 % for some goals and more than 3 % too high for others (measured when the test
was written: overturning at 2d-x R = 1 m and 2d-y R = 2 m)."""

BAD = 0.03
"""An answer is bad when the fine grid finds an exceedance more than this below it."""


def _fine_grid_exceeds_below(analyze, state, alpha, lower, limit, rtol) -> bool:
    """Whether the 0.05 % grid from uplift exceeds ``state`` anywhere below ``limit``."""
    from rocking.dynamics.result import Status
    from rocking.spectra.limit_states import classify

    stop = state.stop_at(alpha)
    n = 1
    while (intensity := lower * 1.0005 ** n) < limit:
        out = analyze(intensity, stop, rtol)
        known, exceeded = classify(out, [state], alpha, stop,
                                   stopped=out.status is Status.STOPPED_AT_LIMIT)
        if known[0] and exceeded[0]:
            return True
        n += 1
    return False


def test_flag_precision_and_recall_against_a_fine_grid():
    from rocking.dynamics.bodies import Cylinder
    from rocking.motions.build import build_ensemble
    from rocking.motions.catalogue import load_record
    from rocking.spectra.critical import MODES, make_analysis, uplift_intensity
    from rocking.spectra.limit_states import parse_limit_states

    motion = build_ensemble(load_record("el-centro-1940"), 0, 2017).motions[0]
    goals = ("overturning", "tilt:1/3")
    flag, bad = [], []
    for mode, R in FLAG_POINTS:
        body = Cylinder(R, 0.2)
        analyze = make_analysis(body, motion, mode, rest_tilt=DEFAULT.rest_tilt)
        lower = uplift_intensity(motion, mode)
        rtol = DEFAULT.rtol_for(MODES[mode][0])
        res = search_critical(analyze, goals, body.alpha, lower=lower, upper=20.0,
                              accuracy=DEFAULT, rtol=rtol)
        for k, state in enumerate(parse_limit_states(res.limit_states)):
            assert np.isfinite(res.intensity[k])
            bad.append(_fine_grid_exceeds_below(analyze, state, body.alpha, lower,
                                                res.intensity[k] / (1.0 + BAD), rtol))
            flag.append(bool(res.unresolved[k]))
    flag, bad = np.array(flag), np.array(bad)
    assert 0 < bad.sum() < bad.size  # the set holds both kinds
    tp = int(np.sum(flag & bad))
    precision, recall = tp / max(1, flag.sum()), tp / bad.sum()
    # the benchmark's targets (docs/performance.md): on this set the flag meets them
    assert precision >= 0.8 and recall >= 0.8, (flag, bad)
