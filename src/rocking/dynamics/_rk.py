"""Shared compiled core of the explicit Runge–Kutta integrators of the rocking models.

Two embedded pairs are available, with the coefficients taken from SciPy's own classes
(:class:`scipy.integrate.RK45`, :class:`scipy.integrate.DOP853`) so that no tableau is typed
by hand:

- ``DP5``: Dormand–Prince 5(4), 6 new right-hand-side evaluations per step (FSAL);
- ``DOP853``: Hairer's 8(5,3) pair, 12 new evaluations per step.

Why DP5 is the default (measured, ``python -m rocking.benchmarks dynamics``, right-hand-side
evaluations being the machine-independent cost): the ground acceleration is only piecewise
linear, so every step ends on a record sample and no step exceeds the record dt (0.005–0.02
s). With steps capped that short the 8th-order pair cannot take the long steps it is made
for, while it pays 12 evaluations per step instead of 6. At the accuracy the analyses need
(θmax to ~1e-5) DP5 is cheaper: El Centro, R = 6 m, PGA/(g tan α) = 2, 3D: DP5 at rtol 1e-8
has θmax error 9e-6 with 7.3e3 steps (4.4e4 evaluations), DOP853 needs rtol 1e-7 for 1e-5
(5.4e3 steps, 6.4e4 evaluations). DOP853 wins below ~1e-8 error (converged references,
long free vibrations), so it stays available (``tableau("dop853")``) and the benchmark uses
it for the references.

Events are located on the cubic Hermite interpolant through the step end points (values and
derivatives are both known, the latter through FSAL) and the state there is then computed by
a genuine Runge–Kutta step of the found length from the step start ("landing"), so an event
state has the accuracy of the integrator, not that of the interpolant.

The model's right-hand side is passed as a compiled function ``rhs(tau, y, P, F, out)``:
``tau`` is the time inside the current record interval [s], ``P`` the model parameters and
``F`` the forcing of the interval (a0x, a0y, slope_x, slope_y), so that the ground
acceleration is ``a0 + slope * tau``. Keeping a local time inside the interval keeps 1e-18 s
resolution during quasi-impacts, which last 1e-10 s at t = 40 s where the absolute time has a
resolution of only 7e-15 s.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from scipy.integrate import DOP853 as _SCIPY_DOP853
from scipy.integrate import RK45 as _SCIPY_RK45

DP5 = 0
"""Dormand–Prince 5(4)."""
DOP853 = 1
"""Hairer's DOP853, 8(5,3)."""

METHODS = {"dp5": DP5, "dop853": DOP853}

MAX_STAGES = 13
"""Rows of the stage work array (DOP853: 12 stages + the derivative at the step end)."""

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

EPS = np.finfo(np.float64).eps


def tableau(method: int | str) -> tuple:
    """``(method, A, B, C, E5, E3)`` of an embedded pair, for the ``tab`` argument of kernels.

    ``E5`` is the error weights of the pair (DP5: 7 weights including the FSAL stage),
    ``E3`` the third-order estimate of DOP853 (zeros for DP5).
    """
    m = METHODS[method.lower()] if isinstance(method, str) else int(method)
    if m == DP5:
        return (DP5, _A5, _B5, _C5, _E5, np.zeros(7))
    if m == DOP853:
        return (DOP853, _A8, _B8, _C8, _E8_5, _E8_3)
    raise ValueError(f"method must be one of {sorted(METHODS)}, got {method!r}")


@njit(cache=True)
def n_stages(method: int) -> int:
    """Stages per step (the FSAL derivative at the end is stored in row ``n_stages``)."""
    return 6 if method == DP5 else 12


@njit(cache=True)
def error_exponent(method: int) -> float:
    """−1/(q + 1), q the order of the embedded error estimate."""
    return -1.0 / 5.0 if method == DP5 else -1.0 / 8.0


@njit(cache=True, inline="always")
def rk_step(rhs, tab, tau, y, h, P, F, K, ytmp, y_new, f_new):
    """One explicit Runge–Kutta step of length ``h`` from ``(tau, y)``.

    ``tab`` is :func:`tableau`; ``K[0]`` must hold ``rhs(tau, y)``. Fills the stages ``K``,
    the solution ``y_new`` and its derivative ``f_new`` (also stored in ``K[n_stages]``).
    """
    A, B, C = tab[1], tab[2], tab[3]
    ns = n_stages(tab[0])
    n = y.size
    for s in range(1, ns):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += A[s, j] * K[j, i]
            ytmp[i] = y[i] + h * acc
        rhs(tau + C[s] * h, ytmp, P, F, K[s])
    for i in range(n):
        acc = 0.0
        for j in range(ns):
            acc += B[j] * K[j, i]
        y_new[i] = y[i] + h * acc
    rhs(tau + h, y_new, P, F, f_new)
    for i in range(n):
        K[ns, i] = f_new[i]


