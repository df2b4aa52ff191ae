"""The one integrator of the rocking models: record intervals, step control, events.

Every model (:mod:`.cylinder3d`, :mod:`.cylinder3d_damped`, :mod:`.housner2d`) is integrated
by :func:`integrate`, as SciPy's ``solve_ivp`` drives every method of ``integrate/_ivp``: one
step loop, methods that differ only by their tableau (explicit Dormand–Prince in
:mod:`._rk`, Rosenbrock RODAS4 in :mod:`._rosenbrock`), events located on the step's cubic
Hermite interpolant by small separate functions. A model is a set of compiled hooks:

- ``rhs(tau, y, P, F, out)``: the right-hand side at time ``tau`` inside the current record
  interval, whose forcing is ``F = (a0x, a0y, slope_x, slope_y, a0z, slope_z)``: the ground
  acceleration is ``a0 + slope * tau`` [m/s²], z vertical (positive up; gravity acts as
  g + a_z in every model, docs/equations.md "Vertical ground motion");
- ``impact(y, P)``: the impact map applied where the tilt crosses zero (2D: rate × e and the
  pivot changes side), for models whose layout asks for impacts;
- ``energy(y, P)``: the rocking energy above rest per unit mass [J/kg] (rest criterion);
- ``bound_energy(y, P)``: the whole mechanical energy above rest per unit mass [J/kg], the
  one the ground's work bounds (:func:`decided`; the damped model adds its contact spring
  and vertical motion, the undamped models pass ``energy``);
- ``output(y, P, row)``: the state the user sees (e.g. φ̇ from the spin momentum);
- ``observe(y, P, diag)``: bookkeeping after each accepted step (e.g. contact force);
- ``contact(tau, y, f, P, F, cf)``: the force the support supplies, from the state ``y``
  and its derivative ``f``: ``cf = (N, |F_h|)`` in units of the weight m g (the validity
  monitors: N < 0 is lift-off, μ_req = |F_h|/N the friction needed; :func:`watch`). The
  driver calls it right after ``rhs`` was evaluated at ``y`` (the last evaluation), so a
  model may read trigonometry its ``rhs`` left in spare entries of ``P``;
- ``factor``/``solve``: the linear algebra of a Rosenbrock step (see :mod:`._rosenbrock`);
- ``monitor``: :func:`watch` (the validity monitors through ``contact``) or :func:`no_watch`
  (none: N and μ_req come out NaN).

A model's hooks come in variants compiled only where asked (:data:`VARIANTS`): with or
without the monitors, with or without the vertical forcing (an ``rhs`` that reads a_z, or
one with gravity exactly g). The monitors and the vertical forcing cost up to +13.5 % per
analysis (``python -m benchmarks monitors``) and change nothing else: without a
vertical component a_z = 0 and g + 0 = g to the bit, and the monitors only read the state.
Each variant is a separate compiled entry point of the model (one line binding the hooks),
so a study compiles, and caches, only those its analyses call.

The model's compiled entry point calls :func:`integrate` with its hooks as module-level
globals; :func:`integrate` is inlined there (``inline="always"``), which is what lets numba
cache the whole kernel (a function taking jitted functions as arguments is otherwise linked
through dynamic globals and not cached).

Conventions of every model: state component 0 is the tilt θ, component ``i_thd`` its rate;
``P[0]`` is the pivot side σ = ±1 (always +1 in 3D), and the driver works with the signed
tilt m = σ θ ≥ 0 between impacts.

Time is kept as (record interval k, local time τ inside it): quasi-impacts last 1e-10 s at
t = 40 s, where an absolute time would have a resolution of only 7e-15 s. No step crosses a
record sample, so the forcing is smooth inside every step.

Events of a step, in the order they occur inside it:

- threshold: m reaches ``stop_level`` (code 2) or π/2 (code 1); the time is refined by up to
  three Newton steps on the landed tilt;
- impact (2D): m crosses zero; the state before it is recorded, the impact map applied and
  the step restarted from there;
- tilt maximum: ṁ from + to −; updates θmax (and ends a run that asked for the first peak);
- tilt minimum (3D quasi-impact): ṁ from − to +; recorded.

An event's state is computed by a genuine step of the stepper from the step start to the
event time ("landing"), so it has the accuracy of the integrator, not of the interpolant.
After a tilt minimum or an impact the rest criterion (docs/equations.md, "Back at rest") may
end the run with code 3.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rocking.dynamics import codes
from rocking.dynamics._numerics import (
    EPS,
    error_scale,
    hermite_root,
    record,
    recorded,
    recorder,
    set_forcing,
)

# Layout of the model (int64 array ``layout`` of the run tuple).
L_NOUT, L_ITHD, L_IMPACTS, L_MINIMA, L_POSITIVE, L_NDIAG = 0, 1, 2, 3, 4, 5
L_WROWS, L_LAROWS, L_LACOLS, L_HISTORY, L_UNTIL_PEAK, L_MAXSTEPS = 6, 7, 8, 9, 10, 11
LAYOUT_SIZE = 12

# Step-size control of the stepper (float array ``ctrl`` of the run tuple, built by the
# stepper's ``control``): largest growth factor; order q of the error estimate; keep a larger
# proposal across a step cut short by a record sample (1/0); no growth right after a
# rejection (1/0); the step returns the derivative at its end (1/0).
C_GROWTH, C_ORDER, C_KEEP_PROPOSAL, C_FREEZE, C_END_DERIVATIVE = 0, 1, 2, 3, 4
CONTROL_SIZE = 5


def control_array(*, growth: float, order: float, keep_proposal: bool, freeze: bool,
                  end_derivative: bool) -> np.ndarray:
    """The ``ctrl`` array of a stepper, each value at its ``C_*`` index.

    Parameters
    ----------
    growth : float
        Largest step growth factor [-].
    order : float
        Order q of the error estimate [-] (the step factor is 0.9 err^(−1/(q+1))).
    keep_proposal : bool
        Keep a larger proposal across a step cut short by a record sample.
    freeze : bool
        No growth right after a rejected step.
    end_derivative : bool
        The stepper returns the derivative at the step end (else the driver evaluates it).
    """
    ctrl = np.empty(CONTROL_SIZE)
    ctrl[C_GROWTH], ctrl[C_ORDER] = growth, order
    ctrl[C_KEEP_PROPOSAL], ctrl[C_FREEZE] = float(keep_proposal), float(freeze)
    ctrl[C_END_DERIVATIVE] = float(end_derivative)
    return ctrl

# Event kinds, in the order that breaks ties inside a step.
_THRESHOLD, _IMPACT, _MAXIMUM, _MINIMUM = 0, 1, 2, 3


@njit(cache=True, error_model="numpy")
def no_factor(tau, y, f0, P, F, c, LA):
    """``factor`` hook of a model integrated by an explicit method (never called)."""
    return True


@njit(cache=True, error_model="numpy")
def no_solve(LA, P, r, g):
    """``solve`` hook of a model integrated by an explicit method (never called)."""


@njit(cache=True, error_model="numpy")
def no_impact(y, P):
    """``impact`` hook of a model without impacts (never called)."""


@njit(cache=True, error_model="numpy")
def no_observe(y, P, diag):
    """``observe`` hook of a model without per-step bookkeeping."""


VARIANTS = ((True, True), (True, False), (False, True), (False, False))
"""The ``(monitors, vertical)`` variants of every model's entry point (:func:`variant`)."""


