"""The body as engineers give it: height and diameter instead of R and tan α.

A column is measured as its height 2h and diameter 2b [m]; the model takes its
semi-diagonal R = √(b² + h²) and slenderness tan α = b/h
(:meth:`rocking.dynamics.bodies.Cylinder.from_dimensions`). :func:`body_size` turns the
one into the other, for the command line and the workflow's configuration
(:mod:`rocking.config.dimensions`), and refuses, in one line naming the keys and values, a
dimension without the other, one that is not a length > 0, and an R or tan α given beside
them that disagrees.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

__all__ = ["AGREE_RTOL", "body_line", "body_size", "swap_warning"]

AGREE_RTOL = 1e-6
"""Relative difference [-] up to which a given R or tan α agrees with the dimensions'
(a tan α written to six digits agrees with the diameter/height it was computed from)."""


def _length(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) \
            or not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a finite length > 0 [m], got {value!r}")
    return float(value)


def body_size(height: float | None, diameter: float | None, *, R: Sequence[float] | None = None,
              tan_alpha: float | Sequence[float] | None = None,
              names: Sequence[str] = ("height", "diameter", "R", "tan_alpha"),
              ) -> tuple[float, float] | None:
    """R [m] and tan α [-] of a cylinder of ``height`` 2h and ``diameter`` 2b [m].

    Parameters
    ----------
    height, diameter : float or None
        The body's height and diameter [m] (a block's width in its rocking plane), both or
        neither.
    R : sequence of float, optional
        Sizes [m] given beside them: each must be the dimensions' R.
    tan_alpha : float or sequence of float, optional
        Slenderness [-] given beside them: must be diameter/height.
    names : four str
        The option or key of each value, for the errors (``"--height"``, …).

    Returns
    -------
    (float, float) or None
        (R, tan α); None when neither dimension is given.

    Raises
    ------
    ValueError
        One line naming the keys and values: one dimension without the other, a dimension
        that is not a finite length > 0, an R or tan α that disagrees with them.
    """
    from rocking.dynamics.bodies import Cylinder

    h_name, d_name, r_name, t_name = names
    if height is None and diameter is None:
        return None
    if height is None or diameter is None:
        given, value = (h_name, height) if diameter is None else (d_name, diameter)
        raise ValueError(f"{h_name} and {d_name} go together (the body's height and diameter "
                         f"[m]); got only {given} {value!r}")
    body = Cylinder.from_dimensions(_length(d_name, diameter), _length(h_name, height))
    dims = f"{h_name} {height:g} and {d_name} {diameter:g}"
    for name, given, want in ((t_name, tan_alpha, body.tan_alpha), (r_name, R, body.R)):
        values = [] if given is None else \
            [given] if isinstance(given, int | float) else list(given)
        bad = [v for v in values if not math.isclose(v, want, rel_tol=AGREE_RTOL)]
        if bad:
            raise ValueError(f"{name} {bad[0]!r} contradicts {dims} ({name} = {want:.6g}); "
                             f"give the dimensions or {name}, not both")
    return body.R, body.tan_alpha


def body_line(height: float, diameter: float, R: float, tan_alpha: float) -> str:
    """The derived body in words: ``height 6 m, diameter 0.66 m: R = 3.018 m, tan α = 0.11``."""
    return (f"height {height:g} m, diameter {diameter:g} m: R = {R:.4g} m, "
            f"tan α = {tan_alpha:.4g} (α = {math.degrees(math.atan(tan_alpha)):.3g}°)")


def swap_warning(height: float, diameter: float,
                 names: Sequence[str] = ("height", "diameter")) -> str | None:
    """One line when the height is below the diameter (tan α > 1, a body wider than tall:
    legal, but more often the two swapped), naming both keys and values; None otherwise."""
    if not height < diameter:
        return None
    h_name, d_name = names[:2]
    return (f"warning: {h_name} {height:g} m is below {d_name} {diameter:g} m (tan α = "
            f"{diameter / height:.4g}): did you swap them?")
