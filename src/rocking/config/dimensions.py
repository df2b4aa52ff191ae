"""The body as engineers give it: height and diameter instead of R and tan α.

A column is measured as its height 2h and diameter 2b [m]; the model takes its
semi-diagonal R = √(b² + h²) and slenderness tan α = b/h
(:func:`rocking.dynamics.dimensions.body_size`, which refuses a dimension without the other,
one that is not a length > 0 and an R or tan α that disagrees). :func:`resolve_dimensions`
does it for every ``height``/``diameter`` of a workflow configuration (a study and its stripes)
before the schema sees it.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Mapping
from typing import Any

from rocking.dynamics.dimensions import AGREE_RTOL, body_line, body_size, swap_warning

__all__ = ["AGREE_RTOL", "body_line", "body_size", "resolve_dimensions"]

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
        swapped = swap_warning(height, diameter, (f"{field}.height", f"{field}.diameter"))
        if swapped:
            say(swapped)
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
