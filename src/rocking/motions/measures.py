"""Intensity measures of a two-component ground motion beside its PGA: PGV and Sa(T).

Every measure is the peak of the horizontal *vector*, like the vector PGA max √(ax² + ay²)
that normalizes the critical intensities (:mod:`rocking.spectra.critical`). The peak of the
vector is the largest peak over every horizontal direction (RotD100): the response of a
linear system to the component along the unit vector n is n·(x response, y response), so
its largest value over n is the length of the response vector. Hence

- PGV = max_t |v(t)|, v the trapezoidal integral of the ground acceleration from rest [m/s];
- Sa(T) = ω² max_t |u(t)|, u the relative displacement vector of a linear oscillator of
  period T and 5 % damping driven by both components (exact recurrence,
  :func:`rocking.motions.response_spectrum.sdof_response`) [g].

All three are linear in the scale of the motion: a record scaled by s has s times each
measure, so the measure at which a scaled record first exceeds a limit state is the
critical scale factor times the record's measure, exactly.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import G
from .motion import GroundMotion

__all__ = ["DEFAULT_DAMPING", "MEASURE_UNITS", "intensity_measure", "parse_measure",
           "peak_vector_velocity", "vector_sa"]

DEFAULT_DAMPING = 0.05
"""Damping ratio of the Sa(T) oscillator [-]."""

MEASURE_UNITS = {"pga": "g", "pgv": "m/s", "sa": "g"}
"""Unit of each kind of measure."""


def parse_measure(name: str) -> tuple[str, float | None]:
    """``"pga"``, ``"pgv"`` or ``"sa:<T>"`` → (kind, period [s] or None).

    Raises
    ------
    ValueError
        Any other spelling, or a period that is not a finite number > 0.
    """
    if not isinstance(name, str):
        raise ValueError(f"an intensity measure is pga, pgv or 'sa:<T in s>', got {name!r}")
    text = name.strip().lower()
    if text in ("pga", "pgv"):
        return text, None
    if text.startswith("sa:"):
        try:
            period = float(text[3:])
        except ValueError:
            period = math.nan
        if not (math.isfinite(period) and period > 0):
            raise ValueError(f"the period of {name!r} must be a number of seconds > 0, "
                             "e.g. 'sa:1.0'")
        return "sa", period
    raise ValueError(f"an intensity measure is pga, pgv or 'sa:<T in s>', got {name!r}")


def peak_vector_velocity(motion: GroundMotion) -> float:
    """PGV of the pair: max_t √(vx² + vy²), v integrated from rest (trapezoid) [m/s]."""
    from scipy.integrate import cumulative_trapezoid

    vx = cumulative_trapezoid(motion.ax, dx=motion.dt, initial=0.0)
    vy = cumulative_trapezoid(motion.ay, dx=motion.dt, initial=0.0)
    return float(np.max(np.hypot(vx, vy)))


def vector_sa(motion: GroundMotion, period: float, damping: float = DEFAULT_DAMPING) -> float:
    """Sa(T) of the pair: ω² max_t |u(t)| of the displacement vector, in g [-].

    Parameters
    ----------
    motion : GroundMotion
        Accelerations [m/s²].
    period : float
        Oscillator period T [s].
    damping : float
        Damping ratio ζ [-].
    """
    from .response_spectrum import sdof_response

    ux, _ = sdof_response(motion.ax, motion.dt, period, damping)
    uy, _ = sdof_response(motion.ay, motion.dt, period, damping)
    omega = 2.0 * math.pi / period
    return float(omega**2 * np.max(np.hypot(ux, uy)) / G)


def intensity_measure(motion: GroundMotion, name: str) -> float:
    """The measure ``name`` (:func:`parse_measure`) of a motion, in :data:`MEASURE_UNITS`."""
    kind, period = parse_measure(name)
    if kind == "pga":
        return motion.pga_g
    if kind == "pgv":
        return peak_vector_velocity(motion)
    return vector_sa(motion, period)
