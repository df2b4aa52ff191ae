"""Damped 3D cylinder model (3 DOF on a contact spring–dashpot) and its RODAS4 kernel.

Every check compares with something independent of the kernel: Housner's restitution
(Eq 31), the energy balance, the analytic pure-wobbling rate, SciPy's Radau on a right-hand
side written here from docs/equations.md (Cramer's rule on the 2×2 system), and SciPy's
DOP853 on the undamped equations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rocking import Status, free_vibration
from rocking.constants import G
from rocking.dynamics import codes, inertia, models
from rocking.dynamics import cylinder3d_damped as cd
from rocking.dynamics.bodies import Cylinder, mu, mu_prime
from rocking.dynamics.contact import Contact
from rocking.dynamics.models import THETA_REST_DAMPED

CYL = Cylinder(6.0, 0.2)  # the paper's Fig 4 cylinder
GRID = [(wn, z) for wn in (200.0, 2000.0) for z in (0.05, 0.5, 5.0, 50.0)]
NO_STOP = -1.0  # no tilt limit (overturning at π/2 still ends a run)


def _run(y0, t_end, omega_n, zeta, rtol, ax=None, ay=None, dt=None, body=CYL, stop=NO_STOP,
         history=True, max_steps=5_000_000, t0=0.0):
    """The damped kernel through the driver from state ``y0`` at ``t0`` (free vibration when
    no ground motion is given). Returns the kernel's
    :class:`~rocking.dynamics.models.KernelResult`."""
    prep = models.prepare(models.MODELS["3d-damped"], body, rtol,
                          models.rest_criterion(body, THETA_REST_DAMPED),
                          contact=Contact(omega_n, zeta), max_steps=max_steps)
    if ax is None:
        dt = 0.1 / body.p
        ax = ay = np.zeros(int(math.ceil(t_end / dt)) + 2)
    k0 = int(t0 // dt)
    return models.run(prep, ax, ay, dt, k0, t0 - k0 * dt, 0.0, np.asarray(y0, dtype=float),
                      t_end, stop, history=history)


def _rhs(y, P, ax=0.0, ay=0.0):
    f = np.empty(7)
    cd.rhs(0.0, np.append(y[:6], 0.0), P, np.array([ax, ay, 0.0, 0.0, 0.0, 0.0]), f)
    return f


# ------------------------------------------------------------------------------------------
# Reference right-hand sides written independently from equations.md
# ------------------------------------------------------------------------------------------
def _ground_fn(ax, ay, dt):
    def ground(t):
        k = min(int(t / dt), len(ax) - 2)
        s = (t - k * dt) / dt
        return ax[k] + s * (ax[k + 1] - ax[k]), ay[k] + s * (ay[k + 1] - ay[k])

    return ground


def _mu_spec(th, a):
    """μ(θ) and μ'(θ) exactly as printed in equations.md (fine for θ > 1e-4)."""
    s, c = math.sin(a), math.cos(a)
    k = 4 / 3 * c * c - 5 / 4 * s * s
    st, ct = math.sin(th), math.cos(th)
    m = k * st * st + 3 * s * s * (1 - ct) + 2 * s * c * st * (1 - ct)
    mp = k * math.sin(2 * th) + 3 * s * s * st + 2 * s * c * (2 * st * st + ct - 1)
    return m, mp


def _damped_rhs(body, omega_n, zeta, ground):
    """equations.md's damped pair, the 2×2 system solved by Cramer's rule (scalar, fast)."""
    R, a, ko = body.R, body.alpha, body.kappa_o

    def rhs(t, y):
        th, ph, w, thd, phd, wd = y
        gx, gy = ground(t)
        ar = gx * math.cos(ph) + gy * math.sin(ph)
        at = gx * math.sin(ph) - gy * math.cos(ph)
        S, C = math.sin(a - th), math.cos(a - th)
        m, mp = _mu_spec(th, a)
        b1 = -(G / R) * S - C * ar / R + mp * phd**2 / 2
        b2 = R * C * thd**2 - 2 * zeta * omega_n * wd - omega_n**2 * w
        det = ko - S * S  # mass matrix [[κo, S/R], [R S, 1]]
        thdd = (b1 - S / R * b2) / det
        wdd = (ko * b2 - R * S * b1) / det
        phdd = ((math.sin(a) + math.sin(th - a)) * at / R - mp * thd * phd) / m
        return [thd, phd, wd, thdd, phdd, wdd]

    return rhs


