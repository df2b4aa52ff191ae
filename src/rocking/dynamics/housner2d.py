"""2D Housner rocking of a block or of the planar section of a cylinder (signed tilt θ).

Equation of motion (docs/equations.md, "2D Housner model"), pivot on the base edge on the
side σ = sgn θ::

    θ̈ = −p² [(1 + a_z/g) sin(α σ − θ) + cos(α σ − θ) a_x/g]

(a_z the vertical ground acceleration, positive up: gravity becomes g + a_z).

At θ = 0 the pivot changes and the angular velocity is multiplied by the restitution
coefficient e (Housner's impact, :func:`impact`). The pivot side is kept in the parameters
(``P[0]``), so a step that crosses θ = 0 is computed with the pre-impact equation; the driver
(:mod:`.driver`) finds the impact time on the step's Hermite interpolant, lands there with a
genuine step, applies the impact map and restarts. An impact after which the body is back at
rest (driver's rest criterion) ends the rocking episode: the caller looks for the next uplift
in the record.

Squat bodies (tan α above ``body.SQUAT_TAN_ALPHA``) have e = 0 (:mod:`.bodies`): the first
impact leaves θ = θ̇ = 0, whose energy is below the rest criterion's floor, so the impact
ends the episode exactly (no chatter); :func:`free_peak` gives the peak already reached.
:func:`restitution_extras` reports the clipping in the result.

Error control: relative, with absolute floors 1e-6 α on θ and 1e-6 p α on θ̇ (θ passes
through zero at every impact, so a purely relative control would stall there).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rocking.constants import G
from rocking.dynamics import driver
from rocking.dynamics._rk import rk_step
from rocking.dynamics.bodies import Block, Cylinder

STATE = ("theta", "theta_dot")


def params(body: Block | Cylinder, side: float = 1.0) -> np.ndarray:
    """Kernel parameters [side σ, p², sin α, cos α, g, e, κo, R, 1/g], then two entries
    where :func:`rhs` leaves sin(σα − θ), cos(σα − θ) of its last evaluation for
    :func:`contact` (never read back by :func:`rhs`)."""
    return np.array([1.0 if side >= 0 else -1.0, G / (body.kappa_o * body.R),
                     math.sin(body.alpha), math.cos(body.alpha), G, body.e, body.kappa_o,
                     body.R, 1.0 / G, 0.0, 0.0])


def tolerances(body: Block | Cylinder) -> tuple[np.ndarray, np.ndarray]:
    """Absolute floors and tilt weights of (θ, θ̇) in the error scales."""
    return np.array([1e-6 * body.alpha, 1e-6 * body.p * body.alpha]), np.zeros(2)


@njit(cache=True, inline="always", error_model="numpy")
def _rhs(tau, y, P, F, out, vertical, keep):
    """Right-hand side on pivot side P[0] = ±1, ground acceleration F[0] + F[2] τ, vertical
    F[4] + F[5] τ if ``vertical`` (else gravity exactly g); ``keep``: leave sin ψ, cos ψ in
    ``P[9:11]`` for :func:`contact`. The flags are constants of each compiled variant
    (:func:`rhs`, :func:`rhs_level`, :func:`rhs_bare`, :func:`rhs_vertical_bare`)."""
    th = y[0]
    side, p2, s, c, g = P[0], P[1], P[2], P[3], P[4]
    a = F[0] + F[2] * tau
    # (g + a_z)/g: exactly 1 without vertical motion (1 + 0·(1/g) = 1, so no bit differs)
    gr = 1.0 + (F[4] + F[5] * tau) * P[8] if vertical else 1.0
    st = math.sin(th)
    ct = math.cos(th)
    sam = side * s * ct - c * st  # sin(α σ − θ)
    cam = c * ct + side * s * st  # cos(α σ − θ)
    out[0] = y[1]
    out[1] = -p2 * (gr * sam + cam * a / g)
    if keep:
        P[9] = sam
        P[10] = cam


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


@njit(cache=True, error_model="numpy")
def impact(y, P):
    """Housner's impact at θ = 0: θ̇ → e θ̇, the pivot moves to the other edge (+ 0.0: e = 0
    leaves θ̇ = +0, not −0)."""
    y[1] = P[5] * y[1] + 0.0
    P[0] = -P[0]


@njit(cache=True, error_model="numpy")
def contact(tau, y, f, P, F, cf):
    """Support force per unit weight between impacts: ``cf = (N, |F|)``.

    The pivot is the corner (σb, 0) and the centre of mass is at R(−sin ψ, cos ψ) from it,
    ψ = σα − θ (θ > 0 tilts towards +x, as a_x < 0 lifts the body), so its acceleration
    relative to the ground is R(cos ψ θ̈ + sin ψ θ̇², sin ψ θ̈ − cos ψ θ̇²); the support
    supplies m (a_ground + that) + m g ẑ (docs/equations.md, "Validity monitors")."""
    thd, thdd = y[1], f[1]
    g, R = P[4], P[7]
    sam, cam = P[9], P[10]  # sin ψ, cos ψ left by rhs at y (the driver's last evaluation)
    cf[0] = (g + F[4] + F[5] * tau + R * (sam * thdd - cam * thd * thd)) / g
    cf[1] = abs(F[0] + F[2] * tau + R * (cam * thdd + sam * thd * thd)) / g


@njit(cache=True, error_model="numpy")
def output(y, P, row):
    """(θ, θ̇): the kernel state itself."""
    row[0] = y[0]
    row[1] = y[1]


@njit(cache=True, error_model="numpy")
def rocking_energy(y, P):
    """Energy above rest per unit mass, ½κoR²θ̇² + gR[cos(α − |θ|) − cos α] [J/kg]."""
    th = abs(y[0])
    s, c, g, kap, R = P[2], P[3], P[4], P[6], P[7]
    sh = math.sin(0.5 * th)
    return 0.5 * kap * R * R * y[1] * y[1] + g * R * (s * math.sin(th) - 2.0 * c * sh * sh)


@njit(cache=True, error_model="numpy")
def integrate(run):
    """Integrate the model (:func:`rocking.dynamics.driver.integrate` with this model), with
    the validity monitors and the vertical forcing."""
    return driver.integrate(rhs, impact, rocking_energy, rocking_energy, output,
                            driver.no_observe, contact, driver.watch, driver.no_factor,
                            driver.no_solve, rk_step, run)


@njit(cache=True, error_model="numpy")
def integrate_level(run):
    """:func:`integrate` without the vertical forcing."""
    return driver.integrate(rhs_level, impact, rocking_energy, rocking_energy, output,
                            driver.no_observe, contact, driver.watch, driver.no_factor,
                            driver.no_solve, rk_step, run)


@njit(cache=True, error_model="numpy")
def integrate_vertical_bare(run):
    """:func:`integrate` without the monitors."""
    return driver.integrate(rhs_vertical_bare, impact, rocking_energy, rocking_energy,
                            output, driver.no_observe, contact, driver.no_watch,
                            driver.no_factor, driver.no_solve, rk_step, run)


@njit(cache=True, error_model="numpy")
def integrate_bare(run):
    """:func:`integrate` without the monitors nor the vertical forcing."""
    return driver.integrate(rhs_bare, impact, rocking_energy, rocking_energy, output,
                            driver.no_observe, contact, driver.no_watch, driver.no_factor,
                            driver.no_solve, rk_step, run)


KERNELS = (integrate, integrate_level, integrate_vertical_bare, integrate_bare)
"""The entry points in the order of :data:`rocking.dynamics.driver.VARIANTS`."""


def restitution_extras(body: Block | Cylinder) -> dict:
    """Result fields of the restitution the model applies: ``restitution`` (e [-]),
    ``restitution_clipped`` (the default formula was negative and e set to 0) and, when
    clipped, ``restitution_note`` (one line for the user)."""
    out = {"restitution": body.e, "restitution_clipped": body.restitution_clipped}
    if body.restitution_clipped:
        out["restitution_note"] = body.restitution_note
    return out


def impact_friction(body: Block | Cylinder) -> float:
    """Friction an impact needs, |J_x|/J_z = (1 − e)/((1 + e) tan α) [-].

    The impulse at the new corner is the change of momentum of the centre of mass: v_G =
    θ̇ (h, σb) on the corner (σb, 0), so from θ̇⁻ about the old corner to e θ̇⁻ about the new
    one v_G jumps by θ̇⁻ [(e − 1) h, −σ (1 + e) b] (docs/equations.md, "Validity
    monitors"). The ratio does
    not depend on the impact's speed; e = 0 (squat body) gives 1/tan α.
    """
    return (1.0 - body.e) / ((1.0 + body.e) * body.tan_alpha)


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
    block must first climb back over θ = α to avoid falling. With e = 0 (squat body) the
    impact stops the body: the peak is the present |θ|.

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
