"""Public rocking analyses: free vibration and response to a ground motion.

This module validates the input, finds the uplift from rest, dispatches to the compiled
kernels (:mod:`.cylinder3d`, :mod:`.housner2d`, :mod:`.cylinder3d_damped`),
decides the motion after the record ends by invariants (the "free tail") and assembles a
:class:`rocking.dynamics.result.Response`.

Free tail. Once the excitation has ended the undamped models cannot gain energy, so their
future is decided without integrating to the end of time:

- 3D: energy E and spin momentum L = μ(θ)φ̇ are conserved, θ oscillates between the roots
  of V(θ) = gR cos(α − θ) + R²L²/(2μ(θ)) = E, and every later tilt maximum is the first root
  above the present tilt (:func:`.cylinder3d.free_peak`); the cylinder overturns iff V
  stays below E up to π/2.
- 2D: the energy above rest is multiplied by e² at each impact, so the next peak is the
  largest and follows from energy in closed form (:func:`rocking.dynamics.housner2d.free_peak`).

The kernel is then run in free vibration only up to that next peak (at most one swing) to
date it; the decision itself is the invariant one.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import finite, nonnegative_finite, positive_finite
from ..constants import G
from ..motions.motion import GroundMotion
from . import cylinder3d, cylinder3d_damped, housner2d
from ._rk import tableau
from .bodies import Block, Cylinder
from .result import QuasiImpacts, Response, Status

MODELS = ("3d", "3d-damped", "2d")

DEFAULT_RTOL = {"3d": 1e-8, "2d": 1e-8, "3d-damped": cylinder3d_damped.DEFAULT_RTOL}
"""Default relative tolerance per model [-].

From ``python -m rocking.benchmarks dynamics``: in every benchmark case the θmax error is
≤ 1e-3 with the right limit-state decision from rtol 1e-6 on ("3d" El Centro: 1.6e-4 at 1e-6,
1.1e-2 at 1e-5; "2d": < 1e-10 at any rtol, the record dt caps its steps). The undamped 3D
default is tighter, 1e-8 (θmax error 9e-6, +24 % steps), because releases at 0.999α must
survive: the energy margin to the barrier at θ = α is only gR(0.001α)²/2 ≈ 2e-8 gR for
tan α = 0.2, and the energy drift through quasi-impacts is ~1e-7 at rtol 1e-6 but ~1e-9 at
1e-8 (tests/test_cylinder3d.py). The 2D default follows for consistency of comparisons. The
damped default, 1e-8, comes from ``python -m rocking.benchmarks damped``: θmax error ≤ 5e-5 on
the paper's whole (ωn, ζ) grid, where 1e-6 reaches 1e-2 at ωn = 2000, ζ = 0.5."""

METHOD = "dp5"
"""Runge–Kutta pair of the undamped kernels (see :mod:`._rk` for the measurement)."""

THETA_EPS = 1e-7
"""Tilt at which a 3D analysis starts from rest at uplift [rad] (equations.md)."""

MAX_STEPS = 20_000_000
"""Budget of integration steps of one kernel call."""

_FAILURES = {
    -1: "step-size underflow (the error could not be controlled)",
    -2: "the tilt reached zero: theta <= 0 (nearly planar 3D motion; use model='2d')",
    -3: "non-finite state (NaN or inf)",
    -4: "too many integration steps",
}
_HALF_PI = 0.5 * math.pi


# ----------------------------------------------------------------------------- validation
def _check_model(model: str, body) -> str:
    if model not in MODELS:
        raise ValueError(f"model must be one of {list(MODELS)}, got {model!r}")
    if not isinstance(body, (Cylinder, Block)):
        raise ValueError(f"body must be a Cylinder or a Block, got {type(body).__name__}")
    if model != "2d" and not isinstance(body, Cylinder):
        raise ValueError(f"model={model!r} needs a Cylinder, got a {type(body).__name__} "
                         "(a rectangular block only has the 2D model, model='2d')")
    return model


