"""The body as engineers give it: height and diameter instead of R and tan α.

A column is measured as its height 2h and diameter 2b [m]; the model takes its
semi-diagonal R = √(b² + h²) and slenderness tan α = b/h
(:meth:`rocking.dynamics.bodies.Cylinder.from_dimensions`). :func:`body_size` turns the
one into the other for the command line and the configuration, and refuses, in one line
naming the keys and values, a dimension without the other, one that is not a length > 0,
and an R or tan α given beside them that disagrees. :func:`resolve_dimensions` does it
for every ``height``/``diameter`` of a workflow configuration (a study and its stripes)
before the schema sees it.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

__all__ = ["AGREE_RTOL", "body_line", "body_size", "resolve_dimensions"]

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
    from ..dynamics.bodies import Cylinder

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


_PARTS = ("stripes",)


def resolve_dimensions(config: Mapping[str, Any],
                       say: Callable[[str], None] | None = None) -> Mapping[str, Any]:
    """``config`` with every ``height``/``diameter`` turned into R and tan α.

    A study (``studies.<name>``) with ``height`` and ``diameter`` gets ``R: [R]`` and every
    run without ``tan_alpha`` gets ``[tan α]``; its ``stripes`` with them get ``R`` and
    ``tan_alpha``. An R or tan α given beside them must agree (else one line).
    The keys are removed, so the rest of the workflow sees what it always saw.

    Parameters
    ----------
    config : mapping
        A workflow configuration (not changed).
    say : callable, optional
        Gets one line per body derived (the workflow prints it).

    Returns
    -------
    mapping
        ``config`` itself when no section gives dimensions, else a changed deep copy.
    """
    studies = config.get("studies") if isinstance(config, Mapping) else None
    if not isinstance(studies, Mapping) or not any(
            _has_dims(s) or any(_has_dims(s.get(p)) for p in _PARTS)
            for s in studies.values() if isinstance(s, Mapping)):
        return config
    out = copy.deepcopy(dict(config))
    for name, s in out["studies"].items():
        if not isinstance(s, dict):
            continue
        field = f"studies.{name}"
        found = _resolve(s, field, "R", None, say)
        if found is not None:
            for i, run in enumerate(s.get("runs") or []):
                if isinstance(run, dict):
                    _agree(run, "tan_alpha", found, f"{field}.runs[{i}]")
        for part in _PARTS:
            if isinstance(s.get(part), dict):
                _resolve(s[part], f"{field}.{part}", "R", "tan_alpha", say)
    return out


def _has_dims(section: Any) -> bool:
    return isinstance(section, Mapping) and ("height" in section or "diameter" in section)


def _grid_values(value: Any) -> list[float] | None:
    """The values of a grid as far as they are fixed (a list; a {start, stop} grid: its
    ends, each must agree), None when absent."""
    if value is None:
        return None
    if isinstance(value, Mapping):
        return [v for v in (value.get("start"), value.get("stop")) if isinstance(v, int | float)]
    return [v for v in value if isinstance(v, int | float)] if isinstance(value, list) \
        else [value]


def _resolve(section: dict, field: str, r_key: str, t_key: str | None, say) -> float | None:
    """Set ``R`` (and ``tan_alpha``) of a section from its dimensions; tan α or None."""
    if not _has_dims(section):
        return None
    height, diameter = section.pop("height", None), section.pop("diameter", None)
    size = body_size(height, diameter, R=_grid_values(section.get(r_key)),
                     tan_alpha=None if t_key is None else _grid_values(section.get(t_key)),
                     names=(f"{field}.height", f"{field}.diameter", f"{field}.{r_key}",
                            f"{field}.{t_key or 'tan_alpha'}"))
    R, tan_alpha = size
    section[r_key] = [R]
    if t_key is not None:
        section[t_key] = tan_alpha
    if say is not None:
        say(f"{field}: {body_line(height, diameter, R, tan_alpha)}")
    return tan_alpha


def _agree(run: dict, key: str, tan_alpha: float, field: str) -> None:
    """A run's ``tan_alpha``: the body's when left out, else it must be the body's."""
    given = _grid_values(run.get(key))
    if given is None:
        run[key] = [tan_alpha]
        return
    bad = [v for v in given if not math.isclose(v, tan_alpha, rel_tol=AGREE_RTOL)]
    if bad:
        raise ValueError(f"{field}.{key} {bad[0]!r} contradicts the study's height and "
                         f"diameter (tan_alpha = {tan_alpha:.6g}); leave it out")
