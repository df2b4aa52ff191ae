"""Gamma modulating function of the Rezaeian–Der Kiureghian model.

    q(t) = α1 (t − T0)^(α2 − 1) exp[−α3 (t − T0)]   for t > T0, 0 otherwise.

q² is proportional to a gamma density with shape k = 2α2 − 1 and rate 2α3, so the expected
Husid function is a regularized incomplete gamma function and the map between (α1, α2, α3)
and the physical parameters (Ia, D5-95, t_mid) is exact and one-dimensional: the ratio
(t_mid − T0)/D5-95 fixes k, D5-95 then fixes the rate, and Ia fixes α1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq
from scipy.special import gammainc, gammaincinv, gammaln

from rocking._validate import finite, positive_finite, positive_finite_array
from rocking.constants import G

#: Bracket of the gamma shape k searched when inverting the duration ratio (R(k) spans
#: about 3e-33 … 30 over it, far beyond any recorded ground motion; below k = 1e-2 the
#: 0.45-quantile underflows to 0 and R stops being strictly increasing).
K_BRACKET = (1e-2, 1e4)



def libm_map(func, x: ArrayLike) -> NDArray[np.float64]:
    """``func`` (``math.exp``, ``math.log``) applied to every element of ``x``, by the C
    library's scalar function.

    numpy evaluates exp and log with SIMD loops chosen by the CPU at run time (AVX-512 on some
    machines, not on others); on this project's machine they differ from the scalar result
    in the last bit for ~5 % of exp values, which made the synthetic motions differ between
    machines (docs/motions.md, "Recorded parameters"). The scalar functions cost ~0.1 µs per
    value.
    """
    a = np.asarray(x, dtype=np.float64)
    return np.fromiter(map(func, a.ravel().tolist()), np.float64, count=a.size).reshape(a.shape)

def duration_ratio(k: ArrayLike) -> float | NDArray[np.float64]:
    """R(k) = G_k⁻¹(0.45) / (G_k⁻¹(0.95) − G_k⁻¹(0.05)) for a gamma shape k > 0 [-].

    It equals (t_mid − T0)/D5-95 of the envelope and increases strictly with k.
    """
    k = positive_finite_array("k", k)
    r = gammaincinv(k, 0.45) / (gammaincinv(k, 0.95) - gammaincinv(k, 0.05))
    return float(r) if r.ndim == 0 else r


def shape_from_ratio(r: float) -> float:
    """Gamma shape k [-] whose duration ratio R(k) equals ``r`` = (t_mid − T0)/D5-95."""
    r = positive_finite("(t_mid - T0) / D5_95", r)
    lo, hi = K_BRACKET
    r_lo, r_hi = duration_ratio(lo), duration_ratio(hi)
    if not r_lo < r < r_hi:
        raise ValueError(
            f"(t_mid - T0) / D5_95 = {r!r} is outside the range [{r_lo:.3g}, {r_hi:.3g}] "
            "a gamma envelope can reproduce"
        )
    # R is monotone in k over decades, so the root is found on log k.
    u = brentq(lambda s: duration_ratio(math.exp(s)) - r, math.log(lo), math.log(hi), xtol=1e-14)
    return math.exp(u)


@dataclass(frozen=True)
class GammaEnvelope:
    """Gamma modulating function q(t) = α1 (t−T0)^(α2−1) exp[−α3 (t−T0)].

    Parameters
    ----------
    alpha1 : float
        Amplitude [m/s^(α2+1)], > 0 (units make q an acceleration in m/s²).
    alpha2 : float
        Shape [-], > 1/2 so that q² is integrable.
    alpha3 : float
        Decay rate [1/s], > 0.
    T0 : float
        Start time [s].
    """

    alpha1: float
    alpha2: float
    alpha3: float
    T0: float = 0.0

    def __post_init__(self) -> None:
        positive_finite("alpha1", self.alpha1)
        a2 = finite("alpha2", self.alpha2)
        if a2 <= 0.5:
            raise ValueError(f"alpha2 must be > 0.5 (q² integrable), got {self.alpha2!r}")
        positive_finite("alpha3", self.alpha3)
        finite("T0", self.T0)

    @property
    def shape(self) -> float:
        """Gamma shape k = 2α2 − 1 of q² [-]."""
        return 2.0 * self.alpha2 - 1.0

    @property
    def rate(self) -> float:
        """Gamma rate 2α3 of q² [1/s]."""
        return 2.0 * self.alpha3

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        """q(t) [m/s²]; 0 for t ≤ T0."""
        t = np.asarray(t, dtype=np.float64)
        s = t - self.T0
        pos = s > 0.0
        sp = np.where(pos, s, 1.0)
        # Evaluated as exp of a log so that large α2 and long times do not overflow; by the C
        # library's scalar log and exp (libm_map), not numpy's SIMD loops, whose last bit
        # depends on the CPU: the synthetic motions must not.
        logq = math.log(self.alpha1) + (self.alpha2 - 1.0) * libm_map(math.log, sp) \
            - self.alpha3 * sp
        return np.where(pos, libm_map(math.exp, logq), 0.0)

    def expected_arias(self) -> float:
        """E[Ia] = (π/2g) α1² Γ(k) (2α3)^(−k) [m/s]."""
        k = self.shape
        return (math.pi / (2.0 * G)) * math.exp(
            2.0 * math.log(self.alpha1) + gammaln(k) - k * math.log(self.rate)
        )

    def expected_husid_fraction(self, t: ArrayLike) -> NDArray[np.float64]:
        """E[I_a(t)] / E[Ia] = P(k, 2α3 (t − T0)) [-]."""
        s = np.maximum(np.asarray(t, dtype=np.float64) - self.T0, 0.0)
        return gammainc(self.shape, self.rate * s)

    def time_at_fraction(self, p: ArrayLike) -> float | NDArray[np.float64]:
        """t_p = T0 + G_k⁻¹(p)/(2α3) [s], where the expected Husid function reaches p."""
        p = np.asarray(p, dtype=np.float64)
        if np.any(~np.isfinite(p)) or np.any((p < 0.0) | (p >= 1.0)):
            raise ValueError(f"p must be fractions in [0, 1), got {p!r}")
        t = self.T0 + gammaincinv(self.shape, p) / self.rate
        return float(t) if t.ndim == 0 else t

    def physical(self) -> tuple[float, float, float]:
        """(Ia [m/s], D5-95 [s], t_mid [s]) of the expected Husid function."""
        t05, t45, t95 = self.time_at_fraction([0.05, 0.45, 0.95])
        return self.expected_arias(), float(t95 - t05), float(t45)


def alphas_from_physical(Ia: float, D5_95: float, t_mid: float, T0: float = 0.0) -> GammaEnvelope:
    """The gamma envelope whose expected Husid function has the given Ia, D5-95 and t_mid.

    Parameters
    ----------
    Ia : float
        Arias intensity [m/s], > 0.
    D5_95 : float
        Significant duration t_0.95 − t_0.05 [s], > 0.
    t_mid : float
        t_0.45 [s], > T0.
    T0 : float
        Envelope start [s].

    Returns
    -------
    GammaEnvelope
        Matches the three values exactly (to root-finder precision).
    """
    Ia = positive_finite("Ia", Ia)
    D5_95 = positive_finite("D5_95", D5_95)
    t_mid = finite("t_mid", t_mid)
    T0 = finite("T0", T0)
    if not t_mid > T0:
        raise ValueError(f"t_mid must be > T0 = {T0!r}, got {t_mid!r}")
    k = shape_from_ratio((t_mid - T0) / D5_95)
    spread = gammaincinv(k, 0.95) - gammaincinv(k, 0.05)
    alpha3 = float(spread / (2.0 * D5_95))
    alpha2 = 0.5 * (k + 1.0)
    # ln α1 from E[Ia] = (π/2g) α1² Γ(k) (2α3)^(−k), in logs to avoid overflow of Γ(k).
    log_a1 = 0.5 * (math.log(2.0 * G * Ia / math.pi) + k * math.log(2.0 * alpha3) - gammaln(k))
    return GammaEnvelope(math.exp(log_a1), alpha2, alpha3, T0)


def physical_from_alphas(
    alpha1: float, alpha2: float, alpha3: float, T0: float = 0.0
) -> tuple[float, float, float]:
    """(Ia [m/s], D5-95 [s], t_mid [s]) of the gamma envelope (α1, α2, α3, T0)."""
    return GammaEnvelope(alpha1, alpha2, alpha3, T0).physical()