def _check_common(rtol, omega_n, zeta, model) -> float:
    positive_finite("omega_n", omega_n)
    nonnegative_finite("zeta", zeta)
    if rtol is None:
        return DEFAULT_RTOL[model]
    r = positive_finite("rtol", rtol)
    if r >= 1e-2:
        raise ValueError(f"rtol must be below 1e-2, got {rtol!r}")
    return r


def _check_stop(stop_at) -> float:
    if stop_at is None:
        return -1.0
    return positive_finite("stop_at", stop_at)


# ----------------------------------------------------------------------------- uplift
def _uplift_3d(ax: np.ndarray, ay: np.ndarray, dt: float, threshold: float, k_from: int = 0,
               tau_from: float = 0.0):
    """First time at or after (k_from, tau_from) where |a| > threshold, |a| linear per interval.

    Returns ``(k, tau, a_x, a_y)`` (interval, time in it, acceleration there) or None.
    """
    n = ax.size
    ak = (ax[k_from] + (ax[k_from + 1] - ax[k_from]) * tau_from / dt) if k_from + 1 < n else 0.0
    bk = (ay[k_from] + (ay[k_from + 1] - ay[k_from]) * tau_from / dt) if k_from + 1 < n else 0.0
    if math.hypot(ak, bk) > threshold:
        return k_from, tau_from, ak, bk
    mag = np.hypot(ax[k_from + 1:], ay[k_from + 1:])
    above = np.flatnonzero(mag > threshold)
    if above.size == 0:
        return None
    j = k_from + 1 + int(above[0])
    k = j - 1
    a0 = np.array([ax[k], ay[k]])
    d = np.array([ax[j] - ax[k], ay[j] - ay[k]])
    # |a0 + s d| = threshold: the root in (0, 1] of |d|² s² + 2 (a0·d) s + |a0|² − thr² = 0
    qa, qb, qc = d @ d, a0 @ d, a0 @ a0 - threshold**2
    disc = max(qb * qb - qa * qc, 0.0)
    s = (-qb + math.sqrt(disc)) / qa if qa > 0.0 else 1.0
    s = min(max(s, 0.0), 1.0)
    tau = s * dt
    if k == k_from:
        tau = max(tau, tau_from)
    a = a0 + (tau / dt) * d
    return k, tau, float(a[0]), float(a[1])


# ----------------------------------------------------------------------------- kernels
def _kernel_3d(body, ax, ay, dt, k0, tau0, t_offset, y0, t_end, stop_level, rtol, history,
               until_peak):
    return cylinder3d.integrate(
        cylinder3d.params(body), cylinder3d.error_floor(body), ax, ay, dt, int(k0),
        float(tau0), float(t_offset), np.asarray(y0, dtype=float), float(t_end),
        float(stop_level), float(rtol), tableau(METHOD), bool(history), bool(until_peak),
        MAX_STEPS)


def _kernel_2d(body, ax, dt, k0, tau0, t_offset, y0, side, t_end, stop_level, rtol, history,
               until_peak):
    return housner2d.integrate(
        housner2d.params(body, side), housner2d.error_floor(body), ax, dt, int(k0),
        float(tau0), float(t_offset), np.asarray(y0, dtype=float), float(t_end),
        float(stop_level), float(rtol), tableau(METHOD), bool(history), bool(until_peak),
        MAX_STEPS)


def _kernel_damped(body, ax, ay, dt, t0, y0, t_end, stop_level, rtol, history, omega_n, zeta):
    """Adapter to ``cylinder3d_damped.integrate_full`` (same contract, 6-component state)."""
    mod = cylinder3d_damped
    omega_n, zeta = mod.check_parameters(omega_n, zeta)
    stop = stop_level if stop_level > 0.0 else 10.0
    return mod.integrate_full(
        np.asarray(y0, dtype=float), float(t0), float(t_end), ax, ay, float(dt), 1.0,
        body.alpha, body.R, body.kappa_o, G, omega_n, zeta, float(rtol), float(stop),
        bool(history), MAX_STEPS)


