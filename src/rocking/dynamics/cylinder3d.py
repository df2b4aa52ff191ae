"""Undamped 3D bounded rocking-and-wobbling cylinder (2 DOF: tilt θ > 0, rolling angle φ).

Equations of motion (``shared/spec/equations.md``, corrected Eqs 21–22)::

    θ̈ = −p² [sin(α − θ) + cos(α − θ) a_r/g] + μ'(θ) φ̇²/(2 κo)
    d/dt [μ(θ) φ̇] = (sin α + sin(θ − α)) a_t / R

The second line is Eq (22) multiplied by μ(θ): μφ̈ + μ'θ̇φ̇ is the derivative of the spin
momentum L = μ(θ)φ̇. The kernel integrates the state (θ, φ, θ̇, L) instead of (θ, φ, θ̇, φ̇)
because L is smooth where φ̇ is not: in a quasi-impact θ drops to 1e-9 … 1e-11 rad and
φ̇ = L/μ(θ) ≈ L/(κt θ²) spikes to 1e8 … 1e9 rad/s, while L only changes through the ground
acceleration (and not at all in free vibration, so the spin momentum is conserved to
round-off). Inputs and outputs use (θ, φ, θ̇, φ̇) as the kernel contract of ``docs/design.md``
says. All differences of nearly equal numbers are written cancellation-free:
1 − cos θ = 2 sin²(θ/2) and sin α + sin(θ − α) = 2 cos(α − θ/2) sin(θ/2).

Error control is relative on θ (no absolute floor: a tolerance like 1e-6 rad on θ would be
meaningless at θ = 1e-11); θ ≤ 0 at a step end is a rejected step, and a failure once the
step cannot shrink further (code −2). The spin momentum is given a small absolute floor
(1e-6 of the momentum of wobbling at θ ~ α) so that steps do not collapse where L changes
sign under ground motion.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy.optimize import brentq

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
from .bodies import Cylinder, mu

STATE = ("theta", "phi", "theta_dot", "phi_dot")

# Return codes of the kernels (docs/design.md); 4 is internal to the free tail.
OK, OVERTURNED, STOPPED, AT_REST, AT_PEAK = 0, 1, 2, 3, 4
UNDERFLOW, NEGATIVE_TILT, NONFINITE, TOO_MANY_STEPS = -1, -2, -3, -4


def params(body: Cylinder) -> np.ndarray:
    """Kernel parameters [p², sin α, cos α, κo, 4/3 c² − 5/4 s², R, g]."""
    s, c = math.sin(body.alpha), math.cos(body.alpha)
    return np.array(
        [G / (body.kappa_o * body.R), s, c, body.kappa_o, 4.0 / 3.0 * c * c - 1.25 * s * s,
         body.R, G]
    )


def error_floor(body: Cylinder) -> np.ndarray:
    """Absolute scales of (θ, φ, θ̇, L) added to |y| in the error control.

    θ: 0 (purely relative); φ: 1 rad; θ̇: p α (the rate of a rocking cycle of amplitude α);
    L: 1e-6 κt α² p.
    """
    p = body.p
    return np.array([0.0, 1.0, p * body.alpha, 1e-6 * body.kappa_t * body.alpha**2 * p])


@njit(cache=True)
def _mu(th, P):
    s, c, k1 = P[1], P[2], P[4]
    st = math.sin(th)
    sh = math.sin(0.5 * th)
    omc = 2.0 * sh * sh
    return k1 * st * st + 3.0 * s * s * omc + 2.0 * s * c * st * omc


@njit(cache=True)
def rhs(tau, y, P, F, out):
    """Right-hand side for the state (θ, φ, θ̇, L), ground acceleration F[0:2] + F[2:4] τ."""
    th, ph, thd, L = y[0], y[1], y[2], y[3]
    p2, s, c, kap, k1, R, g = P[0], P[1], P[2], P[3], P[4], P[5], P[6]
    axg = F[0] + F[2] * tau
    ayg = F[1] + F[3] * tau
    st = math.sin(th)
    ct = math.cos(th)
    sh = math.sin(0.5 * th)
    ch = math.cos(0.5 * th)
    omc = 2.0 * sh * sh
    mu_ = k1 * st * st + 3.0 * s * s * omc + 2.0 * s * c * st * omc
    mup = 2.0 * k1 * st * ct + 3.0 * s * s * st + 2.0 * s * c * (ct * omc + st * st)
    phd = L / mu_
    cph = math.cos(ph)
    sph = math.sin(ph)
    a_r = axg * cph + ayg * sph
    a_t = axg * sph - ayg * cph
    sam = s * ct - c * st  # sin(α − θ)
    cam = c * ct + s * st  # cos(α − θ)
    out[0] = thd
    out[1] = phd
    out[2] = -p2 * (sam + cam * a_r / g) + mup * phd * phd / (2.0 * kap)
    # sin α + sin(θ − α) = 2 cos(α − θ/2) sin(θ/2)
    out[3] = 2.0 * (c * ch + s * sh) * sh * a_t / R


@njit(cache=True)
def _output(y, P, out):
    out[0] = y[0]
    out[1] = y[1]
    out[2] = y[2]
    out[3] = y[3] / _mu(y[0], P)


@njit(cache=True)
def _land(tab, tau, y, f0, hs, P, F, Ks, ytmp, ys, fs):
    """State at tau + hs by one Runge–Kutta step from (tau, y) (event landing)."""
    for i in range(y.size):
        Ks[0, i] = f0[i]
    rk_step(rhs, tab, tau, y, hs, P, F, Ks, ytmp, ys, fs)


@njit(cache=True)
def integrate(P, floor, ax, ay, dt, k0, tau0, t_offset, y0, t_end, stop_level, rtol, tab,
              history, until_peak, max_steps):
    """Integrate the undamped 3D model from record interval ``k0``, local time ``tau0``.

    Parameters
    ----------
    P, floor : ndarray
        :func:`params` and :func:`error_floor` of the body.
    ax, ay : ndarray
        Ground acceleration samples [m/s²] (already scaled), sample j at t_offset + j dt.
    dt : float
        Sample interval [s]; no step is longer, and every step ends on or before a sample.
    k0, tau0 : int, float
        Start interval and time inside it [s].
    t_offset : float
        Absolute time of sample 0 [s].
    y0 : ndarray
        Start state (θ, φ, θ̇, φ̇).
    t_end : float
        Absolute end time [s] (clamped to the last sample).
    stop_level : float
        End with code 2 once θ > stop_level [rad]; ≤ 0 for none. θ ≥ π/2 ends with code 1.
    rtol : float
        Relative tolerance.
    tab : tuple
        Runge–Kutta tableau, :func:`rocking.dynamics._rk.tableau`.
    history : bool
        Keep every accepted step; otherwise only the final state is returned.
    until_peak : bool
        End at the first tilt maximum (code 4; used for the free tail).
    max_steps : int
        Budget of accepted plus rejected steps (code −4 when exhausted).

    Returns
    -------
    tuple
        ``(code, t_hist, y_hist, n_steps, n_rejected, theta_max, t_theta_max, ev_t, ev_y,
        t_stop)`` as in ``docs/design.md``; events are tilt minima (quasi-impacts).
    """
    n = 4
    y = np.empty(n)
    y[0] = y0[0]
    y[1] = y0[1]
    y[2] = y0[2]
    y[3] = _mu(y0[0], P) * y0[3]
    K = np.empty((13, n))
    Ks = np.empty((13, n))
    ytmp = np.empty(n)
    y_new = np.empty(n)
    f_new = np.empty(n)
    ys = np.empty(n)
    fs = np.empty(n)
    row = np.empty(n)
    F = np.empty(4)
    ns = n_stages(tab[0])

    cap = 256 if history else 1
    t_hist = np.empty(cap)
    y_hist = np.empty((cap, n))
    nh = 0
    ev_t = np.empty(16)
    ev_y = np.empty((16, n))
    ne = 0

    # Last interval and the local end time in it.
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
    set_forcing(F, ax, ay, k, dt)
    rhs(tau, y, P, F, K[0])
    h_min = 32.0 * EPS * dt
    h = initial_step(rhs, tab[0], tau, y, K[0], P, F, rtol, floor, dt, ytmp, fs)
    theta_max = y[0]
    t_theta_max = t_offset + k * dt + tau
    if history:
        _output(y, P, row)
        t_hist = push_time(t_hist, nh, t_theta_max)
        y_hist = push_row(y_hist, nh, row)
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
        k = k_last + 1  # nothing to integrate
    while k <= k_last:
        tau_end = dt if k < k_last else tau_last
        if tau_end - tau <= 4.0 * EPS * dt:
            if k == k_last:
                break
            k += 1
            tau = 0.0
            set_forcing(F, ax, ay, k, dt)
            rhs(tau, y, P, F, K[0])
            continue
        if n_steps + n_rej >= max_steps:
            code = TOO_MANY_STEPS
            break
        h_try = h
        last = False
        if h_try >= tau_end - tau:
            h_try = tau_end - tau
            last = True
        rk_step(rhs, tab, tau, y, h_try, P, F, K, ytmp, y_new, f_new)
        err = error_norm(tab, K, h_try, y, y_new, rtol, floor)
        fail = 0
        if not (math.isfinite(err) and math.isfinite(y_new[0]) and math.isfinite(y_new[1])
                and math.isfinite(y_new[2]) and math.isfinite(y_new[3])):
            fail = NONFINITE
            h = 0.2 * h_try
        elif y_new[0] <= 0.0:
            fail = NEGATIVE_TILT
            h = 0.25 * h_try
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
        # Threshold: stop_at or overturning at π/2.
        if y_new[0] > lvl or (lvl_code == OVERTURNED and y_new[0] >= lvl):
            sr = hermite_root(y[0], K[0, 0], y_new[0], f_new[0], h_try, lvl, 1.0)
            _land(tab, tau, y, K[0], sr * h_try, P, F, Ks, ytmp, ys, fs)
            for _ in range(3):  # Newton on the landed tilt: the interpolant is only O(h⁴)
                if ys[2] <= 0.0 or abs(ys[0] - lvl) <= 4.0 * EPS * lvl:
                    break
                sr = min(max(sr + (lvl - ys[0]) / (ys[2] * h_try), 0.0), 1.0)
                _land(tab, tau, y, K[0], sr * h_try, P, F, Ks, ytmp, ys, fs)
            for i in range(n):
                y[i] = ys[i]
            tau += sr * h_try
            t_stop = t0 + sr * h_try
            if y[0] > theta_max:
                theta_max = y[0]
                t_theta_max = t_stop
            code = lvl_code
            if history:
                _output(y, P, row)
                t_hist = push_time(t_hist, nh, t_stop)
                y_hist = push_row(y_hist, nh, row)
                nh += 1
            break
        # Tilt minimum (quasi-impact): θ̇ from − to +.
        if y[2] < 0.0 and y_new[2] >= 0.0:
            sr = hermite_root(y[2], K[0, 2], y_new[2], f_new[2], h_try, 0.0, 1.0)
            _land(tab, tau, y, K[0], sr * h_try, P, F, Ks, ytmp, ys, fs)
            _output(ys, P, row)
            ev_t = push_time(ev_t, ne, t0 + sr * h_try)
            ev_y = push_row(ev_y, ne, row)
            ne += 1
        # Tilt maximum: θ̇ from + to −.
        if y[2] > 0.0 and y_new[2] <= 0.0:
            sr = hermite_root(y[2], K[0, 2], y_new[2], f_new[2], h_try, 0.0, 1.0)
            _land(tab, tau, y, K[0], sr * h_try, P, F, Ks, ytmp, ys, fs)
            if ys[0] > theta_max:
                theta_max = ys[0]
                t_theta_max = t0 + sr * h_try
            if until_peak:
                for i in range(n):
                    y[i] = ys[i]
                tau += sr * h_try
                t_stop = t0 + sr * h_try
                code = AT_PEAK
                if history:
                    _output(y, P, row)
                    t_hist = push_time(t_hist, nh, t_stop)
                    y_hist = push_row(y_hist, nh, row)
                    nh += 1
                break
        if y_new[0] > theta_max:
            theta_max = y_new[0]
            t_theta_max = t0 + h_try
        for i in range(n):
            y[i] = y_new[i]
            K[0, i] = K[ns, i]
        tau = tau_end if last else tau + h_try
        if history:
            _output(y, P, row)
            t_hist = push_time(t_hist, nh, t_offset + k * dt + tau)
            y_hist = push_row(y_hist, nh, row)
            nh += 1
        h_next = h_try * step_factor(tab[0], err)
        h = max(h_next, h) if last else h_next
        h = min(h, dt)
    if code == OK:
        t_stop = t_offset + k_last * dt + tau_last
    if not history:
        _output(y, P, row)
        t_hist[0] = t_offset + min(k, k_last) * dt + tau if code != OK else t_stop
        y_hist[0, :] = row
        nh = 1
    return (code, t_hist[:nh].copy(), y_hist[:nh].copy(), n_steps, n_rej, theta_max,
            t_theta_max, ev_t[:ne].copy(), ev_y[:ne].copy(), t_stop)


def energy(body: Cylinder, theta, theta_dot, phi_dot):
    """Energy per unit mass E = ½R²[κo θ̇² + μ(θ) φ̇²] + g R cos(α − θ) [m²/s²]."""
    th = np.asarray(theta, dtype=float)
    R = body.R
    return 0.5 * R * R * (body.kappa_o * np.asarray(theta_dot) ** 2
                          + mu(th, body.alpha) * np.asarray(phi_dot) ** 2) \
        + G * R * np.cos(body.alpha - th)


def effective_potential(body: Cylinder, theta, spin_momentum: float):
    """V(θ) = g R cos(α − θ) + R² L²/(2 μ(θ)) [m²/s²], L = μ(θ) φ̇ the spin momentum."""
    th = np.asarray(theta, dtype=float)
    return G * body.R * np.cos(body.alpha - th) \
        + 0.5 * body.R**2 * spin_momentum**2 / mu(th, body.alpha)


def free_peak(body: Cylinder, theta: float, theta_dot: float, phi_dot: float,
              n_grid: int = 4096) -> float:
    """The tilt maximum of the unforced motion from a state, by energy (1-DOF reduction).

    With E and L = μ(θ)φ̇ conserved, θ oscillates in the well of the effective potential
    V(θ) = gR cos(α − θ) + R²L²/(2μ(θ)) between the roots of V(θ) = E. Whatever the sign of
    θ̇, the next (and every later) maximum is the first root of V(θ) = E above θ; none up to
    π/2 means the cylinder overturns.

    Returns
    -------
    float
        θ* [rad], or ``inf`` if the cylinder overturns.
    """
    L = float(mu(theta, body.alpha)) * phi_dot
    E = float(energy(body, theta, theta_dot, phi_dot))
    if theta >= 0.5 * math.pi:
        return math.inf
    grid = np.linspace(theta, 0.5 * math.pi, n_grid)
    gap = effective_potential(body, grid, L) - E
    gap[0] = -0.5 * body.R**2 * body.kappa_o * theta_dot**2  # exact at the start point
    above = np.flatnonzero(gap[1:] >= 0.0)
    if above.size == 0:
        return math.inf
    j = int(above[0]) + 1

    def f(th):
        return float(effective_potential(body, th, L)) - E

    a, b = float(grid[j - 1]), float(grid[j])
    fa, fb = f(a), f(b)
    if fa >= 0.0:  # at the turning point already (θ̇ = 0 up to round-off)
        return a
    if fb == 0.0:
        return b
    return brentq(f, a, b, xtol=1e-15, rtol=4 * EPS, maxiter=200)
