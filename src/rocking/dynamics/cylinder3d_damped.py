"""Damped 3D bounded cylinder: 3 DOF (θ, φ, w) on a contact spring–dashpot, stiff kernel.

Model (docs/equations.md, "3D damped model"; Vassiliou et al. 2017 §3 with the corrected
Eqs 28–29). The contact point sits on a vertical spring k = m ωn² and dashpot c = 2 m ζ ωn
in parallel; w is its vertical displacement measured from the static position (so the body
at rest has w = 0, ẇ = 0 and a contact force per unit mass N/m = g):

    κo θ̈ + (sin(α−θ)/R) ẅ = −(g/R) sin(α−θ) − cos(α−θ) a_r/R + μ'(θ) φ̇²/2
    ẅ + R sin(α−θ) θ̈      =  R cos(α−θ) θ̇² − 2 ζ ωn ẇ − ωn² w
    φ̈ = [ (sin α + sin(θ−α)) a_t/R − μ'(θ) θ̇ φ̇ ] / μ(θ)

The first two are solved as a 2×2 linear system in (θ̈, ẅ) at each evaluation (determinant
κo − sin²(α−θ) ≥ (3 + cos²α)/12). The kernel state is (θ, φ, w, θ̇, φ̇, ẇ, D), D the energy
dissipated by the dashpot, ∫2ζωn ẇ² dt per unit mass, so that the energy balance
dE_d/dt = −2ζωn ẇ² can be checked (:func:`energy`).

Why a quasi-impact dissipates Housner's energy: the quasi-impact lasts ~θ_min/|θ̇| ≈ 1e-9 s,
far shorter than 1/ωn, so the contact spring does not act during it; the vertical velocity
of the centre of mass ẇ + R sin(α−θ) θ̇ is kept while θ̇ reverses, leaving
ẇ ≈ −2R sin α |θ̇|. The spring–dashpot then stops ẇ in a time short compared with the
rocking period, conserving p_θ = R²κo θ̇ + R sin(α−θ) ẇ, which gives
θ̇_after/θ̇_before = 1 − 2 sin²α/κo: exactly the restitution of Eq (31), for any ωn and ζ
that keep the three time scales apart.

Squat cylinders (tan α > 4/3, where Eq 31 is negative) need no special treatment here: the
dashpot leaves θ̇ = e |θ̇_before| < 0 while θ is still ~1e-9 rad, so the tilt turns back at
once into another quasi-impact, and a burst of them within a few 1/ωn takes the rocking
energy down to the rest level, the e = 0 that the 2D model applies (:mod:`.bodies`).
Measured (tests/test_squat.py): tan α = 2, R = 1 m, θ0 = α/2, φ̇0 = 1e-8 rad/s, ωn = 2000
rad/s, ζ = 5: approach θ̇ = −2.4994 rad/s, five quasi-impacts within 1 ms, √(rocking
energy / initial) 0.0022 after 5/ωn and 0.0019 (the ~1e-6 rad resting tilt) after 20/ωn,
largest later tilt 2.7e-5 rad (ζ = 50: 0.0059, 0.0041, 1.6e-5 rad; ωn = 200, ζ = 5:
0.0019, 0.0019, 2.7e-4 rad); tan α = 1 gives the apparent restitution 0.2253–0.2270 against
Eq 31's 0.2258. A soft, lightly damped contact (ωn = 200 rad/s, ζ = 0.5) instead pulls the
body back through a tensile contact force (``n_tension`` > 0, the bilateral spring's
artefact) and it rocks on with an apparent e ≈ 0.16 for 0.1 s.

Integrator: RODAS4 (:mod:`._rosenbrock`; 6 stages, order 4(3), L-stable, stiffly accurate)
with the analytic Jacobian, through the driver (:mod:`.driver`). The fast eigenvalue is
≈ −2ζωn when ζ > 1 and a lightly damped pair −ζωn ± iωn otherwise, so explicit methods are
stability-limited; a Rosenbrock step needs no Newton iteration (which converges badly in
quasi-impacts where φ̇ reaches 1e8–1e9 rad/s). The choice and its rtol (in :mod:`.models`) were
measured with ``python -m benchmarks damped``. The 7×7 stage systems reduce to 3×3
ones because the state is (q, q̇, D): with c = 1/(hγ), (c² I − c A_v − A_q) k_v =
c r_v + A_q r_q, k_q = (r_q + k_v)/c and k_D = (r_D + ∂Ḋ/∂ẇ k_ẇ)/c, where A_q and A_v are
the Jacobians of the accelerations with respect to q = (θ, φ, w) and q̇; the 3×3 matrix is
inverted once per step (:func:`factor`) and each stage costs two 3×3 products
(:func:`solve`).

Error control: weighted RMS norm over the six mechanical states with scales rtol·|θ| for θ
(purely relative: quasi-impacts take θ to 1e-9…1e-11 rad), rtol·(1 + |φ|) for φ,
rtol·(|w| + g/ωn²) for w, rtol·(|θ̇| + p |θ|) for θ̇, rtol·(|φ̇| + p) for φ̇ and
rtol·(|ẇ| + g/ωn) for ẇ (p = √(g/(κo R)); g/ωn² and g/ωn are the static deflection and its
velocity scale).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rocking.constants import G
from rocking.dynamics import driver, inertia
from rocking.dynamics._rosenbrock import ros_step
from rocking.dynamics.bodies import Cylinder
from rocking.dynamics.cylinder3d import support_force

STATE = ("theta", "phi", "w", "theta_dot", "phi_dot", "w_dot")
"""Output state; the kernel state appends the dissipated energy D."""

LA_SHAPE = (9, 3)
"""Rows of the linear-algebra work array of :func:`factor` and :func:`solve`."""


def params(body: Cylinder, omega_n: float, zeta: float) -> np.ndarray:
    """Kernel parameters [side = 1, R, κo, g, ωn, ζ, sin α, cos α, α, p]."""
    return np.array([1.0, body.R, body.kappa_o, G, omega_n, zeta, math.sin(body.alpha),
                     math.cos(body.alpha), body.alpha, body.p])


def tolerances(body: Cylinder, omega_n: float) -> tuple[np.ndarray, np.ndarray]:
    """Absolute floors and tilt weights of (θ, φ, w, θ̇, φ̇, ẇ) (module docstring)."""
    p = body.p
    floor = np.array([0.0, 1.0, G / omega_n**2, 0.0, p, G / omega_n])
    wtilt = np.array([0.0, 0.0, 0.0, p, 0.0, 0.0])
    return floor, wtilt


def to_state(y: np.ndarray) -> np.ndarray:
    """Kernel state (θ, φ, w, θ̇, φ̇, ẇ, D = 0) of an output state."""
    return np.append(np.asarray(y, dtype=float), 0.0)


@njit(cache=True, inline="always", error_model="numpy")
def _geometry(th, P):
    """sin(α−θ), cos(α−θ), sin α + sin(θ−α) = 2 sin(θ/2) cos(α − θ/2) (no cancellation),
    μ(θ) and μ'(θ)."""
    s, c, alpha = P[6], P[7], P[8]
    sth, cth = math.sin(th), math.cos(th)
    sh = math.sin(0.5 * th)
    omc = 2.0 * sh * sh
    return (s * cth - c * sth, c * cth + s * sth, 2.0 * sh * math.cos(alpha - 0.5 * th),
            inertia.mu_of(sth, omc, s, c), inertia.mu_prime_of(sth, cth, omc, s, c))