def _free_chunk(body) -> float:
    """Record-interval length used for unforced integration (caps the step) [s]."""
    return 0.1 / body.p


# ----------------------------------------------------------------------------- assembly
class _Acc:
    """Accumulates kernel segments into one response."""

    def __init__(self, width: int, history: bool):
        self.history = history
        self.t: list[np.ndarray] = []
        self.y: list[np.ndarray] = []
        self.ev_t: list[np.ndarray] = []
        self.ev_y: list[np.ndarray] = []
        self.width = width
        self.n_steps = 0
        self.n_rej = 0
        self.theta_max = 0.0
        self.t_theta_max = math.nan
        self.extras: dict = {}

    def add(self, out, skip_first: bool = False) -> None:
        code, t, y, n_steps, n_rej, th_max, t_th_max, ev_t, ev_y, t_stop = out[:10]
        if self.history:
            i0 = 1 if (skip_first and t.size > 1) else 0
            self.t.append(t[i0:])
            self.y.append(y[i0:])
        self.ev_t.append(ev_t)
        self.ev_y.append(ev_y)
        self.n_steps += int(n_steps)
        self.n_rej += int(n_rej)
        if abs(th_max) > self.theta_max:
            self.theta_max = abs(float(th_max))
            self.t_theta_max = float(t_th_max)

    def add_rest(self, t0: float, t1: float) -> None:
        """A stretch at rest (zero state) from t0 to t1."""
        if self.history and t1 > t0:
            self.t.append(np.array([t0, t1]))
            self.y.append(np.zeros((2, self.width)))

    def arrays(self):
        if self.t:
            t = np.concatenate(self.t)
            y = np.concatenate(self.y)
        else:
            t = np.zeros(0)
            y = np.zeros((0, self.width))
        ev_t = np.concatenate(self.ev_t) if self.ev_t else np.zeros(0)
        ev_y = np.concatenate(self.ev_y) if self.ev_y else np.zeros((0, self.width))
        return t, y, ev_t, ev_y


def _status(code: int, t_stop: float) -> tuple[Status, str]:
    if code < 0:
        return Status.FAILED, f"{_FAILURES.get(code, f'kernel code {code}')} at t = {t_stop:.9g} s"
    if code == 1:
        return Status.OVERTURNED, ""
    if code == 2:
        return Status.STOPPED_AT_LIMIT, ""
    return Status.OK, ""


def _response(model: str, acc: _Acc, status: Status, reason: str, uplifted: bool,
              t_uplift: float, omega_n: float, zeta: float) -> Response:
    t, y, ev_t, ev_y = acc.arrays()
    theta_max = acc.theta_max
    if status is not Status.FAILED and not math.isfinite(theta_max):
        status, reason = Status.FAILED, f"non-finite peak tilt {theta_max!r}"
    if status is not Status.FAILED and y.size and not np.all(np.isfinite(y)):
        status, reason = Status.FAILED, "non-finite state in the history"
    w = w_dot = force = None
    if model == "3d-damped":
        th, ph, thd, phd = y[:, 0], y[:, 1], y[:, 3], y[:, 4]
        w, w_dot = y[:, 2], y[:, 5]
        force = G - omega_n**2 * w - 2.0 * zeta * omega_n * w_dot
    elif model == "2d":
        th, thd = y[:, 0], y[:, 1]
        ph = np.zeros_like(th)
        phd = np.zeros_like(th)
    else:
        th, ph, thd, phd = y[:, 0], y[:, 1], y[:, 2], y[:, 3]
    return Response(
        model=model, t=t, theta=th, theta_dot=thd, phi=ph, phi_dot=phd,
        theta_max=float(theta_max), t_theta_max=float(acc.t_theta_max),
        overturned=status is Status.OVERTURNED, status=status,
        quasi_impacts=QuasiImpacts(ev_t, ev_y), n_steps=acc.n_steps, n_rejected=acc.n_rej,
        uplifted=uplifted, t_uplift=float(t_uplift), reason=reason, w=w, w_dot=w_dot,
        contact_force=force, extras=acc.extras,
    )


