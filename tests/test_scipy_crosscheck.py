"""The compiled kernels against an independent SciPy solution (DOP853, rtol 1e-12).

The reference integrates the equations of ``docs/equations.md`` ("3D undamped model",
"2D Housner model") as written there, in the state (θ, φ, θ̇, φ̇) (the kernel uses the spin
momentum μφ̇ instead of φ̇), with the ground acceleration interpolated by ``np.interp`` and
SciPy's own step control and event location. Windows are short (2–3 s after uplift), before
the response becomes chaotic.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.signal import butter, sosfiltfilt

from rocking import Block, Cylinder, GroundMotion, ground_response
from rocking.constants import G

N_CASES = 20
DT = 0.01


def _noise_motion(rng, n, two_components, pga):
    """Band-limited (0.5–5 Hz) Gaussian noise with a smooth envelope, scaled to ``pga``."""
    sos = butter(4, [0.5, 5.0], btype="band", fs=1.0 / DT, output="sos")
    t = np.arange(n) * DT
    env = np.minimum(1.0, t / 0.5)
    ax = sosfiltfilt(sos, rng.standard_normal(n)) * env
    ay = sosfiltfilt(sos, rng.standard_normal(n)) * env if two_components else None
    m = GroundMotion(ax, ay, DT)
    return m.scaled(pga / m.pga)


def _rhs3d(body, m):
    s, c = math.sin(body.alpha), math.cos(body.alpha)
    k1 = 4.0 / 3.0 * c * c - 1.25 * s * s
    p2 = G / (body.kappa_o * body.R)
    tt = m.time

    def f(t, y):
        th, ph, thd, phd = y
        ax = np.interp(t, tt, m.ax)
        ay = np.interp(t, tt, m.ay)
        omc = 2.0 * math.sin(th / 2) ** 2
        mu = k1 * math.sin(th) ** 2 + 3 * s * s * omc + 2 * s * c * math.sin(th) * omc
        mup = (k1 * math.sin(2 * th) + 3 * s * s * math.sin(th)
               + 2 * s * c * (math.cos(th) * omc + math.sin(th) ** 2))
        ar = ax * math.cos(ph) + ay * math.sin(ph)
        at = ax * math.sin(ph) - ay * math.cos(ph)
        thdd = -p2 * (math.sin(body.alpha - th) + math.cos(body.alpha - th) * ar / G) \
            + mup * phd**2 / (2 * body.kappa_o)
        phdd = ((s + math.sin(th - body.alpha)) * at / body.R - mup * thd * phd) / mu
        return [thd, phd, thdd, phdd]

    return f


@pytest.mark.parametrize("case", range(N_CASES))
def test_3d_matches_scipy(case):
    rng = np.random.default_rng(1000 + case)
    body = Cylinder(float(np.exp(rng.uniform(np.log(0.5), np.log(20.0)))),
                    float(rng.uniform(0.1, 0.4)))
    m = _noise_motion(rng, 400, True, rng.uniform(1.5, 3.0) * G * body.tan_alpha)
    res = ground_response(body, m, model="3d", rtol=1e-11, free_tail=False)
    assert res.uplifted and res.ok
    # Start the reference once the tilt is 1e-4 rad: from θ_eps with zero velocities SciPy's
    # first steps (no θ > 0 guard) can step to θ < 0 where the model is undefined.
    i0 = int(np.flatnonzero((res.t >= res.t_uplift) & (res.theta > 1e-4))[0])
    t0 = float(res.t[i0])
    end = min(t0 + 1.0, m.duration)
    keep = (res.t > t0) & (res.t <= end)
    t_k, th_k, ph_k = res.t[keep], res.theta[keep], res.phi[keep]
    y0 = [res.theta[i0], res.phi[i0], res.theta_dot[i0], res.phi_dot[i0]]
    ref = solve_ivp(_rhs3d(body, m), (t0, end), y0, method="DOP853", rtol=1e-12,
                    atol=[1e-22, 1e-12, 1e-14, 1e-12], dense_output=True)
    assert ref.success
    th_r, ph_r = ref.sol(t_k)[:2]
    scale = float(np.max(th_k))
    away = th_k > 0.05 * scale  # away from quasi-impacts, where φ turns within 1e-9 s
    assert np.max(np.abs(th_k - th_r)) < 1e-7 * scale + 1e-12
    assert np.max(np.abs(ph_k - ph_r)[away]) < 1e-5


def _scipy_2d(body, m, t0, side, t_end, zeno):
    """Housner model with impacts located by solve_ivp events; returns a dense evaluator."""
    p2 = G / (body.kappa_o * body.R)
    tt = m.time
    pieces = []
    y = np.array([0.0, 0.0])
    t = t0
    while t < t_end:
        def f(tq, yq, sd=side):
            a = np.interp(tq, tt, m.ax)
            th = yq[0]
            return [yq[1], -p2 * (math.sin(sd * body.alpha - th)
                                  + math.cos(sd * body.alpha - th) * a / G)]

        def hit(tq, yq, sd=side):
            return yq[0]
        hit.terminal = True
        hit.direction = -side
        # From θ = 0 the first event would be the start itself: offset it by one tiny step.
        sol = solve_ivp(f, (t, t_end), y, method="DOP853", rtol=1e-12, atol=1e-15,
                        events=hit, dense_output=True, max_step=DT, first_step=1e-9)
        pieces.append((t, sol.t[-1], sol.sol, side))
        if sol.status != 1:
            break
        t = float(sol.t_events[0][0])
        thd = float(sol.y_events[0][0][1]) * body.e
        side = -side
        y = np.array([0.0, thd])
        if abs(thd) < zeno:
            return pieces, t
    return pieces, t_end


@pytest.mark.parametrize("case", range(N_CASES))
def test_2d_matches_scipy(case):
    rng = np.random.default_rng(2000 + case)
    R = float(np.exp(rng.uniform(np.log(0.5), np.log(20.0))))
    ta = float(rng.uniform(0.1, 0.4))
    body = Block(R, ta) if case % 2 else Cylinder(R, ta)
    m = _noise_motion(rng, 400, False, rng.uniform(1.5, 3.0) * G * body.tan_alpha)
    res = ground_response(body, m, model="2d", rtol=1e-11, free_tail=False)
    assert res.uplifted and res.ok
    t_up = res.t_uplift
    i0 = np.flatnonzero(res.t >= t_up)[0]
    a_up = np.interp(t_up, m.time, m.ax)
    side = -math.copysign(1.0, a_up)
    end = min(t_up + 2.0, m.duration)
    pieces, t_stop = _scipy_2d(body, m, t_up, side, end, 1e-6 * body.p * body.alpha)
    # Compare until the impacts become tiny (the Zeno accumulation is ill-conditioned).
    imp_t, imp_v = res.quasi_impacts.t, np.abs(res.quasi_impacts.state[:, 1])
    small = imp_t[imp_v < 1e-3 * body.p * body.alpha]
    t_cmp = min(end, t_stop, small[0] if small.size else end)
    sel = (res.t > t_up) & (res.t < t_cmp)
    sel[:i0] = False
    worst = 0.0
    scale = float(np.max(np.abs(res.theta[sel])))
    for t0, t1, sol, _ in pieces:
        inside = sel & (res.t > t0) & (res.t < t1)
        if not inside.any():
            continue
        worst = max(worst, float(np.max(np.abs(res.theta[inside] - sol(res.t[inside])[0]))))
    assert worst < 1e-6 * scale
    # Same impact times up to there.
    ref_times = np.array([p[1] for p in pieces[:-1]])
    n = int(np.sum(imp_t < t_cmp))
    assert np.count_nonzero(sel) > 10
    np.testing.assert_allclose(imp_t[:n], ref_times[:n], rtol=0, atol=1e-7)