@njit(cache=True)
def error_norm(tab, K, h, y, y_new, rtol, floor):
    """Scaled RMS error estimate of the last step (accept when ≤ 1).

    The scale of component i is ``rtol * (floor[i] + max(|y_i|, |y_new_i|))``: a zero floor
    makes the control purely relative, which is what the tilt needs in quasi-impacts.
    """
    n = y.size
    E5, E3 = tab[4], tab[5]
    if tab[0] == DP5:
        acc = 0.0
        for i in range(n):
            sc = rtol * (floor[i] + max(abs(y[i]), abs(y_new[i])))
            sc = max(sc, 1e-300)
            e = 0.0
            for j in range(7):
                e += E5[j] * K[j, i]
            r = h * e / sc
            acc += r * r
        return np.sqrt(acc / n)
    e5sum = 0.0
    e3sum = 0.0
    for i in range(n):
        sc = rtol * (floor[i] + max(abs(y[i]), abs(y_new[i])))
        sc = max(sc, 1e-300)
        e5 = 0.0
        e3 = 0.0
        for j in range(13):
            e5 += E5[j] * K[j, i]
            e3 += E3[j] * K[j, i]
        e5sum += (e5 / sc) ** 2
        e3sum += (e3 / sc) ** 2
    if e5sum == 0.0 and e3sum == 0.0:
        return 0.0
    return abs(h) * e5sum / np.sqrt((e5sum + 0.01 * e3sum) * n)


@njit(cache=True)
def step_factor(method, err):
    """Step-size multiplier after a step with scaled error ``err`` (0.2 … 10)."""
    if err == 0.0:
        return 10.0
    return min(10.0, max(0.2, 0.9 * err ** error_exponent(method)))


@njit(cache=True, inline="always")
def initial_step(rhs, method, tau, y, f0, P, F, rtol, floor, h_max, ytmp, f1):
    """Hairer's starting step (as in SciPy's ``select_initial_step``), capped at ``h_max``."""
    n = y.size
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = max(rtol * (floor[i] + abs(y[i])), 1e-300)
        d0 += (y[i] / sc) ** 2
        d1 += (f0[i] / sc) ** 2
    d0 = np.sqrt(d0 / n)
    d1 = np.sqrt(d1 / n)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6 * h_max
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, h_max)
    for i in range(n):
        ytmp[i] = y[i] + h0 * f0[i]
    rhs(tau + h0, ytmp, P, F, f1)
    d2 = 0.0
    for i in range(n):
        sc = max(rtol * (floor[i] + abs(y[i])), 1e-300)
        d2 += ((f1[i] - f0[i]) / sc) ** 2
    d2 = np.sqrt(d2 / n) / h0
    q = 4.0 if method == DP5 else 7.0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (q + 1.0))
    return min(100.0 * h0, h1, h_max)


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
def push_time(buf, n, value):
    """Append ``value`` at index ``n`` of ``buf``, doubling the buffer when full."""
    if n >= buf.size:
        new = np.empty(2 * buf.size)
        new[:n] = buf[:n]
        buf = new
    buf[n] = value
    return buf


@njit(cache=True)
def push_row(buf, n, row):
    """Append ``row`` at row ``n`` of ``buf``, doubling the buffer when full."""
    if n >= buf.shape[0]:
        new = np.empty((2 * buf.shape[0], buf.shape[1]))
        new[:n] = buf[:n]
        buf = new
    for i in range(row.size):
        buf[n, i] = row[i]
    return buf


@njit(cache=True)
def set_forcing(F, ax, ay, k, dt):
    """Forcing of interval k: values at its start and slopes (linear between samples)."""
    n = ax.size
    if k + 1 < n:
        F[0] = ax[k]
        F[1] = ay[k]
        F[2] = (ax[k + 1] - ax[k]) / dt
        F[3] = (ay[k + 1] - ay[k]) / dt
    elif k < n:
        F[0] = ax[k]
        F[1] = ay[k]
        F[2] = 0.0
        F[3] = 0.0
    else:
        F[0] = 0.0
        F[1] = 0.0
        F[2] = 0.0
        F[3] = 0.0