def variant(monitors: bool, vertical: bool) -> int:
    """Index in :data:`VARIANTS` of the entry point with (or without) the validity monitors
    and the vertical forcing."""
    return VARIANTS.index((bool(monitors), bool(vertical)))


@njit(cache=True, error_model="numpy")
def last_interval(n_samples, dt, t_offset, t_end):
    """Last record interval of a run ending at ``t_end`` [s] and the local end time in it."""
    span = (t_end - t_offset) / dt
    k_last = min(int(math.floor(span)), n_samples - 1)
    tau_last = (t_end - t_offset) - k_last * dt
    if k_last >= n_samples - 1:
        k_last = n_samples - 2
        tau_last = dt
    if tau_last <= 4.0 * EPS * dt and k_last > 0:
        k_last -= 1
        tau_last = dt
    return k_last, min(tau_last, dt)


@njit(cache=True, error_model="numpy")
def growth(largest, q, freeze, err, rejected):
    """Step-size factor after a step with scaled error ``err`` (the ``C_*`` controls):
    0.9 err^(−1/(q+1)) within [0.2, ``largest``], at most 1 right after a rejection if
    ``freeze``."""
    if err == 0.0:
        fac = largest
    else:
        fac = min(largest, max(0.2, 0.9 * err ** (-1.0 / (q + 1.0))))
    if rejected and freeze != 0.0:
        fac = min(fac, 1.0)
    return fac