def _undamped_rhs(body):
    R, a, ko = body.R, body.alpha, body.kappa_o
    p2 = G / (ko * R)

    def rhs(t, y):
        th, ph, thd, phd = y
        m, mp = _mu_spec(th, a)
        thdd = -p2 * math.sin(a - th) + mp * phd**2 / (2 * ko)
        phdd = -mp * thd * phd / m
        return [thd, phd, thdd, phdd]

    return rhs


def _theta_dot_before(t, theta_dot, ev_t):
    """Most negative θ̇ on the approach to each quasi-impact (θ̇ just before it)."""
    out, prev = [], -np.inf
    for te in ev_t:
        sel = (t > prev) & (t <= te)
        out.append(theta_dot[sel].min())
        prev = te
    return np.array(out)


# ------------------------------------------------------------------------------------------
# Parameters and building blocks
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("omega_n", "zeta", "field"), [
    (2000.0, -0.1, "zeta"), (0.0, 5.0, "omega_n"), (-200.0, 5.0, "omega_n"),
    (float("nan"), 5.0, "omega_n"), (2000.0, float("inf"), "zeta"), ("abc", 5.0, "omega_n"),
])
def test_a_contact_rejects_bad_values(omega_n, zeta, field):
    with pytest.raises(ValueError, match=field) as info:
        Contact(omega_n, zeta)
    bad = omega_n if field == "omega_n" else zeta
    assert repr(bad) in str(info.value)


def test_a_contact_accepts_zero_damping():
    c = Contact(2000, 0)
    assert (c.omega_n, c.zeta) == (2000.0, 0.0) and isinstance(c.omega_n, float)
    assert Contact.of() == Contact() == models.MODELS["3d-damped"].contact


def test_spin_inertia_matches_printed_form_and_asymptotes():
    """The one μ(θ) (compiled scalar and array forms) against the printed formula where the
    latter is exact, its small-θ asymptote κt θ² down to quasi-impact tilts, and μ', μ''
    against central differences."""
    th = np.logspace(-11, math.log10(1.5), 40)
    s, c = math.sin(CYL.alpha), math.cos(CYL.alpha)
    scalar = np.array([inertia.mu(float(x), s, c) for x in th])
    np.testing.assert_array_equal(scalar, mu(th, CYL.alpha))
    big = th > 1e-2
    printed = np.array([_mu_spec(x, CYL.alpha) for x in th[big]])
    np.testing.assert_allclose(mu(th[big], CYL.alpha), printed[:, 0], rtol=1e-12)
    np.testing.assert_allclose(mu_prime(th[big], CYL.alpha), printed[:, 1], rtol=1e-12)
    thm = th[th > 1e-3]
    hh = 1e-6 * thm
    fd = (mu_prime(thm + hh, CYL.alpha) - mu_prime(thm - hh, CYL.alpha)) / (2 * hh)
    np.testing.assert_allclose(inertia.mu_second(thm, s, c), fd, rtol=1e-7)
    # small-θ asymptotes μ ≈ κt θ², μ' ≈ 2 κt θ
    assert scalar[0] / th[0] ** 2 == pytest.approx(CYL.kappa_t, rel=1e-9)
    assert mu_prime(th[0], CYL.alpha) / th[0] == pytest.approx(2 * CYL.kappa_t, rel=1e-9)


