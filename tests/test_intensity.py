"""Husid function, Arias intensity and durations against closed forms."""

import math

import numpy as np
import pytest

from rocking.constants import G
from rocking.motions.intensity import (
    arias,
    husid,
    significant_duration,
    t_mid,
    time_at_fraction,
    times_from_husid,
)


def test_husid_of_a_sine_matches_the_closed_form():
    # I_a(t) = (π/2g) A² [t/2 − sin(2ωt)/(4ω)] for a = A sin ωt; the trapezoid rule errs by
    # O((ωΔt)²) relative, ~1e-4 here.
    dt, amp, w = 0.001, 2.0, 2 * math.pi * 1.5
    t = np.arange(0, 10.0 + dt / 2, dt)
    exact = math.pi / (2 * G) * amp**2 * (t / 2 - np.sin(2 * w * t) / (4 * w))
    h = husid(amp * np.sin(w * t), dt)
    assert h[0] == 0.0
    np.testing.assert_allclose(h, exact, rtol=0, atol=2e-4 * exact[-1])
    assert arias(amp * np.sin(w * t), dt) == pytest.approx(exact[-1], rel=2e-4)


def test_fraction_times_of_a_constant_signal_are_exact():
    # a = const: I_a grows linearly, so t_p = p·T exactly (linear interpolation is exact).
    dt, T = 0.01, 20.0
    a = np.full(int(round(T / dt)) + 1, 0.3)
    p = np.array([0.0, 0.05, 0.45, 0.95, 1.0])
    np.testing.assert_allclose(time_at_fraction(a, dt, p), p * T, atol=1e-10)
    assert significant_duration(a, dt) == pytest.approx(0.9 * T, abs=1e-10)
    assert t_mid(a, dt) == pytest.approx(0.45 * T, abs=1e-10)
    assert significant_duration(a, dt, 0.25, 0.75) == pytest.approx(0.5 * T, abs=1e-10)


def test_fraction_time_on_a_flat_husid_segment_takes_the_first_crossing():
    # Two equal bursts separated by 5 s of silence: the Husid curve sits at exactly one half
    # from 1.01 s (end of the first burst's trapezoid) to 6.0 s; t_0.5 is the first of these.
    dt = 0.01
    a = np.concatenate([np.ones(101), np.zeros(500), np.ones(101)])
    t50 = time_at_fraction(a, dt, 0.5)
    assert t50 == pytest.approx(1.01, abs=1e-9)
    assert husid(a, dt)[101] / husid(a, dt)[-1] == pytest.approx(0.5, abs=1e-12)


def test_stacked_records_match_one_by_one():
    rng = np.random.default_rng(3)
    a = rng.standard_normal((4, 500))
    np.testing.assert_allclose(husid(a, 0.02), np.vstack([husid(r, 0.02) for r in a]))
    np.testing.assert_allclose(arias(a, 0.02), [arias(r, 0.02) for r in a])


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: husid([1.0, np.nan, 2.0], 0.01), "non-finite"),
        (lambda: husid([1.0, 2.0, 3.0], 0.0), "dt"),
        (lambda: husid([1.0, 2.0, 3.0], -0.01), "dt"),
        (lambda: husid([1.0], 0.01), "at least 2"),
        (lambda: time_at_fraction(np.zeros(10), 0.01, 0.5), "no energy"),
        (lambda: time_at_fraction(np.ones(10), 0.01, 1.5), "fractions"),
        (lambda: significant_duration(np.ones(10), 0.01, 0.9, 0.1), "lo"),
        (lambda: times_from_husid(np.ones((2, 3)), 0.01, 0.5), "one-dimensional"),
    ],
)
def test_bad_input_is_named(call, match):
    with pytest.raises(ValueError, match=match):
        call()