@njit(cache=True, inline="always", error_model="numpy")
def initial_step(rhs, q, tau, y, f0, P, F, tol, h_max, ytmp, f1):
    """Hairer's starting step (as SciPy's ``select_initial_step``), capped at ``h_max``."""
    rtol, SC, n = tol
    tilt = abs(y[0])
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = error_scale(rtol, SC[0, i], SC[1, i], y[i], y[i], tilt)
        d0 += (y[i] / sc) ** 2
        d1 += (f0[i] / sc) ** 2
    d0 = math.sqrt(d0 / n)
    d1 = math.sqrt(d1 / n)
    h0 = 1e-6 * h_max if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, h_max)
    for i in range(y.size):
        ytmp[i] = y[i] + h0 * f0[i]
    rhs(tau + h0, ytmp, P, F, f1)
    d2 = 0.0
    for i in range(n):
        d2 += ((f1[i] - f0[i]) / error_scale(rtol, SC[0, i], SC[1, i], y[i], y[i], tilt)) ** 2
    d2 = math.sqrt(d2 / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (q + 1.0))
    return min(100.0 * h0, h1, h_max)


@njit(cache=True, error_model="numpy")
def find_events(m0, dm0, ddm0, m1, dm1, ddm1, h, lvl, overturn, impacts, minima):
    """Events inside an accepted step: ``(n, s_a, kind_a, s_b, kind_b)``, sorted by their
    fraction s of the step.

    Arguments are the signed tilt m = σθ, its rate and its acceleration at both ends of the
    step. Detection is by sign changes between the step ends; each time is the root of the
    Hermite interpolant of m or of ṁ.
    """
    n, s_a, k_a, s_b, k_b = 0, 0.0, 0, 0.0, 0
    if m1 > lvl or (overturn and m1 >= lvl):
        n, s_a, k_a = 1, hermite_root(m0, dm0, m1, dm1, h, lvl, 1.0), _THRESHOLD
    elif impacts and m1 < 0.0:
        n, s_a, k_a = 1, hermite_root(m0, dm0, m1, dm1, h, 0.0, 1.0), _IMPACT
    turn_max = dm0 > 0.0 and dm1 <= 0.0
    if turn_max or (minima and dm0 < 0.0 and dm1 >= 0.0):
        s = hermite_root(dm0, ddm0, dm1, ddm1, h, 0.0, 1.0)
        kind = _MAXIMUM if turn_max else _MINIMUM
        if n == 0:
            n, s_a, k_a = 1, s, kind
        elif s < s_a:
            n, s_a, k_a, s_b, k_b = 2, s, kind, s_a, k_a
        else:
            n, s_b, k_b = 2, s, kind
    return n, s_a, k_a, s_b, k_b


@njit(cache=True, error_model="numpy")
def newton_fraction(s, ys, sigma, i_thd, lvl, h):
    """Next fraction of a threshold landing (Newton on the landed tilt), or −1 when done.

    The Hermite root is only O(h⁴) accurate; the landed state has the accuracy of the step.
    """
    m, dm = sigma * ys[0], sigma * ys[i_thd]
    if dm <= 0.0 or abs(m - lvl) <= 4.0 * EPS * lvl:
        return -1.0
    return min(max(s + (lvl - m) / (dm * h), 0.0), 1.0)


@njit(cache=True, error_model="numpy")
def at_rest(energy_now, F, tau, rest):
    """The rest criterion: rocking energy below the Zeno floor ``rest[0]``, or below the rest
    energy ``rest[1]`` while the horizontal ground acceleration at ``tau`` is below
    (g + a_z) tan α = ``rest[2]`` + a_z ``rest[3]`` (the ground cannot lift the body again)
    [J/kg, m/s², -]."""
    if energy_now < rest[0]:
        return True
    if energy_now >= rest[1]:
        return False
    return math.hypot(F[0] + F[2] * tau, F[1] + F[3] * tau) <= \
        rest[2] + (F[4] + F[5] * tau) * rest[3]


# Entries of the ``mon`` array the driver returns (the validity monitors, :func:`watch`).
M_NMIN, M_T_NMIN, M_MUMAX, M_T_MUMAX = 0, 1, 2, 3
MON_SIZE = 4