def test_right_hand_side_matches_reference_equations():
    rng = np.random.default_rng(3)
    P = cd.params(CYL, 2000.0, 5.0)
    ref = _damped_rhs(CYL, 2000.0, 5.0, lambda t: (1.3, -0.7))
    for _ in range(10):
        y = np.array([rng.uniform(0.01, 1.2), rng.uniform(-4, 4), rng.normal(0, 1e-5),
                      rng.normal(0, 0.3), rng.normal(0, 3), rng.normal(0, 1e-2), 0.0])
        f = _rhs(y, P, 1.3, -0.7)
        np.testing.assert_allclose(f[:6], ref(0.0, y[:6]), rtol=1e-11, atol=1e-12)
        assert f[6] == pytest.approx(2 * 5.0 * 2000.0 * y[5] ** 2, rel=1e-14)


def test_analytic_jacobian_matches_finite_differences():
    rng = np.random.default_rng(7)
    P = cd.params(CYL, 2000.0, 0.5)
    LA = np.empty(cd.LA_SHAPE)
    axv, ayv, dax, day = 0.9, -1.4, 25.0, -40.0
    for _ in range(10):
        y = np.array([rng.uniform(1e-3, 1.0), rng.uniform(-4, 4), rng.normal(0, 1e-5),
                      rng.normal(0, 0.3), rng.normal(0, 5), rng.normal(0, 1e-2), 0.0])
        f = _rhs(y, P, axv, ayv)
        cd.jacobian(0.0, y, P, np.array([axv, ayv, dax, day, 0.0, 0.0]), f, LA)
        jac = np.hstack([LA[0:3], LA[3:6]])
        for j in range(6):
            h = 1e-6 * max(abs(y[j]), 1e-6 if j in (2, 5) else 1e-2)
            yp, ym = y.copy(), y.copy()
            yp[j] += h
            ym[j] -= h
            fd = (_rhs(yp, P, axv, ayv)[3:6] - _rhs(ym, P, axv, ayv)[3:6]) / (2 * h)
            np.testing.assert_allclose(jac[:, j], fd, rtol=1e-6,
                                       atol=1e-7 * np.abs(fd).max() + 1e-9)
        # time derivative through the ground-acceleration slope
        h = 1e-6
        fp = _rhs(y, P, axv + dax * h, ayv + day * h)
        fm = _rhs(y, P, axv - dax * h, ayv - day * h)
        np.testing.assert_allclose(LA[8], (fp[3:6] - fm[3:6]) / (2 * h), rtol=1e-6,
                                   atol=1e-9)


# ------------------------------------------------------------------------------------------
# Physics
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("omega_n", "zeta"), GRID)
def test_apparent_restitution_is_housners(omega_n, zeta):
    """Paper Eq (32): θ̇ before the 6th quasi-impact over the 1st, to the power 1/5, is Eq (31).

    Measured: within 1e-4 of e = 0.942169 for all eight (ωn, ζ) of the paper.
    """
    r = _run([0.1, 0.0, 0.0, 0.0, 1e-8, 0.0], 11.0, omega_n, zeta, 1e-8)
    assert r.code == codes.OK
    t, y, ev_t, ev_y = r.t, r.y, r.ev_t, r.ev_y
    assert len(ev_t) == 6
    pre = _theta_dot_before(t, y[:, 3], ev_t)
    assert pre[0] == pytest.approx(-0.19, abs=2e-3)  # the paper's 0.19 rad/s
    ratio = (pre[5] / pre[0]) ** 0.2
    assert CYL.e == pytest.approx(0.942169, abs=1e-6)
    assert ratio == pytest.approx(CYL.e, abs=1e-3)
    # quasi-impacts: tilt minima at 1e-9 … 1e-11 rad scale with θ̇ = 0 there
    assert np.all(ev_y[:, 0] < 1e-8) and np.all(ev_y[:, 0] > 0.0)
    assert np.all(np.abs(ev_y[:, 3]) < 1e-6 * np.abs(pre))


