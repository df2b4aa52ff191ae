"""Public rocking analyses: free vibration and response to a ground motion.

This module validates the input, finds the uplift from rest, runs the models through the one
driver (:mod:`.models`, :mod:`.driver`), looks for the next uplift after the body came back
to rest, decides the motion after the record ends by invariants (the "free tail") and
assembles a :class:`rocking.dynamics.result.Response`.

Free tail. Once the excitation has ended the undamped models cannot gain energy, so their
future is decided without integrating to the end of time:

- 3D: energy E and spin momentum L = μ(θ)φ̇ are conserved, θ oscillates between the roots
  of V(θ) = gR cos(α − θ) + R²L²/(2μ(θ)) = E, and every later tilt maximum is the first root
  above the present tilt (:func:`.cylinder3d.free_peak`); the cylinder overturns iff V
  stays below E up to π/2.
- 2D: the energy above rest is multiplied by e² at each impact, so the next peak is the
  largest and follows from energy in closed form (:func:`.housner2d.free_peak`).

The kernel is then run in free vibration only up to that next peak (at most one swing) to
date it; the decision itself is the invariant one.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rocking._validate import finite, nonnegative_finite, positive_finite
from rocking.constants import G
from rocking.dynamics import codes, cylinder3d, cylinder3d_damped, driver, housner2d, models
from rocking.dynamics.bodies import Block, Cylinder
from rocking.dynamics.contact import Contact
from rocking.dynamics.names import DAMPED_OMEGA_N, DAMPED_ZETA, MODEL_2D, MODEL_3D, MODEL_3D_DAMPED
from rocking.dynamics.result import QuasiImpacts, Response, Status
from rocking.motions.motion import GroundMotion

MODELS = tuple(models.MODELS)

METHOD = "dp5"
"""Runge–Kutta pair of the undamped models (see :mod:`._rk` for the measurement)."""

THETA_EPS = 1e-7
"""Tilt at which a 3D analysis starts from rest at uplift [rad] (docs/equations.md)."""

MAX_UPLIFT_SPIN = 1e-3
"""Largest spin at uplift (``ground_response(phi_dot0=)``) as a fraction of the pure-wobbling
rate at the uplift tilt :data:`THETA_EPS` (1.6 rad/s for R = 6 m, tan α = 0.2): the spin's
centrifugal term is then 1e-6 of gravity's there and the answers are those of the small-spin
limit (docs/models.md, "The 3D model under one component"); a larger one starts the body
wobbling."""

MAX_STEPS = 20_000_000
"""Budget of integration steps of one kernel call."""

_HALF_PI = 0.5 * math.pi


# ----------------------------------------------------------------------------- validation
def _check_model(model: str, body) -> str:
    if model not in MODELS:
        raise ValueError(f"model must be one of {list(MODELS)}, got {model!r}")
    if not isinstance(body, (Cylinder, Block)):
        raise ValueError(f"body must be a Cylinder or a Block, got {type(body).__name__}")
    if model != MODEL_2D and not isinstance(body, Cylinder):
        raise ValueError(f"model={model!r} needs a Cylinder, got a {type(body).__name__} "
                         "(a rectangular block only has the 2D model, model='2d')")
    return model


def _check_rtol(rtol, model) -> float:
    if rtol is None:
        return models.MODELS[model].rtol
    r = positive_finite("rtol", rtol)
    if r >= 1e-2:
        raise ValueError(f"rtol must be below 1e-2, got {rtol!r}")
    return r


def _check_spin(phi_dot0, model: str, body) -> float:
    """The spin at uplift [rad/s]: 0 for the 2D model; for the 3D models finite, ≥ 0 (under
    one component a negative spin is the mirror image of a positive one) and at most
    :data:`MAX_UPLIFT_SPIN` of the wobbling rate at the uplift tilt."""
    name = "phi_dot0 (the spin at uplift)"
    if model == MODEL_2D:
        if phi_dot0 != 0.0:
            raise ValueError(f"{name} applies to the 3D models, the 2D model has no spin; got "
                             f"{phi_dot0!r}")
        return 0.0
    spin = nonnegative_finite(name, phi_dot0)
    if spin == 0.0:  # the common case costs no wobbling rate
        return spin
    top = MAX_UPLIFT_SPIN * float(body.wobbling_rate(THETA_EPS))
    if spin > top:
        raise ValueError(f"{name} must be at most {top:.3g} rad/s for this body "
                         f"({MAX_UPLIFT_SPIN:g} of the wobbling rate at the uplift tilt "
                         f"{THETA_EPS:g} rad; a larger spin sets it wobbling), got {phi_dot0!r}")
    return spin


def _check_stop(stop_at) -> float:
    if stop_at is None:
        return -1.0
    return positive_finite("stop_at", stop_at)


def default_rest_tilt(model: str, body: Cylinder | Block) -> float:
    """Rest tilt [rad] of ``model`` on ``body`` when none is given: the registry entry's
    (:attr:`rocking.dynamics.models.Model.rest_tilt`)."""
    return models.MODELS[model].rest_tilt(body)


def _check_rest_tilt(rest_tilt, model: str, body) -> float:
    if rest_tilt is None:
        return default_rest_tilt(model, body)
    r = nonnegative_finite("rest_tilt", rest_tilt)
    if r >= 0.01 * body.alpha:
        raise ValueError(f"rest_tilt must be below 0.01 alpha = {0.01 * body.alpha:.4g} rad "
                         f"(an episode must not end above a tilt a limit state could see), "
                         f"got {rest_tilt!r}")
    return r


# ----------------------------------------------------------------------------- uplift
def next_uplift(ax: np.ndarray, ay: np.ndarray, dt: float, threshold: float,
                above: np.ndarray, k_from: int = 0, tau_from: float = 0.0,
                az: np.ndarray | None = None,
                tan_alpha: float = 0.0) -> tuple[int, float, float, float] | None:
    """First time at or after (k_from, tau_from) where |a| > threshold [m/s²], |a| linear per
    interval of ``dt`` [s].

    ``above`` holds the indices of the samples where |a| > threshold (sorted). With a
    vertical acceleration ``az`` [m/s², up] the threshold is (g + a_z) tan α =
    ``threshold`` + a_z ``tan_alpha`` (never below 0), and ``above`` must hold the samples
    above that (:func:`uplift_samples`). Returns ``(k, tau, a_x, a_y)`` (interval, time in
    it, horizontal acceleration there) or None.
    """
    if az is not None:
        return _next_uplift_vertical(ax, ay, az, dt, threshold, tan_alpha, above, k_from,
                                     tau_from)
    n = ax.size
    ak = (ax[k_from] + (ax[k_from + 1] - ax[k_from]) * tau_from / dt) if k_from + 1 < n else 0.0
    bk = (ay[k_from] + (ay[k_from + 1] - ay[k_from]) * tau_from / dt) if k_from + 1 < n else 0.0
    if math.hypot(ak, bk) > threshold:
        return k_from, tau_from, ak, bk
    i = int(np.searchsorted(above, k_from + 1))
    if i == above.size:
        return None
    j = int(above[i])
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


def uplift_samples(ax: np.ndarray, ay: np.ndarray, threshold: float,
                   az: np.ndarray | None = None, tan_alpha: float = 0.0) -> np.ndarray:
    """Indices of the samples where the horizontal |a| exceeds the uplift level: g tan α =
    ``threshold`` [m/s²], or with vertical motion max(g tan α + a_z tan α, 0)."""
    a = np.hypot(ax, ay)
    if az is None:
        return np.flatnonzero(a > threshold)
    return np.flatnonzero(a > np.maximum(threshold + az * tan_alpha, 0.0))


def _next_uplift_vertical(ax, ay, az, dt, threshold, tan_alpha, above, k_from, tau_from):
    """:func:`next_uplift` under a varying level (g + a_z) tan α: |a_h| − level is convex in
    the interval (a norm minus a linear function), so the crossing from below is its only
    root there, found by bisection."""
    n = ax.size

    def gap(k, tau):  # |a_h| − level at (k, tau), and a_h there
        if k + 1 >= n:
            return -1.0, 0.0, 0.0
        f = tau / dt
        hx = ax[k] + (ax[k + 1] - ax[k]) * f
        hy = ay[k] + (ay[k + 1] - ay[k]) * f
        vz = az[k] + (az[k + 1] - az[k]) * f
        return math.hypot(hx, hy) - max(threshold + vz * tan_alpha, 0.0), hx, hy

    g0, hx, hy = gap(k_from, tau_from)
    if g0 > 0.0:
        return k_from, tau_from, hx, hy
    i = int(np.searchsorted(above, k_from + 1))
    if i == above.size:
        return None
    k = int(above[i]) - 1
    lo = tau_from if k == k_from else 0.0
    hi = dt
    for _ in range(60):  # lo: at or below the level; hi: above it
        mid = 0.5 * (lo + hi)
        if gap(k, mid)[0] > 0.0:
            hi = mid
        else:
            lo = mid
    _, hx, hy = gap(k, hi)
    return k, hi, hx, hy


def energy_reserve(ax: np.ndarray, ay: np.ndarray, dt: float,
                   threshold: float) -> np.ndarray:
    """Energy the ground motion left can still feed into a body, per record interval.

    Entry k bounds ∫|a_g| dt/√2 from the start of interval k to the end of the record
    [√(J/kg)]: since d√E/dt ≤ |a_g|/√2 (:func:`rocking.dynamics.driver.decided`), √E can
    grow by at most this much. |a_g| is linear inside an interval, so dt·max(|a_k|, |a_k+1|)
    bounds its integral there. Up to the last sample above ``threshold`` (g tan α) the entry
    is inf: the ground may still lift a body at rest, and an episode after rest starts from
    a small tilt whose energy the bound does not count.

    Parameters
    ----------
    ax, ay : ndarray
        Scaled ground accelerations [m/s²].
    dt : float
        Sample interval [s].
    threshold : float
        Uplift acceleration g tan α [m/s²].

    Returns
    -------
    ndarray
        One value per sample (the last, after the record, is 0).
    """
    a = np.hypot(ax, ay)
    return _mark_liftable(_reserve_of(a, dt), np.flatnonzero(a > threshold))


def _reserve_of(a: np.ndarray, dt: float) -> np.ndarray:
    """Σ over the intervals from k on of dt·max(|a_k|, |a_k+1|)/√2, per sample k."""
    out = np.zeros(a.size)
    if a.size > 1:
        per_interval = dt * np.maximum(a[:-1], a[1:]) / math.sqrt(2.0)
        out[:-1] = np.cumsum(per_interval[::-1])[::-1]
    return out


def _mark_liftable(reserve: np.ndarray, above: np.ndarray) -> np.ndarray:
    """``reserve`` with inf up to the last sample in ``above`` (|a| above uplift)."""
    if above.size:
        reserve[:int(above[-1]) + 1] = math.inf
    return reserve


class _Unscaled(NamedTuple):
    """What an analysis needs of the unscaled motion, the same at every scale."""

    ax: np.ndarray
    ay: np.ndarray
    dt: float
    a: np.ndarray  # |a| of the horizontal components the model sees [m/s²]
    reserve: np.ndarray  # _reserve_of(|a_g|, dt), |a_g| with the vertical component if any
    unidirectional: bool
    az: np.ndarray | None  # vertical component (None: none, or identically zero)


_UNSCALED: dict[tuple[int, bool, bool], _Unscaled] = {}
"""Per (id of the motion's ax array, planar, vertical): a search analyses one motion at many scales.
Entries hold the arrays themselves, so an id is never reused while its entry lives
(GroundMotion arrays are read-only)."""


def _unscaled(motion: GroundMotion, planar: bool, vertical: bool = False) -> _Unscaled:
    """The cached :class:`_Unscaled` of ``motion`` (x only if ``planar``; with its vertical
    component if ``vertical`` and it has one)."""
    az = motion.az if (vertical and motion.has_vertical) else None
    key = (id(motion.ax), planar, az is not None)
    hit = _UNSCALED.get(key)
    if (hit is None or hit.ax is not motion.ax or hit.ay is not motion.ay
            or hit.dt != motion.dt or hit.az is not az):
        a = np.abs(motion.ax) if planar else np.hypot(motion.ax, motion.ay)
        # The ground's work bound counts the whole acceleration vector (driver.decided).
        a_g = a if az is None else np.hypot(a, az)
        if len(_UNSCALED) >= 16:
            _UNSCALED.pop(next(iter(_UNSCALED)))
        hit = _UNSCALED[key] = _Unscaled(motion.ax, motion.ay, motion.dt, a,
                                         _reserve_of(a_g, motion.dt),
                                         motion.is_unidirectional, az)
    return hit


def _above(unscaled: _Unscaled, ax: np.ndarray, ay: np.ndarray, scale: float,
           threshold: float) -> np.ndarray:
    """``np.flatnonzero(np.hypot(ax, ay) > threshold)`` for ``ax, ay`` = the motion times
    ``scale``, evaluated only where the unscaled |a| comes within 1e-9 of ``threshold/scale``
    (a superset: the scaled hypot differs from scale × |a| by a few ulps), so the samples
    found are exactly those of the full evaluation. With a vertical component the level
    varies: :func:`uplift_samples`."""
    if unscaled.az is not None:
        return uplift_samples(ax, ay, threshold, scale * unscaled.az, threshold / G)
    near = np.flatnonzero(unscaled.a > (threshold / scale) * (1.0 - 1e-9))
    return near[np.hypot(ax[near], ay[near]) > threshold]


def _start_state(model: str, phi0: float, phi_dot0: float = 0.0) -> tuple[np.ndarray, float]:
    """State at uplift along the D'Alembert direction φ0 with the spin ``phi_dot0`` [rad/s]
    (3D), and the 2D pivot side."""
    if model == MODEL_2D:
        return np.zeros(2), (1.0 if math.cos(phi0) >= 0.0 else -1.0)
    state = models.MODELS[model].state
    y0 = np.zeros(len(state))
    y0[0], y0[1] = THETA_EPS, phi0
    y0[state.index("phi_dot")] = phi_dot0
    return y0, 1.0


# ----------------------------------------------------------------------------- kernels
class _Runner:
    """Runs one model on one body with the analysis' settings (all kernel calls go here)."""

    def __init__(self, model: str, body, rtol: float, history: bool, contact: Contact,
                 rest_tilt: float, monitors: bool = True):
        self.model = models.MODELS[model]
        self.body = body
        self.history = history
        self.monitors = monitors
        self.prep = models.prepare(self.model, body, rtol,
                                   models.rest_criterion(body, rest_tilt),
                                   contact=contact, max_steps=MAX_STEPS,
                                   method=None if self.model.implicit else METHOD)

    def __call__(self, ax, ay, dt, k0, tau0, t_offset, y0, t_end, stop_level, side=1.0,
                 until_peak=False, quiet=None, theta_before=0.0,
                 az=None) -> models.KernelResult:
        return models.run(self.prep, ax, ay, dt, k0, tau0, t_offset, y0, t_end, stop_level,
                          history=self.history, until_peak=until_peak, side=side,
                          quiet=quiet, theta_before=theta_before, az=az,
                          monitors=self.monitors)

    def free(self, t0: float, y0: np.ndarray, duration: float, stop_level: float,
             side: float = 1.0, until_peak: bool = False) -> models.KernelResult:
        """Unforced run from ``t0`` [s] for ``duration`` [s], record intervals of 0.1/p s."""
        chunk = min(0.1 / self.body.p, duration)
        z = np.zeros(int(math.ceil(duration / chunk)) + 2)
        return self(z, z, chunk, 0, 0.0, t0, y0, t0 + duration, stop_level, side, until_peak)


# ----------------------------------------------------------------------------- assembly
class _Ground(NamedTuple):
    """The ground motion an analysis runs on, for the monitors at rest: the scaled
    components and the unscaled |a_h| (:class:`_Unscaled`) with the scale."""

    ax: np.ndarray
    ay: np.ndarray
    az: np.ndarray | None
    dt: float
    a: np.ndarray
    scale: float
    tan_alpha: float

    def at(self, t: float) -> tuple[float, float]:
        """(N, μ_req) of the body at rest at time ``t`` [s] (linear between samples)."""
        n = self.ax.size
        k = min(max(int(t // self.dt), 0), n - 2)
        f = t / self.dt - k
        hx = self.ax[k] + (self.ax[k + 1] - self.ax[k]) * f
        hy = self.ay[k] + (self.ay[k + 1] - self.ay[k]) * f
        nf = 1.0
        if self.az is not None:
            nf += (self.az[k] + (self.az[k + 1] - self.az[k]) * f) / G
        return nf, (math.hypot(hx, hy) / (G * nf) if nf > 0.0 else math.inf)


class _Acc:
    """Accumulates kernel runs into one response."""

    def __init__(self, model: str, history: bool, ground: _Ground | None = None,
                 monitors: bool = True):
        self.model = model
        self.history = history
        self.ground = ground
        self.monitors = monitors  # False: N, μ_req and their extremes stay NaN
        self.width = len(models.MODELS[model].state)
        # validity monitors (driver.watch): smallest N, largest μ_req and their times
        self.n_min, self.t_n_min = (math.inf if monitors else math.nan), math.nan
        self.mu_max, self.t_mu_max = (0.0 if monitors else math.nan), math.nan
        self.t: list[np.ndarray] = []
        self.y: list[np.ndarray] = []
        self.ev_t: list[np.ndarray] = []
        self.ev_y: list[np.ndarray] = []
        self.n_steps = 0
        self.n_rej = 0
        self.theta_max = 0.0
        self.t_theta_max = math.nan
        self.extras: dict = {}

    def add(self, out: models.KernelResult, skip_first: bool = False) -> None:
        if self.history:
            i0 = 1 if (skip_first and out.t.size > 1) else 0
            self.t.append(out.t[i0:])
            self.y.append(out.y[i0:])
        self.ev_t.append(out.ev_t)
        self.ev_y.append(out.ev_y)
        self.n_steps += int(out.n_steps)
        self.n_rej += int(out.n_rejected)
        mon = out.monitor
        if self.monitors:
            self._monitor(float(mon[driver.M_NMIN]), float(mon[driver.M_T_NMIN]),
                          float(mon[driver.M_MUMAX]), float(mon[driver.M_T_MUMAX]))
        if abs(out.theta_max) > self.theta_max:
            self.theta_max = abs(float(out.theta_max))
            self.t_theta_max = float(out.t_theta_max)
        if self.model == MODEL_3D_DAMPED:
            ex = self.extras
            ex["dissipated"] = ex.get("dissipated", 0.0) + float(out.y_end[6])
            ex["n_tension"] = ex.get("n_tension", 0) + int(out.diag[0])
            ex["contact_force_min"] = min(ex.get("contact_force_min", G), float(out.diag[1]))

    def _monitor(self, n_min: float, t_n: float, mu_max: float, t_mu: float) -> None:
        if n_min < self.n_min:
            self.n_min, self.t_n_min = n_min, t_n
        if mu_max > self.mu_max:
            self.mu_max, self.t_mu_max = mu_max, t_mu

    def add_rest(self, t0: float, t1: float, uplift: bool = False) -> None:
        """A stretch at rest (zero state) from t0 to t1 (``uplift``: the body lifts at t1).

        At rest the support holds the body with the ground: N = (g + a_z)/g and
        μ_req = |a_h|/(g + a_z), monitored at the record samples of the stretch and its ends.
        Without vertical motion N = 1 and μ_req ≤ tan α, with equality where the body lifts
        (|a_h| = g tan α defines the uplift): a stretch that ends in an uplift needs no look
        at its samples.
        """
        if t1 <= t0 or self.ground is None or not self.monitors:
            if self.history and t1 > t0:  # no ground motion: N = 1 weight, μ_req = 0
                self.t.append(np.array([t0, t1]))
                rows = np.zeros((2, self.width + 2))
                rows[:, self.width] = 1.0
                if not self.monitors:
                    rows[:, self.width:] = math.nan
                self.y.append(rows)
            return
        gr = self.ground
        if gr.az is None and not self.history:
            if self.n_min > 1.0:
                self._monitor(1.0, t0, 0.0, t0)
            if uplift:
                self._monitor(1.0, t1, gr.tan_alpha, t1)
                return
        n0, mu0 = gr.at(t0)
        n1, mu1 = gr.at(t1)
        self._monitor(n0, t0, mu0 if n0 > 0.0 else 0.0, t0)
        self._monitor(n1, t1, mu1 if n1 > 0.0 else 0.0, t1)
        i0 = int(math.ceil(t0 / gr.dt))
        i1 = min(int(t1 // gr.dt), gr.ax.size - 1)
        if i1 >= i0:  # the record samples inside the stretch
            if gr.az is None:  # N = 1: μ_req is largest where |a_h| is
                top = gr.scale * float(gr.a[i0:i1 + 1].max()) / G
                if top > self.mu_max:  # its time only when it is a new maximum
                    j = i0 + int(gr.a[i0:i1 + 1].argmax())
                    self._monitor(1.0, t0, top, j * gr.dt)
            else:
                nf = 1.0 + gr.az[i0:i1 + 1] / G
                i = int(np.argmin(nf))
                with np.errstate(divide="ignore", invalid="ignore"):
                    mu = np.where(nf > 0.0, gr.scale * gr.a[i0:i1 + 1] / (G * nf), 0.0)
                j = int(np.argmax(mu))
                self._monitor(float(nf[i]), (i0 + i) * gr.dt, float(mu[j]), (i0 + j) * gr.dt)
        if self.history:
            self.t.append(np.array([t0, t1]))
            rows = np.zeros((2, self.width + 2))
            rows[:, self.width] = (n0, n1)
            rows[:, self.width + 1] = (mu0, mu1)
            self.y.append(rows)

    def arrays(self):
        """(t, state rows, event times, event state rows, monitor rows (N, μ_req))."""
        if self.t:
            t = np.concatenate(self.t)
            y = np.concatenate(self.y)
        else:
            t = np.zeros(0)
            y = np.zeros((0, self.width + 2))
        ev_t = np.concatenate(self.ev_t) if self.ev_t else np.zeros(0)
        ev_y = np.concatenate(self.ev_y) if self.ev_y else np.zeros((0, self.width + 2))
        return t, y[:, :self.width], ev_t, ev_y[:, :self.width], y[:, self.width:]


def _response(acc: _Acc, status: Status, reason: str, uplifted: bool, t_uplift: float,
              contact: Contact, body: Cylinder | Block) -> Response:
    """The one :class:`Response` assembly of every model."""
    t, y, ev_t, ev_y, mon = acc.arrays()
    if acc.model == MODEL_2D and ev_t.size and acc.monitors:  # every impact: same friction
        mu_imp = housner2d.impact_friction(body)
        if mu_imp > acc.mu_max:
            acc.mu_max, acc.t_mu_max = mu_imp, float(ev_t[0])
    theta_max = acc.theta_max
    if status is not Status.FAILED and not math.isfinite(theta_max):
        status, reason = Status.FAILED, f"non-finite peak tilt {theta_max!r}"
    if status is not Status.FAILED and y.size and not np.all(np.isfinite(y)):
        status, reason = Status.FAILED, "non-finite state in the history"
    w = w_dot = force = None
    if acc.model == MODEL_3D_DAMPED:
        th, ph, thd, phd = y[:, 0], y[:, 1], y[:, 3], y[:, 4]
        w, w_dot = y[:, 2], y[:, 5]
        force = cylinder3d_damped.contact_force(y, contact.omega_n, contact.zeta)
    elif acc.model == MODEL_2D:
        th, thd = y[:, 0], y[:, 1]
        ph = np.zeros_like(th)
        phd = np.zeros_like(th)
    else:
        th, ph, thd, phd = y[:, 0], y[:, 1], y[:, 2], y[:, 3]
    return Response(
        model=acc.model, t=t, theta=th, theta_dot=thd, phi=ph, phi_dot=phd,
        theta_max=float(theta_max), t_theta_max=float(acc.t_theta_max),
        overturned=status is Status.OVERTURNED, status=status,
        quasi_impacts=QuasiImpacts(ev_t, ev_y), n_steps=acc.n_steps, n_rejected=acc.n_rej,
        uplifted=uplifted, t_uplift=float(t_uplift), reason=reason, w=w, w_dot=w_dot,
        contact_force=force, extras=acc.extras,
        normal_force=mon[:, 0], mu_required=mon[:, 1],
        normal_force_min=float(acc.n_min), t_normal_force_min=float(acc.t_n_min),
        mu_required_max=float(acc.mu_max), t_mu_required_max=float(acc.t_mu_max),
        mu=body.mu,
    )


# ----------------------------------------------------------------------------- free tails
def _free_tail(body, acc: _Acc, runner: _Runner, y_end: np.ndarray, t_end: float,
               stop_level: float):
    """Combine the invariant decision on the next peak with a free run up to it.

    The free run integrates the unforced motion up to its next tilt peak (AT_PEAK),
    overturning, the stop level or rest. The decision and θmax come from the invariants; the
    run only supplies the time (and the history). Returns (status, reason).
    """
    if acc.model == MODEL_2D:
        peak = housner2d.free_peak(body, float(y_end[0]), float(y_end[1]))
        # On θ = 0 right after an impact the body moves to the side of θ̇.
        side = math.copysign(1.0, y_end[0] if y_end[0] != 0.0 else y_end[1])
    else:
        theta, _, theta_dot, phi_dot = (float(v) for v in y_end[:4])
        peak = cylinder3d.free_peak(body, theta, theta_dot, phi_dot)
        side = 1.0
    acc.extras["free_tail_peak"] = peak
    limit = stop_level if stop_level > 0.0 else _HALF_PI
    record_max, record_t = acc.theta_max, acc.t_theta_max
    if math.isfinite(peak) and peak <= limit and peak <= record_max and not acc.history:
        return Status.OK, ""  # nothing new can happen and no history is wanted
    out = runner.free(t_end, y_end, 400.0 / body.p, stop_level, side, until_peak=True)
    code = int(out.code)
    if code < 0:
        return codes.status_of(code, float(out.t_stop))
    acc.add(out, skip_first=True)
    if math.isinf(peak) or peak > limit:
        if code in (codes.OVERTURNED, codes.STOPPED):
            return codes.status_of(code, float(out.t_stop))
        acc.theta_max, acc.t_theta_max = limit, math.nan
        status = Status.OVERTURNED if stop_level <= 0.0 else Status.STOPPED_AT_LIMIT
        return status, "decided by energy after the record; the free run did not confirm it"
    if peak > record_max:
        acc.theta_max = peak
        acc.t_theta_max = float(out.t_theta_max) if code == codes.AT_PEAK else math.nan
    else:
        acc.theta_max, acc.t_theta_max = record_max, record_t
    return Status.OK, ""


# ----------------------------------------------------------------------------- public API
def free_vibration(body: Cylinder | Block, theta0: float, phi_dot0: float = 0.0, *,
                   theta_dot0: float = 0.0, phi0: float = 0.0, duration: float,
                   model: str = MODEL_3D, rtol: float | None = None,
                   omega_n: float = DAMPED_OMEGA_N, zeta: float = DAMPED_ZETA,
                   history: bool = True,
                   rest_tilt: float | None = None) -> Response:
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
        Relative tolerance; default the model's (:attr:`rocking.dynamics.models.Model.rtol`).
    omega_n, zeta : float
        Contact spring–dashpot of "3d-damped" [rad/s], [-] (validated for all models); the
        damped model starts at rest on the spring (w = ẇ = 0).
    history : bool
        Keep the time histories (False: summary only).
    rest_tilt : float, optional
        Rest tilt [rad], as in :func:`ground_response` (in free vibration the ground is
        always below g tan α: an episode with less energy ends at its first tilt minimum).

    Returns
    -------
    Response
        ``"3d-damped"`` adds ``w``, ``w_dot``, ``contact_force`` and ``extras``
        (``dissipated`` [J/kg], ``n_tension``, ``contact_force_min`` [m/s²]).
    """
    _check_model(model, body)
    contact = Contact(omega_n, zeta)  # checked once, for every model (the damped reads it)
    rtol = _check_rtol(rtol, model)
    duration = positive_finite("duration", duration)
    rest_tilt = _check_rest_tilt(rest_tilt, model, body)
    theta0 = finite("theta0", theta0)
    phi_dot0 = finite("phi_dot0", phi_dot0)
    theta_dot0 = finite("theta_dot0", theta_dot0)
    phi0 = finite("phi0", phi0)
    if model == MODEL_2D:
        if abs(theta0) >= _HALF_PI:
            raise ValueError(f"theta0 must satisfy |theta0| < pi/2, got {theta0!r}")
        y0 = np.array([theta0, theta_dot0])
        side = 1.0 if theta0 > 0 or (theta0 == 0 and theta_dot0 >= 0) else -1.0
    elif not 0.0 < theta0 < _HALF_PI:
        raise ValueError(f"theta0 must lie in (0, pi/2) for model={model!r}, got {theta0!r}")
    elif model == MODEL_3D_DAMPED:
        y0, side = np.array([theta0, phi0, 0.0, theta_dot0, phi_dot0, 0.0]), 1.0
    else:
        y0, side = np.array([theta0, phi0, theta_dot0, phi_dot0]), 1.0
    runner = _Runner(model, body, rtol, history, contact, rest_tilt)
    out = runner.free(0.0, y0, duration, -1.0, side)
    acc = _Acc(model, history)
    if model == MODEL_2D:  # the restitution used, and whether a squat body's was clipped
        acc.extras.update(housner2d.restitution_extras(body))
    acc.theta_max = abs(theta0)
    acc.t_theta_max = 0.0
    acc.add(out)
    code = int(out.code)
    status, reason = codes.status_of(code, float(out.t_stop))
    if code == codes.AT_REST:
        acc.add_rest(float(out.t_stop), duration)
    return _response(acc, status, reason, True, 0.0, contact, body)


def ground_response(body: Cylinder | Block, motion: GroundMotion, *, model: str = MODEL_3D,
                    scale: float | None = None, pga_ratio: float | None = None,
                    stop_at: float | None = None,
                    rtol: float | None = None, omega_n: float = DAMPED_OMEGA_N,
                    zeta: float = DAMPED_ZETA,
                    history: bool = True, free_tail: bool = True,
                    rest_tilt: float | None = None,
                    stop_when_decided: bool = True, vertical: bool | None = None,
                    monitors: bool = True, phi_dot0: float = 0.0) -> Response:
    """Response of a body initially at rest to a (scaled) ground motion.

    Parameters
    ----------
    body : Cylinder or Block
        The rigid body (a Block only with ``model="2d"``).
    motion : GroundMotion
        Ground accelerations [m/s²]; "2d" uses ``motion.ax`` only, the 3D models both
        components (a unidirectional motion needs ``phi_dot0`` > 0).
    model : {"3d", "3d-damped", "2d"}
    scale : float, optional
        Factor on both components [-], > 0 (default 1: the motion as it is).
    pga_ratio : float, optional
        Instead of ``scale``: the normalized intensity PGA/(g tan α) [-] to scale the
        motion's vector PGA to (``scale = pga_ratio·g·tan α / PGA``).
    stop_at : float, optional
        End as soon as |θ| > stop_at [rad] (status STOPPED_AT_LIMIT).
    rtol : float, optional
        Relative tolerance; default the model's (:attr:`rocking.dynamics.models.Model.rtol`).
    omega_n, zeta : float
        Contact spring–dashpot of "3d-damped" [rad/s], [-].
    history : bool
        Keep the time histories (False: summary-only hot path).
    free_tail : bool
        Decide the motion after the record ends by invariants (undamped models) and include
        the next swing in θmax.
    rest_tilt : float, optional
        Tilt [rad] whose potential energy is the rest energy: at a tilt minimum (3D) or an
        impact (2D) with less rocking energy, while the ground is below g tan α, the episode
        ends and the body rests until the ground lifts it again (docs/equations.md,
        "Micro-uplift: when a rocking episode ends"). Default :func:`default_rest_tilt`;
        0 is the exact treatment (only the Zeno floor ends an episode); below 0.01 α.
    stop_when_decided : bool
        Without history, end an analysis at a tilt minimum (3D) or an impact (2D)
        once the motion left provably cannot raise its peak tilt: every later ground
        acceleration is below uplift and the energy it can feed in
        (:func:`energy_reserve`) keeps the body below that peak with a margin
        (:func:`rocking.dynamics.driver.decided`). θmax, its time, the status and every
        limit-state decision are those of the run to the end, for fewer steps (a quiet
        coda, the zero padding of a high-passed record). False: always run to the end.
        With vertical motion the bound counts the whole acceleration vector |a_g| (the
        vertical component works on the body too) and stays valid.
    vertical : bool, optional
        Include the motion's vertical component (gravity becomes g + a_z(t) in every model,
        scaled by the same ``scale`` as the horizontals). Default: whenever the motion has
        one; True for a motion without one is a ValueError; False: horizontals only.
        Without a vertical component the kernels run their variant with gravity exactly g
        (the same bits for less work).
    monitors : bool
        Run the validity monitors (``normal_force``, ``mu_required`` and their extremes,
        docs/models.md). False: the kernels' variant without them (θmax, its time, the
        status and the steps are the same to the bit, for up to ~10 % less work); those
        fields are NaN and ``lifts_off`` False.
    phi_dot0 : float
        Spin φ̇ [rad/s] of the 3D models at each uplift from rest (default 0), at most
        :data:`MAX_UPLIFT_SPIN` of the wobbling rate at the uplift tilt. A motion with one
        component (placed on x) needs one: without spin its motion would stay exactly planar
        and reach θ = 0, where the 3D model is undefined; with it the motion leaves the
        plane as the paper's does (§2.4; docs/models.md, "The 3D model under one component").

    Returns
    -------
    Response
    """
    _check_model(model, body)
    contact = Contact(omega_n, zeta)  # checked once, for every model (the damped reads it)
    rtol = _check_rtol(rtol, model)
    rest_tilt = _check_rest_tilt(rest_tilt, model, body)
    phi_dot0 = _check_spin(phi_dot0, model, body)
    if vertical is not None and not isinstance(vertical, bool):
        raise ValueError(f"vertical must be True, False or None, got {vertical!r}")
    if not isinstance(stop_when_decided, bool):
        raise ValueError(f"stop_when_decided must be True or False, got {stop_when_decided!r}")
    if not isinstance(monitors, bool):
        raise ValueError(f"monitors must be True or False, got {monitors!r}")
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
    if vertical and not motion.has_vertical:
        raise ValueError(f"vertical=True but motion {motion.name!r} has no vertical component "
                         "(give az, or load the record with vertical=True)")
    use_vertical = motion.has_vertical if vertical is None else vertical
    unscaled = _unscaled(motion, model == MODEL_2D, use_vertical)
    if model != MODEL_2D and unscaled.unidirectional and phi_dot0 == 0.0:
        live = "y" if motion.ay.any() else "x"
        raise ValueError(
            f"motion {motion.name!r} has a zero component: unidirectional excitation of the 3D "
            "model without spin is exactly planar and reaches theta = 0 where the model is "
            "undefined; give it a spin at uplift, phi_dot0 > 0 (as the modes 3d-x and 3d-y do "
            f"with a component of a pair), or use model='2d' (the 2D model under the {live} "
            "component)")
    ax = motion.ax * scale
    ay = np.zeros_like(ax) if model == MODEL_2D else motion.ay * scale
    az = None if unscaled.az is None else unscaled.az * scale
    runner = _Runner(model, body, rtol, history, contact, rest_tilt, monitors)
    acc = _Acc(model, history, _Ground(ax, ay, az, motion.dt, unscaled.a, scale,
                                       body.tan_alpha), monitors)
    if model == MODEL_2D:  # the restitution used, and whether a squat body's was clipped
        acc.extras.update(housner2d.restitution_extras(body))
    threshold = G * body.tan_alpha
    above = _above(unscaled, ax, ay, scale, threshold)
    # Without history, an analysis may end once the rest of the motion cannot raise its peak
    # tilt (same θmax and decisions); a history must run to the end.
    quiet = (_mark_liftable(scale * unscaled.reserve, above)
             if stop_when_decided and not history else None)
    out, t_first, status, reason = _episodes(runner, acc, ax, ay, motion.dt, motion.duration,
                                             threshold, stop_level, above, quiet, az, phi_dot0)
    if math.isnan(t_first):
        acc.t_theta_max = 0.0
        return _response(acc, Status.OK, "", False, math.nan, contact, body)
    if (out is not None and int(out.code) == codes.OK and free_tail
            and model != MODEL_3D_DAMPED):
        status, reason = _free_tail(body, acc, runner, out.y[-1, :acc.width], motion.duration,
                                    stop_level)
    return _response(acc, status, reason, True, t_first, contact, body)


def _episodes(runner: _Runner, acc: _Acc, ax, ay, dt, t_end, threshold, stop_level, above,
              quiet=None, az=None, phi_dot0=0.0):
    """Rocking episodes: from each uplift until the body is back at rest, then the next one.

    ``above``: the samples where |a| > ``threshold``. ``quiet`` (:func:`energy_reserve`, or
    None) lets a run end once the motion left cannot raise the peak tilt (code DECIDED, no
    free tail needed: the bound covers it).

    Returns the last kernel output (None if the record ended at rest), the first uplift time
    [s] (NaN if never) and the status and reason.
    """
    k, tau, t_rest, t_first = 0, 0.0, 0.0, math.nan
    stalls = 0
    while True:
        up = next_uplift(ax, ay, dt, threshold, above, k, tau, az, threshold / G)
        if up is None:
            acc.add_rest(t_rest, t_end)
            return None, t_first, Status.OK, ""
        k, tau, a_x, a_y = up
        t_up = k * dt + tau
        if math.isnan(t_first):
            t_first = t_up
        acc.add_rest(t_rest, t_up, uplift=True)
        y0, side = _start_state(runner.model.name, math.atan2(-a_y, -a_x), phi_dot0)
        out = runner(ax, ay, dt, k, tau, 0.0, y0, t_end, stop_level, side, quiet=quiet,
                     theta_before=acc.theta_max, az=az)
        acc.add(out)
        code, t_stop = int(out.code), float(out.t_stop)
        if code != codes.AT_REST:
            status, reason = codes.status_of(code, t_stop)
            return out, t_first, status, reason
        # Back at rest: look for the next uplift after t_stop.
        stalls = stalls + 1 if t_stop - t_up <= 1e-12 * max(1.0, t_up) else 0
        if stalls > 10:
            return None, t_first, Status.FAILED, f"no progress from rest at t = {t_stop:.9g} s"
        if t_stop >= t_end:
            return None, t_first, Status.OK, ""
        k = min(int(t_stop // dt), ax.size - 2)
        tau = t_stop - k * dt
        t_rest = t_stop
