"""Gamma modulating function: the exact (Ia, D5-95, t_mid) ↔ α map (spec §2.2, §7 item 1)."""

import math

import numpy as np
import pytest
from scipy import integrate, stats

from rocking.constants import G
from rocking.motions.intensity import husid, times_from_husid
from rocking.motions.stochastic.envelope import (
    GammaEnvelope,
    alphas_from_physical,
    duration_ratio,
    physical_from_alphas,
    shape_from_ratio,
)


@pytest.mark.parametrize(
    ("k", "r"),
    [(0.5, 0.0931), (1, 0.2030), (2, 0.3472), (3, 0.4520), (5, 0.6134), (10, 0.9032)],
)
def test_duration_ratio_reference_values(k, r):
    assert duration_ratio(k) == pytest.approx(r, abs=6e-5)
    assert shape_from_ratio(r) == pytest.approx(k, rel=2e-3)


def test_duration_ratio_is_increasing_over_the_search_bracket():
    k = np.logspace(-2, 4, 3000)
    assert np.all(np.diff(duration_ratio(k)) > 0)


def test_ratio_uses_the_gamma_rate_not_the_scale():
    # The quantiles must be those of scipy's gamma distribution with scale 1 (rate-free).
    k = 2.3
    q = stats.gamma.ppf([0.05, 0.45, 0.95], k)
    assert duration_ratio(k) == pytest.approx(q[1] / (q[2] - q[0]), rel=1e-12)


def test_discretized_envelope_returns_its_physical_parameters():
    # Spec round trip: Ia 1.7 m/s, D5-95 24.1 s, t_mid 4.9 s, q sampled at 0.01 s over 80 s.
    env = alphas_from_physical(1.7, 24.1, 4.9)
    dt = 0.01
    t = np.arange(0, 80.0 + dt / 2, dt)
    h = husid(env(t), dt)
    t05, t45, t95 = times_from_husid(h, dt, [0.05, 0.45, 0.95])
    assert h[-1] == pytest.approx(1.7, rel=5e-3)
    assert t95 - t05 == pytest.approx(24.1, rel=5e-3)
    assert t45 == pytest.approx(4.9, rel=5e-3)


@pytest.mark.parametrize(("Ia", "D", "tm"), [(0.05, 8.0, 6.0), (3.0, 30.0, 12.0), (1.0, 5.0, 0.6)])
def test_expected_arias_agrees_with_quadrature(Ia, D, tm):
    env = alphas_from_physical(Ia, D, tm)
    quad, _ = integrate.quad(lambda s: env(s) ** 2, 0, np.inf, limit=200)
    assert math.pi / (2 * G) * quad == pytest.approx(Ia, rel=1e-6)
    assert physical_from_alphas(env.alpha1, env.alpha2, env.alpha3) == pytest.approx(
        (Ia, D, tm), rel=1e-8
    )


def test_expected_husid_fraction_is_the_normalized_integral_of_q2():
    env = GammaEnvelope(0.8, 2.2, 0.3, T0=1.5)
    total, _ = integrate.quad(lambda s: env(s) ** 2, 1.5, np.inf)
    for t in (2.0, 5.0, 11.0):
        part, _ = integrate.quad(lambda s: env(s) ** 2, 1.5, t)
        assert env.expected_husid_fraction(t) == pytest.approx(part / total, rel=1e-8)
    assert env(1.5) == 0.0 and env(1.0) == 0.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"Ia": -1.0, "D5_95": 20.0, "t_mid": 5.0}, "Ia"),
        ({"Ia": 1.0, "D5_95": 0.0, "t_mid": 5.0}, "D5_95"),
        ({"Ia": 1.0, "D5_95": 20.0, "t_mid": 0.0}, "t_mid"),
        ({"Ia": 1.0, "D5_95": 20.0, "t_mid": 5.0, "T0": 6.0}, "t_mid"),
        ({"Ia": float("nan"), "D5_95": 20.0, "t_mid": 5.0}, "Ia"),
        ({"Ia": 1.0, "D5_95": 1.0, "t_mid": 500.0}, "outside the range"),
    ],
)
def test_bad_physical_parameters_are_named(kwargs, match):
    with pytest.raises(ValueError, match=match):
        alphas_from_physical(**kwargs)


def test_bad_alphas_are_named():
    with pytest.raises(ValueError, match="alpha2"):
        GammaEnvelope(1.0, 0.4, 0.1)
    with pytest.raises(ValueError, match="alpha3"):
        GammaEnvelope(1.0, 1.5, -0.1)
