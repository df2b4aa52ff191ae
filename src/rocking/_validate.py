"""Small argument checks that name the offending field and value."""

from __future__ import annotations

import math


def positive_finite(name: str, value: float) -> float:
    """``float(value)`` when it is a finite number > 0, else ``ValueError`` in one line
    naming ``name`` and the value: the one check of a positive number (arguments,
    configuration keys, command-line options, fields of a file). A boolean is refused; text
    that spells a number (a field of a file) is read as that number."""
    try:
        v = math.nan if isinstance(value, bool) else float(value)
    except (TypeError, ValueError):
        v = math.nan
    if not (math.isfinite(v) and v > 0.0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return v


def positive_finite_array(name: str, values):
    """``values`` as a float64 array (any shape) when every one is a finite number > 0, else
    ``ValueError`` in one line naming ``name``, the first offending value and where it is:
    :func:`positive_finite` for an array of them, in one vectorized pass."""
    import numpy as np  # here: the scalar checks load no numpy (the CLI's help)

    a = np.asarray(values, dtype=np.float64)
    bad = np.flatnonzero(~(np.isfinite(a) & (a > 0.0)))
    if bad.size:
        i = int(bad[0])
        at = f" at sample {i}" if a.ndim else ""
        raise ValueError(f"{name} must hold finite numbers > 0, got {float(a.flat[i])!r}{at}")
    return a


def nonnegative_finite(name: str, value: float) -> float:
    """Return ``float(value)`` or raise ``ValueError`` if negative, NaN or infinite."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}") from None
    if not math.isfinite(v) or v < 0.0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return v


def finite(name: str, value: float) -> float:
    """Return ``float(value)`` or raise ``ValueError`` if NaN or infinite."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number, got {value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return v


def finite_array(name: str, values):
    """Return a 1-D float64 copy of ``values``; raise naming the first non-finite sample."""
    import numpy as np  # here: the checks of numbers above load no numpy (the CLI's help)

    a = np.asarray(values, dtype=np.float64)
    if a.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"{name} has a non-finite value {a[i]!r} at sample {i}")
    return a.copy()
