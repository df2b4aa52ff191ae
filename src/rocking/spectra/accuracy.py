"""Named accuracy presets of the critical-intensity search.

Four choices set together how close a performance spectrum is to its converged value and
what it costs:

- ``rtol``: relative tolerance of the ODE integration of each analysis of the undamped 3D
  and the 2D models, and ``rtol_damped`` that of the stiff damped 3D model (its cost grows
  faster with the accuracy asked, so it gets its own value);
- the upward scan in normalized intensity I = PGA/(g tan α) that looks for the first
  exceedance: ``scan="fixed"`` steps by ``scan_step`` everywhere (relative,
  I_{j+1} = I_j·(1 + step), or absolute); ``scan="adaptive"`` sets each step from how far the
  peak tilt θ of the last analysis lies below the next undecided tilt goal τ (capped at α:
  nothing beyond α is reached without passing α), h = ln(τ/θ)/``tilt_growth`` within
  [``scan_step``, ``scan_step_max``] — the step over which θmax, growing like I^κ, could just
  reach the goal; ``scan="seek"`` (window-seeking) shrinks the step geometrically with the
  closeness r = θ/τ, from ``scan_step_max`` at rest to ``scan_step`` at r ≥ ``seek_near``;
- the refinement of near misses: after the scan, ``refine_budget`` analyses per spectrum
  point re-examine the scan points below each first exceedance where the peak tilt came
  close to the goal and fell back, or spiked (the near misses that set ``unresolved``),
  lowest first, in steps of ``refine_step`` (θ ≥ ``refine_near``·τ) to ``refine_step_max``;
  a window found there becomes the answer, a re-examined near miss no longer flags it, and
  ``budget_spent`` says the budget ran out first (:meth:`rocking.spectra.search._Search.refine`);
- ``bisection_tol``: width of the final bracket (lo, hi] relative to hi.

A coarser scan is cheaper but may step over a narrow window of exceedance below the first
one it sees (rocking response is not monotonic in the intensity); the bisection tolerance
bounds the error inside the bracket; the ODE tolerance moves the boundary itself where the
response is sensitive. The presets were chosen from ``python -m benchmarks spectra``
(docs/performance.md): "default" aims at ≤ 1 % median error in I_crit at the
lowest cost.

What that benchmark measured (El Centro, tan α = 0.2, 18 (R, mode) points, 126 answers with
the seven limit states and 36 with the two of Figs 9, 11, 12, against a reference with a fixed
0.5 % scan, 0.01 % brackets, rtol 1e-11 and every micro-uplift followed to its end):

- The scan dominates the error, because rocking response has narrow windows of exceedance
  (0.25–2 % of I wide) below the first robust one (a 10 m cylinder overturns in 3D on a
  < 2 %-wide window near I = 2.44, converged in rtol, while a 10 % scan answers 4.0). Such
  windows appear wherever the peak tilt comes within a factor of about 2–3 of a goal, which
  with goals 0.1, 0.2, 1/3, 0.5, 0.75, 1 α is most of the range. rtol from 1e-6 to 1e-10
  moves the median between 0.5 % and 1 %: the scatter of the median itself.
- "default" (fixed 1 % scan; rtol 1e-7): median / 90th percentile error 0.85 % / 8.9 % (7
  goals, 71 analyses per point) and 0.84 % / 9.8 % (2 goals, 69) — the same answers as before
  the micro-uplift rest criterion, in about half the time.
- The adaptive scan (0.5 % near a goal, at most 5 %, κ = 60) saved analyses while
  micro-uplift was expensive; with the rest criterion it no longer keeps the default's
  accuracy: 1.15 % / 7.1 % (7 goals, 68 analyses) and 2.1 % / 12 % (2 goals, 45). κ = 120
  gives 0.82 % / 5.0 % and 1.04 % / 4.6 % for 94 and 69 analyses; a fixed 0.75 % scan
  0.62 % / 6.5 % and 0.64 % / 6.0 % for 94 and 92.
- "precise" (adaptive, 0.35 % near a goal, at most 3 %, κ = 120; rtol 1e-10): 0.60 % /
  6.5 % (7 goals, 118 analyses), 0.53 % / 4.9 % (2 goals, 78); "fast" (fixed 10 %): 5.9 % /
  47 %, 21 analyses.

About 10 % of the answers stay several per cent off at any affordable step (windows narrower
than the step are missed); the result flags ``non_monotonic`` wherever the search saw such a
window, and ``unresolved`` where such windows may lie unseen below the answer.

Measured again against a converged 0.02–0.05 % grid (``python -m benchmarks
resolution``, docs/performance.md "Resolution of the critical intensity"): the windows are
0.02–0.25 % wide, so the error of every affordable scan is larger than the 0.5 % reference
above says; the table there replaces the numbers of this docstring.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from rocking._validate import positive_finite
from rocking.dynamics.names import MODEL_3D_DAMPED

SCANS = ("fixed", "adaptive", "seek")
"""Kinds of coarse scan (:attr:`Accuracy.scan`)."""


@dataclass(frozen=True)
class Accuracy:
    """Tolerances of one critical-intensity search.

    Parameters
    ----------
    name : str
        Label written to outputs.
    rtol : float
        ODE relative tolerance of the "3d" and "2d" analyses [-], in (0, 1e-2].
    scan_step : float
        Coarse-scan step, relative [-] or absolute in I [-], > 0.
    bisection_tol : float
        Final bracket width relative to its upper end [-], in (0, 1).
    rtol_damped : float, optional
        ODE relative tolerance of the "3d-damped" analyses [-]; default ``rtol``.
    scan_relative : bool
        True: geometric scan I_j = I_0 (1 + step)^j; False: arithmetic I_j = I_0 + j·step.
        The adaptive scan is always relative.
    scan : {"fixed", "adaptive"}
        "fixed": every step is ``scan_step``. "adaptive": each step follows from how far
        the last peak tilt θ is below the next undecided tilt goal τ,
        h = ln(τ/θ)/``tilt_growth``, kept within [``scan_step``, ``scan_step_max``]
        (:meth:`adaptive_step`).
    scan_step_max : float
        Largest relative step of the adaptive and the window-seeking scans [-],
        >= ``scan_step``.
    tilt_growth : float
        Assumed largest growth rate d ln θmax / d ln I of the peak tilt with the intensity
        [-], > 0: the adaptive step is the step that could just lift θ to τ at that rate.
    rest_tilt : float, optional
        Rest tilt of every analysis [rad] (``rest_tilt`` of
        :func:`rocking.dynamics.analysis.ground_response`): None, the engine's default per
        model (micro-uplift below a 5 µm rim lift ends an undamped 3D episode); 0, the exact
        treatment that follows every micro-uplift to its end; at most 1e-4.
    seek_near : float
        Closeness θ/τ of the peak tilt to the next goal at and above which the
        window-seeking scan (``scan="seek"``) takes its finest step ``scan_step`` [-], in
        (0, 1] (:meth:`seek_step`).
    refine_budget : int
        Analyses one search (a spectrum point, all its limit states) may spend
        re-examining the near misses below its answers (scan points where the peak tilt
        came close to the goal and fell back, or spiked), lowest first
        (:meth:`rocking.spectra.search._Search.refine`) [-], >= 0; 0: no refinement (the
        near misses only set ``unresolved``).
    refine_step : float
        Finest relative step of that re-examination [-], in (0, ``scan_step``]: taken where
        the peak tilt is within ``refine_near`` of the goal.
    refine_step_max : float
        Coarsest relative step of the re-examination, where the body stays far from the
        goal [-], >= ``refine_step``; the step shrinks geometrically with the closeness
        between the two (:meth:`refine_step_at`).
    refine_near : float
        Closeness θ/τ at and above which the re-examination takes ``refine_step`` [-], in
        (0, 1].
    """

    name: str
    rtol: float
    scan_step: float
    bisection_tol: float
    rtol_damped: float | None = None
    scan_relative: bool = True
    scan: str = "fixed"
    scan_step_max: float = 0.1
    tilt_growth: float = 40.0
    rest_tilt: float | None = None
    seek_near: float = 0.5
    refine_budget: int = 0
    refine_step: float = 0.0005
    refine_step_max: float = 0.002
    refine_near: float = 0.8

    def __post_init__(self) -> None:
        _check_range("rtol", self.rtol, 0.0, 1e-2)
        if self.rtol_damped is None:
            object.__setattr__(self, "rtol_damped", self.rtol)
        _check_range("rtol_damped", self.rtol_damped, 0.0, 1e-2)
        positive_finite("scan_step", self.scan_step)
        _check_range("bisection_tol", self.bisection_tol, 0.0, 1.0, upper_open=True)
        if self.scan not in SCANS:
            raise ValueError(f"scan must be one of {list(SCANS)}, got {self.scan!r}")
        positive_finite("tilt_growth", self.tilt_growth)
        positive_finite("scan_step_max", self.scan_step_max)
        if self.rest_tilt is not None:
            # ≤ 1e-4 rad stays below the engine's bound 0.01 α for every tan α > 0.0101, so a
            # valid study configuration never fails inside a worker
            _check_range("rest_tilt", self.rest_tilt, 0.0, 1e-4, lower_closed=True)
            object.__setattr__(self, "rest_tilt", float(self.rest_tilt))
        _check_range("seek_near", self.seek_near, 0.0, 1.0)
        object.__setattr__(self, "refine_budget", _check_count("refine_budget",
                                                                self.refine_budget))
        _check_range("refine_step", self.refine_step, 0.0, 1.0)
        _check_range("refine_step_max", self.refine_step_max, 0.0, 1.0)
        _check_range("refine_near", self.refine_near, 0.0, 1.0)
        if self.refine_step_max < self.refine_step:
            raise ValueError(f"refine_step_max must be >= refine_step={self.refine_step!r}, "
                             f"got {self.refine_step_max!r}")
        if self.scan in ("adaptive", "seek"):
            if not self.scan_relative:
                raise ValueError(f"scan={self.scan!r} needs scan_relative=True (its steps "
                                 "are relative), got scan_relative=False")
            if self.scan_step_max < self.scan_step:
                raise ValueError(f"scan_step_max must be >= scan_step={self.scan_step!r}, "
                                 f"got {self.scan_step_max!r}")

    def with_(self, **changes) -> Accuracy:
        """A copy with some fields changed (named ``"custom"`` unless a name is given)."""
        changes.setdefault("name", "custom")
        return replace(self, **changes)

    def rtol_for(self, model: str) -> float:
        """ODE relative tolerance of a dynamics model ("3d", "3d-damped" or "2d") [-]."""
        return self.rtol_damped if model == MODEL_3D_DAMPED else self.rtol

    def scan_point(self, lower: float, j: int) -> float:
        """The j-th point of the fixed scan starting at ``lower`` (j = 0 is ``lower``)."""
        if self.scan_relative:
            return lower * (1.0 + self.scan_step) ** j
        return lower + j * self.scan_step

    def adaptive_step(self, theta: float, goal: float) -> float:
        """Relative step of the adaptive scan after a peak tilt ``theta`` [rad] when the next
        undecided tilt goal is ``goal`` [rad].

        If θmax grew with the intensity no faster than I^κ (κ = ``tilt_growth``), it could
        not reach the goal before I·(τ/θ)^(1/κ): the step is ln(τ/θ)/κ, at least
        ``scan_step`` (near a goal, where narrow windows of exceedance hide) and at most
        ``scan_step_max``. A body at rest (θ = 0) takes the largest step; an unknown tilt
        (NaN, a failed analysis) the smallest.
        """
        if not theta < goal:  # also NaN
            return self.scan_step
        if theta <= 0.0:
            return self.scan_step_max
        h = math.log(goal / theta) / self.tilt_growth
        return min(self.scan_step_max, max(self.scan_step, h))

    def seek_step(self, theta: float, goal: float) -> float:
        """Relative step of the window-seeking scan after a peak tilt ``theta`` [rad] when the
        next undecided tilt goal is ``goal`` [rad].

        Windows of exceedance narrower than a step hide where the peak tilt comes close to a
        goal (resolution benchmark, docs/performance.md), so the step shrinks geometrically
        with the closeness r = θ/τ: ``scan_step_max`` at rest (r = 0), ``scan_step`` from
        r = ``seek_near`` on, h = h_max·(h_min/h_max)^(r/seek_near) between. An unknown
        tilt (NaN, a failed analysis) takes the finest step.
        """
        if not theta < goal:  # also NaN
            return self.scan_step
        r = max(theta, 0.0) / goal
        if r >= self.seek_near:
            return self.scan_step
        return self.scan_step_max * (self.scan_step / self.scan_step_max) ** (r / self.seek_near)

    def refine_step_at(self, theta: float, goal: float) -> float:
        """Relative step of the re-examination of a near miss after a peak tilt ``theta``
        [rad] below the goal ``goal`` [rad]: ``refine_step`` from the closeness
        r = θ/τ >= ``refine_near`` on (and for an unknown tilt), ``refine_step_max`` at
        rest, geometric between (windows of exceedance hide where θ comes close to τ)."""
        if not theta < goal:  # also NaN
            return self.refine_step
        r = max(theta, 0.0) / goal
        if r >= self.refine_near:
            return self.refine_step
        return self.refine_step_max * (self.refine_step
                                       / self.refine_step_max) ** (r / self.refine_near)

    def to_dict(self) -> dict:
        """JSON-serialisable form (written into study attributes and CLI outputs).

        ``seek_near`` only for the window-seeking scan, so that the attributes (and the
        digests) of stores made with the other scans stay as they were."""
        out = {
            "name": self.name,
            "rtol": self.rtol,
            "rtol_damped": self.rtol_damped,
            "scan_step": self.scan_step,
            "scan_relative": self.scan_relative,
            "bisection_tol": self.bisection_tol,
            "scan": self.scan,
            "scan_step_max": self.scan_step_max,
            "tilt_growth": self.tilt_growth,
            "rest_tilt": self.rest_tilt,
        }
        if self.scan == "seek":
            out["seek_near"] = self.seek_near
        # always, 0 included: a record read back (get_accuracy) must not take the default
        # preset's budget
        out["refine_budget"] = self.refine_budget
        if self.refine_budget:
            out.update(refine_step=self.refine_step, refine_step_max=self.refine_step_max,
                       refine_near=self.refine_near)
        return out


def _check_range(name: str, value, lo: float, hi: float, upper_open: bool = False,
                 lower_closed: bool = False) -> None:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    above = v >= hi if upper_open else v > hi
    below = v < lo if lower_closed else v <= lo
    if not math.isfinite(v) or below or above:
        bound = f"< {hi}" if upper_open else f"<= {hi}"
        low = f">= {lo}" if lower_closed else f"> {lo}"
        raise ValueError(f"{name} must be {low} and {bound}, got {value!r}")


def _check_count(name: str, value) -> int:
    """A whole number >= 0 (a float with no fraction is accepted) or a one-line error."""
    ok = (isinstance(value, (int, float)) and not isinstance(value, bool)
          and math.isfinite(value) and value >= 0 and float(value).is_integer())
    if not ok:
        raise ValueError(f"{name} must be a whole number >= 0, got {value!r}")
    return int(value)


PRESETS: dict[str, Accuracy] = {
    "fast": Accuracy("fast", rtol=1e-6, rtol_damped=1e-5, scan_step=0.1, bisection_tol=0.02),
    "default": Accuracy("default", rtol=1e-7, rtol_damped=1e-6, scan_step=0.01,
                        bisection_tol=0.005, scan="fixed", refine_budget=20,
                        refine_step=0.0005, refine_step_max=0.002, refine_near=0.8),
    "precise": Accuracy("precise", rtol=1e-10, rtol_damped=1e-9, scan_step=0.0035,
                        bisection_tol=0.001, scan="adaptive", scan_step_max=0.03,
                        tilt_growth=120.0),
}
"""The named presets, from cheapest to most accurate."""


def get_accuracy(accuracy: str | Accuracy | dict) -> Accuracy:
    """Resolve a preset name, a ready :class:`Accuracy`, or a mapping of its fields.

    A mapping may name a preset under ``"preset"`` and override some of its fields, e.g.
    ``{"preset": "default", "rtol": 1e-9}`` (the form a workflow configuration uses). A
    mapping with a ``"name"`` and no ``"preset"`` is a record (:meth:`Accuracy.to_dict`, the
    tolerances a store keeps): one written before the refinement existed has no
    ``refine_budget`` and did not refine (0).

    Raises
    ------
    ValueError
        For an unknown preset name or field.
    """
    if isinstance(accuracy, Accuracy):
        return accuracy
    if isinstance(accuracy, str):
        key = accuracy.strip().lower()
        if key not in PRESETS:
            raise ValueError(f"accuracy must be one of {sorted(PRESETS)}, got {accuracy!r}")
        return PRESETS[key]
    if isinstance(accuracy, dict):
        fields = dict(accuracy)
        if "name" in fields and "preset" not in fields:
            fields.setdefault("refine_budget", 0)
        base = get_accuracy(fields.pop("preset", "default"))
        allowed = {"name", "rtol", "rtol_damped", "scan_step", "bisection_tol", "scan_relative",
                   "scan", "scan_step_max", "tilt_growth", "rest_tilt", "seek_near",
                   "refine_budget", "refine_step", "refine_step_max", "refine_near"}
        unknown = sorted(set(fields) - allowed)
        if unknown:
            raise ValueError(f"accuracy has unknown field(s) {unknown}; allowed {sorted(allowed)}")
        return base.with_(**fields) if fields else base
    raise ValueError(f"accuracy must be a preset name, an Accuracy or a dict, got {accuracy!r}")
