"""Undamped 3D cylinder: invariants, pure wobbling, quasi-rocking, extremes.

Every check compares the compiled kernel with something independent of it: conservation
laws, the closed-form wobbling rate of the corrected Eq (24), the Srinivasan–Ruina small-spin
turn angle π√(κo/κt), the potential-energy barrier at θ = α.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocking import Cylinder, Status, free_vibration
from rocking.constants import G
from rocking.dynamics.bodies import mu
from rocking.dynamics.cylinder3d import energy, free_peak

TAN_ALPHAS = (0.05, 0.2, 1.0, 1000.0)


def _energy_drift(res, body):
    E = energy(body, res.theta, res.theta_dot, res.phi_dot)
    return float(np.max(np.abs(E - E[0])) / E[0])


def _momentum_drift(res, body):
    L = mu(res.theta, body.alpha) * res.phi_dot
    return float(np.max(np.abs(L - L[0])) / abs(L[0]))


@pytest.mark.parametrize("tan_alpha", [0.2, 1.0])
def test_energy_and_spin_momentum_conserved_drift_shrinks_with_rtol(tan_alpha):
    """E = ½R²[κo θ̇² + μφ̇²] + gR cos(α − θ) and L = μ(θ)φ̇ are invariants of free motion.

    The motion (θ0 = α/2, φ̇0 = 0.3 rad/s, 30 s) has tilt oscillations and fast spin. The
    energy drift must fall by ≥ 30x between rtol 1e-6 and 1e-9 (5th-order method: ~1000x
    expected) and stay below the stated bounds; L is integrated as a state of the kernel so
    its drift is round-off only.
    """
    body = Cylinder(6.0, tan_alpha)
    drifts = {}
    for rtol in (1e-6, 1e-9):
        res = free_vibration(body, 0.5 * body.alpha, 0.3, duration=30.0, rtol=rtol)
        assert res.status is Status.OK
        drifts[rtol] = _energy_drift(res, body)
        assert _momentum_drift(res, body) < 1e-13
        assert np.all(res.theta > 0.0)
    assert drifts[1e-6] < 1e-4 * tan_alpha**0.5
    assert drifts[1e-9] < 3e-7 * tan_alpha**0.5
    assert drifts[1e-9] < drifts[1e-6] / 30.0


@pytest.mark.parametrize("tan_alpha", TAN_ALPHAS)
@pytest.mark.parametrize("ratio", [0.1, 0.4, 0.7])
def test_pure_wobbling_keeps_tilt_and_period(tan_alpha, ratio):
    """Released at θ0 with φ̇0 = wobbling_rate(θ0) (corrected Eq 24), θ stays at θ0 and the
    contact point turns once in 2π/φ̇0."""
    body = Cylinder(6.0, tan_alpha)
    th0 = ratio * body.alpha
    rate = float(body.wobbling_rate(th0))
    period = 2.0 * math.pi / rate
    res = free_vibration(body, th0, rate, duration=2.5 * period, rtol=1e-10)
    assert res.status is Status.OK
    assert np.max(np.abs(res.theta / th0 - 1.0)) < 1e-9
    assert np.max(np.abs(res.phi_dot / rate - 1.0)) < 1e-9
    t_turn = np.interp(2.0 * math.pi, res.phi, res.t)  # φ increases monotonically
    assert t_turn == pytest.approx(period, rel=1e-9)


@pytest.mark.parametrize("tan_alpha", TAN_ALPHAS)
def test_quasi_rocking_turn_angle_matches_srinivasan_ruina(tan_alpha):
    """φ̇0 = 1e-8: the contact point turns by π√(κo/κt) in each quasi-impact; θ stays > 0."""
    body = Cylinder(6.0, tan_alpha)
    res = free_vibration(body, 0.5 * body.alpha, 1e-8, duration=12.0 / body.p, rtol=1e-10)
    assert res.status is Status.OK
    ev = res.quasi_impacts.state
    assert len(ev) >= 3
    turns = np.diff(ev[:, 1])
    np.testing.assert_allclose(turns, body.turn_angle, rtol=0, atol=1e-5)
    assert np.all(res.theta > 0.0)
    assert np.all(ev[:, 0] > 0.0) and np.all(ev[:, 0] < 1e-7)  # true quasi-impacts
    assert np.max(np.abs(res.phi_dot)) > 1e4  # the spin spikes in them


@pytest.mark.parametrize("tan_alpha", [0.05, 0.1, 0.2, 1.0, 1000.0])
def test_extremes_finite_with_invariants(tan_alpha):
    """Slender to flat (Euler's disk) × R from 0.1 m to 100 m × spin 1e-8 … 1 rad/s."""
    for R in (0.1, 1.0, 6.0, 100.0):
        body = Cylinder(R, tan_alpha)
        for spin in (1e-8, 1e-4, 1.0):
            res = free_vibration(body, 0.5 * body.alpha, spin * body.p, duration=8.0 / body.p)
            assert res.status is Status.OK, (R, spin, res.reason)
            assert np.all(np.isfinite(res.theta)) and np.all(res.theta > 0.0)
            assert _energy_drift(res, body) < 2e-6, (R, spin)
            assert _momentum_drift(res, body) < 1e-12


@pytest.mark.parametrize("tan_alpha", [0.05, 0.2, 1.0])
def test_release_just_below_and_above_alpha(tan_alpha):
    """At the default rtol: 0.999α rocks back (and, undamped, never exceeds it by more than the
    energy drift allows), 1.001α overturns."""
    body = Cylinder(6.0, tan_alpha)
    below = free_vibration(body, 0.999 * body.alpha, 1e-8, duration=20.0 / body.p,
                           history=False)
    assert below.status is Status.OK
    assert below.theta_max / body.alpha == pytest.approx(0.999, abs=1e-4)
    above = free_vibration(body, 1.001 * body.alpha, 1e-8, duration=20.0 / body.p,
                           history=False)
    assert above.status is Status.OVERTURNED and above.overturned
    assert above.theta_max == pytest.approx(math.pi / 2, abs=1e-9)


def test_exactly_planar_motion_fails_clearly():
    """No spin: the motion is planar and reaches θ = 0, where the 3D model is undefined."""
    body = Cylinder(6.0, 0.2)
    res = free_vibration(body, 0.1, 0.0, duration=10.0)
    assert res.status is Status.FAILED
    assert "2d" in res.reason and not res.ok


@pytest.mark.parametrize("tan_alpha", [0.2, 1000.0])
def test_free_peak_from_effective_potential_matches_integration(tan_alpha):
    """The 1-DOF reduction predicts the next tilt maximum of the integrated motion."""
    body = Cylinder(6.0, tan_alpha)
    th0, thd0, spin = 0.3 * body.alpha, -0.2 * body.p * body.alpha, 0.05 * body.p
    peak = free_peak(body, th0, thd0, spin)
    res = free_vibration(body, th0, spin, theta_dot0=thd0, duration=20.0 / body.p, rtol=1e-11)
    assert res.theta_max == pytest.approx(peak, rel=1e-8)
    # Energy check of the root itself: V(θ*) = E.
    L = float(mu(th0, body.alpha)) * spin
    E = float(energy(body, th0, thd0, spin))
    V = G * body.R * math.cos(body.alpha - peak) + 0.5 * body.R**2 * L**2 / float(
        mu(peak, body.alpha))
    assert V == pytest.approx(E, rel=1e-13)
