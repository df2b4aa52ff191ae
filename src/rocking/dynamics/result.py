"""The outcome of one rocking analysis (free vibration or ground motion)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from rocking.dynamics.names import MODEL_2D, MODEL_3D_DAMPED


class Status(StrEnum):
    """How an analysis ended."""

    OK = "ok"
    """Ran to the end (record plus free tail, or the requested duration) without overturning."""
    OVERTURNED = "overturned"
    """θ reached π/2."""
    STOPPED_AT_LIMIT = "stopped-at-limit"
    """θ exceeded ``stop_at``; the analysis ended there on purpose."""
    FAILED = "failed"
    """The integration could not proceed; ``reason`` says why. Never a silent result."""


def contact_slides(mu_required_max: float, overturned: bool, mu: float | None) -> bool | None:
    """Whether a body slid while in contact: it did not overturn and needed more friction
    than ``mu`` (``mu_required_max`` > μ, over the instants with N > 0).

    None (says nothing) without ``mu`` or where it overturned: in the fall N → 0⁺ while the
    contact still carries a horizontal force, so μ_req grows without bound whatever μ (62
    to 246 in the falls of the column of docs/risk.md, tan α 0.11, R 3.02 m, under El
    Centro), and the peak of such an analysis is not an answer about sliding."""
    if mu is None or overturned:
        return None
    return bool(slid_in_contact(mu_required_max, False, mu))


def slid_in_contact(mu_required_max, overturned, mu: float) -> np.ndarray:
    """:func:`contact_slides` elementwise over many analyses (a search's): True where an
    analysis did not overturn and ``mu_required_max`` > ``mu``, False elsewhere (an overturned
    analysis, or NaN: nothing monitored). The one place the sliding comparison is written.

    Parameters
    ----------
    mu_required_max : array_like
        Largest μ_req over the instants with N > 0 [-].
    overturned : array_like of bool
        Whether each analysis overturned.
    mu : float
        Friction coefficient of the support [-] (checked where it entered).
    """
    return np.logical_and(np.asarray(mu_required_max, dtype=float) > mu,
                          np.logical_not(overturned))


def leaves_support(normal_force_min: float) -> bool:
    """Whether a body left its support: the normal force fell to N ≤ 0 (no contact force
    holds it; False for NaN, nothing monitored)."""
    return bool(normal_force_min <= 0.0)


@dataclass
class QuasiImpacts:
    """Tilt minima in 3D (quasi-impacts) or impacts in 2D.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times [s].
    state : ndarray, shape (n, k)
        State at each event, columns as :attr:`Response.state_names`.
    """

    t: np.ndarray
    state: np.ndarray

    def __len__(self) -> int:
        return int(self.t.size)


@dataclass
class Response:
    """Result of :func:`rocking.free_vibration` or :func:`rocking.ground_response`.

    History arrays are empty when the analysis ran in summary-only mode
    (``history=False``); the summary fields are always filled.

    Attributes
    ----------
    model : str
        ``"3d"``, ``"3d-damped"`` or ``"2d"``.
    t : ndarray
        Output times [s].
    theta, theta_dot : ndarray
        Tilt [rad] (signed in 2D, > 0 in 3D) and its rate [rad/s].
    phi, phi_dot : ndarray
        Rolling angle of the contact point [rad] and its rate [rad/s]; zeros in 2D.
    w, w_dot, contact_force : ndarray or None
        Contact-spring displacement [m], velocity [m/s] and normal force per unit mass
        [m/s²] of the damped model; ``None`` otherwise.
    theta_max : float
        Largest |θ| reached [rad] (including the free tail decided after the record ends).
    t_theta_max : float
        When it was reached [s].
    overturned : bool
        θ reached π/2.
    status : Status
    reason : str
        Human-readable detail, mandatory when ``status`` is FAILED.
    quasi_impacts : QuasiImpacts
    n_steps : int
        Accepted integration steps.
    n_rejected : int
        Rejected integration steps.
    uplifted : bool
        The body left its rest position at least once.
    t_uplift : float
        First uplift time [s] (NaN if never).
    normal_force, mu_required : ndarray
        Validity monitors along the history: the normal force the support supplies in units
        of the weight, N/(m g) [-] (N < 0: the body would lift off), and the friction it
        needs, μ_req = |F_h|/N [-] (inf where N ≤ 0); docs/equations.md, "Validity
        monitors". At rest: (g + a_z)/g and |a_h|/(g + a_z). NaN from an analysis run
        without the monitors (``ground_response(monitors=False)``), as the four below.
    normal_force_min, t_normal_force_min : float
        Smallest N/(m g) [-] over the analysis and when [s] (every accepted step end,
        every event, the record samples at rest; inf/NaN if nothing was monitored).
    mu_required_max, t_mu_required_max : float
        Largest μ_req [-] over the instants with N > 0 (in 2D including every impact's
        impulse ratio, :func:`rocking.dynamics.housner2d.impact_friction`) and when [s].
        An analysis ended early (``stop_when_decided``) or a free tail decided by
        invariants without integration is monitored up to where it was integrated.
    mu : float or None
        Support friction coefficient of the body [-] (None: not given).
    extras : dict
        Model-specific numbers: ``free_tail_peak`` [rad]; for "3d-damped" ``dissipated``
        (energy dissipated by the contact dashpot per unit mass of the body [J/kg]),
        ``n_tension`` (steps with a tensile contact force) and ``contact_force_min`` [N/kg];
        for "2d" ``restitution`` (e applied at each impact [-]) and ``restitution_clipped``
        (a squat body: the restitution formula was negative and every impact ends the
        rocking, e = 0), with ``restitution_note`` (one line) when True.
    """

    model: str
    t: np.ndarray
    theta: np.ndarray
    theta_dot: np.ndarray
    phi: np.ndarray
    phi_dot: np.ndarray
    theta_max: float
    t_theta_max: float
    overturned: bool
    status: Status
    quasi_impacts: QuasiImpacts
    n_steps: int
    n_rejected: int = 0
    uplifted: bool = True
    t_uplift: float = float("nan")
    reason: str = ""
    w: np.ndarray | None = None
    w_dot: np.ndarray | None = None
    contact_force: np.ndarray | None = None
    extras: dict = field(default_factory=dict)
    normal_force: np.ndarray = field(default_factory=lambda: np.zeros(0))
    mu_required: np.ndarray = field(default_factory=lambda: np.zeros(0))
    normal_force_min: float = float("inf")
    t_normal_force_min: float = float("nan")
    mu_required_max: float = 0.0
    t_mu_required_max: float = float("nan")
    mu: float | None = None

    @property
    def slides(self) -> bool | None:
        """The body slid while in contact (:func:`contact_slides`): it did not overturn and
        needed more friction than ``mu`` somewhere; None without ``mu``, where it
        overturned (the fall needs unbounded friction whatever μ) or where nothing was
        monitored."""
        if math.isnan(self.mu_required_max):
            return None
        return contact_slides(self.mu_required_max, self.overturned, self.mu)

    @property
    def lifts_off(self) -> bool:
        """The body left its support (N ≤ 0) somewhere (:func:`leaves_support`)."""
        return leaves_support(self.normal_force_min)

    @property
    def state_names(self) -> tuple[str, ...]:
        """Column names of :attr:`QuasiImpacts.state`."""
        if self.model == MODEL_3D_DAMPED:
            return ("theta", "phi", "w", "theta_dot", "phi_dot", "w_dot")
        if self.model == MODEL_2D:
            return ("theta", "theta_dot")
        return ("theta", "phi", "theta_dot", "phi_dot")

    @property
    def ok(self) -> bool:
        """False only for FAILED analyses."""
        return self.status is not Status.FAILED

    def summary(self) -> dict:
        """JSON-serialisable summary (no histories)."""
        return {
            "model": self.model,
            "status": self.status.value,
            "reason": self.reason,
            "theta_max": float(self.theta_max),
            "t_theta_max": float(self.t_theta_max),
            "overturned": bool(self.overturned),
            "uplifted": bool(self.uplifted),
            "t_uplift": float(self.t_uplift),
            "n_quasi_impacts": len(self.quasi_impacts),
            "n_steps": int(self.n_steps),
            "n_rejected": int(self.n_rejected),
            "normal_force_min": float(self.normal_force_min),
            "t_normal_force_min": float(self.t_normal_force_min),
            "mu_required_max": float(self.mu_required_max),
            "t_mu_required_max": float(self.t_mu_required_max),
            "mu": self.mu,
            "slides": self.slides,
            "lifts_off": self.lifts_off,
            **{k: v for k, v in self.extras.items() if isinstance(v, (int, float, str, bool))},
        }
