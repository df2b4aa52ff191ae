"""Small argument checks that name the offending field and value."""

from __future__ import annotations

import math

import numpy as np


def positive_finite(name: str, value: float) -> float:
    """Return ``float(value)`` or raise ``ValueError`` naming ``name`` and the value."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


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


def finite_array(name: str, values) -> np.ndarray:
    """Return a 1-D float64 copy of ``values``; raise naming the first non-finite sample."""
    a = np.asarray(values, dtype=np.float64)
    if a.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"{name} has a non-finite value {a[i]!r} at sample {i}")
    return a.copy()
