"""Cumulative zero up-crossing and extrema counts (spec §7 item 3)."""

import numpy as np
import pytest

from rocking.motions.counts import maxima_cum, pmnm_cum, zero_upcrossings_cum


@pytest.mark.parametrize(("f", "T"), [(1.0, 10.0), (3.3, 7.0), (4.78, 24.13)])
def test_sine_has_f_T_upcrossings_and_no_pm_nm(f, T):
    dt = 0.005
    t = np.arange(0.0, T, dt)
    a = np.sin(2 * np.pi * f * t + 0.3)
    n_up = zero_upcrossings_cum(a)
    assert abs(n_up[-1] - f * T) <= 1.0
    assert n_up[0] == 0 and np.all(np.diff(n_up) >= 0)
    # A pure sinusoid has its minima below zero and maxima above: no PM, no NM.
    assert pmnm_cum(a)[-1] == 0
    assert abs(maxima_cum(a)[-1] - f * T) <= 1.0


def test_counts_on_a_hand_made_signal():
    a = np.array([-1.0, 2.0, 1.0, 3.0, -2.0, -0.5, -1.0, 0.0, -1.0, 1.0])
    # Up-crossings (a_k < 0 <= a_k+1) at k+1 = 1, 7, 9; positive minimum at 2 (1 < 2, 3);
    # negative maximum at 5 (−0.5 > −2, −1); maxima at 1, 3, 5, 7.
    np.testing.assert_array_equal(zero_upcrossings_cum(a), [0, 1, 1, 1, 1, 1, 1, 2, 2, 3])
    np.testing.assert_array_equal(pmnm_cum(a), [0, 0, 1, 1, 1, 2, 2, 2, 2, 2])
    np.testing.assert_array_equal(maxima_cum(a), [0, 1, 1, 2, 2, 3, 3, 4, 4, 4])


def test_pmnm_equals_maxima_minus_upcrossings_on_random_signals():
    # Each positive excursion has one more maximum than minima; end effects give at most ±2.
    rng = np.random.default_rng(11)
    for _ in range(20):
        x = np.cumsum(rng.standard_normal(3000)) * 0.1 + rng.standard_normal(3000)
        diff = pmnm_cum(x) - (maxima_cum(x) - zero_upcrossings_cum(x))
        assert np.max(np.abs(diff)) <= 2


def test_stacks_are_counted_row_by_row():
    x = np.random.default_rng(2).standard_normal((3, 400))
    for fn in (zero_upcrossings_cum, pmnm_cum, maxima_cum):
        np.testing.assert_array_equal(fn(x), np.vstack([fn(r) for r in x]))


@pytest.mark.parametrize("fn", [zero_upcrossings_cum, pmnm_cum, maxima_cum])
def test_bad_input_is_named(fn):
    with pytest.raises(ValueError, match="non-finite"):
        fn([0.0, 1.0, np.inf, 2.0])
    with pytest.raises(ValueError, match="at least 3"):
        fn([0.0, 1.0])
