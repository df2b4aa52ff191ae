"""Undamped 3D bounded rocking-and-wobbling cylinder (2 DOF: tilt θ > 0, rolling angle φ).

Equations of motion (docs/equations.md, "3D undamped model")::

    θ̈ = −p² [(1 + a_z/g) sin(α − θ) + cos(α − θ) a_r/g] + μ'(θ) φ̇²/(2 κo)
    d/dt [μ(θ) φ̇] = (sin α + sin(θ − α)) a_t / R

The second line is the φ equation multiplied by μ(θ): μφ̈ + μ'θ̇φ̇ is the derivative of the
spin momentum L = μ(θ)φ̇. The kernel integrates the state (θ, φ, θ̇, L) instead of
(θ, φ, θ̇, φ̇) because L is smooth where φ̇ is not: in a quasi-impact θ drops to 1e-9 … 1e-11
rad and φ̇ = L/μ(θ) ≈ L/(κt θ²) spikes to 1e8 … 1e9 rad/s, while L only changes through the
ground acceleration (and not at all in free vibration, so the spin momentum is conserved to
round-off). The vertical ground acceleration a_z (positive up) only changes gravity to g + a_z
(docs/equations.md, "Vertical ground motion"). Inputs and outputs use (θ, φ, θ̇, φ̇).
Differences of nearly equal numbers are written cancellation-free:
sin α + sin(θ − α) = 2 cos(α − θ/2) sin(θ/2) and μ from :mod:`.inertia`.

Error control (:func:`tolerances`) is relative on θ (no absolute floor: a tolerance like
1e-6 rad on θ would be meaningless at θ = 1e-11); θ ≤ 0 at a step end is a rejected step,
and a failure once the step cannot shrink further. The spin momentum is given a small
absolute floor (1e-6 of the momentum of wobbling at θ ~ α) so that steps do not collapse
where L changes sign under ground motion. The model is integrated by the explicit
Dormand–Prince pair through the driver (:mod:`.driver`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy.optimize import brentq

from rocking.constants import G
from rocking.dynamics import driver, inertia
from rocking.dynamics._numerics import EPS
from rocking.dynamics._rk import rk_step
from rocking.dynamics.bodies import Cylinder, mu

STATE = ("theta", "phi", "theta_dot", "phi_dot")


def params(body: Cylinder) -> np.ndarray:
    """Kernel parameters [side = 1, p², sin α, cos α, κo, R, g, 1/g], then :data:`N_SCRATCH`
    entries :func:`rhs` fills for :func:`contact`."""
    return np.concatenate(([1.0, G / (body.kappa_o * body.R), math.sin(body.alpha),
                            math.cos(body.alpha), body.kappa_o, body.R, G, 1.0 / G],
                           np.zeros(N_SCRATCH)))


N_SCRATCH = 10
"""Entries after the parameters where :func:`rhs` leaves sin θ, cos θ, sin(θ/2), cos(θ/2),
cos φ, sin φ, μ, μ', a_r, a_t of its last evaluation (:func:`contact` reads them: the
monitors cost no trigonometry; nothing in :func:`rhs` reads them back)."""


def tolerances(body: Cylinder) -> tuple[np.ndarray, np.ndarray]:
    """Absolute floors and tilt weights of (θ, φ, θ̇, L) in the error scales.

    θ: 0 (purely relative); φ: 1 rad; θ̇: p α (the rate of a rocking cycle of amplitude α);
    L: 1e-6 κt α² p.
    """
    p = body.p
    floor = np.array([0.0, 1.0, p * body.alpha, 1e-6 * body.kappa_t * body.alpha**2 * p])
    return floor, np.zeros(4)


def to_state(body: Cylinder, y: np.ndarray) -> np.ndarray:
    """Kernel state (θ, φ, θ̇, L = μ(θ)φ̇) of a state (θ, φ, θ̇, φ̇)."""
    return np.array([y[0], y[1], y[2], float(mu(y[0], body.alpha)) * y[3]])


@njit(cache=True, inline="always", error_model="numpy")
def _rhs(tau, y, P, F, out, vertical, keep):
    """Right-hand side for the state (θ, φ, θ̇, L), ground acceleration F[0:2] + F[2:4] τ,
    vertical F[4] + F[5] τ if ``vertical`` (else gravity exactly g); ``keep``: leave the
    terms :func:`contact` reads in ``P[8:18]``. The flags are constants of each compiled
    variant (:func:`rhs`, :func:`rhs_level`, :func:`rhs_bare`, :func:`rhs_vertical_bare`)."""
    th, ph, thd, L = y[0], y[1], y[2], y[3]
    p2, s, c, kap, R, g = P[1], P[2], P[3], P[4], P[5], P[6]
    axg = F[0] + F[2] * tau
    ayg = F[1] + F[3] * tau
    # (g + a_z)/g: exactly 1 without vertical motion (1 + 0·(1/g) = 1, so no bit differs)
    gr = 1.0 + (F[4] + F[5] * tau) * P[7] if vertical else 1.0
    st = math.sin(th)
    ct = math.cos(th)
    sh = math.sin(0.5 * th)
    ch = math.cos(0.5 * th)
    omc = 2.0 * sh * sh
    mu_ = inertia.mu_of(st, omc, s, c)
    phd = L / mu_
    cph = math.cos(ph)
    sph = math.sin(ph)
    a_r = axg * cph + ayg * sph
    a_t = axg * sph - ayg * cph
    sam = s * ct - c * st  # sin(α − θ)
    cam = c * ct + s * st  # cos(α − θ)
    mup = inertia.mu_prime_of(st, ct, omc, s, c)
    out[0] = thd
    out[1] = phd
    out[2] = -p2 * (gr * sam + cam * a_r / g) + mup * phd * phd / (2.0 * kap)
    if keep:
        P[8], P[9], P[10], P[11], P[12] = st, ct, sh, ch, cph
        P[13], P[14], P[15], P[16], P[17] = sph, mu_, mup, a_r, a_t
    # sin α + sin(θ − α) = 2 cos(α − θ/2) sin(θ/2)
    out[3] = 2.0 * (c * ch + s * sh) * sh * a_t / R


@njit(cache=True, error_model="numpy")
def rhs(tau, y, P, F, out):
    """:func:`_rhs` with the vertical forcing, for the monitors."""
    _rhs(tau, y, P, F, out, True, True)


@njit(cache=True, error_model="numpy")
def rhs_level(tau, y, P, F, out):
    """:func:`_rhs` without the vertical forcing, for the monitors."""
    _rhs(tau, y, P, F, out, False, True)


@njit(cache=True, error_model="numpy")
def rhs_vertical_bare(tau, y, P, F, out):
    """:func:`_rhs` with the vertical forcing, no monitors."""
    _rhs(tau, y, P, F, out, True, False)


@njit(cache=True, error_model="numpy")
def rhs_bare(tau, y, P, F, out):
    """:func:`_rhs` without the vertical forcing nor the monitors."""
    _rhs(tau, y, P, F, out, False, False)


@njit(cache=True, inline="always", error_model="numpy")
def support_force(st, ct, sh, ch, cph, sph, a_r, a_t, thd, phd, thdd, phdd, s, c, R, g, F,
                  tau, cf):
    """The force the support supplies, per unit weight (shared by the undamped and damped
    3D models): ``cf = (N, |F_h|)`` with N from gravity, the vertical ground motion and the
    centre of mass's vertical acceleration.

    The centre of mass is at r_S = ρ(θ)(cos φ, sin φ, 0) + (0, 0, R cos(α − θ)) relative to
    the ground (docs/equations.md, "Kinematics and Lagrangian"), ρ = R(sin α − sin(α − θ)),
    ρ' = R cos(α − θ), ρ'' = R sin(α − θ); its acceleration along (cos φ, sin φ), along
    (−sin φ, cos φ) and up is ρ'θ̈ + ρ''θ̇² − ρφ̇², ρφ̈ + 2ρ'θ̇φ̇ and
    R sin(α − θ)θ̈ − R cos(α − θ)θ̇². Contact force = m (a_ground + r̈_S) + m g ẑ
    (docs/equations.md, "Validity monitors"). ``st``, ``ct``, ``sh``, ``ch``, ``cph``,
    ``sph``: sin and cos of θ, θ/2 and φ; ``a_r``, ``a_t``: the horizontal ground
    acceleration along and across the tilt (as in :func:`rhs`); ``s``, ``c``: sin α, cos α.
    """
    sam = s * ct - c * st
    cam = c * ct + s * st
    rho = 2.0 * R * sh * (c * ch + s * sh)  # R(sin α − sin(α − θ)) without cancellation
    a_rad = a_r + R * (cam * thdd + sam * thd * thd) - rho * phd * phd
    a_tan = -a_t + rho * phdd + 2.0 * R * cam * thd * phd
    cf[0] = (g + F[4] + F[5] * tau + R * (sam * thdd - cam * thd * thd)) / g
    cf[1] = math.sqrt(a_rad * a_rad + a_tan * a_tan) / g


@njit(cache=True, error_model="numpy")
def contact(tau, y, f, P, F, cf):
    """Support force (N, |F_h|) per unit weight of the state (θ, φ, θ̇, L) with derivative
    ``f`` (:func:`support_force`; φ̈ = (L̇ − μ'θ̇φ̇)/μ), from what :func:`rhs` left in
    ``P[8:18]`` at ``y`` (the driver evaluates ``rhs`` at ``y`` just before)."""
    phd = f[1]
    phdd = (f[3] - P[15] * y[2] * phd) / P[14]
    support_force(P[8], P[9], P[10], P[11], P[12], P[13], P[16], P[17], y[2], phd, f[2],
                  phdd, P[2], P[3], P[5], P[6], F, tau, cf)


@njit(cache=True, error_model="numpy")
def output(y, P, row):
    """(θ, φ, θ̇, φ̇) of the kernel state."""
    row[0] = y[0]
    row[1] = y[1]
    row[2] = y[2]
    row[3] = y[3] / inertia.mu(y[0], P[2], P[3])


@njit(cache=True, error_model="numpy")
def rocking_energy(y, P):
    """Energy above rest per unit mass, ½R²(κo θ̇² + L²/μ) + gR(cos(α − θ) − cos α) [J/kg].

    cos(α − θ) − cos α = sin α sin θ − cos α · 2 sin²(θ/2), without cancellation.
    """
    th = y[0]
    s, c, kap, R, g = P[2], P[3], P[4], P[5], P[6]
    st = math.sin(th)
    omc = inertia.one_minus_cos(th)
    pot = g * R * (s * st - c * omc)
    return 0.5 * R * R * (kap * y[2] * y[2] + y[3] * y[3] / inertia.mu_of(st, omc, s, c)) + pot


@njit(cache=True, error_model="numpy")
def integrate(run):
    """Integrate the model (:func:`rocking.dynamics.driver.integrate` with this model), with
    the validity monitors and the vertical forcing."""
    return driver.integrate(rhs, driver.no_impact, rocking_energy, rocking_energy, output,
                            driver.no_observe, contact, driver.watch, driver.no_factor,
                            driver.no_solve, rk_step, run)


@njit(cache=True, error_model="numpy")
def integrate_level(run):
    """:func:`integrate` without the vertical forcing."""
    return driver.integrate(rhs_level, driver.no_impact, rocking_energy, rocking_energy,
                            output, driver.no_observe, contact, driver.watch,
                            driver.no_factor, driver.no_solve, rk_step, run)


@njit(cache=True, error_model="numpy")
def integrate_vertical_bare(run):
    """:func:`integrate` without the monitors."""
    return driver.integrate(rhs_vertical_bare, driver.no_impact, rocking_energy,
                            rocking_energy, output, driver.no_observe, contact,
                            driver.no_watch, driver.no_factor, driver.no_solve, rk_step, run)


@njit(cache=True, error_model="numpy")
def integrate_bare(run):
    """:func:`integrate` without the monitors nor the vertical forcing."""
    return driver.integrate(rhs_bare, driver.no_impact, rocking_energy, rocking_energy,
                            output, driver.no_observe, contact, driver.no_watch,
                            driver.no_factor, driver.no_solve, rk_step, run)


KERNELS = (integrate, integrate_level, integrate_vertical_bare, integrate_bare)
"""The entry points in the order of :data:`rocking.dynamics.driver.VARIANTS`."""


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