# ----------------------------------------------------------------------------- free tails
def _decide_tail(body, acc: _Acc, peak: float, run, stop_level: float):
    """Combine the invariant decision ``peak`` with a free run up to the next peak.

    ``run()`` integrates the unforced motion up to its next tilt peak (code 4), overturning
    (1), the stop level (2) or rest (3, 2D). The decision and θmax come from ``peak``; the
    run only supplies the time (and the history). Returns (status, reason).
    """
    acc.extras["free_tail_peak"] = peak
    limit = stop_level if stop_level > 0.0 else _HALF_PI
    record_max, record_t = acc.theta_max, acc.t_theta_max
    if math.isfinite(peak) and peak <= limit and peak <= record_max and not acc.history:
        return Status.OK, ""  # nothing new can happen and no history is wanted
    out = run()
    code = int(out[0])
    if code < 0:
        return _status(code, float(out[9]))
    acc.add(out, skip_first=True)
    if math.isinf(peak) or peak > limit:
        if code in (1, 2):
            return _status(code, float(out[9]))
        acc.theta_max, acc.t_theta_max = limit, math.nan
        status = Status.OVERTURNED if stop_level <= 0.0 else Status.STOPPED_AT_LIMIT
        return status, "decided by energy after the record; the free run did not confirm it"
    if peak > record_max:
        acc.theta_max = peak
        acc.t_theta_max = float(out[6]) if code == 4 else math.nan
    else:
        acc.theta_max, acc.t_theta_max = record_max, record_t
    return Status.OK, ""


def _tail_3d(body, acc: _Acc, y_end: np.ndarray, t_end: float, stop_level: float, rtol: float):
    """Free tail of the undamped 3D model (see the module docstring)."""
    theta, _, theta_dot, phi_dot = (float(v) for v in y_end)
    peak = cylinder3d.free_peak(body, theta, theta_dot, phi_dot)

    def run():
        chunk = _free_chunk(body)
        n = int(math.ceil(400.0 / (body.p * chunk))) + 2  # 400/p s: far beyond one swing
        z = np.zeros(n)
        return _kernel_3d(body, z, z, chunk, 0, 0.0, t_end, y_end, t_end + (n - 1) * chunk,
                          stop_level, rtol, acc.history, True)

    return _decide_tail(body, acc, peak, run, stop_level)


def _tail_2d(body, acc: _Acc, y_end: np.ndarray, side: float, t_end: float, stop_level: float,
             rtol: float):
    """Free tail of the 2D model: next peak from energy and e (closed form)."""
    peak = housner2d.free_peak(body, float(y_end[0]), float(y_end[1]))

    def run():
        chunk = _free_chunk(body)
        n = int(math.ceil(400.0 / (body.p * chunk))) + 2
        z = np.zeros(n)
        return _kernel_2d(body, z, chunk, 0, 0.0, t_end, y_end, side, t_end + (n - 1) * chunk,
                          stop_level, rtol, acc.history, True)

    return _decide_tail(body, acc, peak, run, stop_level)


