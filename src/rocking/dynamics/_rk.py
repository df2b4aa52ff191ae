"""Explicit Runge–Kutta steppers of the driver: Dormand–Prince 5(4) and DOP853.

Two embedded pairs are available, with the coefficients taken from SciPy's own classes
(:class:`scipy.integrate.RK45`, :class:`scipy.integrate.DOP853`) so that no tableau is typed
by hand:

- ``DP5``: Dormand–Prince 5(4), 6 new right-hand-side evaluations per step (FSAL);
- ``DOP853``: Hairer's 8(5,3) pair, 12 new evaluations per step.

Why DP5 is the default of the undamped models (measured, ``python -m benchmarks
dynamics``, right-hand-side evaluations being the machine-independent cost): the ground
acceleration is only piecewise linear, so every step ends on a record sample and no step
exceeds the record dt. With steps capped that short the 8th-order pair cannot take the long
steps it is made for, while it pays 12 evaluations per step instead of 6. DOP853 wins only
for errors below ~1e-8 (converged references, long free vibrations); it stays available
(``tableau("dop853")``) and the benchmark uses it for its references.

:func:`rk_step` has the stepper signature of :mod:`.driver` (the Rosenbrock stepper of
:mod:`._rosenbrock` has the same one); the ``factor``/``solve`` hooks of the model are not
used by an explicit method.
"""

from __future__ import annotations

import functools

import numpy as np
from numba import njit
from scipy.integrate import DOP853 as _SCIPY_DOP853
from scipy.integrate import RK45 as _SCIPY_RK45

from rocking.dynamics._numerics import error_scale
from rocking.dynamics.driver import control_array

DP5 = 0
"""Dormand–Prince 5(4)."""
DOP853 = 1
"""Hairer's DOP853, 8(5,3)."""

METHODS = {"dp5": DP5, "dop853": DOP853}

WORK_ROWS = 13
"""Rows of the work array: 12 stages + the derivative at the step end."""

# The tableaux are passed to the kernels as arguments: numba cannot cache functions that
# read global arrays of this size (it links them as dynamic globals).

_A5 = np.zeros((6, 6))
_A5[:, :5] = _SCIPY_RK45.A
_B5 = np.ascontiguousarray(_SCIPY_RK45.B, dtype=np.float64)
_C5 = np.ascontiguousarray(_SCIPY_RK45.C, dtype=np.float64)
_E5 = np.ascontiguousarray(_SCIPY_RK45.E, dtype=np.float64)
_A8 = np.ascontiguousarray(_SCIPY_DOP853.A[:12, :12], dtype=np.float64)
_B8 = np.ascontiguousarray(_SCIPY_DOP853.B, dtype=np.float64)
_C8 = np.ascontiguousarray(_SCIPY_DOP853.C[:12], dtype=np.float64)
_E8_5 = np.ascontiguousarray(_SCIPY_DOP853.E5, dtype=np.float64)
_E8_3 = np.ascontiguousarray(_SCIPY_DOP853.E3, dtype=np.float64)


@functools.cache
def tableau(method: int | str) -> tuple:
    """``(T, method)``: the coefficients of an embedded pair packed in one array ``T``, the
    ``tab`` of :func:`rk_step`.

    With s stages, rows 0 … s−1 of ``T`` hold A, then B, C, the error weights E5 (DP5: 7
    including the FSAL stage) and DOP853's third-order weights E3 (zeros for DP5).
    """
    m = METHODS[method.lower()] if isinstance(method, str) else int(method)
    if m == DP5:
        A, B, C, E5, E3 = _A5, _B5, _C5, _E5, np.zeros(7)
    elif m == DOP853:
        A, B, C, E5, E3 = _A8, _B8, _C8, _E8_5, _E8_3
    else:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {method!r}")
    s = B.size
    T = np.zeros((s + 4, s + 1))
    T[:s, :s] = A
    T[s, :s] = B
    T[s + 1, :s] = C
    T[s + 2, :E5.size] = E5
    T[s + 3, :E3.size] = E3
    return T, m


@functools.cache
def control(method: int | str) -> np.ndarray:
    """Step-size control constants of the pair, indexed by the ``C_*`` names of
    :mod:`.driver` (used in :func:`rocking.dynamics.driver.integrate` and
    :func:`rocking.dynamics.driver.growth`).

    Growth at most 10× a step, the order of the error estimate (the values of SciPy's explicit
    Runge–Kutta classes), a larger proposal kept across a step cut short by a record sample,
    growth allowed right after a rejection, the derivative at the step end returned (FSAL).
    """
    m = tableau(method)[1]
    return control_array(growth=10.0, order=4.0 if m == DP5 else 7.0, keep_proposal=True,
                         freeze=False, end_derivative=True)


@njit(cache=True, error_model="numpy")
def n_stages(method: int) -> int:
    """Stages per step (the derivative at the end is stored in row ``n_stages``)."""
    return 6 if method == DP5 else 12


@njit(cache=True, error_model="numpy")
def _error_norm(T, ns, method, K, h, y, y_new, rtol, SC, n):
    """Scaled RMS error estimate of the step (accept when ≤ 1)."""
    tilt = max(abs(y[0]), abs(y_new[0]))
    if method == DP5:
        acc = 0.0
        for i in range(n):
            e = 0.0
            for j in range(7):
                e += T[ns + 2, j] * K[j, i]
            r = h * e / error_scale(rtol, SC[0, i], SC[1, i], y[i], y_new[i], tilt)
            acc += r * r
        return np.sqrt(acc / n)
    e5sum = 0.0
    e3sum = 0.0
    for i in range(n):
        sc = error_scale(rtol, SC[0, i], SC[1, i], y[i], y_new[i], tilt)
        e5 = 0.0
        e3 = 0.0
        for j in range(13):
            e5 += T[ns + 2, j] * K[j, i]
            e3 += T[ns + 3, j] * K[j, i]
        e5sum += (e5 / sc) ** 2
        e3sum += (e3 / sc) ** 2
    if e5sum == 0.0 and e3sum == 0.0:
        return 0.0
    return abs(h) * e5sum / np.sqrt((e5sum + 0.01 * e3sum) * n)


@njit(cache=True, inline="always", error_model="numpy")
def rk_step(rhs, factor, solve, tab, tau, y, f0, h, P, F, tol, W, LA, y_new, f_new):
    """One explicit Runge–Kutta step of length ``h`` from ``(tau, y)`` with ``f0 = rhs(tau, y)``.

    Fills ``y_new`` and its derivative ``f_new``; returns the scaled error norm (NaN when the
    step is not finite). ``W`` is the work array (:data:`WORK_ROWS` rows).
    """
    T, method = tab
    ns = n_stages(method)
    n = y.size
    K = W
    for i in range(n):
        K[0, i] = f0[i]
    for s in range(1, ns):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += T[s, j] * K[j, i]
            y_new[i] = y[i] + h * acc
        rhs(tau + T[ns + 1, s] * h, y_new, P, F, f_new)  # stage point and slope in the outputs
        for i in range(n):
            K[s, i] = f_new[i]
    for i in range(n):
        acc = 0.0
        for j in range(ns):
            acc += T[ns, j] * K[j, i]
        y_new[i] = y[i] + h * acc
    rhs(tau + h, y_new, P, F, f_new)
    for i in range(n):
        K[ns, i] = f_new[i]
    return _error_norm(T, ns, method, K, h, y, y_new, tol[0], tol[1], tol[2])
