"""Rosenbrock (linearly implicit Runge–Kutta) tableaux for the stiff damped 3D kernel.

All methods are written in the Hairer–Wanner form without matrix–vector products with J
(Hairer & Wanner, *Solving ODEs II*, §IV.7; the same form as ``rodas.f`` and KPP):

    (I/(h γ) − J) K_i = f(t + α_i h, y + Σ_j a_ij K_j) + Σ_j (c_ij/h) K_j + γ_i h ∂f/∂t
    y_new = y + Σ m_i K_i,        err = Σ e_i K_i

with J = ∂f/∂y at the start of the step. Each step costs one Jacobian, one factorization and
``stages`` linear solves, and no Newton iteration (the reason Rosenbrock methods suit small,
cheap systems such as this 6-state one).

Tableaux (coefficients of Hairer's ``rodas.f`` and of the KPP Rosenbrock integrators):

- ``RODAS4``: 6 stages, order 4(3), L-stable, stiffly accurate (Hairer & Wanner 1996).
- ``RODAS3``: 4 stages, order 3(2), L-stable, stiffly accurate (Sandu et al. 1997).
- ``ROS3``: 3 stages (2 function evaluations), order 3(2), L-stable (Sandu et al. 1997).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


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
