"""Rigid bodies: the solid cylinder of the paper and the rectangular block of the 2D literature.

Geometry follows Vassiliou et al. (2017), Fig 1: base radius (or half-width) b, height 2h,
semi-diagonal R = √(b² + h²), slenderness tan α = b/h. Inertia constants are the corrected
forms of docs/equations.md:

- cylinder: κo = I_o/(mR²) = (15 + cos²α)/12, κt = (3 + 13 cos²α)/12,
  Housner restitution e = 1 − 2 sin²α/κo (Eq 31);
- rectangular block: κo = 4/3, e = 1 − 1.5 sin²α (Housner 1963).

In both, p² = g/(κo R) is the frequency parameter of the tilt equation.

Squat bodies. Both restitution formulas come from the balance of angular momentum about the
new pivot, I_o θ̇⁺ = (I_o − 2 m b²) θ̇⁻, assuming the body goes on rocking about the new
corner (Housner 1963). The formula changes sign at I_o = 2 m b², i.e. sin²α = κo/2: at
tan α = √2 ≈ 1.41 for the block and tan α = 4/3 ≈ 1.33 for the cylinder
(:attr:`_RigidBody.SQUAT_TAN_ALPHA`). Beyond it rotating on about the new corner would push
the old one into the ground: the only outcome compatible with compressive impulses at both
corners is the body stopped flat (no bouncing, enough friction). The default ``e`` is
therefore clipped at 0 there (the impact ends the rocking episode); ``e_formula`` keeps the
formula's value and ``restitution_clipped`` says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from rocking._validate import positive_finite
from rocking.constants import G
from rocking.dynamics import inertia as _inertia


def _restitution(name: str, value: float | None, default: float) -> float:
    if value is None:
        return default
    v = float(value)
    if not math.isfinite(v) or not 0.0 <= v <= 1.0:
        raise ValueError(f"{name} must be within [0, 1], got {value!r}")
    return v


@dataclass(frozen=True)
class _RigidBody:
    R: float
    tan_alpha: float
    restitution: float | None = None
    mu: float | None = None
    alpha: float = field(init=False)
    kappa_o: float = field(init=False)
    e: float = field(init=False)
    e_formula: float = field(init=False)
    restitution_clipped: bool = field(init=False)

    SQUAT_TAN_ALPHA: ClassVar[float]
    """tan α above which the restitution formula is negative (module docstring) [-]."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "R", positive_finite("R", self.R))
        object.__setattr__(self, "tan_alpha", positive_finite("tan_alpha", self.tan_alpha))
        if self.mu is not None:
            object.__setattr__(self, "mu", positive_finite("mu", self.mu))
        object.__setattr__(self, "alpha", math.atan(self.tan_alpha))
        object.__setattr__(self, "kappa_o", self._kappa_o())
        e_formula = 1.0 - self._impact_loss()
        clipped = self.restitution is None and e_formula < 0.0
        object.__setattr__(self, "e_formula", e_formula)
        object.__setattr__(self, "restitution_clipped", clipped)
        object.__setattr__(self, "e", _restitution("restitution", self.restitution,
                                                   max(e_formula, 0.0)))

    def _kappa_o(self) -> float:  # pragma: no cover - abstract
        raise NotImplementedError

    def _impact_loss(self) -> float:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def restitution_note(self) -> str:
        """One line on the clipped restitution of a squat body ("" when not clipped)."""
        if not self.restitution_clipped:
            return ""
        e = f"{self.e_formula:.2f}".replace("-", "−")
        return (f"restitution formula gives e = {e} for tan α = {self.tan_alpha:g} (squat "
                f"body, tan α > {self.SQUAT_TAN_ALPHA:.3g}): impacts end the rocking (e = 0)")

    @property
    def b(self) -> float:
        """Base radius or half-width [m]."""
        return self.R * math.sin(self.alpha)

    @property
    def h(self) -> float:
        """Half height [m]."""
        return self.R * math.cos(self.alpha)

    @property
    def p(self) -> float:
        """Frequency parameter p = √(g/(κo R)) [rad/s]."""
        return math.sqrt(G / (self.kappa_o * self.R))

    @property
    def uplift_acceleration(self) -> float:
        """Ground acceleration that starts rocking from rest, g tan α [m/s²]."""
        return G * self.tan_alpha