@pytest.mark.parametrize(("omega_n", "zeta"), [(2000.0, 0.5), (200.0, 5.0), (2000.0, 50.0)])
def test_energy_balance_closes_and_tightens_with_rtol(omega_n, zeta):
    y0 = np.array([0.1, 0.0, 0.0, 0.0, 1e-8, 0.0])
    e0 = cd.energy(CYL, y0, omega_n)
    residual = []
    for rtol in (1e-6, 1e-10):
        r = _run(y0, 4.0, omega_n, zeta, rtol, history=False)
        assert r.code == codes.OK and len(r.ev_t) == 2
        dissipated, y_end = r.y_end[6], r.y_end[:6]
        # two quasi-impacts dissipate ≈ (1 − e⁴) of the kinetic energy before the first
        kin = 0.5 * CYL.R**2 * CYL.kappa_o * 0.18994**2
        assert dissipated == pytest.approx(kin * (1 - CYL.e**2) * (1 + CYL.e**2), rel=0.02)
        residual.append(abs(cd.energy(CYL, y_end, omega_n) + dissipated - e0) / dissipated)
    assert residual[1] < 1e-7
    assert residual[1] < residual[0] / 20


def test_pure_wobbling_keeps_tilt_and_spring_at_rest():
    """Paper §3 / Fig 4c–d: constant tilt, contact force = weight, no damping at all."""
    theta0 = 0.5 * CYL.alpha
    rate = float(CYL.wobbling_rate(theta0))
    period = 2 * math.pi / rate
    r = _run([theta0, 0.0, 0.0, 0.0, rate, 0.0], 3 * period, 2000.0, 5.0, 1e-10)
    assert r.code == codes.OK
    y = r.y
    assert np.max(np.abs(y[:, 0] - theta0)) < 1e-8 * theta0
    assert np.max(np.abs(y[:, 4] - rate)) < 1e-8 * rate
    assert r.y_end[1] == pytest.approx(3 * 2 * math.pi, rel=1e-8)  # three turns
    np.testing.assert_allclose(cd.contact_force(y, 2000.0, 5.0), G, rtol=1e-8)
    assert r.y_end[6] < 1e-15 * cd.energy(CYL, y[0], 2000.0)  # nothing dissipated


def test_damped_tends_to_undamped_as_the_spring_stiffens():
    """Wobbling-dominated motion (no quasi-impact): the spring's effect falls like 1/ωn²."""
    theta0 = 0.1
    phd0 = 0.6 * float(CYL.wobbling_rate(theta0))
    T = 3.0
    und = solve_ivp(_undamped_rhs(CYL), (0, T), [theta0, 0, 0, phd0], method="DOP853",
                    rtol=1e-12, atol=1e-14)
    th_und = und.y[:, -1]
    assert und.y[0].min() > 1e-3  # no quasi-impact in this motion
    diffs = []
    for wn in (200.0, 2000.0):
        r = _run([theta0, 0.0, 0.0, 0.0, phd0, 0.0], T, wn, 5.0, 1e-11, history=False)
        assert r.code == codes.OK and len(r.ev_t) >= 1
        y = r.y_end
        diffs.append(np.abs(np.array([y[0], y[1], y[3], y[4]]) - th_und))
    assert np.all(diffs[1] < 1e-6 * np.array([theta0, 1.0, 1.0, phd0]))
    # the rolling angle accumulates the difference steadily (θ's depends on the phase)
    ratio = diffs[1][1] / diffs[0][1]
    assert 0.5e-2 < ratio < 2e-2  # ∝ 1/ωn²: (200/2000)² = 1e-2


def test_free_overturning_time_matches_undamped():
    theta0 = CYL.alpha + 0.02  # beyond the tipping point: falls over without quasi-impact
    r = _run([theta0, 0.0, 0.0, 0.0, 1e-8, 0.0], 10.0, 2000.0, 5.0, 1e-10)
    assert r.code == codes.OVERTURNED
    assert r.theta_max == math.pi / 2 and r.y[-1, 0] == pytest.approx(math.pi / 2, abs=1e-12)

    def over(t, y):
        return y[0] - math.pi / 2

    over.terminal = True
    und = solve_ivp(_undamped_rhs(CYL), (0, 10), [theta0, 0, 0, 1e-8], method="DOP853",
                    rtol=1e-12, atol=1e-14, events=over)
    assert r.t_stop == pytest.approx(und.t_events[0][0], rel=1e-5)


