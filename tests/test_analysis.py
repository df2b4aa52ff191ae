"""Public API: validation, uplift from rest, stop_at, summary mode, free tail, dispatch."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocking import Block, Cylinder, GroundMotion, Status, free_vibration, ground_response
from rocking.constants import G
from rocking.dynamics.cylinder3d import energy, free_peak


def _pulse_pair(body, amp=2.0, angle=0.6, dt=0.005, T=1.2, tail=2.0):
    """A one-sine pulse along an oblique direction plus a weaker orthogonal wiggle."""
    t = np.arange(int((T + tail) / dt) + 1) * dt
    s = np.where(t < T, np.sin(2 * np.pi * t / T), 0.0)
    w = np.where(t < T, np.sin(6 * np.pi * t / T), 0.0)
    a = amp * G * body.tan_alpha
    ax = a * (math.cos(angle) * s - 0.2 * math.sin(angle) * w)
    ay = a * (math.sin(angle) * s + 0.2 * math.cos(angle) * w)
    return GroundMotion(ax, ay, dt, name="pulse")


# ------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: Cylinder(0.0, 0.2), "R"),
        (lambda: Cylinder(-1.0, 0.2), "R"),
        (lambda: GroundMotion([0.0, float("nan"), 1.0], [0.0, 1.0, 2.0], 0.01), "ax"),
        (lambda: GroundMotion([0.0, 1.0], [0.0, 1.0], 0.0), "dt"),
        (lambda: GroundMotion([0.0, 1.0], [0.0, 1.0], -0.01), "dt"),
        (lambda: free_vibration(Cylinder(1.0, 0.2), 0.1, 0.1, duration=1.0, zeta=-1.0), "zeta"),
        (lambda: free_vibration(Cylinder(1.0, 0.2), 0.1, 0.1, duration=0.0), "duration"),
        (lambda: free_vibration(Cylinder(1.0, 0.2), 0.1, 0.1, duration=-2.0), "duration"),
        (lambda: free_vibration(Cylinder(1.0, 0.2), 0.1, 0.1, duration=1.0, model="4d"),
         "model"),
        (lambda: free_vibration(Cylinder(1.0, 0.2), 0.1, float("nan"), duration=1.0),
         "phi_dot0"),
        (lambda: free_vibration(Cylinder(1.0, 0.2), 0.1, 0.1, duration=1.0, rtol=0.0), "rtol"),
        (lambda: free_vibration(Cylinder(1.0, 0.2), -0.1, 0.1, duration=1.0), "theta0"),
        (lambda: free_vibration(Cylinder(1.0, 0.2), 0.1, 0.1, duration=1.0, omega_n=0.0),
         "omega_n"),
        (lambda: free_vibration(Block(1.0, 0.2), 0.1, 0.1, duration=1.0), "Block"),
        (lambda: ground_response(Cylinder(1.0, 0.2), GroundMotion([0, 1.0], [1.0, 0], 0.01),
                                 scale=float("inf")), "scale"),
        (lambda: ground_response(Cylinder(1.0, 0.2), GroundMotion([0, 1.0], [1.0, 0], 0.01),
                                 stop_at=-0.1), "stop_at"),
    ],
)
def test_bad_input_names_the_field(call, field):
    with pytest.raises(ValueError, match=field):
        call()


def test_unidirectional_3d_points_to_2d():
    body = Cylinder(1.0, 0.2)
    m = GroundMotion(np.sin(np.arange(100) * 0.1) * 5.0, None, 0.01)
    with pytest.raises(ValueError, match="2d"):
        ground_response(body, m, model="3d")
    assert ground_response(body, m, model="2d").ok


# ------------------------------------------------------------------------- 3D uplift
def test_3d_rest_then_uplift_along_dalembert_force():
    body = Cylinder(2.0, 0.2)
    m = _pulse_pair(body)
    res = ground_response(body, m)
    assert res.uplifted and res.ok
    # Independent: first crossing of |a| = g tan α on a fine grid of the linear interpolant.
    fine = np.linspace(0.0, 0.5, 2_000_001)
    ax, ay = np.interp(fine, m.time, m.ax), np.interp(fine, m.time, m.ay)
    i = int(np.argmax(np.hypot(ax, ay) > G * body.tan_alpha))
    assert res.t_uplift == pytest.approx(fine[i], abs=1e-6)
    moving = np.flatnonzero(res.theta > 0.0)[0]
    assert res.t[moving] == res.t_uplift
    assert res.theta[moving] == 1e-7
    phi0 = math.atan2(-ay[i], -ax[i])
    assert res.phi[moving] == pytest.approx(phi0, abs=1e-5)
    assert np.all(res.theta[res.t < res.t_uplift] == 0.0)
    # While at rest nothing is integrated: weaker by 1 % below the vector threshold.
    weak = m.scaled(0.99 * G * body.tan_alpha / m.pga)
    r0 = ground_response(body, weak)
    assert not r0.uplifted and r0.n_steps == 0 and r0.theta_max == 0.0


def test_summary_mode_equals_history_mode():
    body = Cylinder(2.0, 0.2)
    m = _pulse_pair(body)
    full = ground_response(body, m, rtol=1e-9)
    fast = ground_response(body, m, rtol=1e-9, history=False)
    assert fast.t.size <= 1 and full.t.size > 100
    assert fast.theta_max == full.theta_max
    assert fast.t_theta_max == full.t_theta_max or (
        math.isnan(fast.t_theta_max) and math.isnan(full.t_theta_max))
    assert fast.status == full.status
    assert len(fast.quasi_impacts) == len(full.quasi_impacts)


def test_stop_at_ends_the_analysis_there():
    body = Cylinder(2.0, 0.2)
    m = _pulse_pair(body, amp=1.25)
    free = ground_response(body, m, rtol=1e-10)
    assert free.status is Status.OK and free.theta_max > 0.3 * body.alpha
    level = 0.5 * free.theta_max
    res = ground_response(body, m, stop_at=level, rtol=1e-10)
    assert res.status is Status.STOPPED_AT_LIMIT and not res.overturned
    assert res.theta[-1] == pytest.approx(level, rel=1e-12)
    assert res.t[-1] < free.t_theta_max
    # Above the peak the limit is not reached.
    res = ground_response(body, m, stop_at=1.01 * free.theta_max, rtol=1e-10)
    assert res.status is Status.OK


def test_free_tail_decided_by_invariants():
    """After the record the undamped cylinder keeps E and L: θmax includes the next swing,
    computed from the effective potential and confirmed by integrating further."""
    body = Cylinder(3.0, 0.2)
    m = _pulse_pair(body, amp=1.2, tail=0.05)  # record ends right after the pulse
    res = ground_response(body, m, rtol=1e-11)
    no_tail = ground_response(body, m, rtol=1e-11, free_tail=False)
    assert res.ok
    end = np.flatnonzero(res.t <= m.duration)[-1]
    peak = free_peak(body, res.theta[end], res.theta_dot[end], res.phi_dot[end])
    assert res.extras["free_tail_peak"] == pytest.approx(peak, rel=1e-12)
    assert res.theta_max == pytest.approx(max(no_tail.theta_max, peak), rel=1e-12)
    # The integrated continuation reaches the same peak and conserves the energy.
    after = res.t > m.duration
    assert np.max(res.theta[after]) == pytest.approx(peak, rel=1e-8)
    E = energy(body, res.theta[after], res.theta_dot[after], res.phi_dot[after])
    assert np.ptp(E) / E[0] < 1e-9


def test_failed_analysis_is_never_silent():
    res = free_vibration(Cylinder(1.0, 0.2), 0.1, 0.0, duration=5.0)
    assert res.status is Status.FAILED and res.reason and not res.ok


# ------------------------------------------------------------------------- El Centro
def test_el_centro_3d_and_2d_converge():
    from rocking.motions.catalogue import load_record

    m = load_record("el-centro-1940")
    body = Cylinder(6.0, 0.2)
    scale = 2.0 * G * body.tan_alpha / m.pga
    ref = ground_response(body, m, scale=scale, rtol=1e-12, history=False)
    dflt = ground_response(body, m, scale=scale, history=False)
    assert ref.status is Status.OK and dflt.status is Status.OK
    assert dflt.theta_max == pytest.approx(ref.theta_max, rel=1e-3)
    assert len(ref.quasi_impacts) > 10  # wobbling with quasi-impacts, as in the paper
    r2 = ground_response(body, m.component("x"), model="2d", scale=scale, history=False)
    r2ref = ground_response(body, m.component("x"), model="2d", scale=scale, rtol=1e-12,
                            history=False)
    assert r2.theta_max == pytest.approx(r2ref.theta_max, rel=1e-3)


# ------------------------------------------------------------------------- dispatch
def test_damped_model_dispatch():
    body = Cylinder(6.0, 0.2)
    res = free_vibration(body, 0.1, 0.3, duration=2.0, model="3d-damped")
    und = free_vibration(body, 0.1, 0.3, duration=2.0, rtol=1e-10)
    assert res.model == "3d-damped" and res.ok and res.w is not None
    # Without quasi-impacts the damped and undamped models coincide (paper, Fig 4c–f).
    assert res.theta_max == pytest.approx(und.theta_max, rel=1e-3)