@njit(cache=True, inline="always", error_model="numpy")
def watch(contact, tau, y, f, P, F, cf, mon, t, row, nout):
    """The validity monitors at one state: contact force ``cf = (N, |F_h|)`` [weights]; the
    smallest N and the largest μ_req = |F_h|/N (over N > 0) with their times [s] in ``mon``
    (``M_*``); N and μ_req (inf where N ≤ 0: no friction holds a body that lifts off) in
    ``row[nout]``, ``row[nout + 1]``."""
    contact(tau, y, f, P, F, cf)
    n_f = cf[0]
    if n_f < mon[M_NMIN]:
        mon[M_NMIN], mon[M_T_NMIN] = n_f, t
    mu = cf[1] / n_f if n_f > 0.0 else math.inf
    if n_f > 0.0 and mu > mon[M_MUMAX]:
        mon[M_MUMAX], mon[M_T_MUMAX] = mu, t
    row[nout] = n_f
    row[nout + 1] = mu


@njit(cache=True, inline="always", error_model="numpy")
def no_watch(contact, tau, y, f, P, F, cf, mon, t, row, nout):
    """``monitor`` hook of a run without the validity monitors: nothing (``mon`` and the
    monitor columns of the rows stay NaN)."""


# Entries of the ``qpar`` array of the run tuple (the "decided" test, :func:`decided`).
Q_CAP, Q_BEFORE, Q_MARGIN = 0, 1, 2
QPAR_SIZE = 3


@njit(cache=True, error_model="numpy")
def decided(e_now, reserve, e_cap, margin):
    """Whether the rest of the motion cannot lift the body to the tilt whose potential
    energy is ``e_cap`` [J/kg] (docs/performance.md, "An analysis decided before its end").

    The ground acceleration a_g does work −a_g·v_G per unit mass on a rigid body rolling or
    rocking on it, and ½|v_G|² is at most the kinetic energy, so the energy above rest obeys
    d√E/dt ≤ |a_g|/√2: from now on √E stays below √``e_now`` + ``reserve``, ``reserve`` =
    ∫|a_g|dt/√2 over the motion left [√(J/kg)]. A tilt θ needs E ≥ gR[cos(α − θ) − cos α];
    with the energy bound times (1 + ``margin``) below ``e_cap`` the body never reaches it.
    """
    bound = math.sqrt(max(e_now, 0.0)) + reserve
    return bound * bound * (1.0 + margin) < e_cap


@njit(cache=True, error_model="numpy")
def step_failure(err, tilt, positive):
    """Failure code of a step (0 if it can be accepted): a non-finite error estimate (a
    non-finite state makes it so), a tilt ≤ 0 where the model needs θ > 0, or an error above
    the tolerance."""
    if not math.isfinite(err):
        return codes.NONFINITE
    if positive and tilt <= 0.0:
        return codes.NEGATIVE_TILT
    if err > 1.0:
        return codes.UNDERFLOW
    return 0


@njit(cache=True, error_model="numpy")
def outcome(kind, rest_now, until_peak, lvl_code):
    """(action, code) of an event: action 0 continues the step, 1 ends the run, 2 restarts
    the step after an impact."""
    if kind == _THRESHOLD:
        return 1, lvl_code
    if kind == _MAXIMUM:
        return (1, codes.AT_PEAK) if until_peak else (0, codes.OK)
    if rest_now:
        return 1, codes.AT_REST
    return (2, codes.OK) if kind == _IMPACT else (0, codes.OK)


@njit(cache=True, inline="always", error_model="numpy")
def land(step, rhs, factor, solve, tab, tau, y, f0, h, P, F, tol, W, LA, ys, fs, kind, s,
         i_thd, lvl):
    """State ``ys`` at fraction ``s`` of the step by a genuine step of length s·h; a threshold
    is refined by up to three Newton steps. Returns the final fraction."""
    for _ in range(4):
        step(rhs, factor, solve, tab, tau, y, f0, s * h, P, F, tol, W, LA, ys, fs)
        if kind != _THRESHOLD:
            return s
        s_next = newton_fraction(s, ys, P[0], i_thd, lvl, h)
        if s_next < 0.0:
            return s
        s = s_next
    return s