# ----------------------------------------------------------------------------- public API
def free_vibration(body: Cylinder | Block, theta0: float, phi_dot0: float = 0.0, *,
                   theta_dot0: float = 0.0, phi0: float = 0.0, duration: float,
                   model: str = "3d", rtol: float | None = None, omega_n: float = 2000.0,
                   zeta: float = 5.0, history: bool = True) -> Response:
    """Free rocking (2D) or rocking and wobbling (3D) from an initial state.

    Parameters
    ----------
    body : Cylinder or Block
        The rigid body (a Block only with ``model="2d"``).
    theta0 : float
        Initial tilt [rad]; in 3D in (0, π/2), in 2D signed with |θ0| < π/2.
    phi_dot0 : float
        Initial spin rate φ̇ [rad/s] (3D).
    theta_dot0, phi0 : float
        Initial tilt rate [rad/s] and rolling angle [rad].
    duration : float
        Length of the analysis [s], > 0.
    model : {"3d", "3d-damped", "2d"}
    rtol : float, optional
        Relative tolerance; default :data:`DEFAULT_RTOL` of the model.
    omega_n, zeta : float
        Contact spring–dashpot of "3d-damped" [rad/s], [-] (validated for all models).
    history : bool
        Keep the time histories (False: summary only).

    Returns
    -------
    Response
    """
    _check_model(model, body)
    rtol = _check_common(rtol, omega_n, zeta, model)
    duration = positive_finite("duration", duration)
    theta0 = finite("theta0", theta0)
    phi_dot0 = finite("phi_dot0", phi_dot0)
    theta_dot0 = finite("theta_dot0", theta_dot0)
    phi0 = finite("phi0", phi0)
    if model == "2d":
        if abs(theta0) >= _HALF_PI:
            raise ValueError(f"theta0 must satisfy |theta0| < pi/2, got {theta0!r}")
    elif not 0.0 < theta0 < _HALF_PI:
        raise ValueError(f"theta0 must lie in (0, pi/2) for model={model!r}, got {theta0!r}")
    if model == "3d-damped":
        y0 = np.array([theta0, phi0, 0.0, theta_dot0, phi_dot0, 0.0])
        e = np.zeros(0)
        out = _kernel_damped(body, e, e, 1.0, 0.0, y0, duration, -1.0, rtol, history,
                             omega_n, zeta)
        acc = _Acc(6, history)
        acc.add(out)
        if len(out) > 10:
            acc.extras.update(dissipated=float(out[10]), n_tension=int(out[11]),
                              contact_force_min=float(out[12]))
        status, reason = _status(int(out[0]), float(out[9]))
        return _response(model, acc, status, reason, True, 0.0, omega_n, zeta)
    chunk = min(_free_chunk(body), duration)
    n = int(math.ceil(duration / chunk)) + 1
    z = np.zeros(n)
    if model == "2d":
        out = _kernel_2d(body, z, chunk, 0, 0.0, 0.0, np.array([theta0, theta_dot0]),
                         1.0 if theta0 > 0 or (theta0 == 0 and theta_dot0 >= 0) else -1.0,
                         duration, -1.0, rtol, history, False)
        acc = _Acc(2, history)
    else:
        out = _kernel_3d(body, z, z, chunk, 0, 0.0, 0.0,
                         np.array([theta0, phi0, theta_dot0, phi_dot0]), duration, -1.0, rtol,
                         history, False)
        acc = _Acc(4, history)
    acc.theta_max = abs(theta0)
    acc.t_theta_max = 0.0
    acc.add(out)
    code = int(out[0])
    status, reason = _status(code, float(out[9]))
    if code == 3:
        reason = f"came back to rest at t = {float(out[9]):.9g} s"
        acc.add_rest(float(out[9]), duration)
    return _response(model, acc, status, reason, True, 0.0, omega_n, zeta)


