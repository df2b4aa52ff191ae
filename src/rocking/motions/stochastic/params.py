"""The six physical parameters of one Rezaeian–Der Kiureghian ground-motion component."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._validate import finite, positive_finite
from .envelope import GammaEnvelope, alphas_from_physical
from .filter import DEFAULT_FLOOR_HZ, check_zeta, omega_f

#: Fractions of the expected Husid function between which ω_f follows its fitted line;
#: outside, it is held at the end values (the window over which the line is fitted).
HOLD_FRACTIONS = (0.01, 0.99)


@dataclass(frozen=True)
class RDKParams:
    """Parameters θ = (Ia, D5-95, t_mid, f_mid, f′, ζ_f) of one component (T0 = 0).

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
    diagnostics : dict
        Provenance of a fit (intermediate values, grid errors); not compared by ``==``.
    """

    Ia: float
    D5_95: float
    t_mid: float
    f_mid: float
    f_slope: float
    zeta_f: float
    diagnostics: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        for name in ("Ia", "D5_95", "t_mid", "f_mid"):
            object.__setattr__(self, name, positive_finite(name, getattr(self, name)))
        object.__setattr__(self, "f_slope", finite("f_slope", self.f_slope))
        object.__setattr__(self, "zeta_f", check_zeta(self.zeta_f))
        # Fails early (naming the ratio) if no gamma envelope has this t_mid / D5-95.
        object.__setattr__(self, "_envelope", alphas_from_physical(self.Ia, self.D5_95, self.t_mid))

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
            "alpha1": env.alpha1,
            "alpha2": env.alpha2,
            "alpha3": env.alpha3,
            "T0": env.T0,
            "diagnostics": _jsonable(self.diagnostics),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> RDKParams:
        """Inverse of :meth:`to_dict` (derived values are recomputed, not read)."""
        keys = ("Ia", "D5_95", "t_mid", "f_mid", "f_slope", "zeta_f")
        missing = [k for k in keys if k not in d]
        if missing:
            raise ValueError(f"RDK parameter dictionary lacks {missing}")
        return cls(**{k: d[k] for k in keys}, diagnostics=dict(d.get("diagnostics", {})))


def _jsonable(value: Any) -> Any:
    """Numpy scalars and arrays turned into Python numbers and lists (recursively)."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    return value
