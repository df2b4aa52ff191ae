"""Response spectra against independent solutions: scipy lsim, matrix exponential, closed
forms for harmonic input, and the rigid (T → 0) and very flexible (T → ∞) limits."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal

from rocking.motions.catalogue import load_record
from rocking.motions.motion import GroundMotion
from rocking.motions.response_spectrum import (
    foh_coefficients,
    nigam_jennings_coefficients,
    pseudo_acceleration,
    sdof_response,
    spectral_displacement,
)


@pytest.fixture(scope="module")
def el_centro() -> GroundMotion:
    return load_record("el-centro-1940")


def _lsim(acc: np.ndarray, dt: float, period: float, damping: float) -> np.ndarray:
    """(u, u̇) of ü + 2ζωu̇ + ω²u = −a_g by scipy (first-order hold, from rest)."""
    w = 2.0 * math.pi / period
    sys = signal.StateSpace(
        [[0.0, 1.0], [-w * w, -2.0 * damping * w]], [[0.0], [-1.0]], np.eye(2), np.zeros((2, 1))
    )
    _, y, _ = signal.lsim(sys, acc, np.arange(acc.size) * dt, interp=True)
    return y


@pytest.mark.parametrize("damping", [0.0, 0.02, 0.05, 0.3, 0.9])
def test_closed_form_coefficients_match_matrix_exponential(damping: float) -> None:
    T = np.array([0.03, 0.1, 0.5, 1.0, 3.0, 6.0])
    dt = 0.01
    nj = nigam_jennings_coefficients(T, damping, dt)
    ref = foh_coefficients(T, damping, dt)
    # Scale each coefficient by its natural size (displacement terms ~dt, force terms ~dt²),
    # because some of them cross zero (e.g. sin(ωΔt) when T = Δt multiples).
    scale = np.array([1, dt, dt**2, dt**2, 1 / dt, 1, dt, dt])
    # The closed form cancels terms of size 2ζ/(ωΔt): rounding ~eps·2ζ/(ωΔt)³, 2e-10 at
    # ζ = 0.9, T = 6 s (ωΔt = 0.01, below which the matrix exponential takes over).
    np.testing.assert_allclose(nj / scale, ref / scale, rtol=0, atol=1e-9)


@pytest.mark.parametrize(("period", "damping"), [(0.05, 0.05), (0.5, 0.05), (2.0, 0.02),
                                                  (4.0, 0.2), (20.0, 0.05)])
def test_history_matches_lsim(el_centro: GroundMotion, period: float, damping: float) -> None:
    u, v = sdof_response(el_centro.ay, el_centro.dt, period, damping)
    ref = _lsim(el_centro.ay, el_centro.dt, period, damping)
    np.testing.assert_allclose(u, ref[:, 0], rtol=0, atol=1e-9 * np.max(np.abs(ref[:, 0])))
    np.testing.assert_allclose(v, ref[:, 1], rtol=0, atol=1e-9 * np.max(np.abs(ref[:, 1])))
    # The spectral ordinate is the peak of that same history.
    psa = pseudo_acceleration(el_centro.ay, el_centro.dt, [period], damping)[0]
    expected = (2 * math.pi / period) ** 2 * np.max(np.abs(ref[:, 0]))
    assert psa == pytest.approx(expected, rel=1e-6)


def test_harmonic_closed_form() -> None:
    # a_g = a0 sin(Ωt) from rest: u = e^(−ζωt)(A cos ω_D t + B sin ω_D t) + C sin Ωt + D cos Ωt
    # with p = −a_g (Chopra eq. 3.2.2). The only error is the linear interpolation of the
    # sampled sine, ~(ΩΔt)²/8 = 2.5e-6 at Δt = 1 ms.
    a0, big_w, T, z, dt = 3.0, 2 * math.pi * 0.8, 1.0, 0.05, 0.001
    t = np.arange(40_001) * dt
    w = 2 * math.pi / T
    wd = w * math.sqrt(1 - z * z)
    r = big_w / w
    den = (1 - r * r) ** 2 + (2 * z * r) ** 2
    p0 = -a0
    c = p0 / w**2 * (1 - r * r) / den
    d = p0 / w**2 * (-2 * z * r) / den
    a_coef = -d
    b_coef = (z * w * a_coef - c * big_w) / wd
    exact = (np.exp(-z * w * t) * (a_coef * np.cos(wd * t) + b_coef * np.sin(wd * t))
             + c * np.sin(big_w * t) + d * np.cos(big_w * t))
    u, _ = sdof_response(a0 * np.sin(big_w * t), dt, T, z)
    np.testing.assert_allclose(u, exact, rtol=0, atol=1e-5 * np.max(np.abs(exact)))
    # Steady-state amplitude: the dynamic amplification (a0/ω²)/√den once the transient
    # (e^(−ζωt) = 8e-5 at 30 s) is gone.
    late = t > 30.0
    assert np.max(np.abs(u[late])) == pytest.approx(a0 / w**2 / math.sqrt(den), rel=3e-4)


def test_rigid_limit_is_pga(el_centro: GroundMotion) -> None:
    pga = np.max(np.abs(el_centro.ax))
    psa = pseudo_acceleration(el_centro.ax, el_centro.dt, [0.0, 1e-3, 3e-3])
    assert psa[0] == pga
    np.testing.assert_allclose(psa[1:], pga, rtol=2e-4)


def test_flexible_limit_is_peak_ground_displacement(el_centro: GroundMotion) -> None:
    # A very long-period oscillator stays put: u = −d_g. The exact double integral of the
    # piecewise-linear record: v += Δt(a_k + a_k+1)/2, d += Δt v_k + Δt²(2a_k + a_k+1)/6.
    a, dt = el_centro.ax, el_centro.dt
    v = np.concatenate([[0.0], np.cumsum(dt * (a[:-1] + a[1:]) / 2)])
    d = np.concatenate([[0.0], np.cumsum(dt * v[:-1] + dt * dt * (2 * a[:-1] + a[1:]) / 6)])
    pgd = np.max(np.abs(d))
    assert spectral_displacement(a, dt, [1e6], 0.0)[0] == pytest.approx(pgd, rel=1e-9)
    assert spectral_displacement(a, dt, [1e6], 0.05)[0] == pytest.approx(pgd, rel=1e-6)


def test_many_records_and_periods(el_centro: GroundMotion) -> None:
    periods = np.logspace(-2, 1, 40)
    both = pseudo_acceleration(np.vstack([el_centro.ax, el_centro.ay]), el_centro.dt, periods)
    assert both.shape == (2, 40)
    np.testing.assert_array_equal(both[1], pseudo_acceleration(el_centro.ay, el_centro.dt,
                                                               periods))
    # PSA = ω² SD by definition; the spectrum of the N-S record peaks near 0.5 g.
    sd = spectral_displacement(el_centro.ay, el_centro.dt, periods)
    np.testing.assert_allclose(both[1], (2 * np.pi / periods) ** 2 * sd, rtol=1e-15)
    assert 0.4 < both[1].max() / 9.80665 < 1.2


def test_bad_input() -> None:
    a = np.sin(np.arange(100) * 0.1)
    with pytest.raises(ValueError, match="damping"):
        pseudo_acceleration(a, 0.01, [1.0], damping=1.0)
    with pytest.raises(ValueError, match="periods"):
        pseudo_acceleration(a, 0.01, [-1.0])
    with pytest.raises(ValueError, match="periods"):
        pseudo_acceleration(a, 0.01, [np.nan])
    with pytest.raises(ValueError, match="dt"):
        pseudo_acceleration(a, 0.0, [1.0])
    with pytest.raises(ValueError, match="non-finite"):
        pseudo_acceleration(np.array([0.0, np.inf, 0.0]), 0.01, [1.0])
    with pytest.raises(ValueError, match="period"):
        sdof_response(a, 0.01, 0.0)