def ground_response(body: Cylinder | Block, motion: GroundMotion, *, model: str = "3d",
                    scale: float | None = None, pga_ratio: float | None = None,
                    stop_at: float | None = None,
                    rtol: float | None = None, omega_n: float = 2000.0, zeta: float = 5.0,
                    history: bool = True, free_tail: bool = True) -> Response:
    """Response of a body initially at rest to a (scaled) ground motion.

    Parameters
    ----------
    body : Cylinder or Block
        The rigid body (a Block only with ``model="2d"``).
    motion : GroundMotion
        Ground accelerations [m/s²]; "2d" uses ``motion.ax`` only, the 3D models need both
        components (a unidirectional motion is a ValueError pointing to "2d").
    model : {"3d", "3d-damped", "2d"}
    scale : float, optional
        Factor on both components [-], > 0 (default 1: the motion as it is).
    pga_ratio : float, optional
        Instead of ``scale``: the normalized intensity PGA/(g tan α) [-] to scale the
        motion's vector PGA to (``scale = pga_ratio·g·tan α / PGA``).
    stop_at : float, optional
        End as soon as |θ| > stop_at [rad] (status STOPPED_AT_LIMIT).
    rtol : float, optional
        Relative tolerance; default :data:`DEFAULT_RTOL` of the model.
    omega_n, zeta : float
        Contact spring–dashpot of "3d-damped" [rad/s], [-].
    history : bool
        Keep the time histories (False: summary-only hot path).
    free_tail : bool
        Decide the motion after the record ends by invariants (undamped models) and include
        the next swing in θmax.

    Returns
    -------
    Response
    """
    _check_model(model, body)
    rtol = _check_common(rtol, omega_n, zeta, model)
    if not isinstance(motion, GroundMotion):
        raise ValueError(f"motion must be a GroundMotion, got {type(motion).__name__}")
    if pga_ratio is not None:
        if scale is not None:
            raise ValueError(f"give scale or pga_ratio, not both; got scale={scale!r}, "
                             f"pga_ratio={pga_ratio!r}")
        if motion.pga <= 0.0:
            raise ValueError(f"motion {motion.name!r} has zero PGA: pga_ratio cannot scale it")
        scale = positive_finite("pga_ratio", pga_ratio) * G * body.tan_alpha / motion.pga
    scale = positive_finite("scale", 1.0 if scale is None else scale)
    stop_level = _check_stop(stop_at)
    if model != "2d" and motion.is_unidirectional:
        raise ValueError(
            f"motion {motion.name!r} has a zero component: unidirectional excitation of the 3D "
            "model is exactly planar and reaches theta = 0 where the model is undefined; "
            "use model='2d'")
    dt = motion.dt
    ax = motion.ax * scale
    ay = motion.ay * scale
    t_end = motion.duration
    threshold = G * body.tan_alpha
    if model == "2d":
        return _ground_2d(body, ax, dt, t_end, threshold, stop_level, rtol, history, free_tail,
                          omega_n, zeta)
    width = 6 if model == "3d-damped" else 4
    acc = _Acc(width, history)
    up = _uplift_3d(ax, ay, dt, threshold)
    if up is None:
        acc.add_rest(0.0, t_end)
        acc.t_theta_max = 0.0
        return _response(model, acc, Status.OK, "", False, math.nan, omega_n, zeta)
    k, tau, a_x, a_y = up
    t_up = k * dt + tau
    acc.add_rest(0.0, t_up)
    phi0 = math.atan2(-a_y, -a_x)  # along the D'Alembert force
    if model == "3d-damped":
        return _ground_damped(body, acc, ax, ay, dt, t_up, phi0, t_end, threshold, stop_level,
                              rtol, history, omega_n, zeta)
    y0 = np.array([THETA_EPS, phi0, 0.0, 0.0])
    out = _kernel_3d(body, ax, ay, dt, k, tau, 0.0, y0, t_end, stop_level, rtol, history,
                     False)
    acc.add(out)
    code = int(out[0])
    status, reason = _status(code, float(out[9]))
    if code == 0 and free_tail:
        status, reason = _tail_3d(body, acc, out[2][-1], t_end, stop_level, rtol)
    return _response(model, acc, status, reason, True, t_up, omega_n, zeta)


def _uplift_2d(ax: np.ndarray, dt: float, threshold: float, k_from: int, tau_from: float):
    """First time at or after (k_from, tau_from) with |a_x| > threshold: (k, tau, side)."""
    n = ax.size
    if k_from + 1 < n:
        a = ax[k_from] + (ax[k_from + 1] - ax[k_from]) * tau_from / dt
        if abs(a) > threshold:
            return k_from, tau_from, -math.copysign(1.0, a)
    above = np.flatnonzero(np.abs(ax[k_from + 1:]) > threshold)
    if above.size == 0:
        return None
    j = k_from + 1 + int(above[0])
    k = j - 1
    level = math.copysign(threshold, ax[j])
    d = ax[j] - ax[k]
    s = (level - ax[k]) / d if d != 0.0 else 1.0
    tau = min(max(s, 0.0), 1.0) * dt
    if k == k_from:
        tau = max(tau, tau_from)
    return k, tau, -math.copysign(1.0, ax[j])


