"""Damped 3D bounded cylinder: 3 DOF (θ, φ, w) on a contact spring–dashpot, stiff kernel.

Model (``shared/spec/equations.md``, "3D damped model"; Vassiliou et al. 2017 §3 with the
corrected Eqs 28–29). The contact point sits on a vertical spring k = m ωn² and dashpot
c = 2 m ζ ωn in parallel; w is its vertical displacement measured from the static position
(so the body at rest has w = 0, ẇ = 0 and a contact force per unit mass N/m = g):

    κo θ̈ + (sin(α−θ)/R) ẅ = −(g/R) sin(α−θ) − cos(α−θ) a_r/R + μ'(θ) φ̇²/2
    ẅ + R sin(α−θ) θ̈      =  R cos(α−θ) θ̇² − 2 ζ ωn ẇ − ωn² w
    φ̈ = [ (sin α + sin(θ−α)) a_t/R − μ'(θ) θ̇ φ̇ ] / μ(θ)

The first two are solved as a 2×2 linear system in (θ̈, ẅ) at each evaluation (determinant
κo − sin²(α−θ) ≥ (3 + cos²α)/12). Energy per unit mass
E_d = ½[R²κo θ̇² + R²μ φ̇² + ẇ² + 2R sin(α−θ) θ̇ ẇ] + gR cos(α−θ) + ½ωn² w² obeys
dE_d/dt = −2ζωn ẇ² in free vibration; the kernel integrates the dissipated energy
∫2ζωn ẇ² dt alongside the state so that the balance can be checked.

Why a quasi-impact dissipates Housner's energy: the quasi-impact lasts ~θ_min/|θ̇| ≈ 1e-9 s,
far shorter than 1/ωn, so the contact spring does not act during it; the vertical velocity
of the centre of mass ẇ + R sin(α−θ) θ̇ is kept while θ̇ reverses, leaving
ẇ ≈ −2R sin α |θ̇|. The spring–dashpot then stops ẇ in a time short compared with the
rocking period, conserving p_θ = R²κo θ̇ + R sin(α−θ) ẇ, which gives
θ̇_after/θ̇_before = 1 − 2 sin²α/κo: exactly the restitution of Eq (31), for any ωn and ζ
that keep the three time scales apart.

Integrator — choice by measurement (``python -m rocking.benchmarks damped``, table in
``results/benchmarks/dynamics_damped.md``: 40 s El Centro, R = 6 m, tan α = 0.2,
PGA/(g tan α) = 2, θmax error against RODAS4 at rtol 1e-11). The fast eigenvalue is
≈ −2ζωn when ζ > 1 and a lightly damped pair −ζωn ± iωn otherwise, so explicit methods are
stability-limited. The kernel uses RODAS4 (6 stages, order 4(3), L-stable, stiffly accurate)
with the analytic Jacobian:

- at the paper's ωn = 2000, ζ = 50 it takes 9 ms (rtol 1e-6, θmax error 9e-4) or 23 ms
  (rtol 1e-8, error 9e-6); a compiled explicit DOP853 on the same equations needs 1.2e6
  steps and 1.5 s (at ζ = 5: 0.23 s against 8–32 ms). The undamped explicit kernel takes
  8–10 ms on this case, so the damped one costs 1–2.5× as much (target: ≤ 10×);
- RODAS3 and ROS3 (order 3, same code, other tableau) are less accurate at a given rtol and
  not faster at rtol 1e-8 (ωn = 2000, ζ = 0.5: 75 / 59 ms for errors 6e-5 / 9e-4, RODAS4
  56 ms for 5e-5);
- SciPy's Radau / BDF / LSODA need 10⁴–10⁵ steps and 0.5–15 s through Python, and at rtol
  1e-6 miss θmax by up to 10–30 % (their steps straddle the record samples);
- a Rosenbrock step needs no Newton iteration (Radau IIA / BDF do, and converge badly in
  quasi-impacts where φ̇ reaches 1e8–1e9 rad/s); an IMEX split is awkward because the
  spring–dashpot enters θ̈ through the state-dependent 2×2 mass matrix;
- the 6×6 stage systems reduce to 3×3 ones because the state is (q, q̇): with c = 1/(hγ),
  (c² I − c A_v − A_q) k_v = c r_v + A_q r_q and k_q = (r_q + k_v)/c, where A_q and A_v are
  the Jacobians of the accelerations with respect to q = (θ, φ, w) and q̇.

Measured limits: where the contact mode is not stiff (ωn = 200 with ζ ≤ 0.5, and
ωn = 2000, ζ = 0.05) the explicit DOP853 is as fast or faster (e.g. 27 ms against 124 ms at
rtol 1e-8 for ωn = 2000, ζ = 0.05). With ωn = 2000 and ζ ∈ {0.5, 5} up to a quarter of the
steps are rejected, at the record samples where the slope of the ground acceleration jumps and
excites the contact mode. :data:`DEFAULT_RTOL` = 1e-8 keeps the θmax error ≤ 5e-5 on the
whole grid (rtol 1e-6 gives up to 1e-2) at ≤ 125 ms per 40 s analysis.

Error control: weighted RMS norm with scales rtol·(|θ|) for θ (purely relative: quasi-impacts
take θ to 1e-9…1e-11 rad), rtol·(1 rad) for φ, rtol·(|w| + g/ωn²) for w,
rtol·(|θ̇| + p θ) for θ̇, rtol·(|φ̇| + p) for φ̇ and rtol·(|ẇ| + g/ωn) for ẇ (p = √(g/(κo R))):
g/ωn² and g/ωn are the static deflection and its velocity scale. Steps end at record samples
(the ground acceleration is linear between them and zero after the last one).

Kernel contract (``docs/design.md``): :func:`integrate` returns
``(code, t_hist, y_hist, n_steps, n_rejected, theta_max, t_theta_max, ev_t, ev_y, t_stop)``
with state rows (θ, φ, w, θ̇, φ̇, ẇ) and events at tilt minima (quasi-impacts).
:func:`integrate_full` also returns the dissipated energy, the number of accepted steps with a
tensile (negative) contact force, the smallest contact force and the final state.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from .._validate import finite, nonnegative_finite, positive_finite
from ..constants import G
from ._rosenbrock import RODAS4
from .bodies import Cylinder
from .result import QuasiImpacts, Response, Status

N_STATE = 6
"""State (θ, φ, w, θ̇, φ̇, ẇ)."""

DEFAULT_RTOL = 1e-8
"""Measured default relative tolerance: θmax error ≤ 5e-5 on the paper's (ωn, ζ) grid for the
40 s El Centro case (``results/benchmarks/dynamics_damped.md``)."""

THETA_REST = 1e-6
"""Tilt [rad] whose potential energy gR(cos(α − θ) − cos α) is the rest threshold: at a tilt
minimum with less rocking energy than this, and a ground acceleration below g tan α, the
body is back at rest (code 3). Equations.md: results do not change for θ_eps ≤ 1e-6."""

CODE_OK, CODE_OVERTURNED, CODE_STOPPED, CODE_REST = 0, 1, 2, 3
CODE_UNDERFLOW, CODE_NEGATIVE_TILT, CODE_NONFINITE, CODE_MAX_STEPS = -1, -2, -3, -4

FAILURE_REASONS = {
    CODE_UNDERFLOW: "step size underflow",
    CODE_NEGATIVE_TILT: "tilt became negative (theta < 0)",
    CODE_NONFINITE: "non-finite state",
    CODE_MAX_STEPS: "too many steps",
}

_HALF_PI = 0.5 * math.pi
_EPS = np.finfo(np.float64).eps


def check_parameters(omega_n: float, zeta: float) -> tuple[float, float]:
    """Validate the contact spring–dashpot parameters.

    Parameters
    ----------
    omega_n : float
        Contact natural frequency √(k/m) [rad/s], > 0 and finite.
    zeta : float
        Damping ratio c/(2 m ωn) [-], ≥ 0 and finite.

    Returns
    -------
    (float, float)
        ``(omega_n, zeta)`` as floats.

    Raises
    ------
    ValueError
        Naming the field and the value.
    """
    return positive_finite("omega_n", omega_n), nonnegative_finite("zeta", zeta)


# ---------------------------------------------------------------------------------------------
# Spin inertia μ(θ) and its derivatives (numba scalar twins of bodies.mu / mu_prime)
# ---------------------------------------------------------------------------------------------
@nb.njit(cache=True, inline="always")
def _mu(theta, sa, ca, amu):
    # 1 − cos θ as 2 sin²(θ/2): θ reaches 1e-11 rad, where the literal form rounds to zero.
    st = math.sin(theta)
    hs = math.sin(0.5 * theta)
    omc = 2.0 * hs * hs
    return amu * st * st + 3.0 * sa * sa * omc + 2.0 * sa * ca * st * omc


@nb.njit(cache=True, inline="always")
def _mu_p(theta, sa, ca, amu):
    # 2 sin²θ + cos θ − 1 as cos θ (1 − cos θ) + sin²θ (same cancellation).
    st = math.sin(theta)
    ct = math.cos(theta)
    hs = math.sin(0.5 * theta)
    omc = 2.0 * hs * hs
    return 2.0 * amu * st * ct + 3.0 * sa * sa * st + 2.0 * sa * ca * (ct * omc + st * st)


@nb.njit(cache=True, inline="always")
def _mu_pp(theta, sa, ca, amu):
    st = math.sin(theta)
    ct = math.cos(theta)
    return 2.0 * amu * math.cos(2.0 * theta) + 3.0 * sa * sa * ct + 2.0 * sa * ca * st * (
        4.0 * ct - 1.0
    )


# par = (R, kappa_o, g, omega_n, zeta, sin α, cos α, 4/3 cos²α − 5/4 sin²α, α)
@nb.njit(cache=True)
def _params(alpha, R, kappa_o, g, omega_n, zeta):
    sa = math.sin(alpha)
    ca = math.cos(alpha)
    par = np.empty(9)
    par[0] = R
    par[1] = kappa_o
    par[2] = g
    par[3] = omega_n
    par[4] = zeta
    par[5] = sa
    par[6] = ca
    par[7] = 4.0 / 3.0 * ca * ca - 1.25 * sa * sa
    par[8] = alpha
    return par


@nb.njit(cache=True)
def _deriv(y, axv, ayv, par, f):
    """f = dy/dt for y = (θ, φ, w, θ̇, φ̇, ẇ, D), D = dissipated energy per unit mass."""
    R, ko, g, wn, z = par[0], par[1], par[2], par[3], par[4]
    sa, ca, amu = par[5], par[6], par[7]
    th, ph, w, thd, phd, wd = y[0], y[1], y[2], y[3], y[4], y[5]
    sth, cth = math.sin(th), math.cos(th)
    S = sa * cth - ca * sth  # sin(α − θ)
    C = ca * cth + sa * sth  # cos(α − θ)
    cp, sp = math.cos(ph), math.sin(ph)
    ar = axv * cp + ayv * sp
    at = axv * sp - ayv * cp
    mup = _mu_p(th, sa, ca, amu)
    mu = _mu(th, sa, ca, amu)
    b1 = -(g / R) * S - C * ar / R + 0.5 * mup * phd * phd
    b2 = R * C * thd * thd - 2.0 * z * wn * wd - wn * wn * w
    det = ko - S * S
    # sin α + sin(θ − α) = 2 sin(θ/2) cos(α − θ/2): no cancellation at small θ.
    Q = 2.0 * math.sin(0.5 * th) * math.cos(par[8] - 0.5 * th)
    f[0] = thd
    f[1] = phd
    f[2] = wd
    f[3] = (b1 - (S / R) * b2) / det
    f[4] = (Q * at / R - mup * thd * phd) / mu
    f[5] = (ko * b2 - R * S * b1) / det
    f[6] = 2.0 * z * wn * wd * wd


@nb.njit(cache=True)
def _jacobian(y, axv, ayv, dax, day, par, acc, Aq, Av, ft):
    """Jacobians of the accelerations acc = (θ̈, φ̈, ẅ) w.r.t. q = (θ, φ, w) and q̇, and ∂acc/∂t.

    ``acc`` must hold f[3], f[4], f[5] at y (already computed by :func:`_deriv`).
    """
    R, ko, g, wn, z = par[0], par[1], par[2], par[3], par[4]
    sa, ca, amu = par[5], par[6], par[7]
    th, ph, w, thd, phd, wd = y[0], y[1], y[2], y[3], y[4], y[5]
    thdd, phdd, wdd = acc[0], acc[1], acc[2]
    sth, cth = math.sin(th), math.cos(th)
    S = sa * cth - ca * sth
    C = ca * cth + sa * sth
    cp, sp = math.cos(ph), math.sin(ph)
    ar = axv * cp + ayv * sp
    at = axv * sp - ayv * cp
    mup = _mu_p(th, sa, ca, amu)
    mu = _mu(th, sa, ca, amu)
    mupp = _mu_pp(th, sa, ca, amu)
    b1 = -(g / R) * S - C * ar / R + 0.5 * mup * phd * phd
    b2 = R * C * thd * thd - 2.0 * z * wn * wd - wn * wn * w
    det = ko - S * S
    Q = 2.0 * math.sin(0.5 * th) * math.cos(par[8] - 0.5 * th)
    # d/dθ: dS/dθ = −C, dC/dθ = S, d(det)/dθ = 2 S C.
    b1_th = (g / R) * C - S * ar / R + 0.5 * mupp * phd * phd
    b2_th = R * S * thd * thd
    det_th = 2.0 * S * C
    Aq[0, 0] = (b1_th + (C / R) * b2 - (S / R) * b2_th - thdd * det_th) / det
    Aq[2, 0] = (ko * b2_th + R * C * b1 - R * S * b1_th - wdd * det_th) / det
    n_th = C * at / R - mupp * thd * phd
    Aq[1, 0] = (n_th - phdd * mup) / mu
    # d/dφ: d a_r/dφ = −a_t, d a_t/dφ = a_r.
    b1_ph = C * at / R
    Aq[0, 1] = b1_ph / det
    Aq[2, 1] = -R * S * b1_ph / det
    Aq[1, 1] = Q * ar / (R * mu)
    # d/dw
    Aq[0, 2] = (S / R) * wn * wn / det
    Aq[2, 2] = -ko * wn * wn / det
    Aq[1, 2] = 0.0
    # d/dθ̇
    Av[0, 0] = -2.0 * S * C * thd / det
    Av[2, 0] = 2.0 * ko * R * C * thd / det
    Av[1, 0] = -mup * phd / mu
    # d/dφ̇
    Av[0, 1] = mup * phd / det
    Av[2, 1] = -R * S * mup * phd / det
    Av[1, 1] = -mup * thd / mu
    # d/dẇ
    Av[0, 2] = (S / R) * 2.0 * z * wn / det
    Av[2, 2] = -ko * 2.0 * z * wn / det
    Av[1, 2] = 0.0
    # d/dt through the ground acceleration (piecewise linear: constant slope in a step).
    ar_t = dax * cp + day * sp
    at_t = dax * sp - day * cp
    b1_t = -C * ar_t / R
    ft[0] = b1_t / det
    ft[1] = Q * at_t / (R * mu)
    ft[2] = -R * S * b1_t / det


@nb.njit(cache=True)
def _lu3(M, piv):
    """In-place LU factorization with partial pivoting of a 3×3 matrix; False if singular."""
    for k in range(3):
        p = k
        big = abs(M[k, k])
        for i in range(k + 1, 3):
            if abs(M[i, k]) > big:
                big = abs(M[i, k])
                p = i
        if not big > 0.0:  # also catches NaN
            return False
        piv[k] = p
        if p != k:
            for j in range(3):
                tmp = M[k, j]
                M[k, j] = M[p, j]
                M[p, j] = tmp
        for i in range(k + 1, 3):
            M[i, k] /= M[k, k]
            for j in range(k + 1, 3):
                M[i, j] -= M[i, k] * M[k, j]
    return True


@nb.njit(cache=True)
def _solve3(M, piv, b):
    """Solve with the factors of :func:`_lu3`, overwriting b."""
    for k in range(3):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(1, 3):
        for j in range(i):
            b[i] -= M[i, j] * b[j]
    for i in range(2, -1, -1):
        for j in range(i + 1, 3):
            b[i] -= M[i, j] * b[j]
        b[i] /= M[i, i]


@nb.njit(cache=True)
def _hermite(y0, y1, f0, f1, h, s, out):
    """Cubic Hermite interpolation of the 6 states at fraction s of a step of length h."""
    s2 = s * s
    s3 = s2 * s
    h00 = 2.0 * s3 - 3.0 * s2 + 1.0
    h10 = s3 - 2.0 * s2 + s
    h01 = -2.0 * s3 + 3.0 * s2
    h11 = s3 - s2
    for i in range(N_STATE):
        out[i] = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i]


@nb.njit(cache=True)
def _hermite1(a0, a1, d0, d1, h, s):
    s2 = s * s
    s3 = s2 * s
    return ((2.0 * s3 - 3.0 * s2 + 1.0) * a0 + (s3 - 2.0 * s2 + s) * h * d0
            + (-2.0 * s3 + 3.0 * s2) * a1 + (s3 - s2) * h * d1)


@nb.njit(cache=True)
def _root(a0, a1, d0, d1, h, target):
    """Fraction s ∈ [0, 1] where the Hermite cubic of one component crosses ``target``.

    The caller guarantees a sign change between the step ends; bisection is robust and
    events are rare, so its ~50 cubic evaluations do not matter.
    """
    lo, hi = 0.0, 1.0
    flo = a0 - target
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        fm = _hermite1(a0, a1, d0, d1, h, mid) - target
        if (fm < 0.0) == (flo < 0.0):
            lo, flo = mid, fm
        else:
            hi = mid
        if hi - lo < 1e-15:
            break
    return 0.5 * (lo + hi)


@nb.njit(cache=True)
def _ground(t, ax, ay, dt_rec, scale, k, n):
    """Scaled ground acceleration and its slope at t in segment k (zero after the record)."""
    if n < 2 or k >= n - 1:
        return 0.0, 0.0, 0.0, 0.0
    t0 = k * dt_rec
    dax = scale * (ax[k + 1] - ax[k]) / dt_rec
    day = scale * (ay[k + 1] - ay[k]) / dt_rec
    return scale * ax[k] + dax * (t - t0), scale * ay[k] + day * (t - t0), dax, day


@nb.njit(cache=True)
def _rocking_energy(y, par):
    """Rocking energy above rest ½R²(κo θ̇² + μ φ̇²) + gR(cos(α−θ) − cos α) [J/kg]."""
    R, ko, g = par[0], par[1], par[2]
    sa, ca, amu = par[5], par[6], par[7]
    th = y[0]
    # cos(α − θ) − cos α = sin α sin θ − cos α (1 − cos θ), written without cancellation.
    hs = math.sin(0.5 * th)
    dpot = sa * math.sin(th) - ca * 2.0 * hs * hs
    return 0.5 * R * R * (ko * y[3] * y[3] + _mu(th, sa, ca, amu) * y[4] * y[4]) + g * R * dpot


@nb.njit(cache=True)
def _grow(a, n_rows):
    out = np.empty((2 * a.shape[0] + 16,) + a.shape[1:])
    out[:n_rows] = a[:n_rows]
    return out


@nb.njit(cache=True)
def _grow1(a, n_rows):
    out = np.empty(2 * a.shape[0] + 16)
    out[:n_rows] = a[:n_rows]
    return out


@nb.njit(cache=True)
def _integrate_core(y0, t0, t_end, ax, ay, dt_rec, scale, alpha, R, kappa_o, g, omega_n, zeta,
                    rtol, stop_theta, store_history, max_steps, tab_a, tab_c, tab_m, tab_e,
                    tab_alpha, tab_gt, tab_newf, tab_gamma, tab_order):
    par = _params(alpha, R, kappa_o, g, omega_n, zeta)
    s_st = tab_m.shape[0]
    n = ax.shape[0]
    p = math.sqrt(g / (kappa_o * R))
    w_ref = g / (omega_n * omega_n)
    wd_ref = g / omega_n
    e_rest = g * R * (math.sin(alpha) * math.sin(THETA_REST)
                      - math.cos(alpha) * 2.0 * math.sin(0.5 * THETA_REST) ** 2)
    a_uplift = g * math.tan(alpha)

    y = np.zeros(7)
    y[:6] = y0[:6]
    ynew = np.empty(7)
    f0 = np.empty(7)
    f1 = np.empty(7)
    fs = np.empty(7)
    ystage = np.empty(7)
    K = np.empty((s_st, 7))
    rhs = np.empty(7)
    err = np.empty(7)
    Aq = np.empty((3, 3))
    Av = np.empty((3, 3))
    M = np.empty((3, 3))
    piv = np.empty(3, dtype=np.int64)
    ft = np.empty(3)
    bv = np.empty(3)
    yint = np.empty(6)

    cap_h = 1024 if store_history else 1
    t_hist = np.empty(cap_h)
    y_hist = np.empty((cap_h, 6))
    nh = 0
    ev_t = np.empty(16)
    ev_y = np.empty((16, 6))
    ne = 0

    t = t0
    theta_max = y[0]
    t_theta_max = t0
    n_steps = 0
    n_rej = 0
    n_tension = 0
    n_min = g - omega_n * omega_n * y[2] - 2.0 * zeta * omega_n * y[5]
    code = 0
    t_stop = t0

    if store_history:
        t_hist[0] = t
        y_hist[0, :] = y[:6]
        nh = 1
    for i in range(6):
        if not math.isfinite(y[i]):
            return (CODE_NONFINITE, t_hist[:nh], y_hist[:nh], 0, 0, theta_max, t_theta_max,
                    ev_t[:0], ev_y[:0], t0, 0.0, 0, n_min, y[:6].copy())
    if not y[0] > 0.0:
        return (CODE_NEGATIVE_TILT, t_hist[:nh], y_hist[:nh], 0, 0, theta_max, t_theta_max,
                ev_t[:0], ev_y[:0], t0, 0.0, 0, n_min, y[:6].copy())
    if not t_end > t0:
        return (CODE_OK, t_hist[:nh], y_hist[:nh], 0, 0, theta_max, t_theta_max,
                ev_t[:0], ev_y[:0], t0, 0.0, 0, n_min, y[:6].copy())

    # record segment containing t0
    if n >= 2:
        k = int(math.floor(t0 / dt_rec))
        if k < 0:
            k = 0
        if k > n - 1:
            k = n - 1
        if k < n - 1 and (k + 1) * dt_rec <= t0:
            k += 1
    else:
        k = 0
    axv, ayv, dax, day = _ground(t, ax, ay, dt_rec, scale, k, n)
    _deriv(y, axv, ayv, par, f0)

    # initial step: 1 % of the time in which the state changes by one tolerance unit
    d0 = 0.0
    d1 = 0.0
    for i in range(6):
        if i == 0:
            sc = rtol * abs(y[0])
        elif i == 1:
            sc = rtol
        elif i == 2:
            sc = rtol * (abs(y[2]) + w_ref)
        elif i == 3:
            sc = rtol * (abs(y[3]) + p * abs(y[0]))
        elif i == 4:
            sc = rtol * (abs(y[4]) + p)
        else:
            sc = rtol * (abs(y[5]) + wd_ref)
        d1 += (f0[i] / sc) ** 2
    d0 = 1.0
    d1 = math.sqrt(d1 / 6.0)
    h = 0.01 * d0 / d1 if d1 > 0.0 else 1e-4
    h = min(max(h, 1e-12), 1e-2)
    reject_streak = 0

    while True:
        if n_steps + n_rej >= max_steps:
            code = CODE_MAX_STEPS
            t_stop = t
            break
        # segment end: a record sample, the end of the record, or t_end
        if n >= 2 and k < n - 1:
            seg_end = (k + 1) * dt_rec
            if seg_end > t_end:
                seg_end = t_end
        else:
            seg_end = t_end
        hmin = 16.0 * _EPS * max(abs(t), 1.0)
        if seg_end - t <= hmin:
            # a sample within rounding of t: move to the next segment without stepping
            if seg_end >= t_end:
                break
            t = seg_end
            k += 1
            axv, ayv, dax, day = _ground(t, ax, ay, dt_rec, scale, k, n)
            continue
        hit = False
        if h >= seg_end - t:
            h_try = seg_end - t
            hit = True
        else:
            h_try = h
        t_new = seg_end if hit else t + h_try
        h_try = t_new - t  # the step actually represented in floating point

        # ---- one Rosenbrock step ----
        _jacobian(y, axv, ayv, dax, day, par, f0[3:6], Aq, Av, ft)
        jd = 4.0 * zeta * omega_n * y[5]  # dḊ/dẇ
        cinv = 1.0 / (h_try * tab_gamma)
        for i in range(3):
            for j in range(3):
                M[i, j] = -cinv * Av[i, j] - Aq[i, j]
            M[i, i] += cinv * cinv
        ok = _lu3(M, piv)
        if ok:
            for st in range(s_st):
                # stage point and its right-hand side
                if st == 0:
                    for i in range(7):
                        fs[i] = f0[i]
                elif tab_newf[st]:
                    for i in range(7):
                        acc = y[i]
                        for j in range(st):
                            acc += tab_a[st, j] * K[j, i]
                        ystage[i] = acc
                    ts = t + tab_alpha[st] * h_try
                    ax_s, ay_s = axv + dax * (ts - t), ayv + day * (ts - t)
                    _deriv(ystage, ax_s, ay_s, par, fs)
                for i in range(7):
                    acc = fs[i]
                    for j in range(st):
                        acc += (tab_c[st, j] / h_try) * K[j, i]
                    rhs[i] = acc
                gth = tab_gt[st] * h_try
                rhs[3] += gth * ft[0]
                rhs[4] += gth * ft[1]
                rhs[5] += gth * ft[2]
                # reduced 3×3 solve: (c² − c A_v − A_q) k_v = c r_v + A_q r_q
                for i in range(3):
                    bv[i] = cinv * rhs[3 + i] + (Aq[i, 0] * rhs[0] + Aq[i, 1] * rhs[1]
                                                 + Aq[i, 2] * rhs[2])
                _solve3(M, piv, bv)
                for i in range(3):
                    K[st, 3 + i] = bv[i]
                    K[st, i] = (rhs[i] + bv[i]) / cinv
                K[st, 6] = (rhs[6] + jd * bv[2]) / cinv
            for i in range(7):
                acc = y[i]
                er = 0.0
                for st in range(s_st):
                    acc += tab_m[st] * K[st, i]
                    er += tab_e[st] * K[st, i]
                ynew[i] = acc
                err[i] = er
        # ---- error norm ----
        finite_ok = ok
        en = 0.0
        if ok:
            for i in range(6):
                if not math.isfinite(ynew[i]) or not math.isfinite(err[i]):
                    finite_ok = False
                    break
                if i == 0:
                    sc = rtol * max(abs(y[0]), abs(ynew[0]))
                elif i == 1:
                    sc = rtol
                elif i == 2:
                    sc = rtol * (max(abs(y[2]), abs(ynew[2])) + w_ref)
                elif i == 3:
                    sc = rtol * (max(abs(y[3]), abs(ynew[3]))
                                 + p * max(abs(y[0]), abs(ynew[0])))
                elif i == 4:
                    sc = rtol * (max(abs(y[4]), abs(ynew[4])) + p)
                else:
                    sc = rtol * (max(abs(y[5]), abs(ynew[5])) + wd_ref)
                en += (err[i] / sc) ** 2
            en = math.sqrt(en / 6.0)
        if not finite_ok or not math.isfinite(en) or not ynew[0] > 0.0 or en > 1.0:
            n_rej += 1
            reject_streak += 1
            if finite_ok and math.isfinite(en) and ynew[0] > 0.0:
                fac = max(0.2, 0.9 * en ** (-1.0 / tab_order))
            else:
                fac = 0.25
            h = h_try * fac
            if h < hmin:
                if not finite_ok or not math.isfinite(en):
                    code = CODE_NONFINITE
                elif not ynew[0] > 0.0:
                    code = CODE_NEGATIVE_TILT
                else:
                    code = CODE_UNDERFLOW
                t_stop = t
                break
            continue

        # ---- accepted ----
        n_steps += 1
        k_step = k  # segment of this step (for the ground acceleration inside it)
        if hit and t_new < t_end and n >= 2 and k < n - 1:
            k += 1
        ax1, ay1, dax1, day1 = _ground(t_new, ax, ay, dt_rec, scale, k, n)
        _deriv(ynew, ax1, ay1, par, f1)
        fac = min(6.0, max(0.2, 0.9 * max(en, 1e-10) ** (-1.0 / tab_order)))
        if reject_streak > 0:
            fac = min(fac, 1.0)
        reject_streak = 0
        # No memory of a larger proposal when a sample cut the step short: the ground
        # acceleration changes slope there, and reusing it made the next step fail more often.
        h = h_try * fac

        # contact force per unit mass; tension means the body would lift off
        nf = g - omega_n * omega_n * ynew[2] - 2.0 * zeta * omega_n * ynew[5]
        if nf < 0.0:
            n_tension += 1
        if nf < n_min:
            n_min = nf

        stop_now = False
        # maxima found after a stop inside this step must not count: keep the previous ones
        th_max_prev = theta_max
        t_th_max_prev = t_theta_max
        # tilt maximum inside the step
        if y[3] > 0.0 and ynew[3] <= 0.0:
            s = _root(y[3], ynew[3], f0[3], f1[3], h_try, 0.0)
            thm = _hermite1(y[0], ynew[0], f0[0], f1[0], h_try, s)
            if thm > theta_max:
                theta_max = thm
                t_theta_max = t + s * h_try
        if ynew[0] > theta_max:
            theta_max = ynew[0]
            t_theta_max = t_new
        # tilt minimum inside the step: a quasi-impact
        if y[3] < 0.0 and ynew[3] >= 0.0:
            s = _root(y[3], ynew[3], f0[3], f1[3], h_try, 0.0)
            _hermite(y, ynew, f0, f1, h_try, s, yint)
            te = t + s * h_try
            if ne == ev_t.shape[0]:
                ev_t = _grow1(ev_t, ne)
                ev_y = _grow(ev_y, ne)
            ev_t[ne] = te
            ev_y[ne, :] = yint
            ne += 1
            axe, aye, _, _ = _ground(te, ax, ay, dt_rec, scale, k_step, n)
            if (_rocking_energy(yint, par) < e_rest
                    and math.sqrt(axe * axe + aye * aye) <= a_uplift):
                code = CODE_REST
                t_stop = te
                theta_max = th_max_prev
                t_theta_max = t_th_max_prev
                stop_now = True
        if not stop_now and ynew[0] >= _HALF_PI:
            s = _root(y[0], ynew[0], f0[0], f1[0], h_try, _HALF_PI)
            _hermite(y, ynew, f0, f1, h_try, s, yint)
            yint[0] = _HALF_PI
            code = CODE_OVERTURNED
            t_stop = t + s * h_try
            theta_max = _HALF_PI
            t_theta_max = t_stop
            stop_now = True
        elif not stop_now and stop_theta < _HALF_PI and ynew[0] > stop_theta:
            s = _root(y[0], ynew[0], f0[0], f1[0], h_try, stop_theta)
            _hermite(y, ynew, f0, f1, h_try, s, yint)
            code = CODE_STOPPED
            t_stop = t + s * h_try
            theta_max = th_max_prev
            t_theta_max = t_th_max_prev
            if yint[0] >= theta_max:
                theta_max = yint[0]
                t_theta_max = t_stop
            stop_now = True

        if stop_now:
            # integrate the dissipation only up to the stop (linear share of the last step)
            y[6] += (ynew[6] - y[6]) * ((t_stop - t) / h_try)
            for i in range(6):
                y[i] = yint[i]
            if store_history:
                if nh == t_hist.shape[0]:
                    t_hist = _grow1(t_hist, nh)
                    y_hist = _grow(y_hist, nh)
                t_hist[nh] = t_stop
                y_hist[nh, :] = yint
                nh += 1
            t = t_stop
            break

        t = t_new
        for i in range(7):
            y[i] = ynew[i]
            f0[i] = f1[i]
        axv, ayv, dax, day = ax1, ay1, dax1, day1
        if store_history:
            if nh == t_hist.shape[0]:
                t_hist = _grow1(t_hist, nh)
                y_hist = _grow(y_hist, nh)
            t_hist[nh] = t
            y_hist[nh, :] = y[:6]
            nh += 1
        if t >= t_end:
            t_stop = t
            break

    if code == CODE_OK:
        t_stop = t
    return (code, t_hist[:nh].copy(), y_hist[:nh].copy(), n_steps, n_rej, theta_max,
            t_theta_max, ev_t[:ne].copy(), ev_y[:ne].copy(), t_stop, y[6], n_tension, n_min,
            y[:6].copy())


_TAB = RODAS4
_TAB_A, _TAB_C, _TAB_M, _TAB_E = _TAB.a, _TAB.c, _TAB.m, _TAB.e
_TAB_ALPHA, _TAB_GT, _TAB_NEWF = _TAB.alpha, _TAB.gamma_t, _TAB.new_f
_TAB_GAMMA, _TAB_ORDER = float(_TAB.gamma), float(_TAB.order)


@nb.njit(cache=True)
def integrate_full(y0, t0, t_end, ax, ay, dt_rec, scale, alpha, R, kappa_o, g, omega_n, zeta,
                   rtol, stop_theta, store_history, max_steps):
    """:func:`integrate` plus the damping bookkeeping.

    Returns
    -------
    tuple
        The 10 entries of :func:`integrate`, then ``dissipated`` (∫2ζωn ẇ² dt up to
        ``t_stop`` [J/kg]), ``n_tension`` (accepted steps ending with a negative contact
        force, i.e. the bilateral spring pulling: lift-off the model assumes away),
        ``n_min`` (smallest contact force per unit mass at step ends [m/s²]) and ``y_end``
        (state at ``t_stop``, shape (6,)).
    """
    return _integrate_core(y0, t0, t_end, ax, ay, dt_rec, scale, alpha, R, kappa_o, g,
                           omega_n, zeta, rtol, stop_theta, store_history, max_steps,
                           _TAB_A, _TAB_C, _TAB_M, _TAB_E, _TAB_ALPHA, _TAB_GT, _TAB_NEWF,
                           _TAB_GAMMA, _TAB_ORDER)


@nb.njit(cache=True)
def integrate(y0, t0, t_end, ax, ay, dt_rec, scale, alpha, R, kappa_o, g, omega_n, zeta, rtol,
              stop_theta, store_history, max_steps):
    """Integrate the damped 3D model with RODAS4 (compiled kernel of ``docs/design.md``).

    Parameters
    ----------
    y0 : ndarray, shape (6,)
        Initial state (θ [rad] > 0, φ [rad], w [m], θ̇ [rad/s], φ̇ [rad/s], ẇ [m/s]).
        At rest on the support w = ẇ = 0 (w is measured from the static position).
    t0, t_end : float
        Start and end times [s] (record time: sample i of ``ax`` is at i·dt_rec).
    ax, ay : ndarray, shape (n,)
        Ground accelerations [m/s²] sampled at ``dt_rec`` from t = 0, linear in between and
        zero after the last sample; n < 2 (or zeros) means free vibration.
    dt_rec : float
        Record time step [s] (> 0; any positive value when n < 2).
    scale : float
        Factor applied to ``ax`` and ``ay`` [-].
    alpha : float
        Slenderness angle α [rad].
    R : float
        Semi-diagonal [m].
    kappa_o : float
        I_o/(mR²) [-].
    g : float
        Gravity [m/s²].
    omega_n : float
        Contact natural frequency [rad/s] (> 0; validate with :func:`check_parameters`).
    zeta : float
        Contact damping ratio [-] (≥ 0).
    rtol : float
        Relative tolerance (see the module docstring for the error scales).
    stop_theta : float
        Stop with code 2 when θ exceeds it [rad]; any value ≥ π/2 disables it.
    store_history : bool
        Keep every accepted step in ``t_hist``/``y_hist`` (else both are empty).
    max_steps : int
        Limit on accepted plus rejected steps (code −4 beyond).

    Returns
    -------
    code : int
        0 reached ``t_end``; 1 overturned (θ = π/2); 2 θ exceeded ``stop_theta``; 3 back at
        rest (rocking energy at a tilt minimum below that of a tilt of :data:`THETA_REST`
        with |a_g| ≤ g tan α); −1 step-size underflow; −2 θ < 0; −3 non-finite state;
        −4 too many steps.
    t_hist : ndarray, shape (m,)
        Times of the initial state and of every accepted step [s], ending at ``t_stop``.
    y_hist : ndarray, shape (m, 6)
        States (θ, φ, w, θ̇, φ̇, ẇ) at ``t_hist``.
    n_steps, n_rejected : int
        Accepted and rejected steps.
    theta_max, t_theta_max : float
        Largest tilt [rad] (local maxima located by Hermite interpolation) and its time [s].
    ev_t : ndarray, shape (n_ev,)
        Times of the tilt minima (quasi-impacts) [s].
    ev_y : ndarray, shape (n_ev, 6)
        States at the tilt minima.
    t_stop : float
        Time the integration ended [s].
    """
    r = integrate_full(y0, t0, t_end, ax, ay, dt_rec, scale, alpha, R, kappa_o, g, omega_n,
                       zeta, rtol, stop_theta, store_history, max_steps)
    return r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9]


# ---------------------------------------------------------------------------------------------
# Python-level helpers
# ---------------------------------------------------------------------------------------------
def contact_force(y: np.ndarray, omega_n: float, zeta: float, g: float = G) -> np.ndarray:
    """Contact force per unit mass N/m = g − ωn² w − 2ζωn ẇ [m/s²] for state rows ``y``."""
    y = np.asarray(y, dtype=float)
    return g - omega_n**2 * y[..., 2] - 2.0 * zeta * omega_n * y[..., 5]


def energy(cylinder: Cylinder, y: np.ndarray, omega_n: float, g: float = G) -> np.ndarray:
    """Energy per unit mass E_d of state rows ``y`` (θ, φ, w, θ̇, φ̇, ẇ) [J/kg].

    E_d = ½[R²κo θ̇² + R²μ φ̇² + ẇ² + 2R sin(α−θ) θ̇ ẇ] + gR cos(α−θ) + ½ωn² w².
    """
    y = np.asarray(y, dtype=float)
    th, thd, phd, w, wd = y[..., 0], y[..., 3], y[..., 4], y[..., 2], y[..., 5]
    R, a = cylinder.R, cylinder.alpha
    kin = 0.5 * (R * R * cylinder.kappa_o * thd**2 + R * R * cylinder.mu(th) * phd**2 + wd**2
                 + 2.0 * R * np.sin(a - th) * thd * wd)
    return kin + g * R * np.cos(a - th) + 0.5 * omega_n**2 * w**2


def simulate_free(cylinder: Cylinder, theta0: float, phi_dot0: float, duration: float,
                  omega_n: float, zeta: float, rtol: float = DEFAULT_RTOL, theta_dot0: float = 0.0,
                  phi0: float = 0.0, max_steps: int = 5_000_000) -> Response:
    """Free vibration of the damped model from rest on the spring (w = ẇ = 0).

    A thin convenience for tests and examples; ``rocking.free_vibration(model="3d-damped")``
    is the public entry point.

    Parameters
    ----------
    cylinder : Cylinder
    theta0 : float
        Initial tilt [rad], in (0, π/2).
    phi_dot0 : float
        Initial spin [rad/s].
    duration : float
        Length of the analysis [s].
    omega_n, zeta : float
        Contact spring–dashpot parameters [rad/s], [-].
    rtol : float
        Relative tolerance.
    theta_dot0, phi0 : float
        Initial tilt rate [rad/s] and rolling angle [rad].
    max_steps : int
        Step limit.

    Returns
    -------
    Response
        ``model="3d-damped"`` with ``w``, ``w_dot``, ``contact_force`` and ``extras``
        (``dissipated`` [J/kg], ``n_tension``, ``contact_force_min`` [m/s²]).
    """
    omega_n, zeta = check_parameters(omega_n, zeta)
    theta0 = positive_finite("theta0", theta0)
    if theta0 >= _HALF_PI:
        raise ValueError(f"theta0 must be below pi/2, got {theta0!r}")
    duration = positive_finite("duration", duration)
    rtol = positive_finite("rtol", rtol)
    y0 = np.array([theta0, finite("phi0", phi0), 0.0, finite("theta_dot0", theta_dot0),
                   finite("phi_dot0", phi_dot0), 0.0])
    empty = np.zeros(0)
    r = integrate_full(y0, 0.0, duration, empty, empty, 1.0, 1.0, cylinder.alpha, cylinder.R,
                       cylinder.kappa_o, G, omega_n, zeta, rtol, 10.0, True, int(max_steps))
    return _response(r, omega_n, zeta)


def _response(r: tuple, omega_n: float, zeta: float) -> Response:
    code, t, y, n_steps, n_rej, th_max, t_th_max, ev_t, ev_y, t_stop = r[:10]
    dissipated, n_tension, n_min = r[10], r[11], r[12]
    if code < 0:
        status, reason = Status.FAILED, f"{FAILURE_REASONS[code]} at t = {t_stop:.9g} s"
    elif code == CODE_OVERTURNED:
        status, reason = Status.OVERTURNED, ""
    elif code == CODE_STOPPED:
        status, reason = Status.STOPPED_AT_LIMIT, ""
    else:
        status, reason = Status.OK, "came back to rest" if code == CODE_REST else ""
    return Response(
        model="3d-damped", t=t, theta=y[:, 0], theta_dot=y[:, 3], phi=y[:, 1], phi_dot=y[:, 4],
        theta_max=float(th_max), t_theta_max=float(t_th_max),
        overturned=code == CODE_OVERTURNED, status=status,
        quasi_impacts=QuasiImpacts(ev_t, ev_y), n_steps=int(n_steps), n_rejected=int(n_rej),
        reason=reason, w=y[:, 2], w_dot=y[:, 5], contact_force=contact_force(y, omega_n, zeta),
        extras={"dissipated": float(dissipated), "n_tension": int(n_tension),
                "contact_force_min": float(n_min), "code": int(code), "t_stop": float(t_stop)},
    )