@njit(cache=True, inline="always", error_model="numpy")
def _terms(tau, y, P, F, vertical=True):
    """Shared terms of :func:`rhs` and :func:`jacobian`: the geometry, cos φ, sin φ, the ground
    acceleration along and across the tilt direction, the right sides b1, b2 of the 2×2 system
    and its determinant. Without ``vertical`` (a constant of each compiled variant) a_z is
    exactly 0, as F[4] + F[5] τ is without vertical motion: no bit differs."""
    R, ko, g, wn, z = P[1], P[2], P[3], P[4], P[5]
    th, ph, w, thd, phd, wd = y[0], y[1], y[2], y[3], y[4], y[5]
    S, C, Q, mu, mup = _geometry(th, P)
    axv = F[0] + F[2] * tau
    ayv = F[1] + F[3] * tau
    # vertical: gravity acts as g + a_z, the spring sees −a_z
    azv = F[4] + F[5] * tau if vertical else 0.0
    cp, sp = math.cos(ph), math.sin(ph)
    ar = axv * cp + ayv * sp
    at = axv * sp - ayv * cp
    b1 = -((g + azv) / R) * S - C * ar / R + 0.5 * mup * phd * phd
    b2 = R * C * thd * thd - 2.0 * z * wn * wd - wn * wn * w - azv
    return S, C, Q, mu, mup, cp, sp, ar, at, b1, b2, ko - S * S


