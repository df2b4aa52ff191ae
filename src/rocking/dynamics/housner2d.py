"""2D Housner rocking of a block or of the planar section of a cylinder (signed tilt θ).

Equation of motion (``shared/spec/equations.md``), pivot on the base edge on the side sgn θ::

    θ̈ = −p² [sin(α sgn θ − θ) + cos(α sgn θ − θ) a_x/g]

At θ = 0 the pivot changes and the angular velocity is multiplied by the restitution
coefficient e (Housner's impact). The pivot side ``s`` is kept as a separate flag, so a step
that crosses θ = 0 is computed with the pre-impact equation, the impact time is found on the
step's Hermite interpolant and the state there by a genuine Runge–Kutta step of that length
("landing", see :mod:`rocking.dynamics._rk`). Impacts whose outgoing rate is below a Zeno threshold
(by default 1e-6 p α, an amplitude ~1e-6 α) end the rocking episode: the block is back at
rest (code 3) and the caller looks for the next uplift in the record.

Error control: relative, with absolute floors 1e-6 α on θ and 1e-6 p α on θ̇ (θ passes
through zero at every impact, so a purely relative control would stall there).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..constants import G
from ._rk import (
    EPS,
    error_norm,
    hermite_root,
    initial_step,
    n_stages,
    push_row,
    push_time,
    rk_step,
    set_forcing,
    step_factor,
)
from .bodies import Block, Cylinder

STATE = ("theta", "theta_dot")

OK, OVERTURNED, STOPPED, AT_REST, AT_PEAK = 0, 1, 2, 3, 4
UNDERFLOW, NEGATIVE_TILT, NONFINITE, TOO_MANY_STEPS = -1, -2, -3, -4

ZENO_RATE = 1e-6
"""Outgoing impact rate, as a fraction of p α, below which the body is back at rest [-]."""


def params(body: Block | Cylinder, side: float = 1.0, zeno: float = ZENO_RATE) -> np.ndarray:
    """Kernel parameters [p², sin α, cos α, g, side, e, Zeno rate threshold [rad/s]]."""
    return np.array([
        G / (body.kappa_o * body.R), math.sin(body.alpha), math.cos(body.alpha), G,
        1.0 if side >= 0 else -1.0, body.e, zeno * body.p * body.alpha,
    ])


def error_floor(body: Block | Cylinder) -> np.ndarray:
    """Absolute scales of (θ, θ̇) added to |y| in the error control."""
    return np.array([1e-6 * body.alpha, 1e-6 * body.p * body.alpha])


@njit(cache=True)
def rhs(tau, y, P, F, out):
    """Right-hand side on pivot side P[4] = ±1, ground acceleration F[0] + F[2] τ."""
    th = y[0]
    p2, s, c, g, side = P[0], P[1], P[2], P[3], P[4]
    a = F[0] + F[2] * tau
    st = math.sin(th)
    ct = math.cos(th)
    sam = side * s * ct - c * st  # sin(α s − θ)
    cam = c * ct + side * s * st  # cos(α s − θ)
    out[0] = y[1]
    out[1] = -p2 * (sam + cam * a / g)


@njit(cache=True)
def _land(tab, tau, y, f0, hs, P, F, Ks, ytmp, ys, fs):
    for i in range(y.size):
        Ks[0, i] = f0[i]
    rk_step(rhs, tab, tau, y, hs, P, F, Ks, ytmp, ys, fs)


@njit(cache=True)
def integrate(P, floor, ax, dt, k0, tau0, t_offset, y0, t_end, stop_level, rtol, tab, history,
              until_peak, max_steps):
    """Integrate the 2D model from record interval ``k0``, local time ``tau0``.

    Arguments as :func:`rocking.dynamics.cylinder3d.integrate` (one acceleration component ``ax``);
    ``P[4]`` is the initial pivot side (used when θ0 = 0), ``y0`` = (θ, θ̇). Events are the
    impacts, with the state just before the impact. ``stop_level`` applies to |θ|.
    """
    n = 2
    Pl = P.copy()
    y = np.empty(n)
    y[0] = y0[0]
    y[1] = y0[1]
    if y[0] != 0.0:
        Pl[4] = 1.0 if y[0] > 0.0 else -1.0
    e = Pl[5]
    zeno = Pl[6]
    K = np.empty((13, n))
    Ks = np.empty((13, n))
    ytmp = np.empty(n)
    y_new = np.empty(n)
    f_new = np.empty(n)
    ys = np.empty(n)
    fs = np.empty(n)
    F = np.empty(4)
    ns = n_stages(tab[0])

    cap = 256 if history else 1
    t_hist = np.empty(cap)
    y_hist = np.empty((cap, n))
    nh = 0
    ev_t = np.empty(16)
    ev_y = np.empty((16, n))
    ne = 0

    span = (t_end - t_offset) / dt
    k_last = min(int(math.floor(span)), ax.size - 1)
    tau_last = (t_end - t_offset) - k_last * dt
    if k_last >= ax.size - 1:
        k_last = ax.size - 2
        tau_last = dt
    if tau_last <= 4.0 * EPS * dt and k_last > 0:
        k_last -= 1
        tau_last = dt
    tau_last = min(tau_last, dt)

    k = k0
    tau = tau0
    set_forcing(F, ax, ax, k, dt)  # only F[0], F[2] (the x component) are used
    rhs(tau, y, Pl, F, K[0])
    h_min = 32.0 * EPS * dt
    h = initial_step(rhs, tab[0], tau, y, K[0], Pl, F, rtol, floor, dt, ytmp, fs)
    theta_max = abs(y[0])
    t_theta_max = t_offset + k * dt + tau
    if history:
        t_hist = push_time(t_hist, nh, t_theta_max)
        y_hist = push_row(y_hist, nh, y)
        nh += 1
    code = OK
    t_stop = math.nan
    n_steps = 0
    n_rej = 0
    lvl = math.pi / 2.0
    lvl_code = OVERTURNED
    if 0.0 < stop_level < lvl:
        lvl = stop_level
        lvl_code = STOPPED
    if k > k_last or (k == k_last and tau >= tau_last):
        k = k_last + 1
    while k <= k_last:
        tau_end = dt if k < k_last else tau_last
        if tau_end - tau <= 4.0 * EPS * dt:
            if k == k_last:
                break
            k += 1
            tau = 0.0
            set_forcing(F, ax, ax, k, dt)
            rhs(tau, y, Pl, F, K[0])
            continue
        if n_steps + n_rej >= max_steps:
            code = TOO_MANY_STEPS
            break
        h_try = h
        last = False
        if h_try >= tau_end - tau:
            h_try = tau_end - tau
            last = True
        rk_step(rhs, tab, tau, y, h_try, Pl, F, K, ytmp, y_new, f_new)
        err = error_norm(tab, K, h_try, y, y_new, rtol, floor)
        fail = 0
        if not (math.isfinite(err) and math.isfinite(y_new[0]) and math.isfinite(y_new[1])):
            fail = NONFINITE
            h = 0.2 * h_try
        elif err > 1.0:
            fail = UNDERFLOW
            h = h_try * step_factor(tab[0], err)
        if fail != 0:
            n_rej += 1
            if h < h_min:
                code = fail
                t_stop = t_offset + k * dt + tau
                break
            continue
        n_steps += 1
        t0 = t_offset + k * dt + tau
        side = Pl[4]
        # Impact: the tilt crosses zero within the step.
        if side * y_new[0] < 0.0:
            s_imp = hermite_root(y[0], K[0, 0], y_new[0], f_new[0], h_try, 0.0, 1.0)
            _land(tab, tau, y, K[0], s_imp * h_try, Pl, F, Ks, ytmp, ys, fs)
            # A peak between the step start and the impact.
            if side * y[1] > 0.0 and side * ys[1] < 0.0:
                sp = hermite_root(y[1], K[0, 1], y_new[1], f_new[1], h_try, 0.0, s_imp)
                _land(tab, tau, y, K[0], sp * h_try, Pl, F, Ks, ytmp, y_new, f_new)
                if abs(y_new[0]) > theta_max:
                    theta_max = abs(y_new[0])
                    t_theta_max = t0 + sp * h_try
                if until_peak:
                    for i in range(n):
                        y[i] = y_new[i]
                    t_stop = t0 + sp * h_try
                    code = AT_PEAK
                    break
            t_imp = t0 + s_imp * h_try
            ys[0] = 0.0
            ev_t = push_time(ev_t, ne, t_imp)
            ev_y = push_row(ev_y, ne, ys)
            ne += 1
            if history:
                t_hist = push_time(t_hist, nh, t_imp)
                y_hist = push_row(y_hist, nh, ys)
                nh += 1
            y[0] = 0.0
            y[1] = e * ys[1]
            Pl[4] = -side
            tau += s_imp * h_try
            if history:
                t_hist = push_time(t_hist, nh, t_imp)
                y_hist = push_row(y_hist, nh, y)
                nh += 1
            if abs(y[1]) < zeno:
                y[1] = 0.0
                code = AT_REST
                t_stop = t_imp
                break
            rhs(tau, y, Pl, F, K[0])
            continue
        # Threshold: stop_at or overturning at π/2.
        if side * y_new[0] > lvl or (lvl_code == OVERTURNED and side * y_new[0] >= lvl):
            sr = hermite_root(side * y[0], side * K[0, 0], side * y_new[0], side * f_new[0],
                              h_try, lvl, 1.0)
            _land(tab, tau, y, K[0], sr * h_try, Pl, F, Ks, ytmp, ys, fs)
            for _ in range(3):  # Newton on the landed tilt: the interpolant is only O(h⁴)
                if side * ys[1] <= 0.0 or abs(side * ys[0] - lvl) <= 4.0 * EPS * lvl:
                    break
                sr = min(max(sr + (lvl - side * ys[0]) / (side * ys[1] * h_try), 0.0), 1.0)
                _land(tab, tau, y, K[0], sr * h_try, Pl, F, Ks, ytmp, ys, fs)
            for i in range(n):
                y[i] = ys[i]
            tau += sr * h_try
            t_stop = t0 + sr * h_try
            if abs(y[0]) > theta_max:
                theta_max = abs(y[0])
                t_theta_max = t_stop
            code = lvl_code
            if history:
                t_hist = push_time(t_hist, nh, t_stop)
                y_hist = push_row(y_hist, nh, y)
                nh += 1
            break
        # Peak: |θ| stops growing.
        if side * y[1] > 0.0 and side * y_new[1] <= 0.0:
            sr = hermite_root(y[1], K[0, 1], y_new[1], f_new[1], h_try, 0.0, 1.0)
            _land(tab, tau, y, K[0], sr * h_try, Pl, F, Ks, ytmp, ys, fs)
            if abs(ys[0]) > theta_max:
                theta_max = abs(ys[0])
                t_theta_max = t0 + sr * h_try
            if until_peak:
                for i in range(n):
                    y[i] = ys[i]
                tau += sr * h_try
                t_stop = t0 + sr * h_try
                code = AT_PEAK
                if history:
                    t_hist = push_time(t_hist, nh, t_stop)
                    y_hist = push_row(y_hist, nh, y)
                    nh += 1
                break
        if abs(y_new[0]) > theta_max:
            theta_max = abs(y_new[0])
            t_theta_max = t0 + h_try
        for i in range(n):
            y[i] = y_new[i]
            K[0, i] = K[ns, i]
        tau = tau_end if last else tau + h_try
        if history:
            t_hist = push_time(t_hist, nh, t_offset + k * dt + tau)
            y_hist = push_row(y_hist, nh, y)
            nh += 1
        h_next = h_try * step_factor(tab[0], err)
        h = max(h_next, h) if last else h_next
        h = min(h, dt)
    if code == OK:
        t_stop = t_offset + k_last * dt + tau_last
    if not history:
        t_hist[0] = t_stop
        y_hist[0, 0] = y[0]
        y_hist[0, 1] = y[1]
        nh = 1
    return (code, t_hist[:nh].copy(), y_hist[:nh].copy(), n_steps, n_rej, theta_max,
            t_theta_max, ev_t[:ne].copy(), ev_y[:ne].copy(), t_stop)


def energy(body: Block | Cylinder, theta, theta_dot):
    """Energy per unit mass above the rest position, ½κoR²θ̇² + gR[cos(α − |θ|) − cos α].

    The potential difference is written cancellation-free as
    2 sin(|θ|/2) sin(α − |θ|/2) (cos(α − θ) − cos α for θ > 0).
    """
    th = np.abs(np.asarray(theta, dtype=float))
    pot = 2.0 * np.sin(0.5 * th) * np.sin(body.alpha - 0.5 * th)
    return 0.5 * body.kappa_o * body.R**2 * np.asarray(theta_dot) ** 2 + G * body.R * pot


def peak_from_energy(body: Block | Cylinder, e_rel: float) -> float:
    """Peak |θ| of a swing with energy ``e_rel`` above rest (see :func:`energy`).

    Solves gR[cos(α − θp) − cos α] = e_rel; ``inf`` when e_rel exceeds the barrier
    gR(1 − cos α) at θ = α (the block then falls to π/2).
    """
    barrier = G * body.R * 2.0 * math.sin(0.5 * body.alpha) ** 2
    if e_rel > barrier:
        return math.inf
    c = math.cos(body.alpha) + e_rel / (G * body.R)
    return body.alpha - math.acos(min(c, 1.0))


def free_peak(body: Block | Cylinder, theta: float, theta_dot: float) -> float:
    """The largest future |θ| of the unforced motion from a state, in closed form.

    The energy above rest is conserved between impacts and multiplied by e² at each impact.
    Moving away from θ = 0 (θ θ̇ > 0) the next peak has the present energy; moving towards
    it, the swing first passes the impact and the peak has e² times the kinetic energy at
    θ = 0 (which is the whole energy above rest). Later peaks only decrease. When |θ| > α the
    block must first climb back over θ = α to avoid falling.

    Returns
    -------
    float
        Peak |θ| [rad], or ``inf`` if the block overturns.
    """
    e_rel = float(energy(body, theta, theta_dot))
    barrier = G * body.R * 2.0 * math.sin(0.5 * body.alpha) ** 2
    away = theta * theta_dot > 0.0 or (theta == 0.0 and theta_dot != 0.0)
    if abs(theta) > body.alpha:
        if away or e_rel <= barrier:
            return math.inf
        return peak_from_energy(body, body.e**2 * e_rel)
    if away or theta_dot == 0.0:
        return max(peak_from_energy(body, e_rel), abs(theta))
    return max(peak_from_energy(body, body.e**2 * e_rel), abs(theta))