def test_stop_at_tilt_limit():
    r = _run([0.1, 0.0, 0.0, 0.1, 0.3, 0.0], 10.0, 2000.0, 5.0, 1e-9, stop=0.12)
    assert r.code == codes.STOPPED
    assert r.y[-1, 0] == pytest.approx(0.12, rel=1e-9)
    assert r.t[-1] == r.t_stop and r.theta_max == pytest.approx(0.12, rel=1e-9)


def test_quasi_rocking_decays_to_rest():
    """Damped quasi-rocking loses e² of its energy per quasi-impact and comes back to rest.

    The e² law holds while the quasi-impact, spring and rocking time scales stay apart; at
    tilts of ~1e-5 rad the rocking half-cycle nears the spring's and the decay slows.
    """
    omega_n, zeta = 2000.0, 0.5
    r = _run([0.05, 0.0, 0.0, 0.0, 1e-8, 0.0], 200.0, omega_n, zeta, 1e-8, history=False)
    assert r.code == codes.AT_REST
    t_rest, ev_t, ev_y = r.t_stop, r.ev_t, r.ev_y
    assert 10.0 < t_rest < 200.0 and ev_t[-1] == t_rest
    P = cd.params(CYL, omega_n, zeta)
    energy = np.array([cd.rocking_energy(np.append(y, 0.0), P) for y in ev_y])
    k = np.arange(energy.size)
    np.testing.assert_allclose(energy[:41] / energy[0], CYL.e ** (2 * k[:41]), rtol=2e-3)
    e_rest = G * CYL.R * (math.cos(CYL.alpha - THETA_REST_DAMPED) - math.cos(CYL.alpha))
    assert energy[-1] < e_rest < energy[-2]
    # impacts from θ0 = 0.05 down to the rest threshold at e² per impact: 89.7
    e_start = G * CYL.R * (math.cos(CYL.alpha - 0.05) - math.cos(CYL.alpha))
    n_expected = math.log(e_rest / e_start) / (2 * math.log(CYL.e))
    assert abs(energy.size - n_expected) < 5


# ------------------------------------------------------------------------------------------
# Against SciPy Radau with ground motion
# ------------------------------------------------------------------------------------------
def _random_case(rng):
    body = Cylinder(rng.uniform(1.0, 10.0), rng.uniform(0.1, 0.4))
    omega_n = float(rng.choice([200.0, 2000.0]))
    zeta = float(rng.choice([0.05, 0.5, 5.0, 50.0]))
    theta0 = rng.uniform(0.2, 0.8) * body.alpha
    phd0 = rng.choice([-1, 1]) * rng.uniform(0.6, 1.0) * float(body.wobbling_rate(theta0))
    amp = rng.uniform(0.3, 1.0) * G * body.tan_alpha
    ax, ay = amp * rng.standard_normal(4), amp * rng.standard_normal(4)
    y0 = np.array([theta0, rng.uniform(0, 2 * np.pi), 0.0,
                   rng.uniform(-0.5, 0.5) * body.p * theta0, phd0, 0.0])
    return body, omega_n, zeta, ax, ay, y0