@njit(cache=True, inline="always", error_model="numpy")
def _rhs(tau, y, P, F, f, vertical):
    """dy/dt for y = (θ, φ, w, θ̇, φ̇, ẇ, D), ground acceleration F[0:2] + F[2:4] τ, vertical
    F[4] + F[5] τ if ``vertical`` (:func:`rhs`, :func:`rhs_level`)."""
    R, ko, wn, z = P[1], P[2], P[4], P[5]
    S, C, Q, mu, mup, cp, sp, ar, at, b1, b2, det = _terms(tau, y, P, F, vertical)
    f[0] = y[3]
    f[1] = y[4]
    f[2] = y[5]
    f[3] = (b1 - (S / R) * b2) / det
    f[4] = (Q * at / R - mup * y[3] * y[4]) / mu
    f[5] = (ko * b2 - R * S * b1) / det
    f[6] = 2.0 * z * wn * y[5] * y[5]


@njit(cache=True, error_model="numpy")
def rhs(tau, y, P, F, f):
    """:func:`_rhs` with the vertical forcing."""
    _rhs(tau, y, P, F, f, True)


@njit(cache=True, error_model="numpy")
def rhs_level(tau, y, P, F, f):
    """:func:`_rhs` without the vertical forcing (gravity exactly g). The Jacobian of a
    Rosenbrock step (once per step) always reads a_z, which is 0 then."""
    _rhs(tau, y, P, F, f, False)


@njit(cache=True, inline="always", error_model="numpy")
def jacobian(tau, y, P, F, f, LA):
    """Jacobians of the accelerations (θ̈, φ̈, ẅ) w.r.t. q = (θ, φ, w) and q̇, and ∂/∂t.

    ``f`` must hold :func:`rhs` at y. Writes A_q into rows 0–2 of ``LA``, A_v into rows 3–5
    and the time derivatives into row 8.
    """
    R, ko, g, wn, z, s, c = P[1], P[2], P[3], P[4], P[5], P[6], P[7]
    th, thd, phd = y[0], y[3], y[4]
    thdd, phdd, wdd = f[3], f[4], f[5]
    S, C, Q, mu, mup, cp, sp, ar, at, b1, b2, det = _terms(tau, y, P, F)
    mupp = inertia.mu_second_of(math.sin(th), math.cos(th), s, c)
    # d/dθ: dS/dθ = −C, dC/dθ = S, d(det)/dθ = 2 S C.
    b1_th = ((g + F[4] + F[5] * tau) / R) * C - S * ar / R + 0.5 * mupp * phd * phd
    b2_th = R * S * thd * thd
    det_th = 2.0 * S * C
    LA[0, 0] = (b1_th + (C / R) * b2 - (S / R) * b2_th - thdd * det_th) / det
    LA[2, 0] = (ko * b2_th + R * C * b1 - R * S * b1_th - wdd * det_th) / det
    LA[1, 0] = (C * at / R - mupp * thd * phd - phdd * mup) / mu
    # d/dφ: d a_r/dφ = −a_t, d a_t/dφ = a_r.
    b1_ph = C * at / R
    LA[0, 1] = b1_ph / det
    LA[2, 1] = -R * S * b1_ph / det
    LA[1, 1] = Q * ar / (R * mu)
    # d/dw
    LA[0, 2] = (S / R) * wn * wn / det
    LA[2, 2] = -ko * wn * wn / det
    LA[1, 2] = 0.0
    # d/dθ̇
    LA[3, 0] = -2.0 * S * C * thd / det
    LA[5, 0] = 2.0 * ko * R * C * thd / det
    LA[4, 0] = -mup * phd / mu
    # d/dφ̇
    LA[3, 1] = mup * phd / det
    LA[5, 1] = -R * S * mup * phd / det
    LA[4, 1] = -mup * thd / mu
    # d/dẇ
    LA[3, 2] = (S / R) * 2.0 * z * wn / det
    LA[5, 2] = -ko * 2.0 * z * wn / det
    LA[4, 2] = 0.0
    # d/dt through the ground acceleration (piecewise linear: constant slope in a step).
    ar_t = F[2] * cp + F[3] * sp
    at_t = F[2] * sp - F[3] * cp
    b1_t = -C * ar_t / R - (F[5] / R) * S
    b2_t = -F[5]
    LA[8, 0] = (b1_t - (S / R) * b2_t) / det
    LA[8, 1] = Q * at_t / (R * mu)
    LA[8, 2] = (ko * b2_t - R * S * b1_t) / det


