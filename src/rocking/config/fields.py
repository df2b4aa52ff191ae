"""Fields of a workflow configuration: the schema's defaults and their checked parsing.

The one place grids are expanded (:func:`expand_grid`); the small checkers (a number, a
positive number, a mapping with only known keys over its defaults, a list of modes, a task
size, an accuracy) every spec class of :mod:`rocking.study` builds itself with, each error
naming the key and the value.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from rocking._validate import positive_finite_array
from rocking.dynamics.names import DAMPED_OMEGA_N, DAMPED_ZETA
from rocking.grids import grid_values
from rocking.motions.measures import DEFAULT_COMPONENT
from rocking.spectra.accuracy import DEFAULT_UPPER, Accuracy
from rocking.spectra.modes import MODE_3D, MODE_3D_DAMPED

__all__ = ["DEFAULTS", "expand_grid"]

DEFAULTS: dict[str, Any] = {
    "accuracy": "default",
    "quantity": "exceedance_quantile",
    "search": {"upper": DEFAULT_UPPER},
    "damped": {"omega_n": DAMPED_OMEGA_N, "zeta": DAMPED_ZETA},
    "motions": {"max_duration": None},
    "dask": {"min_task_seconds": 0.1},
    "ensemble": {"paths": None, "units": "g", "dt": None, "n_synthetic": 10, "seed": 2017,
                 "mw": None, "rotation_deg": "auto", "highpass": "oscillator", "fc_hz": None,
                 "fit_method": "spectrum", "vertical": False, "params": None},
    "study": {"chunk_R": "auto", "upper": None, "intensity_measures": ["pga", "pgv"],
              "mu": None, "component": DEFAULT_COMPONENT},
    "tilt_map": {"motion": None, "modes": [MODE_3D, MODE_3D_DAMPED], "tan_alpha": 0.2,
                 "chunk_R": 1},
    "stripes": {"modes": [MODE_3D], "tan_alpha": 0.2,
                "limit_states": ["overturning", "tilt:1/3"], "chunk_R": 1, "measure": "pga",
                "refine": 8, "bootstrap": 1000, "jitter": 0.02},
}
"""The schema's defaults (tests/test_spec.py holds them equal), for configurations read
without the workflow (the benchmark drivers); the workflow has filled them in already."""

def expand_grid(spec: Sequence[float] | Mapping[str, Any], field: str) -> list[float]:
    """Values of a grid given as a list or ``{start, stop, num[, spacing]}``.

    Parameters
    ----------
    spec : list of float or mapping
        The values, or ``start``, ``stop``, ``num`` and optional ``spacing`` (``"linear"``,
        default, or ``"log"``); the endpoints are included.
    field : str
        Configuration key, for errors (e.g. ``"studies.elcentro.R"``).

    Returns
    -------
    list of float
        Generated values rounded to 12 significant digits (0.5 + 3·0.95 is 3.35, not
        3.3499999999999996).

    Raises
    ------
    ValueError
        Naming ``field``: a malformed grid, stop below start, values that are not finite and
        > 0, or repeated values.
    """
    if isinstance(spec, (list, tuple)):
        values = [number_field(v, field) for v in spec]
    elif isinstance(spec, Mapping):
        missing = [k for k in ("start", "stop", "num") if k not in spec]
        if missing:
            raise ValueError(f"{field}={dict(spec)!r} lacks {missing}; give a list or "
                             "{start, stop, num[, spacing]}")
        start, stop = number_field(spec["start"], f"{field}.start"), number_field(spec["stop"],
                                                                         f"{field}.stop")
        num = spec["num"]
        if isinstance(num, bool) or not isinstance(num, int) or num < 1:
            raise ValueError(f"{field}.num must be an integer >= 1, got {num!r}")
        if stop < start:
            raise ValueError(f"{field}: stop={stop!r} is below start={start!r}")
        spacing = spec.get("spacing", "linear")
        if spacing not in ("linear", "log"):
            raise ValueError(f"{field}.spacing must be 'linear' or 'log', got {spacing!r}")
        values = grid_values(start, stop, num, spacing)
    else:
        raise ValueError(f"{field} must be a list of numbers or {{start, stop, num}}, "
                         f"got {spec!r}")
    if not values:
        raise ValueError(f"{field} must hold finite numbers > 0, got {values!r}")
    positive_finite_array(field, values)
    if len(set(values)) != len(values):
        raise ValueError(f"{field}: repeated values {values!r}")
    return values


def number_field(value: Any, field: str) -> float:
    """``value`` as a float, or one line naming ``field`` when it is no number (bools
    refused)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
        raise ValueError(f"{field} must be a number, got {value!r}")
    return float(value)


def config_section(config: Mapping[str, Any], key: str) -> dict[str, Any]:
    """``config[key]`` over its defaults."""
    given = config.get(key)
    if given is not None and not isinstance(given, Mapping):
        raise ValueError(f"{key} must be a mapping, got {given!r}")
    return {**DEFAULTS[key], **(given or {})}


def checked_mapping(value: Any, field: str, defaults: Mapping[str, Any], required: Sequence[str],
             ) -> dict[str, Any]:
    """``value`` (a mapping with only the keys of ``defaults`` and ``required``) over
    ``defaults``."""
    if not isinstance(value, Mapping):
        raise ValueError(f"{field} must be a mapping, got {value!r}")
    allowed = set(defaults) | set(required)
    unknown = sorted(set(value) - allowed)
    if unknown:
        raise ValueError(f"{field} has unknown key(s) {unknown}; allowed: {sorted(allowed)}")
    missing = [k for k in required if k not in value]
    if missing:
        raise ValueError(f"{field} lacks {missing}")
    return {**defaults, **value}


def mode_list(value: Any, field: str) -> tuple[str, ...]:
    """A non-empty list of modes of :data:`rocking.spectra.modes.MODES`, as a tuple."""
    from rocking.spectra.modes import MODES

    if not isinstance(value, (list, tuple)) or not value or any(m not in MODES for m in value):
        raise ValueError(f"{field} must be a non-empty list of modes {list(MODES)}, "
                         f"got {value!r}")
    return tuple(value)


def chunk_R_field(value: Any, field: str, auto: bool) -> int | str:
    """An integer >= 1 (or ``"auto"`` where ``auto``): sizes R per task."""
    if auto and value == "auto":
        return "auto"
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"{field} must be an integer >= 1{' or auto' if auto else ''}, "
                         f"got {value!r}")
    return value


def quantity_field(value: Any) -> dict[str, Any]:
    """The configuration's ``quantity`` (a name, or a mapping of ``name``, ``p`` and ``w``)
    as :meth:`rocking.spectra.quantity.Quantity.to_dict` (all three, so that equal choices
    hash alike); one line naming ``quantity``, ``quantity.p`` or ``quantity.w`` and the
    value otherwise."""
    from rocking.spectra.quantity import Quantity

    return Quantity.from_value(value).to_dict()


def accuracy_field(value: Any, w: float | None = None) -> Accuracy:
    """The configuration's ``accuracy`` (a preset name or tolerances mapping) as the
    :class:`rocking.spectra.accuracy.Accuracy` every part of the study hands down (it keeps
    the value as configured, which the stores record); one line naming it otherwise, and
    where its local sample is not wider than the window 2w of the quantity (``w``, when
    given)."""
    try:
        acc = Accuracy.of(value)
        if w is not None:
            acc.check_window(w)
    except (ValueError, TypeError, KeyError) as exc:
        raise ValueError(f"accuracy={value!r}: {exc}") from None
    return acc