@dataclass(frozen=True)
class Cylinder(_RigidBody):
    """Solid homogeneous cylinder rocking and wobbling on the rim of its base.

    Parameters
    ----------
    R : float
        Semi-diagonal √(b² + h²) [m].
    tan_alpha : float
        Slenderness b/h [-].
    restitution : float, optional
        Coefficient of restitution for the 2D model [-], in [0, 1]; default Eq (31),
        1 − 2 sin²α/κo, clipped at 0 for tan α > 4/3 (module docstring).
    mu : float, optional
        Friction coefficient of the support [-], > 0: an analysis says whether the body
        needed more (``Response.slides``). None: not given (the models assume no sliding).

    Attributes
    ----------
    e : float
        Restitution the 2D model applies [-].
    e_formula : float
        Eq (31)'s value, negative for squat cylinders [-].
    restitution_clipped : bool
        The default restitution was clipped at 0 (``e_formula`` < 0).
    """

    SQUAT_TAN_ALPHA: ClassVar[float] = 4.0 / 3.0

    @classmethod
    def from_dimensions(cls, diameter: float, height: float, **kwargs) -> Cylinder:
        """The cylinder of a measured ``diameter`` 2b [m] and ``height`` 2h [m].

        R = √(b² + h²), tan α = b/h = diameter/height; ``kwargs`` as the constructor's.
        """
        d = positive_finite("diameter", diameter)
        h = positive_finite("height", height)
        return cls(0.5 * math.hypot(d, h), d / h, **kwargs)

    def _kappa_o(self) -> float:
        c2 = math.cos(self.alpha) ** 2
        return (15.0 + c2) / 12.0

    def _impact_loss(self) -> float:
        return 2.0 * math.sin(self.alpha) ** 2 / self.kappa_o

    @property
    def kappa_t(self) -> float:
        """κt = (I_x + m h²)/(mR²) = (3 + 13 cos²α)/12 [-]."""
        c2 = math.cos(self.alpha) ** 2
        return (3.0 + 13.0 * c2) / 12.0

    @property
    def turn_angle(self) -> float:
        """Small-spin asymptotic turn of the contact point per quasi-impact, π√(κo/κt) [rad]."""
        return math.pi * math.sqrt(self.kappa_o / self.kappa_t)

    def spin_inertia(self, theta):
        """Spin inertia function μ(θ) (docs/equations.md, cancellation-free form) [-].
        (``mu`` is the support's friction coefficient.)"""
        return mu(theta, self.alpha)

    def spin_inertia_prime(self, theta):
        """Derivative μ'(θ) [-]."""
        return mu_prime(theta, self.alpha)

    def wobbling_rate(self, theta):
        """Spin rate |φ̇| that keeps the tilt constant at ``theta`` (pure wobbling) [rad/s].

        φ̇² = 2 (g/R) sin(α − θ)/μ'(θ), the corrected Eq (24); defined for 0 < θ < α.
        """
        th = np.asarray(theta, dtype=float)
        if np.any((th <= 0.0) | (th >= self.alpha)):
            raise ValueError(f"theta must lie in (0, alpha={self.alpha!r}), got {theta!r}")
        return np.sqrt(2.0 * (G / self.R) * np.sin(self.alpha - th) / mu_prime(th, self.alpha))

    def wobbling_period(self, theta):
        """Period of one turn of the contact point in pure wobbling at tilt ``theta`` [s]."""
        return 2.0 * np.pi / self.wobbling_rate(theta)


@dataclass(frozen=True)
class Block(_RigidBody):
    """Rectangular rigid block for the 2D Housner model (I_o = 4/3 m R²).

    Parameters
    ----------
    R : float
        Semi-diagonal [m].
    tan_alpha : float
        Slenderness b/h [-].
    restitution : float, optional
        Coefficient of restitution [-], in [0, 1]; default Housner's 1 − 1.5 sin²α, clipped
        at 0 for tan α > √2 (module docstring).
    mu : float, optional
        Friction coefficient of the support [-], > 0 (as :class:`Cylinder`'s). Attributes
        as :class:`Cylinder`'s.
    """

    SQUAT_TAN_ALPHA: ClassVar[float] = math.sqrt(2.0)

    @classmethod
    def from_dimensions(cls, width: float, height: float, **kwargs) -> Block:
        """The block of a measured ``width`` 2b [m] and ``height`` 2h [m] (in the rocking
        plane): R = √(b² + h²), tan α = width/height; ``kwargs`` as the constructor's."""
        w = positive_finite("width", width)
        h = positive_finite("height", height)
        return cls(0.5 * math.hypot(w, h), w / h, **kwargs)

    def _kappa_o(self) -> float:
        return 4.0 / 3.0

    def _impact_loss(self) -> float:
        return 1.5 * math.sin(self.alpha) ** 2


def _tilts(theta):
    """``theta`` as a float or a float array (the two forms the compiled functions take)."""
    th = np.asarray(theta, dtype=float)
    return float(th) if th.ndim == 0 else th


def mu(theta, alpha: float):
    """Spin inertia μ(θ) [-] of a cylinder of slenderness angle ``alpha`` (:mod:`.inertia`)."""
    return _inertia.mu(_tilts(theta), math.sin(alpha), math.cos(alpha))


def mu_prime(theta, alpha: float):
    """μ'(θ) [-] (:mod:`.inertia`)."""
    return _inertia.mu_prime(_tilts(theta), math.sin(alpha), math.cos(alpha))
