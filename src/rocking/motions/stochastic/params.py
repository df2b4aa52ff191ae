"""The physical parameters of one Rezaeian–Der Kiureghian ground-motion component.

The six parameters of RDK (2010) — Ia, D5-95, t_mid (envelope) and f_mid, f′, ζ_f (filter) —
and, for the spectrum-matched identification, an extension within the same model family:
a second filtered process sharing the envelope and the relative frequency drift
(f_mid2, ζ_f2, its variance share) and a time-invariant low-frequency filter (f_low, ζ_low).
See docs/design.md (ground-motion ensembles).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocking._json import to_plain
from rocking._validate import finite, positive_finite
from rocking.motions.stochastic.envelope import GammaEnvelope, alphas_from_physical
from rocking.motions.stochastic.filter import DEFAULT_FLOOR_HZ, check_low, check_zeta, omega_f

#: Fractions of the expected Husid function between which ω_f follows its fitted line;
#: outside, it is held at the end values (the window over which the line is fitted).
HOLD_FRACTIONS = (0.01, 0.99)


@dataclass(frozen=True)
class RDKParams:
    """Parameters θ = (Ia, D5-95, t_mid, f_mid, f′, ζ_f) of one component (T0 = 0), extended.

    The process is x(t) = q(t) [√(1 − s₂) y₁(t)/σ₁(t) + √s₂ y₂(t)/σ₂(t)]: y₁ and y₂ are
    independent white noises through filters 1 and 2, each followed by the optional
    low-frequency filter, and normalized to unit variance, so E[x²] = q² whatever s₂. Without
    the extension (s₂ = 0, no low-frequency filter) it is the RDK (2010) model.

    Parameters
    ----------
    Ia : float
        Arias intensity [m/s], > 0.
    D5_95 : float
        Significant duration t_0.95 − t_0.05 [s], > 0.
    t_mid : float
        Time t_0.45 at which 45 % of Ia is reached [s], > 0 (measured from the record start).
    f_mid : float
        Filter frequency at t_mid [Hz], > 0.
    f_slope : float
        Rate of change of the filter frequency [Hz/s].
    zeta_f : float
        Filter damping ratio [-], 0 < ζ_f < 1.
    f_mid2 : float or None
        Frequency of the second filter at t_mid [Hz], > 0; it drifts with the same relative
        rate as the first, f′₂ = f′·f_mid2/f_mid. None: one filtered process.
    zeta_f2 : float or None
        Damping ratio of the second filter [-], 0 < ζ < 1 (with ``f_mid2``).
    share2 : float
        Share s₂ of the variance carried by the second process [-], 0 ≤ s₂ < 1 (> 0 with
        ``f_mid2``).
    f_low : float or None
        Frequency of the low-frequency filter [Hz], > 0. None: no such filter (the RDK
        filter's spectrum is flat at long periods).
    zeta_low : float or None
        Damping ratio of the low-frequency filter [-], 0 < ζ < 1 (with ``f_low``).
    diagnostics : dict
        Provenance of a fit (intermediate values, grid errors); not compared by ``==``.
    """

    Ia: float
    D5_95: float
    t_mid: float
    f_mid: float
    f_slope: float
    zeta_f: float
    f_mid2: float | None = None
    zeta_f2: float | None = None
    share2: float = 0.0
    f_low: float | None = None
    zeta_low: float | None = None
    diagnostics: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        for name in ("Ia", "D5_95", "t_mid", "f_mid"):
            object.__setattr__(self, name, positive_finite(name, getattr(self, name)))
        object.__setattr__(self, "f_slope", finite("f_slope", self.f_slope))
        object.__setattr__(self, "zeta_f", check_zeta(self.zeta_f))
        self._check_extension()
        # Fails early (naming the ratio) if no gamma envelope has this t_mid / D5-95.
        object.__setattr__(self, "_envelope", alphas_from_physical(self.Ia, self.D5_95, self.t_mid))

    def _check_extension(self) -> None:
        """Validate the second process and the low-frequency filter (named errors)."""
        share = finite("share2", self.share2)
        if self.f_mid2 is None:
            if self.zeta_f2 is not None or share != 0.0:
                raise ValueError(
                    f"zeta_f2={self.zeta_f2!r} and share2={self.share2!r} need f_mid2"
                )
        else:
            object.__setattr__(self, "f_mid2", positive_finite("f_mid2", self.f_mid2))
            if self.zeta_f2 is None:
                raise ValueError("f_mid2 needs zeta_f2")
            object.__setattr__(self, "zeta_f2", check_zeta(self.zeta_f2))
            if not 0.0 < share < 1.0:
                raise ValueError(f"share2 must be in (0, 1) with f_mid2, got {self.share2!r}")
        object.__setattr__(self, "share2", share)
        if (self.f_low is None) != (self.zeta_low is None):
            raise ValueError(
                f"f_low and zeta_low come together, got f_low={self.f_low!r}, "
                f"zeta_low={self.zeta_low!r}"
            )
        if self.f_low is not None:
            w_low, z_low = check_low((2.0 * math.pi * positive_finite("f_low", self.f_low),
                                      self.zeta_low))
            object.__setattr__(self, "f_low", w_low / (2.0 * math.pi))
            object.__setattr__(self, "zeta_low", z_low)

    @property
    def extended(self) -> bool:
        """True when the second process or the low-frequency filter is used."""
        return self.f_mid2 is not None or self.f_low is not None

    @property
    def low(self) -> tuple[float, float] | None:
        """(ω_low [rad/s], ζ_low) of the low-frequency filter, or None."""
        if self.f_low is None:
            return None
        return 2.0 * math.pi * self.f_low, float(self.zeta_low)  # type: ignore[arg-type]

    def terms(
        self, t: ArrayLike, floor_hz: float = DEFAULT_FLOOR_HZ
    ) -> list[tuple[float, NDArray[np.float64], float]]:
        """(variance share, ω_f(t) [rad/s], ζ) of each filtered process (one or two).

        The second filter drifts with the same relative rate as the first, so the mean
        zero-crossing rate of the sum follows the first filter's line up to a constant factor.
        """
        out = [(1.0 - self.share2, self.omega(t, floor_hz), self.zeta_f)]
        if self.f_mid2 is not None:
            slope2 = self.f_slope * self.f_mid2 / self.f_mid
            w2 = omega_f(t, self.f_mid2, slope2, self.t_mid, self.hold_window(), floor_hz)
            out.append((self.share2, w2, float(self.zeta_f2)))  # type: ignore[arg-type]
        return out

    @property
    def envelope(self) -> GammaEnvelope:
        """Gamma modulating function with T0 = 0 matching Ia, D5-95 and t_mid exactly."""
        return self._envelope  # type: ignore[attr-defined]

    @property
    def omega_mid(self) -> float:
        """ω_mid = 2π f_mid [rad/s]."""
        return 2.0 * math.pi * self.f_mid

    @property
    def omega_slope(self) -> float:
        """ω′ = 2π f′ [rad/s²]."""
        return 2.0 * math.pi * self.f_slope

    def hold_window(self) -> tuple[float, float]:
        """(t_0.01, t_0.99) of the expected Husid function [s]: ω_f is held outside."""
        lo, hi = self.envelope.time_at_fraction(list(HOLD_FRACTIONS))
        return float(lo), float(hi)

    def omega(self, t: ArrayLike, floor_hz: float = DEFAULT_FLOOR_HZ) -> NDArray[np.float64]:
        """Filter frequency ω_f(t) [rad/s]: linear, held outside t_0.01…t_0.99, floored."""
        return omega_f(t, self.f_mid, self.f_slope, self.t_mid, self.hold_window(), floor_hz)

    def model_duration(self, fraction: float = 0.999) -> float:
        """Time [s] at which the expected Husid function reaches ``fraction`` of Ia."""
        return float(self.envelope.time_at_fraction(fraction))

    def to_dict(self) -> dict[str, Any]:
        """Plain-JSON dictionary: the six parameters, the envelope's α and the diagnostics."""
        env = self.envelope
        return {
            "Ia": self.Ia,
            "D5_95": self.D5_95,
            "t_mid": self.t_mid,
            "f_mid": self.f_mid,
            "f_slope": self.f_slope,
            "zeta_f": self.zeta_f,
            "f_mid2": self.f_mid2,
            "zeta_f2": self.zeta_f2,
            "share2": self.share2,
            "f_low": self.f_low,
            "zeta_low": self.zeta_low,
            "alpha1": env.alpha1,
            "alpha2": env.alpha2,
            "alpha3": env.alpha3,
            "T0": env.T0,
            "diagnostics": to_plain(self.diagnostics),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> RDKParams:
        """Inverse of :meth:`to_dict` (derived values are recomputed, not read)."""
        keys = ("Ia", "D5_95", "t_mid", "f_mid", "f_slope", "zeta_f")
        missing = [k for k in keys if k not in d]
        if missing:
            raise ValueError(f"RDK parameter dictionary lacks {missing}")
        extension = {k: d[k] for k in _EXTENSION if d.get(k) is not None}
        return cls(**{k: d[k] for k in keys}, **extension,
                   diagnostics=dict(d.get("diagnostics", {})))


#: Keys of the extension (second process, low-frequency filter); absent or None when unused.
_EXTENSION = ("f_mid2", "zeta_f2", "share2", "f_low", "zeta_low")