def _ground_2d(body, ax, dt, t_end, threshold, stop_level, rtol, history, free_tail, omega_n,
               zeta) -> Response:
    acc = _Acc(2, history)
    k, tau = 0, 0.0
    t_rest = 0.0
    t_first = math.nan
    status, reason = Status.OK, ""
    out = None
    stalls = 0
    while True:
        up = _uplift_2d(ax, dt, threshold, k, tau)
        if up is None:
            acc.add_rest(t_rest, t_end)
            out = None
            break
        k, tau, side = up
        t_up = k * dt + tau
        if not math.isfinite(t_first):
            t_first = t_up
        acc.add_rest(t_rest, t_up)
        out = _kernel_2d(body, ax, dt, k, tau, 0.0, np.zeros(2), side, t_end, stop_level, rtol,
                         history, False)
        acc.add(out)
        code = int(out[0])
        t_stop = float(out[9])
        if code != 3:
            status, reason = _status(code, t_stop)
            break
        # Back at rest (Zeno guard): look for the next uplift after t_stop.
        stalls = stalls + 1 if t_stop - t_up <= 1e-12 * max(1.0, t_up) else 0
        if stalls > 10:
            status, reason = Status.FAILED, f"no progress from rest at t = {t_stop:.9g} s"
            out = None
            break
        k = min(int(t_stop // dt), ax.size - 2)
        tau = t_stop - k * dt
        t_rest = t_stop
        if t_stop >= t_end:
            out = None
            break
    if math.isnan(t_first):
        acc.t_theta_max = 0.0
        return _response("2d", acc, Status.OK, "", False, math.nan, omega_n, zeta)
    if out is not None and int(out[0]) == 0 and free_tail:
        y_end = out[2][-1]
        # On θ = 0 right after an impact the body moves to the side of θ̇.
        side = math.copysign(1.0, y_end[0] if y_end[0] != 0.0 else y_end[1])
        status, reason = _tail_2d(body, acc, y_end, side, t_end, stop_level, rtol)
    return _response("2d", acc, status, reason, True, t_first, omega_n, zeta)


def _ground_damped(body, acc, ax, ay, dt, t_up, phi0, t_end, threshold, stop_level, rtol,
                   history, omega_n, zeta) -> Response:
    """3d-damped through the adapter; uplifts again after coming back to rest (code 3)."""
    t_first = t_up
    status, reason = Status.OK, ""
    while True:
        y0 = np.array([THETA_EPS, phi0, 0.0, 0.0, 0.0, 0.0])
        out = _kernel_damped(body, ax, ay, dt, t_up, y0, t_end, stop_level, rtol, history,
                             omega_n, zeta)
        acc.add(out)
        if len(out) > 10:
            acc.extras["dissipated"] = acc.extras.get("dissipated", 0.0) + float(out[10])
            acc.extras["n_tension"] = acc.extras.get("n_tension", 0) + int(out[11])
            acc.extras["contact_force_min"] = min(acc.extras.get("contact_force_min", G),
                                                  float(out[12]))
        code = int(out[0])
        t_stop = float(out[9])
        if code != 3 or t_stop >= t_end:
            status, reason = _status(code, t_stop)
            break
        k = min(int(t_stop // dt), ax.size - 2)
        up = _uplift_3d(ax, ay, dt, threshold, k, t_stop - k * dt)
        if up is None:
            acc.add_rest(t_stop, t_end)
            break
        k, tau, a_x, a_y = up
        t_next = k * dt + tau
        if t_next <= t_stop + 1e-12 and t_next - t_up <= 1e-12:
            status, reason = Status.FAILED, f"no progress from rest at t = {t_stop:.9g} s"
            break
        acc.add_rest(t_stop, t_next)
        t_up = t_next
        phi0 = math.atan2(-a_y, -a_x)
    return _response("3d-damped", acc, status, reason, True, t_first, omega_n, zeta)
