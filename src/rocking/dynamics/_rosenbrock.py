"""Rosenbrock (linearly implicit Runge–Kutta) steppers of the driver, for the stiff damped model.

All methods are written in the Hairer–Wanner form without matrix–vector products with J
(Hairer & Wanner, *Solving ODEs II*, §IV.7; the same form as ``rodas.f`` and KPP):

    (I/(h γ) − J) K_i = f(t + α_i h, y + Σ_j a_ij K_j) + Σ_j (c_ij/h) K_j + γ_i h ∂f/∂t
    y_new = y + Σ m_i K_i,        err = Σ e_i K_i

with J = ∂f/∂y at the start of the step. Each step costs one Jacobian, one factorization and
``stages`` linear solves, and no Newton iteration (the reason Rosenbrock methods suit small,
cheap systems such as the damped model's).

:func:`ros_step` has the stepper signature of :mod:`.driver`; the model supplies the linear
algebra through two hooks, ``factor(tau, y, f0, P, F, c, LA)`` (Jacobian J and ∂f/∂t at the
step start, factorization of c I − J with c = 1/(hγ), all kept in ``LA``; False if
singular) and ``solve(LA, P, r, g)`` (overwrites r with (c I − J)⁻¹ (r + g ∂f/∂t)), so that
it can use the structure of its Jacobian (the damped model reduces 7×7 systems to 3×3 ones).
Every stage evaluates the right-hand side (the methods whose stage repeats the previous
point, RODAS3 and ROS3, pay one evaluation more than they need).

Tableaux (coefficients of Hairer's ``rodas.f`` and of the KPP Rosenbrock integrators):

- ``RODAS4``: 6 stages, order 4(3), L-stable, stiffly accurate (Hairer & Wanner 1996).
- ``RODAS3``: 4 stages, order 3(2), L-stable, stiffly accurate (Sandu et al. 1997).
- ``ROS3``: 3 stages (2 function evaluations), order 3(2), L-stable (Sandu et al. 1997).
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np
from numba import njit

from rocking.dynamics._numerics import error_scale
from rocking.dynamics.driver import control_array


class Tableau(NamedTuple):
    """Coefficients of one Rosenbrock method (see the module docstring for the scheme).

    Attributes
    ----------
    name : str
    order : int
        Order of the solution; the step-size controller uses err^(−1/order).
    gamma : float
        Diagonal coefficient γ.
    a, c : ndarray, shape (s, s)
        Strictly lower-triangular stage coefficients a_ij and c_ij.
    m, e : ndarray, shape (s,)
        Solution weights and error-estimate weights.
    alpha : ndarray, shape (s,)
        Stage times as fractions of h.
    gamma_t : ndarray, shape (s,)
        Weights γ_i of h ∂f/∂t (non-autonomous right-hand side).
    new_f : ndarray of bool, shape (s,)
        False where a stage evaluates f at the same point as the previous stage.
    """

    name: str
    order: int
    gamma: float
    a: np.ndarray
    c: np.ndarray
    m: np.ndarray
    e: np.ndarray
    alpha: np.ndarray
    gamma_t: np.ndarray
    new_f: np.ndarray


def _lower(s: int, packed: list[float]) -> np.ndarray:
    """Unpack row-wise strictly lower-triangular coefficients (a21, a31, a32, a41, ...)."""
    out = np.zeros((s, s))
    k = 0
    for i in range(1, s):
        for j in range(i):
            out[i, j] = packed[k]
            k += 1
    return out


_A4 = [
    1.544,
    0.9466785280815826, 0.2557011698983284,
    3.314825187068521, 2.896124015972201, 0.9986419139977817,
    1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950,
    1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950, 1.0,
]
_C4 = [
    -5.6688,
    -2.430093356833875, -0.2063599157091915,
    -0.1073529058151375, -9.594562251023355, -20.47028614809616,
    7.496443313967647, -10.24680431464352, -33.99990352819905, 11.70890893206160,
    8.083246795921522, -7.981132988064893, -31.52159432874371, 16.31930543123136,
    -6.058818238834054,
]

RODAS4 = Tableau(
    name="rodas4",
    order=4,
    gamma=0.25,
    a=_lower(6, _A4),
    c=_lower(6, _C4),
    m=np.array([1.221224509226641, 6.019134481288629, 12.53708332932087,
                -0.6878860361058950, 1.0, 1.0]),
    e=np.array([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]),
    alpha=np.array([0.0, 0.386, 0.21, 0.63, 1.0, 1.0]),
    gamma_t=np.array([0.25, -0.1043, 0.1035, -0.03620000000000023, 0.0, 0.0]),
    new_f=np.ones(6, dtype=np.bool_),
)

RODAS3 = Tableau(
    name="rodas3",
    order=3,
    gamma=0.5,
    a=_lower(4, [0.0, 2.0, 0.0, 2.0, 0.0, 1.0]),
    c=_lower(4, [4.0, 1.0, -1.0, 1.0, -1.0, -8.0 / 3.0]),
    m=np.array([2.0, 0.0, 1.0, 1.0]),
    e=np.array([0.0, 0.0, 0.0, 1.0]),
    alpha=np.array([0.0, 0.0, 1.0, 1.0]),
    gamma_t=np.array([0.5, 1.5, 0.0, 0.0]),
    new_f=np.array([True, False, True, True]),
)

_G3 = 0.43586652150845899941601945119356
ROS3 = Tableau(
    name="ros3",
    order=3,
    gamma=_G3,
    a=_lower(3, [1.0, 1.0, 0.0]),
    c=_lower(3, [-1.0156171083877702091975600115545,
                 4.0759956452537699824805835358067,
                 9.2076794298330791242156818474003]),
    m=np.array([1.0, 6.1697947043828245592553615689730, -0.42772256543218573326238373806514]),
    e=np.array([0.5, -2.9079558716805469821718236208017, 0.22354069897811569627360909276199]),
    alpha=np.array([0.0, _G3, _G3]),
    gamma_t=np.array([_G3, 0.24291996454816804366592249683314,
                      2.1851380027664058511513169485832]),
    new_f=np.array([True, True, False]),
)

TABLEAUX: dict[str, Tableau] = {t.name: t for t in (RODAS4, RODAS3, ROS3)}
"""The available methods by name."""


@functools.cache
def tableau(method: str = "rodas4") -> tuple:
    """``(T, γ)``: the coefficients of a method packed in one array, the ``tab`` of
    :func:`ros_step`.

    With s stages, the rows of ``T`` are a (s rows), c (s rows), m, e, α, γ_i and the
    new-evaluation flags (1.0/0.0).
    """
    t = TABLEAUX[method]
    s = t.m.size
    T = np.zeros((2 * s + 5, s))
    T[:s], T[s:2 * s] = t.a, t.c
    T[2 * s], T[2 * s + 1], T[2 * s + 2], T[2 * s + 3] = t.m, t.e, t.alpha, t.gamma_t
    T[2 * s + 4] = t.new_f
    return T, float(t.gamma)


@functools.cache
def control(method: str = "rodas4") -> np.ndarray:
    """Step-size control constants (see :func:`rocking.dynamics._rk.control`).

    Growth at most 6× a step and none right after a rejection, no memory of a larger
    proposal across a record sample: the slope of the ground acceleration jumps there and
    excites the contact mode, and reusing the proposal made the next step fail more often.
    The error estimate of an order-p method here is of order p − 1.
    """
    return control_array(growth=6.0, order=float(TABLEAUX[method].order - 1),
                         keep_proposal=False, freeze=True, end_derivative=False)


def work_rows(method: str = "rodas4") -> int:
    """Rows of the work array of :func:`ros_step`: the stages and the error estimate."""
    return max(len(TABLEAUX[method].m) + 1, 2)


@njit(cache=True, inline="always", error_model="numpy")
def ros_step(rhs, factor, solve, tab, tau, y, f0, h, P, F, tol, W, LA, y_new, f_new):
    """One Rosenbrock step of length ``h`` from ``(tau, y)`` with ``f0 = rhs(tau, y)``.

    Fills ``y_new`` (``f_new`` is scratch: the derivative at the step end is not part of the
    method, the driver evaluates it once a step is accepted); returns the scaled RMS error
    norm (NaN when the step is not finite or the stage matrix is singular). The stages are
    the rows of ``W``; no array is sliced or rebound here, which keeps the compiled step free
    of reference counting.
    """
    T, gamma = tab
    ns = T.shape[1]
    n = y.size
    cinv = 1.0 / (h * gamma)
    if not factor(tau, y, f0, P, F, cinv, LA):
        return math.nan
    for st in range(ns):
        if st == 0:
            for i in range(n):
                f_new[i] = f0[i]
        else:
            for i in range(n):  # the stage point, in y_new until the end of the step
                acc = y[i]
                for j in range(st):
                    acc += T[st, j] * W[j, i]
                y_new[i] = acc
            rhs(tau + T[2 * ns + 2, st] * h, y_new, P, F, f_new)
        for i in range(n):  # the stage's right side, solved in place in f_new
            acc = f_new[i]
            for j in range(st):
                acc += (T[ns + st, j] / h) * W[j, i]
            f_new[i] = acc
        solve(LA, P, f_new, T[2 * ns + 3, st] * h)
        for i in range(n):
            W[st, i] = f_new[i]
    for i in range(n):
        acc = y[i]
        er = 0.0
        for st in range(ns):
            acc += T[2 * ns, st] * W[st, i]
            er += T[2 * ns + 1, st] * W[st, i]
        y_new[i] = acc
        W[ns, i] = er
    return _error_norm(W, ns, y, y_new, tol[0], tol[1], tol[2])


@njit(cache=True, error_model="numpy")
def _error_norm(W, row, y, y_new, rtol, SC, n):
    """Scaled RMS norm of the error estimate in ``W[row]`` over the first ``n`` components."""
    tilt = max(abs(y[0]), abs(y_new[0]))
    acc = 0.0
    for i in range(n):
        q = W[row, i] / error_scale(rtol, SC[0, i], SC[1, i], y[i], y_new[i], tilt)
        acc += q * q
    return math.sqrt(acc / n)
