"""Which modes a study runs, at which slendernesses and limit states.

A study's ``runs`` (workflow configuration, ``studies.<name>.runs``) list what the figures and
outputs need, e.g. the undamped 3D model at three tan α for Fig 11 but the damped model only
at tan α = 0.2 for Fig 9. Each run is a product modes × tan α × limit states; the study's
store holds the union grid (every mode, tan α and limit state named by some run) and marks
which (mode, limit_state, tan_alpha) cells some run asked for (``requested``). Cells nobody
asked for are never computed: they stay NaN with every flag false and ``requested`` false,
which tells "not computed" apart from "not reached" (NaN with ``not_reached`` true).

One search serves every limit state of a (mode, tan α, motion, R) point, so a run's limit
states cost little beyond its most demanding one; a mode or tan α costs a whole search per
point. The plan therefore decides the cost of a study (:meth:`StudyPlan.points`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from rocking.spectra.limit_states import parse_limit_states
from rocking.spectra.modes import MODE_3D, MODES, ONE_COMPONENT_MODES


@dataclass(frozen=True)
class Run:
    """One product of modes × tan α × limit states asked for by a study.

    Attributes
    ----------
    modes : tuple of str
        Modes of :data:`rocking.spectra.critical.MODES`.
    tan_alpha : tuple of float
        Slendernesses [-].
    limit_states : tuple of str
        Canonical limit-state names, by increasing tilt goal.
    purpose : str
        What needs it (e.g. ``"Fig 11"``); a label, not part of the result.
    """

    modes: tuple[str, ...]
    tan_alpha: tuple[float, ...]
    limit_states: tuple[str, ...]
    purpose: str = ""

    def to_dict(self) -> dict:
        """The result-affecting fields (the purpose label is left out of store hashes)."""
        return {"modes": list(self.modes), "tan_alpha": list(self.tan_alpha),
                "limit_states": list(self.limit_states)}


@dataclass(frozen=True, eq=False)
class StudyPlan:
    """The union grid of a study's runs and which of its cells are requested.

    Attributes
    ----------
    runs : tuple of Run
    modes : tuple of str
        Every mode of some run, in the order of :data:`~rocking.spectra.critical.MODES`.
    limit_states : tuple of str
        Every limit state of some run, by increasing tilt goal.
    tan_alpha : tuple of float
        Every slenderness of some run, increasing [-].
    requested : ndarray of bool
        (mode, limit_state, tan_alpha): True where some run asks for the cell.
    """

    runs: tuple[Run, ...]
    modes: tuple[str, ...]
    limit_states: tuple[str, ...]
    tan_alpha: tuple[float, ...]
    requested: np.ndarray

    def limit_states_of(self, mode: str, tan_alpha: float) -> list[str]:
        """Limit states requested for ``mode`` at ``tan_alpha`` (empty: nothing to compute)."""
        i = self.modes.index(mode)
        k = _index_of_value(self.tan_alpha, tan_alpha)
        return [ls for j, ls in enumerate(self.limit_states) if self.requested[i, j, k]]

    def points(self, n_motions: int, n_R: int) -> dict[str, int]:
        """Spectrum points (searches) per mode: requested (mode, tan α) × motions × sizes."""
        per_mode = self.requested.any(axis=1).sum(axis=1)
        return {m: int(n) * n_motions * n_R for m, n in zip(self.modes, per_mode, strict=True)}

    def compares_2d_with_3d(self) -> bool:
        """Whether the plan runs "3d" and a mode under one component (the 3D model's or
        Housner's 2D block) at a common tan α: the comparison of Fig 12."""
        flat = [m for m in ONE_COMPONENT_MODES if m in self.modes]
        return MODE_3D in self.modes and any(
            self.limit_states_of(MODE_3D, t) and any(self.limit_states_of(m, t) for m in flat)
            for t in self.tan_alpha)

    def to_dict(self) -> dict:
        """JSON form of the runs (what a store records and hashes)."""
        return {"runs": [r.to_dict() for r in self.runs]}


def _index_of_value(values: Sequence[float], value: float) -> int:
    hits = [i for i, v in enumerate(values) if math.isclose(v, float(value), rel_tol=1e-12)]
    if not hits:
        raise ValueError(f"tan_alpha={value!r} is not in the study's {list(values)}")
    return hits[0]


def parse_run(spec: Mapping, field: str) -> Run:
    """One run from its configuration mapping, every value checked.

    Parameters
    ----------
    spec : mapping
        ``modes``, ``tan_alpha`` (list of numbers), ``limit_states``, optional ``purpose``.
    field : str
        Its place in the configuration (e.g. ``"studies.elcentro.runs[2]"``), for errors.

    Raises
    ------
    ValueError
        Naming the field and the value: unknown keys or modes, empty or repeated lists,
        slendernesses that are not finite and > 0, limit states that cannot be parsed or
        whose tilt goal is not below π/2 at one of the run's slendernesses.
    """
    if not isinstance(spec, Mapping):
        raise ValueError(f"{field} must be a mapping with modes, tan_alpha and limit_states, "
                         f"got {spec!r}")
    unknown = sorted(set(spec) - {"modes", "tan_alpha", "limit_states", "purpose"})
    if unknown:
        raise ValueError(f"{field} has unknown key(s) {unknown}; allowed: modes, tan_alpha, "
                         "limit_states, purpose")
    modes = _nonempty_unique(spec, "modes", field)
    unknown_modes = [m for m in modes if m not in MODES]
    if unknown_modes:
        raise ValueError(f"{field}.modes: unknown mode(s) {unknown_modes}; allowed {list(MODES)}")
    tan_alpha = []
    for t in _nonempty_unique(spec, "tan_alpha", field):
        value = float(t) if isinstance(t, (int, float)) and not isinstance(t, bool) else math.nan
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f"{field}.tan_alpha must hold finite numbers > 0, got {t!r}")
        tan_alpha.append(value)
    specs = _nonempty_unique(spec, "limit_states", field)
    try:
        states = parse_limit_states(specs)
        for t in tan_alpha:  # a goal at or beyond π/2 can only be met by overturning
            for s in states:
                s.threshold(math.atan(t))
    except ValueError as exc:
        raise ValueError(f"{field}.limit_states: {exc}") from None
    names = [s.name for s in states]
    if len(names) != len(specs):
        raise ValueError(f"{field}.limit_states names one tilt goal twice: {specs!r} "
                         f"(distinct goals: {names})")
    return Run(tuple(modes), tuple(sorted(tan_alpha)), tuple(names),
               str(spec.get("purpose", "")))


