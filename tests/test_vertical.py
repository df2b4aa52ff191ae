"""Vertical ground motion and the validity monitors (issue 33), against independent checks.

- a constant vertical acceleration c is gravity g + c: by time scaling, the response to
  (a_x(t), a_y(t), c) is the response to (a_x, a_y)/λ on the time axis stretched by √λ,
  λ = (g + c)/g, with no vertical motion;
- the support force of free rocking of a 2D block against the closed form of a body rotating
  about a corner, written with the energy (not the integrated rate);
- the 3D support force against the centre of mass's acceleration differentiated
  numerically from the histories of tilt and spin;
- the 2D impact's impulse ratio against the momentum change of the impact, computed here
  from the corner geometry;
- the energy balance with the work of all three ground components;
- no vertical component (None, zeros, or vertical=False) gives the same answers to the bit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocking.constants import G
from rocking.dynamics import Block, Cylinder, free_vibration, ground_response
from rocking.dynamics.bodies import mu as spin_inertia
from rocking.dynamics.housner2d import impact_friction
from rocking.motions.motion import GroundMotion
from rocking.motions.readers import Record, with_vertical


def _pulses(n=1500, dt=0.01, amp=3.0, seed=3):
    """A short bidirectional motion: two smooth pulse trains [m/s²]."""
    t = np.arange(n) * dt
    rng = np.random.default_rng(seed)
    env = np.exp(-((t - 4.0) / 2.0) ** 2)
    ax = amp * env * np.sin(2 * np.pi * 1.3 * t + rng.uniform(0, 1))
    ay = 0.7 * amp * env * np.sin(2 * np.pi * 0.9 * t + rng.uniform(0, 1))
    az = 0.8 * amp * env * np.sin(2 * np.pi * 2.1 * t + rng.uniform(0, 1))
    return ax, ay, az, dt


# ----------------------------------------------------------------------------- bit identity
@pytest.mark.parametrize("model", ["3d", "2d", "3d-damped"])
def test_no_vertical_is_bit_identical(model):
    ax, ay, az, dt = _pulses()
    body = Cylinder(1.0, 0.2)
    plain = GroundMotion(ax, ay, dt, "p")
    zero = GroundMotion(ax, ay, dt, "p", az=np.zeros_like(ax))
    with_z = GroundMotion(ax, ay, dt, "p", az=az)
    for hist in (True, False):
        ref = ground_response(body, plain, model=model, history=hist)
        for m, kw in ((zero, {}), (with_z, {"vertical": False})):
            r = ground_response(body, m, model=model, history=hist, **kw)
            assert r.theta_max == ref.theta_max and r.t_theta_max == ref.t_theta_max
            assert r.n_steps == ref.n_steps
            np.testing.assert_array_equal(r.theta, ref.theta)
            np.testing.assert_array_equal(r.theta_dot, ref.theta_dot)
            np.testing.assert_array_equal(r.normal_force, ref.normal_force)
    # and the vertical component does change the answer
    r = ground_response(body, with_z, model=model, history=False)
    assert (r.theta_max, r.t_theta_max) != (ref.theta_max, ref.t_theta_max)


# ----------------------------------------------------------------------------- g + c
@pytest.mark.parametrize("model", ["3d", "2d"])
def test_constant_vertical_is_a_change_of_gravity(model):
    ax, ay, _, dt = _pulses(amp=4.0)
    if model == "2d":
        ay = np.zeros_like(ax)
    c = 2.0  # [m/s², up]: gravity 11.81
    lam = (G + c) / G
    body = Cylinder(1.0, 0.2)
    a = GroundMotion(ax, ay, dt, "a", az=np.full(ax.size, c))
    b = GroundMotion(ax / lam, ay / lam, dt * math.sqrt(lam), "b")
    kw = dict(model=model, rtol=1e-11, free_tail=False, rest_tilt=0.0)
    ra = ground_response(body, a, **kw)
    rb = ground_response(body, b, **kw)
    assert ra.uplifted and ra.theta_max > 0.2 * body.alpha
    assert ra.theta_max == pytest.approx(rb.theta_max, rel=1e-6)
    assert ra.t_theta_max * math.sqrt(lam) == pytest.approx(rb.t_theta_max, rel=1e-6)
    assert ra.t_uplift * math.sqrt(lam) == pytest.approx(rb.t_uplift, rel=1e-9)
    theta_b = np.interp(ra.t * math.sqrt(lam), rb.t, rb.theta)
    assert np.max(np.abs(ra.theta - theta_b)) < 2e-3 * ra.theta_max  # interpolation error
    # the support carries (g + c)/g weights at rest before the uplift
    assert ra.normal_force[0] == pytest.approx(lam, rel=1e-12)


# ----------------------------------------------------------------------------- 2D closed form
def test_free_rocking_support_force_matches_the_corner_closed_form():
    body = Block(2.0, 0.25)
    th0 = 0.6 * body.alpha
    r = free_vibration(body, th0, duration=1.0, model="2d", rtol=1e-10)
    first = r.quasi_impacts.t[0]
    sel = (r.t < first) & (r.theta > 1e-3)
    psi = body.alpha - r.theta[sel]
    k = body.kappa_o
    # θ̈ = −p² sin ψ and θ̇² = 2p²[cos(α − θ0) − cos ψ] (energy), p² = g/(κo R)
    rate2 = 2.0 * (math.cos(body.alpha - th0) - np.cos(psi)) / k  # θ̇² R/g
    acc = -np.sin(psi) / k  # θ̈ R/g
    n_closed = 1.0 + np.sin(psi) * acc - np.cos(psi) * rate2
    f_closed = np.cos(psi) * acc + np.sin(psi) * rate2
    assert sel.sum() > 20
    np.testing.assert_allclose(r.normal_force[sel], n_closed, rtol=1e-8)
    np.testing.assert_allclose(r.mu_required[sel], np.abs(f_closed) / n_closed, rtol=1e-7,
                               atol=1e-12)
    assert r.normal_force_min == pytest.approx(np.min(r.normal_force), rel=1e-12)


def test_impact_impulse_ratio_is_the_momentum_change():
    body = Block(2.0, 0.25)
    r = free_vibration(body, 0.6 * body.alpha, duration=3.0, model="2d")
    assert len(r.quasi_impacts) >= 2
    b, h = body.b, body.h
    for t_imp, (th, thd) in zip(r.quasi_impacts.t, r.quasi_impacts.state, strict=True):
        assert th == 0.0
        # before: on the corner (σb, 0) of the side it comes from; after, e θ̇ on the other.
        # θ > 0 tilts towards +x (clockwise, ω = −θ̇); G − corner = (−σb, h)
        sigma = -math.copysign(1.0, thd)
        after = r.theta_dot[(r.t == t_imp)][-1]

        def v_g(rate, side):
            return -rate * np.array([-h, -side * b])  # ω ẑ × (G − corner)

        v_before, v_after = v_g(thd, sigma), v_g(after, -sigma)
        jx, jz = v_after - v_before
        assert jz > 0.0
        assert abs(jx) / jz == pytest.approx(impact_friction(body), rel=1e-9)
    assert r.mu_required_max >= impact_friction(body)


def test_2d_support_force_under_ground_motion_matches_the_differentiated_centre():
    ax, _, az, dt = _pulses(amp=2.4)
    body = Block(1.0, 0.25)
    m = GroundMotion(ax, None, dt, "v", az=az)
    r = ground_response(body, m, model="2d", rtol=1e-11, free_tail=False)
    assert r.uplifted and len(r.quasi_impacts) >= 2
    from scipy.interpolate import CubicSpline

    # between two impacts: one pivot, the corner (σb, 0); G at (σb − R sin ψ, R cos ψ)
    t0, t1 = r.quasi_impacts.t[0], r.quasi_impacts.t[1]
    sel = (r.t > t0) & (r.t < t1)
    t, th = r.t[sel], r.theta[sel]
    sigma = math.copysign(1.0, th[len(th) // 2])
    psi = sigma * body.alpha - th
    xg = sigma * body.b - body.R * np.sin(psi)
    zg = body.R * np.cos(psi)
    tu = np.linspace(t[3], t[-4], 2001)
    gx = np.interp(tu, m.time, ax) + CubicSpline(t, xg)(tu, 2)
    gz = np.interp(tu, m.time, az) + CubicSpline(t, zg)(tu, 2)
    n_num = 1.0 + gz / G
    np.testing.assert_allclose(np.interp(tu, t, r.normal_force[sel]), n_num, atol=2e-3)
    np.testing.assert_allclose(np.interp(tu, t, r.mu_required[sel]), np.abs(gx) / G / n_num,
                               atol=2e-3)


# ----------------------------------------------------------------------------- 3D numerical
def test_3d_support_force_matches_the_differentiated_centre_of_mass():
    body = Cylinder(2.0, 0.2)
    th0 = 0.5 * body.alpha
    spin = 0.8 * float(body.wobbling_rate(th0))
    r = free_vibration(body, th0, spin, duration=3.0, rtol=1e-12)
    t, th, ph, thd, phd = r.t, r.theta, r.phi, r.theta_dot, r.phi_dot
    a, R = body.alpha, body.R
    rho = R * (math.sin(a) - np.sin(a - th))
    rho_dot = R * np.cos(a - th) * thd
    v = np.stack([rho_dot * np.cos(ph) - rho * phd * np.sin(ph),
                  rho_dot * np.sin(ph) + rho * phd * np.cos(ph),
                  R * np.sin(a - th) * thd])
    # the run's steps are uneven: differentiate on a fine uniform grid (cubic splines)
    from scipy.interpolate import CubicSpline

    keep = np.concatenate(([True], np.diff(t) > 0))
    tu = np.linspace(t[keep][5], t[keep][-5], 4001)
    acc = np.stack([CubicSpline(t[keep], vi[keep])(tu, 1) for vi in v])
    n_num = 1.0 + acc[2] / G
    mu_num = np.hypot(acc[0], acc[1]) / G / n_num
    n_run = np.interp(tu, t[keep], r.normal_force[keep])
    mu_run = np.interp(tu, t[keep], r.mu_required[keep])
    assert np.min(th) > 0.05 * body.alpha  # no quasi-impact: smooth motion
    np.testing.assert_allclose(n_run, n_num, atol=2e-4)
    np.testing.assert_allclose(mu_run, mu_num, atol=2e-4)
    assert np.ptp(mu_num) > 1e-2  # the comparison is not of constants


# ----------------------------------------------------------------------------- energy
def test_energy_balance_closes_with_the_vertical_work():
    ax, ay, az, dt = _pulses(amp=2.6)
    body = Cylinder(1.0, 0.2)
    m = GroundMotion(ax, ay, dt, "v", az=az)
    r = ground_response(body, m, rtol=1e-11, free_tail=False, rest_tilt=0.0)
    assert r.uplifted and r.theta_max > 0.2 * body.alpha
    i = np.flatnonzero(r.t >= r.t_uplift)[0]
    t, th, ph, thd, phd = (x[i:] for x in (r.t, r.theta, r.phi, r.theta_dot, r.phi_dot))
    a, R = body.alpha, body.R
    mu_th = spin_inertia(th, a)
    e = 0.5 * R * R * (body.kappa_o * thd**2 + mu_th * phd**2) + G * R * np.cos(a - th)
    rho = R * (math.sin(a) - np.sin(a - th))
    rho_dot = R * np.cos(a - th) * thd
    vx = rho_dot * np.cos(ph) - rho * phd * np.sin(ph)
    vy = rho_dot * np.sin(ph) + rho * phd * np.cos(ph)
    vz = R * np.sin(a - th) * thd
    tk = m.time
    gx, gy, gz = (np.interp(t, tk, comp) for comp in (ax, ay, az))
    # power of the ground's inertial force −m a_g on the centre of mass (per unit mass)
    p_h = -(gx * vx + gy * vy)
    p_z = -gz * vz
    w_h = np.concatenate(([0.0], np.cumsum(0.5 * (p_h[1:] + p_h[:-1]) * np.diff(t))))
    w_z = np.concatenate(([0.0], np.cumsum(0.5 * (p_z[1:] + p_z[:-1]) * np.diff(t))))
    gap = e - e[0] - w_h - w_z  # the trapezoid's error on the run's steps
    assert np.max(np.abs(gap)) < 2e-4 * np.ptp(e)
    assert np.max(np.abs(w_z)) > 20 * np.max(np.abs(gap))  # the vertical work matters


# ----------------------------------------------------------------------------- flags
def test_slides_and_lifts_off_flags():
    ax, ay, az, dt = _pulses(amp=4.0)
    strong_up = GroundMotion(ax, ay, dt, "v", az=az * 4.0)  # |a_z| above g: lift-off
    r = ground_response(Cylinder(1.0, 0.2, mu=0.05), strong_up, history=False)
    assert r.lifts_off and r.normal_force_min < 0.0
    # it overturned: its peak μ_req is the fall's (N → 0⁺), which says nothing of sliding
    assert r.overturned and r.slides is None and r.mu_required_max > 0.05
    bx, by, bz, _ = _pulses(amp=2.6)
    gentle = GroundMotion(bx, by, dt, "v", az=bz)
    r = ground_response(Cylinder(1.0, 0.2, mu=0.9), gentle, history=False)
    assert r.uplifted and not r.overturned
    assert r.slides is False and not r.lifts_off and r.normal_force_min > 0.0
    assert 0.2 < r.mu_required_max < 0.9
    assert ground_response(Cylinder(1.0, 0.2), gentle, history=False).slides is None


# ----------------------------------------------------------------------------- bad input
def test_bad_input_is_one_line_before_any_analysis():
    ax, ay, az, dt = _pulses()
    with pytest.raises(ValueError, match="mu must be"):
        Cylinder(1.0, 0.2, mu=0.0)
    with pytest.raises(ValueError, match="mu must be"):
        Block(1.0, 0.2, mu=-0.3)
    with pytest.raises(ValueError, match="az must have the length"):
        GroundMotion(ax, ay, dt, "v", az=az[:-3])
    with pytest.raises(ValueError, match="no vertical component"):
        ground_response(Cylinder(1.0, 0.2), GroundMotion(ax, ay, dt, "h"), vertical=True)
    pair = GroundMotion(ax, ay, dt, "h")
    with pytest.raises(ValueError, match="dt 0.02 s differs"):
        with_vertical(pair, Record(az[::2], 0.02, {"file": "z.AT2"}))
    with pytest.raises(ValueError, match="samples against"):
        with_vertical(pair, Record(az[:1000], dt, {"file": "z.AT2"}))


def test_dwn_file_is_turned_up_and_said():
    ax, ay, az, dt = _pulses()
    pair = GroundMotion(ax, ay, dt, "h")
    header = ["PEER NGA STRONG MOTION DATABASE RECORD", "San Fernando, Pacoima Dam, DWN"]
    m = with_vertical(pair, Record(az, dt, {"file": "z.AT2", "header": header}))
    np.testing.assert_array_equal(m.az, -az)
    assert "sign turned to up" in m.metadata["processing"][-1]["sign"]
    header[1] = "Imperial Valley-02, El Centro Array #9, UP"
    m = with_vertical(pair, Record(az, dt, {"file": "z.AT2", "header": header}))
    np.testing.assert_array_equal(m.az, az)


def test_shipped_records_load_their_vertical_file():
    from rocking.motions.source import load_motion

    pac = load_motion("san-fernando-pacoima-dam-1971", vertical=True)
    assert pac.has_vertical and "DWN" in pac.metadata["processing"][-1]["sign"]
    assert pac.pga_vertical / G == pytest.approx(0.687, abs=2e-3)
    elc = load_motion("el-centro-1940", vertical=True)
    assert elc.npts == 5378 and not np.any(elc.ax[5372:])  # horizontals padded to the UP file
    with pytest.raises(ValueError, match="vertical"):
        load_motion("loma-prieta-sjte", vertical=True)
    # the scale factor scales all three; the intensity stays horizontal
    s = elc.scaled(2.0)
    assert s.pga == pytest.approx(2.0 * elc.pga) and s.pga_vertical == 2.0 * elc.pga_vertical


@pytest.mark.parametrize("model", ["3d", "2d"])
def test_summary_monitors_equal_the_history_monitors(model):
    """The summary-only path (rest stretches closed by tan α at each uplift) and the
    history path (every rest sample) find the same extremes."""
    ax, ay, _, dt = _pulses(amp=2.2)
    m = GroundMotion(ax, None if model == "2d" else ay, dt, "h")
    body = Cylinder(1.0, 0.2)
    a = ground_response(body, m, model=model, history=True)
    b = ground_response(body, m, model=model, history=False, stop_when_decided=False)
    assert a.uplifted
    assert b.mu_required_max == pytest.approx(a.mu_required_max, rel=1e-9)
    assert b.normal_force_min == pytest.approx(a.normal_force_min, rel=1e-12)
    assert np.nanmax(np.where(np.isfinite(a.mu_required), a.mu_required, np.nan)) == \
        pytest.approx(a.mu_required_max, rel=1e-12)


def test_damped_energy_balance_closes_with_the_vertical_work():
    """3D damped: E_d(end) − E_d(uplift) + dissipated = −∫ a_g·v_S dt, v_S with ẇ."""
    ax, ay, az, dt = _pulses(amp=2.6)
    body = Cylinder(1.0, 0.2)
    wn = 2000.0
    m = GroundMotion(ax, ay, dt, "v", az=az)
    r = ground_response(body, m, model="3d-damped", omega_n=wn, zeta=0.5)
    i = np.flatnonzero(r.t >= r.t_uplift)[0]
    assert r.theta_max > 0.2 * body.alpha and np.all(r.theta[i + 1:] > 0.0)  # one episode
    t, th, ph, w, thd, phd, wd = (x[i:] for x in (r.t, r.theta, r.phi, r.w, r.theta_dot,
                                                  r.phi_dot, r.w_dot))
    a, R = body.alpha, body.R
    e = 0.5 * (R * R * body.kappa_o * thd**2 + R * R * spin_inertia(th, a) * phd**2 + wd**2
               + 2.0 * R * np.sin(a - th) * thd * wd) \
        + G * R * np.cos(a - th) + 0.5 * wn**2 * w**2
    rho = R * (math.sin(a) - np.sin(a - th))
    rho_dot = R * np.cos(a - th) * thd
    vx = rho_dot * np.cos(ph) - rho * phd * np.sin(ph)
    vy = rho_dot * np.sin(ph) + rho * phd * np.cos(ph)
    vz = wd + R * np.sin(a - th) * thd
    gx, gy, gz = (np.interp(t, m.time, comp) for comp in (ax, ay, az))
    p_z = -gz * vz
    p = -(gx * vx + gy * vy) + p_z
    work = np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(t))
    work_z = np.sum(0.5 * (p_z[1:] + p_z[:-1]) * np.diff(t))
    gap = e[-1] - e[0] + r.extras["dissipated"] - work
    assert abs(gap) < 1e-5 * abs(work_z)