def test_agrees_with_scipy_radau_on_random_ground_motions():
    rng = np.random.default_rng(2024)
    dt = 0.04
    worst = np.zeros(6)
    for _ in range(20):
        body, omega_n, zeta, ax, ay, y0 = _random_case(rng)
        rhs = _damped_rhs(body, omega_n, zeta, _ground_fn(ax, ay, dt))
        y = y0.copy()
        for k in range(len(ax) - 1):  # one solve per record interval: no kink inside
            sol = solve_ivp(rhs, (k * dt, (k + 1) * dt), y, method="Radau", rtol=1e-10,
                            atol=1e-14)
            y = sol.y[:, -1]
        r = _run(y0, dt * (len(ax) - 1), omega_n, zeta, 1e-10, ax=ax, ay=ay, dt=dt,
                 body=body, history=False, max_steps=1_000_000)
        assert r.code == codes.OK
        scale = np.array([abs(y[0]), 1.0, G / omega_n**2, body.p * y0[0],
                          abs(y[4]) + body.p, G / omega_n])
        worst = np.maximum(worst, np.abs(r.y_end[:6] - y) / scale)
    assert np.all(worst < 2e-8), worst


# ------------------------------------------------------------------------------------------
# Extremes and failures
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("omega_n", [200.0, 2000.0, 2e4])
@pytest.mark.parametrize("zeta", [0.05, 50.0])
def test_extreme_contact_parameters_give_finite_results(omega_n, zeta):
    dt = 0.01
    t = np.arange(301) * dt
    env = np.sin(np.pi * t / t[-1]) ** 2
    amp = 2.0 * G * CYL.tan_alpha  # a bidirectional 1.5 Hz shake at twice the uplift level
    ax = amp * env * np.sin(2 * np.pi * 1.5 * t)
    ay = 0.7 * amp * env * np.cos(2 * np.pi * 1.1 * t)
    k = int(np.argmax(np.hypot(ax, ay) > G * CYL.tan_alpha))
    y0 = [1e-7, math.atan2(-ay[k], -ax[k]), 0.0, 0.0, 0.0, 0.0]
    r = _run(y0, 4.0, omega_n, zeta, 1e-6, ax=ax, ay=ay, dt=dt, t0=k * dt)
    assert r.code in (codes.OK, codes.AT_REST)
    assert np.all(np.isfinite(r.y)) and np.isfinite(r.theta_max) and np.all(np.isfinite(r.y_end))
    assert 1e-2 < r.theta_max < CYL.alpha  # rocked, did not overturn
    assert r.t[0] == k * dt and r.t[-1] == r.t_stop


def test_failure_codes():
    """Bad states fail with a failure code (the public API rejects them before any work),
    and the step budget is honoured."""
    assert _run([0.0, 0, 0, 0, 1e-8, 0], 1.0, 2000.0, 5.0, 1e-8, max_steps=1000).code < 0
    assert _run([0.1, np.nan, 0, 0, 0, 0], 1.0, 2000.0, 5.0, 1e-8)[0] == codes.NONFINITE
    r = _run([0.1, 0, 0, 0, 1e-8, 0], 5.0, 2000.0, 5.0, 1e-8, max_steps=50)
    assert r.code == codes.TOO_MANY_STEPS and r.n_steps + r.n_rejected == 50 and r.t_stop < 5.0


def test_free_vibration_response_fields():
    """The public free vibration of the damped model: fields, contact force, bookkeeping."""
    res = free_vibration(CYL, 0.1, 1e-8, duration=2.0, model="3d-damped", omega_n=2000.0,
                         zeta=50.0)
    assert res.model == "3d-damped" and res.ok and len(res.quasi_impacts) == 1
    assert res.state_names == ("theta", "phi", "w", "theta_dot", "phi_dot", "w_dot")
    assert res.contact_force[0] == pytest.approx(G, rel=1e-12)  # at rest on the spring
    # the quasi-impact shows as a spike of the contact force well above the weight
    assert res.contact_force.max() > 5 * G
    assert res.extras["n_tension"] == 0 and res.extras["dissipated"] > 0
    assert res.status is Status.OK
    with pytest.raises(ValueError, match="zeta"):
        free_vibration(CYL, 0.1, 1e-8, duration=2.0, model="3d-damped", zeta=-1.0)
    with pytest.raises(ValueError, match="theta0"):
        free_vibration(CYL, 2.0, 1e-8, duration=2.0, model="3d-damped")