def _nonempty_unique(spec: Mapping, key: str, field: str) -> list:
    values = spec.get(key)
    if not isinstance(values, (list, tuple)) or not values:
        raise ValueError(f"{field}.{key} must be a non-empty list, got {values!r}")
    if len({repr(v) for v in values}) != len(values):
        raise ValueError(f"{field}.{key} has repeated values {list(values)!r}")
    return list(values)


def plan_study(runs: Sequence[Mapping | Run], field: str = "runs") -> StudyPlan:
    """The union grid and request mask of a study's runs.

    Parameters
    ----------
    runs : sequence of mapping or Run
        The study's ``runs`` (mappings are checked by :func:`parse_run`).
    field : str
        Configuration path of the list, for errors (e.g. ``"studies.elcentro.runs"``).

    Returns
    -------
    StudyPlan
    """
    if not isinstance(runs, (list, tuple)) or not runs:
        raise ValueError(f"{field} must be a non-empty list of runs, got {runs!r}")
    parsed = tuple(r if isinstance(r, Run) else parse_run(r, f"{field}[{i}]")
                   for i, r in enumerate(runs))
    modes = tuple(m for m in MODES if any(m in r.modes for r in parsed))
    # one name per tilt goal ("tilt:1/2" and "tilt:0.5" are one)
    union = parse_limit_states([ls for r in parsed for ls in r.limit_states])
    states = tuple(s.name for s in union)
    tan_alpha = tuple(sorted({t for r in parsed for t in r.tan_alpha}))
    requested = np.zeros((len(modes), len(states), len(tan_alpha)), dtype=bool)
    for r in parsed:
        i = [modes.index(m) for m in r.modes]
        j = [states.index(s.name) for s in parse_limit_states(r.limit_states)]
        k = [tan_alpha.index(t) for t in r.tan_alpha]
        requested[np.ix_(i, j, k)] = True
    return StudyPlan(parsed, modes, states, tan_alpha, requested)
