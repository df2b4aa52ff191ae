"""The three rocking models as the driver sees them, and one call that runs any of them.

A :class:`Model` names a model's compiled entry point, its state layout and the Python-level
set-up of a run (parameters, error scales, kernel state); :func:`run` builds the run tuple of
:func:`rocking.dynamics.driver.integrate`, calls the entry point and names what it returns
(:class:`KernelResult`). :mod:`.analysis` runs every kernel through here.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from rocking.constants import G
from rocking.dynamics import _rk, _rosenbrock, cylinder3d, cylinder3d_damped, driver, housner2d
from rocking.dynamics.bodies import Block, Cylinder
from rocking.dynamics.contact import Contact
from rocking.dynamics.names import MODEL_2D, MODEL_3D, MODEL_3D_DAMPED

ZENO_RATE = 1e-6
"""Impact rate, as a fraction of p α, below which a 2D body is back at rest whatever the rest
tolerance [-]: the accumulation point of ever shorter hops cannot be resolved in floating
point (its energy ½κoR²(1e-6 p α)² is the rest criterion's floor in every model)."""


class KernelResult(NamedTuple):
    """What one kernel run returns (:func:`run`; the compiled
    :func:`rocking.dynamics.driver.integrate` returns the same fields as a plain tuple, in
    this order, and :func:`run` names them).

    Attributes
    ----------
    code : int
        Outcome, a code of :mod:`.codes` (negative: a failure).
    t : ndarray
        Times of the output rows [s] (only the final row without history).
    y : ndarray
        Output rows, one per time, in the model's ``state`` layout followed by the two
        monitor columns N [weights] and μ_req [-] (:func:`rocking.dynamics.driver.watch`).
    n_steps, n_rejected : int
        Accepted and rejected steps.
    theta_max : float
        Largest |θ| of the run [rad].
    t_theta_max : float
        Its time [s].
    ev_t, ev_y : ndarray
        Events (tilt minima in 3D, the state before each impact in 2D): times [s] and output
        rows (with the monitor columns).
    t_stop : float
        End time [s].
    y_end : ndarray
        Final internal (kernel) state.
    diag : ndarray
        The model's diagnostics (damped model: tension count, smallest contact force).
    monitor : ndarray
        Validity monitors (smallest N [weights], its time [s], largest μ_req [-], its time
        [s]; indices ``driver.M_*``); NaN from a run without them.
    """

    code: int
    t: np.ndarray
    y: np.ndarray
    n_steps: int
    n_rejected: int
    theta_max: float
    t_theta_max: float
    ev_t: np.ndarray
    ev_y: np.ndarray
    t_stop: float
    y_end: np.ndarray
    diag: np.ndarray
    monitor: np.ndarray


class Model(NamedTuple):
    """How the driver integrates one model.

    Attributes
    ----------
    name : str
        One of :data:`.names.MODEL_NAMES`.
    kernels : tuple of callable
        Compiled entry points ``kernel(run)``, one per ``(monitors, vertical)`` variant in
        the order of :data:`rocking.dynamics.driver.VARIANTS` (:meth:`kernel`); each is
        compiled on its first call only.
    state : tuple of str
        Names of the output state.
    i_thd : int
        Index of the tilt rate in the kernel state.
    impacts : bool
        The tilt crosses zero through an impact map (2D); otherwise θ > 0 is enforced (3D).
    implicit : bool
        Integrated by the Rosenbrock stepper (else by the explicit Runge–Kutta pair).
    n_diag : int
        Length of the model's per-step diagnostics.
    la_shape : tuple of int
        Shape of the linear-algebra work array of an implicit step.
    params : callable
        ``params(body, contact) -> (P, floor, wtilt)``: parameters and error scales (the
        :class:`~rocking.dynamics.contact.Contact` is read by the damped model only).
    kernel_state : callable
        ``kernel_state(body, y0, P) -> (y, diag0)``: kernel state of an output state and the
        initial diagnostics.
    rtol : float
        Default relative tolerance [-] (:data:`DEFAULT_RTOL`, :data:`DEFAULT_RTOL_DAMPED`).
    rest_tilt : callable
        ``rest_tilt(body) -> float``: default rest tilt [rad], the tilt whose potential energy
        is the rest energy of :func:`rest_criterion` (:data:`REST_LIFT` at the rim in "3d",
        :data:`THETA_REST_2D`, :data:`THETA_REST_DAMPED`).
    contact : Contact or None
        The model's own parameters, declared here with their defaults: the contact
        spring–dashpot (ωn [rad/s], ζ [-]) of a model on one; None for a rigid contact.
    """

    name: str
    kernels: tuple[Callable, ...]
    state: tuple[str, ...]
    i_thd: int
    impacts: bool
    implicit: bool
    n_diag: int
    la_shape: tuple[int, int]
    params: Callable
    kernel_state: Callable
    rtol: float
    rest_tilt: Callable
    contact: Contact | None

    def kernel(self, monitors: bool = True, vertical: bool = True) -> Callable:
        """The entry point with (or without) the validity monitors and the vertical forcing."""
        return self.kernels[driver.variant(monitors, vertical)]


def _params_3d(body, contact):
    return (cylinder3d.params(body), *cylinder3d.tolerances(body))


def _params_2d(body, contact):
    return (housner2d.params(body), *housner2d.tolerances(body))


def _params_damped(body, contact):
    # a Contact was checked when it was made: its numbers go to the kernel as they are
    return (cylinder3d_damped.params(body, contact.omega_n, contact.zeta),
            *cylinder3d_damped.tolerances(body, contact.omega_n))


def _state_3d(body, y0, P):
    return cylinder3d.to_state(body, y0), _NO_DIAG


def _state_2d(body, y0, P):
    return np.asarray(y0, dtype=float).copy(), _NO_DIAG


def _state_damped(body, y0, P):
    y = cylinder3d_damped.to_state(y0)
    return y, np.array([0.0, float(cylinder3d_damped.contact_force_of(y, P))])


_NO_DIAG = np.zeros(0)

DEFAULT_RTOL = 1e-8
"""Default relative tolerance of the undamped models [-] (the damped one's is
:data:`DEFAULT_RTOL_DAMPED`).

From ``python -m benchmarks dynamics``: in every benchmark case the θmax error is
≤ 1e-3 with the right limit-state decision from rtol 1e-6 on ("3d" El Centro: 1.6e-4 at 1e-6,
1.1e-2 at 1e-5; "2d": < 1e-10 at any rtol, the record dt caps its steps). The undamped 3D
default is tighter, 1e-8 (θmax error 9e-6, +24 % steps), because releases at 0.999α must
survive: the energy margin to the barrier at θ = α is only gR(0.001α)²/2 ≈ 2e-8 gR for
tan α = 0.2, and the energy drift through quasi-impacts is ~1e-7 at rtol 1e-6 but ~1e-9 at
1e-8 (tests/test_cylinder3d.py). The 2D default follows for consistency of comparisons. The
damped default, 1e-8, comes from ``python -m benchmarks damped``: θmax error ≤ 5e-5 on
the paper's whole (ωn, ζ) grid, where 1e-6 reaches 1e-2 at ωn = 2000, ζ = 0.5."""

DEFAULT_RTOL_DAMPED = 1e-8
"""Measured default relative tolerance of the damped model [-]: θmax error ≤ 5e-5 on the
paper's (ωn, ζ) grid for the 40 s El Centro case (``python -m benchmarks damped``)."""

REST_LIFT = 5e-6
"""Rim lift [m] below which an episode of the undamped 3D model ends (docs/equations.md,
"Micro-uplift: when a rocking episode ends"): the default rest tilt of "3d" is the tilt that
lifts the rim of the base, of diameter 2R sin α, by this much, REST_LIFT/(2R sin α).

The undamped model conserves energy exactly, so a body lifted by a sub-threshold pulse keeps
rocking by micrometres, with ever faster quasi-impacts, until the next strong pulse: up to
1.5 M steps (1.3 s) for one analysis whose peak tilt is 1e-6 rad. Any real contact (and the
damped model) dissipates that energy, and no rigid contact model means anything below the
roughness of the contact surfaces (tens of µm for dressed stone or concrete). The value is
the measured trade (a benchmark of the first-exceedance search, retired with it; its numbers
in docs/performance.md): the cost of the slowest analysis near uplift against how many
critical intensities move."""

THETA_REST_2D = 0.0
"""Default rest tilt of the 2D model [rad]: it loses energy at every impact and ends its
episodes at the Zeno floor (:data:`ZENO_RATE`)."""

THETA_REST_DAMPED = 1e-6
"""Default rest tilt of the damped model [rad]: it dissipates its micro-rocking in the contact
dashpot, and 1e-6 rad only ends what is left of it."""


def _rest_3d(body):
    return REST_LIFT / (2.0 * body.R * math.sin(body.alpha))


def _rest_2d(body):
    return THETA_REST_2D


def _rest_damped(body):
    return THETA_REST_DAMPED


MODELS: dict[str, Model] = {
    MODEL_3D: Model(MODEL_3D, cylinder3d.KERNELS, cylinder3d.STATE, 2, False, False, 0,
                    (1, 1), _params_3d, _state_3d, DEFAULT_RTOL, _rest_3d, None),
    MODEL_3D_DAMPED: Model(MODEL_3D_DAMPED, cylinder3d_damped.KERNELS,
                           cylinder3d_damped.STATE, 3, False, True, 2,
                           cylinder3d_damped.LA_SHAPE, _params_damped, _state_damped,
                           DEFAULT_RTOL_DAMPED, _rest_damped, Contact()),
    MODEL_2D: Model(MODEL_2D, housner2d.KERNELS, housner2d.STATE, 1, True, False, 0, (1, 1),
                    _params_2d, _state_2d, DEFAULT_RTOL, _rest_2d, None),
}
"""The models by name."""


DEFAULT_CONTACT = MODELS[MODEL_3D_DAMPED].contact
"""The damped model's declared contact: what a run is given when its caller names none."""


def rest_criterion(body: Block | Cylinder, theta_rest: float) -> np.ndarray:
    """``[Zeno floor energy, rest energy, g tan α, tan α]`` of the driver's rest test
    [J/kg, J/kg, m/s², -] (the uplift level is (g + a_z) tan α with vertical motion).

    The rest energy is what lifting the body from rest to the tilt ``theta_rest`` [rad]
    takes, gR[cos(α − θ_rest) − cos α] (docs/equations.md, "Back at rest"); the floor is the
    energy of the 2D hop of rate :data:`ZENO_RATE` p α.
    """
    a = body.alpha
    e_rest = G * body.R * (math.sin(a) * math.sin(theta_rest)
                           - 2.0 * math.cos(a) * math.sin(0.5 * theta_rest) ** 2)
    e_floor = 0.5 * body.kappa_o * body.R**2 * (ZENO_RATE * body.p * a) ** 2
    return np.array([e_floor, max(e_rest, 0.0), G * body.tan_alpha, body.tan_alpha])


class Prepared(NamedTuple):
    """Everything of a run that does not change between the runs of one analysis."""

    model: Model
    body: Block | Cylinder
    P: np.ndarray
    tol: tuple
    tab: tuple
    ctrl: np.ndarray
    layout: np.ndarray
    rest: np.ndarray
    tilt_cap: float
    """Tilt above which the potential energy no longer grows with θ: α [rad]."""


def prepare(model: Model, body: Block | Cylinder, rtol: float, rest: np.ndarray, *,
            contact: Contact = DEFAULT_CONTACT, max_steps: int = 20_000_000,
            method: str | None = None) -> Prepared:
    """Parameters, tolerances, stepper and layout of the runs of ``model`` on ``body``.

    Parameters
    ----------
    model : Model
    body : Cylinder or Block
    rtol : float
        Relative tolerance.
    rest : ndarray
        :func:`rest_criterion`.
    contact : Contact
        Contact spring–dashpot of the damped model (ignored by the others).
    max_steps : int
        Budget of accepted plus rejected steps of one run.
    method : str, optional
        Stepper: a Runge–Kutta pair of :mod:`._rk` for the explicit models (default
        ``"dp5"``), a Rosenbrock method of :mod:`._rosenbrock` for the damped one (default
        ``"rodas4"``).
    """
    P, floor, wtilt = model.params(body, contact)
    if model.implicit:
        method = method or "rodas4"
        tab, ctrl = _rosenbrock.tableau(method), _rosenbrock.control(method)
        work_rows = _rosenbrock.work_rows(method)
    else:
        method = method or "dp5"
        tab, ctrl, work_rows = _rk.tableau(method), _rk.control(method), _rk.WORK_ROWS
    layout = np.zeros(driver.LAYOUT_SIZE, dtype=np.int64)
    layout[driver.L_NOUT] = len(model.state)
    layout[driver.L_ITHD] = model.i_thd
    layout[driver.L_IMPACTS] = model.impacts
    layout[driver.L_MINIMA] = not model.impacts
    layout[driver.L_POSITIVE] = not model.impacts
    layout[driver.L_NDIAG] = model.n_diag
    layout[driver.L_WROWS] = work_rows
    layout[driver.L_LAROWS], layout[driver.L_LACOLS] = model.la_shape
    layout[driver.L_MAXSTEPS] = max_steps
    tol = (float(rtol), np.array([floor, wtilt]), floor.size)
    return Prepared(model, body, P, tol, tab, ctrl, layout, rest, float(body.alpha))


def run(prep: Prepared, ax: np.ndarray, ay: np.ndarray, dt: float, k0: int, tau0: float,
        t_offset: float, y0: np.ndarray, t_end: float, stop_level: float, *, history: bool,
        until_peak: bool = False, side: float = 1.0, quiet: np.ndarray | None = None,
        theta_before: float = 0.0, az: np.ndarray | None = None,
        monitors: bool = True) -> KernelResult:
    """Integrate a prepared model from record interval ``k0``, local time ``tau0`` [s].

    Parameters
    ----------
    prep : Prepared
    ax, ay : ndarray
        Ground accelerations [m/s²] (already scaled), sample j at ``t_offset + j dt``.
    dt : float
        Sample interval [s]; no step is longer, and every step ends on or before a sample.
    k0, tau0 : int, float
        Start interval and local time in it [s].
    t_offset : float
        Absolute time of sample 0 [s].
    y0 : ndarray
        Start state in output form (``model.state``).
    t_end : float
        End time [s] (clamped to the last sample).
    stop_level : float
        End with code STOPPED once |θ| > stop_level [rad]; ≤ 0 for none.
    history, until_peak : bool
        Keep every step; end at the first tilt maximum.
    side : float
        Initial pivot side (±1; the 2D model).
    quiet : ndarray, optional
        Energy reserve of the motion left from the start of each record interval
        [√(J/kg)] (:func:`rocking.dynamics.analysis.energy_reserve`): the run ends with code
        DECIDED once that motion cannot raise the peak tilt (:func:`.driver.decided`).
        None: never (every undamped analysis without history passes it).
    theta_before : float
        Peak tilt of the analysis' earlier episodes [rad] (the ``quiet`` test's cap).
    az : ndarray, optional
        Vertical ground acceleration [m/s², up] (already scaled), on the samples of ``ax``;
        None: none, integrated by the variant with gravity exactly g (the same bits as an
        all-zero ``az``, for less work).
    monitors : bool
        Run the validity monitors (N, μ_req and their extremes); False: the variant without
        them, whose monitor columns and ``monitor`` are NaN.

    Returns
    -------
    KernelResult
        The output of :func:`rocking.dynamics.driver.integrate`, named.
    """
    P = prep.P.copy()
    P[0] = 1.0 if side >= 0 else -1.0
    y, diag0 = prep.model.kernel_state(prep.body, y0, P)
    layout = prep.layout.copy()
    layout[driver.L_HISTORY] = history
    layout[driver.L_UNTIL_PEAK] = until_peak
    kernel = prep.model.kernel(monitors, az is not None)
    if az is None:  # set_forcing still reads it; the variant's rhs does not
        az = np.zeros(ax.size)
    out = kernel((P, ax, ay, az, float(dt), int(k0), float(tau0), float(t_offset), y,
                             float(t_end), float(stop_level), prep.tol, prep.tab, prep.ctrl,
                             layout, prep.rest, diag0,
                             _NO_QUIET if quiet is None else quiet,
                             np.array([prep.tilt_cap, float(theta_before), DECIDED_MARGIN])))
    if not monitors:
        out = (*out[:-1], np.full(driver.MON_SIZE, math.nan))
    return KernelResult(*out)


_NO_QUIET = np.zeros(0)

DECIDED_MARGIN = 0.02
"""Relative margin on the energy of the "decided" test [-] (:func:`.driver.decided`): the
integrated energy drifts by far less (~1e-7 relative per quasi-impact at rtol 1e-6), so a
run ends early only where the exact bound holds with room to spare and the θmax the
integration would have reached cannot differ."""
