"""The quantity a search answers: P(s), I_p and their estimators against closed forms, the
search on constructed responses, the random offsets per cell and the quantity's checks.

A constructed response is a set of exceeding intensities known exactly, so P(s) and I_p
follow from their definitions (rocking.spectra.quantity) by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocking.dynamics.result import Status
from rocking.spectra.accuracy import PRESETS
from rocking.spectra.quantity import Quantity, exceedance_quantile, local_exceedance
from rocking.spectra.search import (
    Outcome,
    cell_seed,
    scan_offset,
    search_critical,
    stratum_offset,
)

ALPHA = math.atan(0.2)
W = 0.02


def lattice(lo: float, hi: float, step: float) -> np.ndarray:
    """Intensities evenly spaced in ln s from lo to hi (step in ln s)."""
    n = int(round(math.log(hi / lo) / step))
    return lo * np.exp(step * np.arange(n + 1))


# ------------------------------------------------------------------- P(s), closed forms
def test_local_exceedance_of_a_step_is_the_share_of_the_window_above_it():
    """Exceeding from s* on: P(s) = (ln s + w − ln s*)/(2w), clamped to [0, 1]."""
    s_star = 2.0
    x = lattice(1.5, 2.7, 1e-4)
    s = np.array([1.9, 1.97, 1.99, 2.0, 2.01, 2.03, 2.1])
    P = local_exceedance(x, x >= s_star, s, W)
    exact = np.clip((np.log(s) + W - math.log(s_star)) / (2 * W), 0.0, 1.0)
    np.testing.assert_allclose(P, exact, atol=2e-3)  # one lattice point in 400


def test_local_exceedance_of_windows_is_their_share_of_the_window():
    """Two exceeding bands inside one window: P is their total width over 2w."""
    x = lattice(1.0, 3.0, 2e-5)
    lx = np.log(x)
    bands = [(math.log(2.0) - 0.012, math.log(2.0) - 0.008),
             (math.log(2.0) + 0.001, math.log(2.0) + 0.004)]
    exc = np.zeros(x.size, bool)
    for a, b in bands:
        exc |= (lx >= a) & (lx < b)
    P = local_exceedance(x, exc, 2.0, W)
    assert float(P) == pytest.approx((0.004 + 0.003) / (2 * W), abs=1e-3)
    # a window holding no analysed intensity says nothing
    assert np.isnan(local_exceedance(x, exc, 10.0, W))


def test_quantile_of_a_step_is_its_closed_form():
    """I_p = s*·exp(−w(1 − 2p)) for a clean step at s*, for several p and w."""
    s_star = 2.5
    x = lattice(1.5, 4.0, 1e-5)
    for p, w in [(0.1, 0.02), (0.5, 0.02), (0.05, 0.01), (0.3, 0.1)]:
        ip, plateau = exceedance_quantile(x, x >= s_star, p, w)
        assert ip == pytest.approx(s_star * math.exp(-w * (1 - 2 * p)), rel=2e-5), (p, w)
        assert not plateau


def test_an_isolated_window_far_below_a_robust_rise_does_not_move_I10():
    """First exceedance in a window 0.05 % wide at 1.5; the robust rise at 2.0: I10 is the
    rise's (2.0·e^(−0.016)), not the window's, and the window below does not raise the
    plateau flag (it holds 1/80 of its ±2 % band)."""
    x = lattice(1.0, 3.0, 1e-4)
    exc = (x >= 2.0) | ((x >= 1.5) & (x < 1.5 * math.exp(0.0005)))
    assert x[exc].min() == pytest.approx(1.5, rel=1e-4)
    ip, plateau = exceedance_quantile(x, exc, 0.1, W)
    assert ip == pytest.approx(2.0 * math.exp(-W * 0.8), rel=2e-4)
    assert not plateau


def test_a_plateau_below_the_answer_is_flagged():
    """P = b = 0.075 over a long stretch below the rise (3 in every 40 intensities of a
    lattice of step 1e-3 exceed): P rises near p without crossing it. Its I10 is where the
    share f above the rise lifts b + (1 − b) f to p: s*·exp(−w + 2 w f)."""
    x = lattice(1.0, 3.0, 1e-3)
    n = np.arange(x.size)
    exc = (x >= 2.0) | ((x >= 1.3) & (n % 40 < 3))
    ip, plateau = exceedance_quantile(x, exc, 0.1, W)
    b = 3 / 40
    f = (0.1 - b) / (1 - b)
    assert ip == pytest.approx(2.0 * math.exp(-W + 2 * W * f), rel=2e-3)
    assert plateau
    # not reached at all, but rising near p: plateau, NaN
    ip, plateau = exceedance_quantile(x, (x >= 1.3) & (x < 2.5) & (n % 40 < 3), 0.1, W)
    assert math.isnan(ip) and plateau
    ip, plateau = exceedance_quantile(x, np.zeros(x.size, bool), 0.1, W)
    assert math.isnan(ip) and not plateau


# ------------------------------------------------------------------ the search
def fake_analysis(exceeds, calls=None):
    """An analysis whose peak tilt is α·(1.2 if exceeds(I) else 0.05): every tilt goal up to
    α and overturning from ``exceeds``; honours ``stop_at`` like the engine."""
    def analyze(I, stop_at, rtol):
        if calls is not None:
            calls.append((I, stop_at))
        if not exceeds(I):
            return Outcome(0.05 * ALPHA, False, Status.OK)
        if stop_at is not None:
            return Outcome(stop_at, False, Status.STOPPED_AT_LIMIT)
        return Outcome(math.pi / 2, True, Status.OVERTURNED)
    return analyze


def window_and_rise(I: float) -> bool:
    """A window 0.1 % wide at 1.5 (which the scan may see), the robust rise at 2.0."""
    return I >= 2.0 or 1.5 <= I < 1.5015


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 4])
def test_the_search_answers_the_rise_not_the_window(seed):
    """Whatever the cell's offsets, the search's I10 is the rise's closed form within one
    stratum of its local sample, though the scan may first see the window."""
    res = search_critical(fake_analysis(window_and_rise), ["overturning"], ALPHA, lower=1.0,
                          upper=10.0, seed=seed)
    exact = 2.0 * math.exp(-W * 0.8)
    assert res.intensity[0] == pytest.approx(exact, rel=2 * res.accuracy.local_step)
    assert not res.plateau[0] and not res.not_reached[0]
    assert res.first_exceedance[0] >= 1.5


def test_windows_the_scan_sees_are_examined_and_dismissed():
    """Windows 0.02 % wide, one in every 1 % between 1.4 and 1.5 (P = 0.02 there), far
    below the rise at 2.0: where the scan lands in one, the local sample around it finds P
    below p and the search goes on to the rise. (A local sample of 2w/δ analyses per window
    tells P = 0.02 from p = 0.1 only with enough of them: δ = 0.25 % here.)"""
    def sparse(I):
        if I >= 2.0:
            return True
        if 1.4 <= I < 1.5:
            return (math.log(I / 1.4) / 0.01) % 1.0 < 0.02
        return False

    acc = PRESETS["default"].with_(local_step=0.0025)
    seen = 0
    for seed in range(400):
        res = search_critical(fake_analysis(sparse), ["overturning"], ALPHA, lower=1.0,
                              upper=10.0, accuracy=acc, seed=seed)
        if res.first_exceedance[0] < 1.5:
            seen += 1
            assert res.intensity[0] == pytest.approx(2.0 * math.exp(-W * 0.8), rel=0.006)
    assert seen >= 3


def test_first_exceedance_is_still_available_and_labelled_with_its_grid():
    q = Quantity("first_exceedance")
    res = search_critical(fake_analysis(lambda I: I >= 2.0), ["overturning"], ALPHA,
                          lower=1.0, upper=10.0, quantity=q, seed=7)
    h = res.accuracy.scan_step
    # the first grid point at or above 2.0: within one step above it
    assert 2.0 <= res.intensity[0] < 2.0 * (1 + h)
    assert res.intensity[0] == res.first_exceedance[0]
    assert np.isnan(res.i50[0])
    assert res.answer == f"first exceedance on the {100 * h:g} % scan grid"
    assert res.to_records()[0]["quantity"] == "first_exceedance"
    # the same grid under the default quantity reports the same first exceedance
    default = search_critical(fake_analysis(lambda I: I >= 2.0), ["overturning"], ALPHA,
                              lower=1.0, upper=10.0, seed=7)
    assert default.first_exceedance[0] == res.first_exceedance[0]
    assert default.answer.startswith("I10")


def test_i50_of_a_step():
    res = search_critical(fake_analysis(lambda I: I >= 2.0), ["overturning"], ALPHA,
                          lower=1.0, upper=10.0, seed=3)
    assert res.i50[0] == pytest.approx(2.0, rel=2 * res.accuracy.local_step)


# ------------------------------------------------------------------ random offsets
def test_offsets_are_reproducible_and_differ_between_cells():
    a = cell_seed("el-centro-1940", 2.0, 0.2, "3d")
    assert a == cell_seed("el-centro-1940", 2.0, 0.2, "3d")
    others = {cell_seed("el-centro-1940", 2.5, 0.2, "3d"),
              cell_seed("el-centro-1940", 2.0, 0.3, "3d"),
              cell_seed("el-centro-1940", 2.0, 0.2, "2d-x"),
              cell_seed("el-centro-1940-rdk-000", 2.0, 0.2, "3d")}
    assert a not in others and len(others) == 4
    offsets = [scan_offset(s) for s in (a, *others)]
    assert len(set(offsets)) == 5 and all(0.0 <= u < 1.0 for u in offsets)
    assert scan_offset(a) == scan_offset(a)
    assert stratum_offset(a, 17) == stratum_offset(a, 17) != stratum_offset(a, 18)


def test_two_runs_of_a_cell_are_bit_identical_and_two_cells_differ():
    def run(seed):
        calls = []
        res = search_critical(fake_analysis(window_and_rise, calls), ["tilt:0.5",
                              "overturning"], ALPHA, lower=1.0, upper=10.0, seed=seed)
        return res, calls

    (r1, c1), (r2, c2) = run(11), run(11)
    assert c1 == c2
    assert np.array_equal(r1.intensity, r2.intensity)
    r3, c3 = run(12)
    assert {c[0] for c in c3}.isdisjoint({c[0] for c in c1})


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize(("value", "message"), [
    ("first", r"^quantity must be one of \['exceedance_quantile', 'first_exceedance'\], "
              r"got 'first'$"),
    ({"p": 0.0}, r"^quantity.p must be a number in \(0, 1\), got 0.0$"),
    ({"p": 1.0}, r"^quantity.p must be a number in \(0, 1\), got 1.0$"),
    ({"p": "x"}, r"^quantity.p must be a number in \(0, 1\), got 'x'$"),
    ({"w": 0.0}, r"^quantity.w must be a number in \(0, 0.5\), got 0.0$"),
    ({"w": 0.5}, r"^quantity.w must be a number in \(0, 0.5\), got 0.5$"),
    ({"w": -1}, r"^quantity.w must be a number in \(0, 0.5\), got -1$"),
    ({"q": 1}, r"^quantity has unknown key\(s\) \['q'\]"),
])
def test_a_bad_quantity_is_one_line_naming_the_key(value, message):
    with pytest.raises(ValueError, match=message):
        Quantity.from_value(value)


def test_a_bad_quantity_stops_the_search_before_any_analysis():
    calls = []
    with pytest.raises(ValueError, match="quantity.w"):
        search_critical(fake_analysis(lambda I: True, calls), ["overturning"], ALPHA,
                        lower=1.0, quantity={"w": 0.7})
    assert not calls


def test_quantity_labels_and_records():
    assert Quantity().label == "I10"
    assert Quantity(p=0.5).label == "I50"
    assert Quantity("first_exceedance").label == "first exceedance"
    assert Quantity.from_value(None) == Quantity()
    assert Quantity.from_value({"name": "exceedance_quantile", "p": 0.2, "w": 0.01}) \
        == Quantity(p=0.2, w=0.01)
    assert Quantity.from_value(Quantity().to_dict()) == Quantity()
    assert Quantity().columns() == {"quantity": "exceedance_quantile", "quantity_p": 0.1,
                                    "quantity_w": 0.02}
