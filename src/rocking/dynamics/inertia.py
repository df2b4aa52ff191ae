"""Spin inertia μ(θ) of the cylinder rolling on its rim, and its first two derivatives.

μ(θ) multiplies φ̇² in the kinetic energy, ½R²μ(θ)φ̇² (docs/equations.md, "3D undamped
model"); with s = sin α, c = cos α and k = 4/3 c² − 5/4 s²:

    μ(θ)   = k sin²θ + 3 s² (1 − cos θ) + 2 s c sin θ (1 − cos θ)
    μ'(θ)  = k sin 2θ + 3 s² sin θ + 2 s c (cos θ (1 − cos θ) + sin²θ)
    μ''(θ) = 2k cos 2θ + 3 s² cos θ + 2 s c sin θ (4 cos θ − 1)

1 − cos θ is evaluated as 2 sin²(θ/2): quasi-impacts take θ to 1e-9 … 1e-11 rad, where the
literal form rounds to zero and μ(θ) ≈ κt θ² would be lost.

The functions are compiled with numba and use only ``numpy`` ufuncs and arithmetic, so the
same code serves floats in the kernels and NumPy arrays in Python (:mod:`.bodies`). The
kernels that already hold sin θ, cos θ and 1 − cos θ call :func:`mu_of` and
:func:`mu_prime_of` directly.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always", error_model="numpy")
def mu_of(st, omc, s, c):
    """μ from sin θ = ``st`` and 1 − cos θ = ``omc`` (kernels that have them already)."""
    k = 4.0 / 3.0 * c * c - 1.25 * s * s
    return k * st * st + 3.0 * s * s * omc + 2.0 * s * c * st * omc


@njit(cache=True, inline="always", error_model="numpy")
def mu_prime_of(st, ct, omc, s, c):
    """μ' from sin θ, cos θ and 1 − cos θ; 2 sin²θ + cos θ − 1 = cos θ (1 − cos θ) + sin²θ."""
    k = 4.0 / 3.0 * c * c - 1.25 * s * s
    return 2.0 * k * st * ct + 3.0 * s * s * st + 2.0 * s * c * (ct * omc + st * st)


@njit(cache=True, error_model="numpy")
def one_minus_cos(theta):
    """1 − cos θ = 2 sin²(θ/2), exact down to the smallest tilts."""
    sh = np.sin(0.5 * theta)
    return 2.0 * sh * sh


@njit(cache=True, error_model="numpy")
def mu(theta, s, c):
    """μ(θ) [-] for sin α = ``s``, cos α = ``c`` (float or array ``theta`` [rad])."""
    return mu_of(np.sin(theta), one_minus_cos(theta), s, c)


@njit(cache=True, error_model="numpy")
def mu_prime(theta, s, c):
    """μ'(θ) [-]."""
    return mu_prime_of(np.sin(theta), np.cos(theta), one_minus_cos(theta), s, c)


@njit(cache=True, inline="always", error_model="numpy")
def mu_second_of(st, ct, s, c):
    """μ'' from sin θ and cos θ (cos 2θ = cos²θ − sin²θ)."""
    k = 4.0 / 3.0 * c * c - 1.25 * s * s
    return 2.0 * k * (ct * ct - st * st) + 3.0 * s * s * ct + 2.0 * s * c * st * (4.0 * ct - 1.0)


@njit(cache=True, error_model="numpy")
def mu_second(theta, s, c):
    """μ''(θ) [-]."""
    return mu_second_of(np.sin(theta), np.cos(theta), s, c)
