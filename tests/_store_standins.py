"""Cheap deterministic stand-ins for the engine, for tests of the store and Dask machinery.

They have the signatures of :func:`rocking.spectra.critical.critical_intensity_batch` and
:func:`rocking.spectra.tilt_map.tilt_map` but compute closed forms, so that a test can evaluate
the expected value of every grid point directly and compare it with what the store holds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from rocking.motions.motion import GroundMotion
from rocking.spectra.limit_states import parse_limit_states

NOT_REACHED_R = 8.0
"""Sizes above this never reach overturning in the stand-in (NaN + not_reached)."""


@dataclass(frozen=True)
class FakeResult:
    """The fields of CriticalResult the store reads."""

    limit_states: tuple[str, ...]
    intensity: np.ndarray
    not_reached: np.ndarray
    non_monotonic: np.ndarray
    failed: np.ndarray
    n_analyses: int
    i50: np.ndarray
    first_exceedance: np.ndarray
    plateau: np.ndarray


def expected_intensity(R: float, tan_alpha: float, motion: GroundMotion, mode: str,
                       ratio: float) -> float:
    """Closed form of the stand-in's answer for one limit state (NaN = not reached)."""
    if math.isinf(ratio) and R > NOT_REACHED_R:
        return math.nan
    r = 4.0 if math.isinf(ratio) else ratio
    return 1.0 + 0.3 * R * r + 0.1 * tan_alpha + 0.01 * motion.pga + 0.5 * len(mode)


I50_FACTOR = 1.25
"""The stand-in's I50 over its answer [-]."""
FIRST_FACTOR = 0.97
"""The stand-in's first exceedance over its answer [-]."""


def batch(tasks, limit_states, *, accuracy="default", quantity=None, upper=20.0, omega_n=None,
          zeta=None):
    """Stand-in of critical_intensity_batch (I50 and the first exceedance fixed multiples of
    the answer; ``plateau`` at R = 4)."""
    states = parse_limit_states(limit_states)
    out = []
    for R, tan_alpha, motion, mode in tasks:
        values = np.array([expected_intensity(R, tan_alpha, motion, mode, s.severity[1])
                           for s in states])
        out.append(FakeResult(
            tuple(s.name for s in states), values, np.isnan(values),
            np.array([R == 2.0 and s.severity[1] < 1 for s in states]),
            np.zeros(len(states), dtype=bool), int(3 + 2 * R), I50_FACTOR * values,
            FIRST_FACTOR * values, np.full(len(states), R == 4.0) & ~np.isnan(values),
        ))
    return out


def failing_batch(tasks, limit_states, **kw):
    """Stand-in that fails for the size R = 2 (to test failure reporting)."""
    if any(t[0] == 2.0 for t in tasks):
        raise ValueError("stand-in failure at R=2.0")
    return batch(tasks, limit_states, **kw)


def expected_theta(R: float, intensity: float, mode: str, tan_alpha: float) -> float:
    """Closed form of the stand-in tilt map."""
    return intensity / (1.0 + R) + (0.5 if mode == "3d-damped" else 0.0) + tan_alpha


def tilt_map(R_values, tan_alpha, motion, intensities, mode="3d", *, accuracy="default",
             omega_n=None, zeta=None):
    """Stand-in of rocking.spectra.tilt_map.tilt_map."""
    R = np.asarray(R_values, dtype=float)
    intensity = np.asarray(intensities, dtype=float)
    theta = np.array([[expected_theta(r, i, mode, tan_alpha) for i in intensity] for r in R])
    return xr.Dataset(
        {"theta_max_over_alpha": (("R", "intensity"), theta),
         "overturned": (("R", "intensity"), theta > 3.0),
         "failed": (("R", "intensity"), np.zeros(theta.shape, dtype=bool))},
        coords={"R": R, "intensity": intensity},
    )


def motions(n: int = 2, npts: int = 200, dt: float = 0.01) -> list[GroundMotion]:
    """Small deterministic pairs with distinct PGAs."""
    t = np.arange(npts) * dt
    return [GroundMotion((1.0 + k) * np.sin(7.0 * t), np.cos(5.0 * t), dt, f"m{k}",
                         {"stand_in": k == 1, "label": f"motion {k}"}) for k in range(n)]