@njit(cache=True, inline="always", error_model="numpy")
def integrate(rhs, impact, energy, bound_energy, output, observe, contact, monitor, factor,
              solve, step, run):
    """Integrate a model from record interval ``k0``, local time ``tau0`` (module docstring).

    ``run = (P, ax, ay, az, dt, k0, tau0, t_offset, y0, t_end, stop_level, tol, tab, ctrl,
    layout, rest, diag, quiet, qpar)`` is built by :func:`rocking.dynamics.models.run`; ``quiet``
    (empty: no such test) holds per record interval the energy reserve of the motion left
    from its start (:func:`decided`), ``qpar`` the ``Q_*`` entries: the tilt cap (α), the
    peak tilt of earlier episodes [rad] and the energy margin [-]. At a tilt minimum or an
    impact where :func:`decided` holds for the peak so far the run ends with code DECIDED:
    integrating on could not change θmax nor any decision. It names the returned
    tuple (:class:`rocking.dynamics.models.KernelResult`, same order): ``(code,
    t_hist, y_hist, n_steps, n_rejected, theta_max, t_theta_max, ev_t, ev_y, t_stop, y_end,
    diag, mon)``, a code of :mod:`.codes`, the history of output rows (the final row only
    without history; each row ends with the contact force N and μ_req of :func:`watch`),
    step counts, the largest |θ| [rad] and its time [s], the events (tilt minima in 3D, the
    state before each impact in 2D), the end time [s], the final internal state, the model's
    diagnostics and the validity monitors (``M_*``: smallest N, largest μ_req, their times,
    at every accepted step end and every event).
    """
    (P0, ax, ay, az, dt, k0, tau0, t_offset, y0, t_end, stop_level, tol, tab, ctrl, layout,
     rest, diag0, quiet, qpar) = run
    P, diag, y = P0.copy(), diag0.copy(), y0.copy()
    n = y.size
    i_thd = layout[L_ITHD]
    history = layout[L_HISTORY] != 0
    f0, y_new, f_new, ys, fs = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    F = np.empty(6)
    W = np.empty((layout[L_WROWS], n))
    LA = np.empty((layout[L_LAROWS], layout[L_LACOLS]))
    nout = layout[L_NOUT]
    row = np.empty(nout + 2)
    cf = np.empty(2)
    row[nout], row[nout + 1] = math.nan, math.nan  # what no_watch leaves
    mon = np.array([math.inf, math.nan, 0.0, math.nan])
    y_cap = np.zeros(n)  # the state at rest at the tilt cap of the "decided" test
    hist, events = recorder(), recorder()
    n_steps, n_rej, rejected = 0, 0, False
    k_last, tau_last = last_interval(ax.size, dt, t_offset, t_end)
    k, tau = k0, tau0
    set_forcing(F, ax, ay, az, k, dt)
    rhs(tau, y, P, F, f0)
    theta_max, t_theta_max = abs(y[0]), t_offset + k * dt + tau
    monitor(contact, tau, y, f0, P, F, cf, mon, t_theta_max, row, nout)  # right after rhs(y)
    h_min = 32.0 * EPS * dt
    h = initial_step(rhs, ctrl[C_ORDER], tau, y, f0, P, F, tol, dt, W[0], W[1])
    if history:
        output(y, P, row)
        record(hist, t_theta_max, row)
    code, t_stop = codes.OK, math.nan
    lvl, lvl_code = 0.5 * math.pi, codes.OVERTURNED
    if 0.0 < stop_level < lvl:
        lvl, lvl_code = stop_level, codes.STOPPED
    if k > k_last or (k == k_last and tau >= tau_last):
        k = k_last + 1  # nothing to integrate
    while k <= k_last:
        tau_end = dt if k < k_last else tau_last
        if tau_end - tau <= 4.0 * EPS * dt:  # at a record sample: next interval
            if k == k_last:
                break
            k, tau = k + 1, 0.0
            set_forcing(F, ax, ay, az, k, dt)
            rhs(tau, y, P, F, f0)
            continue
        if n_steps + n_rej >= layout[L_MAXSTEPS]:
            code, t_stop = codes.TOO_MANY_STEPS, t_offset + k * dt + tau
            break
        last = h >= tau_end - tau
        h_try = tau_end - tau if last else h
        err = step(rhs, factor, solve, tab, tau, y, f0, h_try, P, F, tol, W, LA, y_new, f_new)
        fail = step_failure(err, y_new[0], layout[L_POSITIVE])
        if fail != 0:
            n_rej += 1
            rejected = True
            h = h_try * (min(ctrl[C_GROWTH], max(0.2, 0.9 * err ** (-1.0 / (ctrl[C_ORDER] + 1.0))))
                         if fail == codes.UNDERFLOW else 0.25)
            if not h >= h_min:  # also a NaN step size
                code, t_stop = fail, t_offset + k * dt + tau
                break
            continue
        n_steps += 1
        if ctrl[C_END_DERIVATIVE] == 0.0:  # the stepper does not return the end derivative
            rhs(tau + h_try, y_new, P, F, f_new)
        observe(y_new, P, diag)
        t0 = t_offset + k * dt + tau
        sg = P[0]
        n_ev, s_a, k_a, s_b, k_b = find_events(
            sg * y[0], sg * f0[0], sg * f0[i_thd], sg * y_new[0], sg * f_new[0],
            sg * f_new[i_thd], h_try, lvl, lvl_code == codes.OVERTURNED, layout[L_IMPACTS],
            layout[L_MINIMA])
        action = 0
        for j in range(n_ev):
            kind = k_a if j == 0 else k_b
            s = land(step, rhs, factor, solve, tab, tau, y, f0, h_try, P, F, tol, W, LA, ys,
                     fs, kind, s_a if j == 0 else s_b, i_thd, lvl)
            t_ev = t0 + s * h_try
            if ctrl[C_END_DERIVATIVE] == 0.0:
                rhs(tau + s * h_try, ys, P, F, fs)
            monitor(contact, tau + s * h_try, ys, fs, P, F, cf, mon, t_ev, row, nout)
            rest_now = False
            if kind == _THRESHOLD:  # landed within rounding of the level: put it there
                ys[0] = P[0] * lvl
            if kind == _MAXIMUM or kind == _THRESHOLD:
                if P[0] * ys[0] > theta_max:
                    theta_max, t_theta_max = P[0] * ys[0], t_ev
            else:  # a tilt minimum or an impact: recorded, and the body may be at rest
                if kind == _IMPACT:
                    ys[0] = 0.0
                output(ys, P, row)
                record(events, t_ev, row)
                if kind == _IMPACT:
                    if history:
                        record(hist, t_ev, row)
                    impact(ys, P)
                rest_now = at_rest(energy(ys, P), F, tau + s * h_try, rest)
            action, code = outcome(kind, rest_now, layout[L_UNTIL_PEAK], lvl_code)
            if action != 1 and kind != _MAXIMUM and kind != _THRESHOLD and k < quiet.size:
                # the peak so far (this and earlier episodes), never above α: below α the
                # potential grows with θ, so a bound under its potential caps the tilt
                cap = min(max(theta_max, qpar[Q_BEFORE]), qpar[Q_CAP])
                if P[0] * ys[0] < cap:
                    y_cap[0] = cap
                    if decided(bound_energy(ys, P), quiet[k], bound_energy(y_cap, P),
                               qpar[Q_MARGIN]):
                        action, code = 1, codes.DECIDED
            if action != 0:
                for i in range(n):
                    y[i] = ys[i]
                tau += s * h_try
                t_stop = t_ev
                if action == 2:  # after the impact: the new pivot's derivative and force
                    rhs(tau, y, P, F, f0)
                    monitor(contact, tau, y, f0, P, F, cf, mon, t_ev, row, nout)
                if history:
                    output(y, P, row)
                    record(hist, t_ev, row)
                break
        if action == 1:
            break
        if action == 2:  # restart from the impact with the new pivot (f0 set above)
            continue
        if abs(y_new[0]) > theta_max:
            theta_max, t_theta_max = abs(y_new[0]), t0 + h_try
        if n_ev > 0:  # the landings evaluated rhs elsewhere: back at the step end
            rhs(tau + h_try, y_new, P, F, f_new)
        monitor(contact, tau + h_try, y_new, f_new, P, F, cf, mon, t0 + h_try, row, nout)
        for i in range(n):
            y[i] = y_new[i]
            f0[i] = f_new[i]
        tau = tau_end if last else tau + h_try
        if history:
            output(y, P, row)
            record(hist, t_offset + k * dt + tau, row)
        h_next = h_try * growth(ctrl[C_GROWTH], ctrl[C_ORDER], ctrl[C_FREEZE], err, rejected)
        h = min(max(h_next, h) if (last and ctrl[C_KEEP_PROPOSAL] != 0.0) else h_next, dt)
        rejected = False
    if code == codes.OK:
        t_stop = t_offset + k_last * dt + tau_last
    if not history:
        output(y, P, row)
        record(hist, t_stop, row)
    t_hist, y_hist = recorded(hist, row.size)
    ev_t, ev_y = recorded(events, row.size)
    return (code, t_hist, y_hist, n_steps, n_rej, theta_max, t_theta_max, ev_t, ev_y, t_stop,
            y, diag, mon)
