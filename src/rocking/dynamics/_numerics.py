"""Small compiled helpers shared by the driver and the steppers.

Error scales, the cubic Hermite interpolant of a step and the root of one of its components
(event location), recorders of (time, state) rows and the piecewise-linear ground forcing of
one record interval.
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.typed import List

EPS = np.finfo(np.float64).eps


@njit(cache=True, inline="always", error_model="numpy")
def error_scale(rtol, floor_i, wtilt_i, y_i, y_new_i, tilt):
    """Scale of one component in the error norm: ``rtol (floor_i + |y_i| + wtilt_i |θ|)``.

    |y_i| is the larger of the step's two ends and ``tilt`` the larger |θ| (component 0,
    the tilt, in every model). A zero floor makes the control purely relative, which is what
    the tilt needs in quasi-impacts; ``wtilt`` ties the scale of a rate to the tilt (the
    damped model's θ̇, see :mod:`.cylinder3d_damped`). The tolerances of a run are the tuple
    ``tol = (rtol, scales, n_err)`` with rows (floor, wtilt) in ``scales``: only the first
    ``n_err`` components are controlled.
    """
    big = max(abs(y_i), abs(y_new_i))
    return max(rtol * (floor_i + big + wtilt_i * tilt), 1e-300)


@njit(cache=True, error_model="numpy")
def hermite(y0, d0, y1, d1, h, s):
    """Cubic Hermite interpolant at fraction ``s`` of a step of length ``h``."""
    s2 = s * s
    s3 = s2 * s
    return (
        (2.0 * s3 - 3.0 * s2 + 1.0) * y0
        + (s3 - 2.0 * s2 + s) * h * d0
        + (3.0 * s2 - 2.0 * s3) * y1
        + (s3 - s2) * h * d1
    )


@njit(cache=True, error_model="numpy")
def hermite_root(y0, d0, y1, d1, h, level, s_hi):
    """Fraction s in (0, s_hi] where the Hermite interpolant crosses ``level``.

    Assumes a sign change of (interpolant − level) between s = 0 and s = s_hi. Illinois
    (modified regula falsi): guaranteed bracketing, superlinear convergence.
    """
    a, b = 0.0, s_hi
    fa = y0 - level
    fb = hermite(y0, d0, y1, d1, h, b) - level
    if fa == 0.0:
        return 0.0
    if fb == 0.0 or fa * fb > 0.0:
        return b
    side = 0
    for _ in range(100):
        c = (a * fb - b * fa) / (fb - fa)
        if not (a < c < b):
            c = 0.5 * (a + b)
        fc = hermite(y0, d0, y1, d1, h, c) - level
        if fc == 0.0:
            return c
        if fc * fb < 0.0:
            a, fa = b, fb
            b, fb = c, fc
            side = 0
        else:
            b, fb = c, fc
            if side == 1:
                fa *= 0.5
            side = 1
        if abs(b - a) <= 4.0 * EPS * max(abs(b), 1e-300):
            break
    return b


@njit(cache=True, error_model="numpy")
def recorder():
    """An empty recorder of (t, row) pairs.

    ``(time chunks, row chunks, [count, index in the last chunk])``: a list of chunks that
    only grows, so that the compiled driver never rebinds a buffer inside its step loop (a
    rebound array is reference-counted at every iteration).
    """
    ts = List.empty_list(types.float64[::1])
    ys = List.empty_list(types.float64[:, ::1])
    return ts, ys, np.zeros(2, dtype=np.int64)


@njit(cache=True, error_model="numpy")
def record(rec, t, row):
    """Append ``t`` and ``row`` to a recorder; each new chunk doubles the capacity."""
    ts, ys, count = rec
    j = count[1]
    if len(ts) == 0 or j == ts[len(ts) - 1].size:
        size = max(64, count[0])
        ts.append(np.empty(size))
        ys.append(np.empty((size, row.size)))
        j = 0
    last = len(ts) - 1
    ts[last][j] = t
    yl = ys[last]
    for i in range(row.size):
        yl[j, i] = row[i]
    count[0] += 1
    count[1] = j + 1


@njit(cache=True, error_model="numpy")
def recorded(rec, width):
    """The recorded times and rows as two arrays."""
    ts, ys, count = rec
    t = np.empty(count[0])
    y = np.empty((count[0], width))
    n = 0
    for c in range(len(ts)):
        m = ts[c].size if c < len(ts) - 1 else count[1]
        t[n:n + m] = ts[c][:m]
        y[n:n + m] = ys[c][:m]
        n += m
    return t, y


@njit(cache=True, error_model="numpy")
def set_forcing(F, ax, ay, az, k, dt):
    """Forcing of interval k: values at its start and slopes (linear between samples).

    ``F = (a0x, a0y, slope_x, slope_y, a0z, slope_z)``; ``az`` is the vertical ground
    acceleration (positive up; an all-zero array for a motion without one, which makes
    every model's effective gravity g + 0 = g exactly).
    """
    n = ax.size
    if k + 1 < n:
        F[0] = ax[k]
        F[1] = ay[k]
        F[2] = (ax[k + 1] - ax[k]) / dt
        F[3] = (ay[k + 1] - ay[k]) / dt
        F[4] = az[k]
        F[5] = (az[k + 1] - az[k]) / dt
    elif k < n:
        F[0] = ax[k]
        F[1] = ay[k]
        F[2] = 0.0
        F[3] = 0.0
        F[4] = az[k]
        F[5] = 0.0
    else:
        for i in range(6):
            F[i] = 0.0