@njit(cache=True, error_model="numpy")
def factor(tau, y, f0, P, F, c, LA):
    """Rosenbrock hook: Jacobian at the step start and the inverse of M = c² I − c A_v − A_q.

    The 3×3 inverse is formed once per step from the adjugate (M is dominated by c² I for
    the short steps of a stiff run), so that each of the six stage solves is two 3×3
    products. ``LA`` rows afterwards: M⁻¹ (0–2), M⁻¹ A_q (3–5), (c, ∂Ḋ/∂ẇ) (6),
    c M⁻¹ ∂(θ̈, φ̈, ẅ)/∂t (7). False if M is singular or not finite.
    """
    jacobian(tau, y, P, F, f0, LA)
    cc = c * c
    m00 = cc - c * LA[3, 0] - LA[0, 0]
    m01 = -c * LA[3, 1] - LA[0, 1]
    m02 = -c * LA[3, 2] - LA[0, 2]
    m10 = -c * LA[4, 0] - LA[1, 0]
    m11 = cc - c * LA[4, 1] - LA[1, 1]
    m12 = -c * LA[4, 2] - LA[1, 2]
    m20 = -c * LA[5, 0] - LA[2, 0]
    m21 = -c * LA[5, 1] - LA[2, 1]
    m22 = cc - c * LA[5, 2] - LA[2, 2]
    a00, a01, a02 = m11 * m22 - m12 * m21, m02 * m21 - m01 * m22, m01 * m12 - m02 * m11
    det = m00 * a00 + m10 * a01 + m20 * a02
    if not (math.isfinite(det) and det != 0.0):
        return False
    inv = 1.0 / det
    n00, n01, n02 = a00 * inv, a01 * inv, a02 * inv
    n10 = (m12 * m20 - m10 * m22) * inv
    n11 = (m00 * m22 - m02 * m20) * inv
    n12 = (m02 * m10 - m00 * m12) * inv
    n20 = (m10 * m21 - m11 * m20) * inv
    n21 = (m01 * m20 - m00 * m21) * inv
    n22 = (m00 * m11 - m01 * m10) * inv
    for j in range(3):
        q0, q1, q2 = LA[0, j], LA[1, j], LA[2, j]
        LA[3, j] = n00 * q0 + n01 * q1 + n02 * q2
        LA[4, j] = n10 * q0 + n11 * q1 + n12 * q2
        LA[5, j] = n20 * q0 + n21 * q1 + n22 * q2
    t0, t1, t2 = LA[8, 0], LA[8, 1], LA[8, 2]
    LA[7, 0] = c * (n00 * t0 + n01 * t1 + n02 * t2)
    LA[7, 1] = c * (n10 * t0 + n11 * t1 + n12 * t2)
    LA[7, 2] = c * (n20 * t0 + n21 * t1 + n22 * t2)
    LA[0, 0], LA[0, 1], LA[0, 2] = n00, n01, n02
    LA[1, 0], LA[1, 1], LA[1, 2] = n10, n11, n12
    LA[2, 0], LA[2, 1], LA[2, 2] = n20, n21, n22
    LA[6, 0] = c
    LA[6, 1] = 4.0 * P[5] * P[4] * y[5]  # ∂Ḋ/∂ẇ = 4 ζ ωn ẇ
    return True


@njit(cache=True, error_model="numpy")
def solve(LA, P, r, g):
    """Rosenbrock hook: r ← (c I − J)⁻¹ (r + g ∂f/∂t) through the reduced 3×3 system
    (module docstring): k_v = M⁻¹ (c (r_v + g ∂f/∂t) + A_q r_q), k_q = (r_q + k_v)/c."""
    c, jd = LA[6, 0], LA[6, 1]
    q0, q1, q2, v0, v1, v2 = r[0], r[1], r[2], r[3], r[4], r[5]
    for i in range(3):
        k = (c * (LA[i, 0] * v0 + LA[i, 1] * v1 + LA[i, 2] * v2) + g * LA[7, i]
             + LA[3 + i, 0] * q0 + LA[3 + i, 1] * q1 + LA[3 + i, 2] * q2)
        r[i] = (r[i] + k) / c
        r[3 + i] = k
    r[6] = (r[6] + jd * r[5]) / c


@njit(cache=True, inline="always", error_model="numpy")
def contact_force_of(y, P):
    """Contact force per unit mass N/m = g − ωn² w − 2ζωn ẇ [m/s²]."""
    return P[3] - P[4] * P[4] * y[2] - 2.0 * P[5] * P[4] * y[5]


@njit(cache=True, error_model="numpy")
def observe(y, P, diag):
    """After each step: count tensile contact forces (diag[0]) and keep the smallest (diag[1])."""
    nf = contact_force_of(y, P)
    if nf < 0.0:
        diag[0] += 1.0
    diag[1] = min(diag[1], nf)


