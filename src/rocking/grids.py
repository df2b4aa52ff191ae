"""Grids of values given by their ends: the one place they are generated.

A grid ``{start, stop, num, spacing}`` of the configuration (sizes R, slenderness, stripes) and
the stripes of ``rocking stripes --stripes/--lower/--upper`` are the same list
(:func:`grid_values`): ``num`` values from ``start`` to ``stop``, both included, linear or
geometric, each rounded to :data:`GRID_DIGITS` significant digits so that a value typed in a
configuration (3.35) and one generated (0.5 + 3·0.95 = 3.3499999999999996) are one number.
"""

from __future__ import annotations

import math

import numpy as np

GRID_DIGITS = 12
"""Significant digits of a generated grid value."""

SPACINGS = ("linear", "log")


def grid_values(start: float, stop: float, num: int, spacing: str = "linear") -> list[float]:
    """``num`` values from ``start`` to ``stop`` (both included), rounded to
    :data:`GRID_DIGITS` significant digits.

    Parameters
    ----------
    start, stop : float
        Ends, finite, 0 < start ≤ stop (start < stop when num > 1).
    num : int
        Number of values, ≥ 1 (1: ``[start]``).
    spacing : {"linear", "log"}
        Equal steps, or equal ratios (geometric).

    Returns
    -------
    list of float

    Raises
    ------
    ValueError
        For a bad number of values, ends or spacing (the caller names the field).
    """
    if isinstance(num, bool) or not isinstance(num, int | np.integer) or num < 1:
        raise ValueError(f"num must be an integer >= 1, got {num!r}")
    start, stop = float(start), float(stop)
    if not (math.isfinite(start) and math.isfinite(stop) and 0.0 < start <= stop):
        raise ValueError(f"need 0 < start <= stop (finite), got start={start!r}, stop={stop!r}")
    if spacing not in SPACINGS:
        raise ValueError(f"spacing must be 'linear' or 'log', got {spacing!r}")
    grid = np.geomspace(start, stop, int(num)) if spacing == "log" else \
        np.linspace(start, stop, int(num))
    return [float(f"{v:.{GRID_DIGITS}g}") for v in grid]