@njit(cache=True, error_model="numpy")
def contact(tau, y, f, P, F, cf):
    """Support force per unit weight ``cf = (N, |F_h|)``: N from the spring and dashpot
    (:func:`contact`), the horizontal force from the centre of mass's acceleration as in
    the undamped model (:func:`rocking.dynamics.cylinder3d.support_force`; w moves S only
    vertically)."""
    th, ph = y[0], y[1]
    cph, sph = math.cos(ph), math.sin(ph)
    axv = F[0] + F[2] * tau
    ayv = F[1] + F[3] * tau
    support_force(math.sin(th), math.cos(th), math.sin(0.5 * th), math.cos(0.5 * th), cph,
                  sph, axv * cph + ayv * sph, axv * sph - ayv * cph, y[3], y[4], f[3], f[4],
                  P[6], P[7], P[1], P[3], F, tau, cf)
    cf[0] = contact_force_of(y, P) / P[3]


@njit(cache=True, error_model="numpy")
def output(y, P, row):
    """(θ, φ, w, θ̇, φ̇, ẇ): the kernel state without D."""
    for i in range(6):
        row[i] = y[i]


@njit(cache=True, error_model="numpy")
def rocking_energy(y, P):
    """Rocking energy above rest ½R²(κo θ̇² + μ φ̇²) + gR(cos(α−θ) − cos α) [J/kg]."""
    R, ko, g, s, c = P[1], P[2], P[3], P[6], P[7]
    th = y[0]
    # cos(α − θ) − cos α = sin α sin θ − cos α (1 − cos θ), written without cancellation.
    st = math.sin(th)
    omc = inertia.one_minus_cos(th)
    dpot = s * st - c * omc
    return 0.5 * R * R * (ko * y[3] * y[3] + inertia.mu_of(st, omc, s, c) * y[4] * y[4]) \
        + g * R * dpot


@njit(cache=True, error_model="numpy")
def total_energy(y, P):
    """Whole mechanical energy above rest per unit mass [J/kg]: the rocking energy plus the
    vertical motion and the contact spring, ½[ẇ² + 2R sin(α − θ) θ̇ ẇ] + ½ωn² w² (E_d of
    :func:`energy` minus gR cos α). Only the ground's work and the dashpot change it, so it
    is what the driver's "decided" test bounds (:func:`rocking.dynamics.driver.decided`)."""
    R, wn, s, c = P[1], P[4], P[6], P[7]
    th, thd, wd = y[0], y[3], y[5]
    sam = s * math.cos(th) - c * math.sin(th)  # sin(α − θ)
    return rocking_energy(y, P) + 0.5 * (wd * wd + 2.0 * R * sam * thd * wd) \
        + 0.5 * wn * wn * y[2] * y[2]


@njit(cache=True, error_model="numpy")
def integrate(run):
    """Integrate the model (:func:`rocking.dynamics.driver.integrate` with this model), with
    the validity monitors and the vertical forcing."""
    return driver.integrate(rhs, driver.no_impact, rocking_energy, total_energy, output,
                            observe, contact, driver.watch, factor, solve, ros_step, run)


@njit(cache=True, error_model="numpy")
def integrate_level(run):
    """:func:`integrate` without the vertical forcing."""
    return driver.integrate(rhs_level, driver.no_impact, rocking_energy, total_energy, output,
                            observe, contact, driver.watch, factor, solve, ros_step, run)


@njit(cache=True, error_model="numpy")
def integrate_vertical_bare(run):
    """:func:`integrate` without the monitors."""
    return driver.integrate(rhs, driver.no_impact, rocking_energy, total_energy, output,
                            observe, contact, driver.no_watch, factor, solve, ros_step, run)


@njit(cache=True, error_model="numpy")
def integrate_bare(run):
    """:func:`integrate` without the monitors nor the vertical forcing."""
    return driver.integrate(rhs_level, driver.no_impact, rocking_energy, total_energy, output,
                            observe, contact, driver.no_watch, factor, solve, ros_step, run)


KERNELS = (integrate, integrate_level, integrate_vertical_bare, integrate_bare)
"""The entry points in the order of :data:`rocking.dynamics.driver.VARIANTS`."""


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
    kin = 0.5 * (R * R * cylinder.kappa_o * thd**2
                 + R * R * cylinder.spin_inertia(th) * phd**2 + wd**2
                 + 2.0 * R * np.sin(a - th) * thd * wd)
    return kin + g * R * np.cos(a - th) + 0.5 * omega_n**2 * w**2
