"""Bidirectional ground motion on one time step, with an optional vertical component: the
input every rocking model takes."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rocking._validate import finite_array, positive_finite
from rocking.constants import G


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """Two horizontal ground-acceleration components, and optionally the vertical one,
    sampled on one time step.

    Parameters
    ----------
    ax, ay : array_like or None
        Accelerations along x and y [m/s²]. A missing component (``None``) is zeros.
        Both must have the same length; samples must be finite.
    dt : float
        Time step [s], > 0.
    name : str
        Label used in outputs.
    metadata : dict
        Free-form provenance (source file, rotation angle, seed, filter, stand-in flags).
    az : array_like, optional
        Vertical acceleration [m/s², positive up], same length as ``ax``; None: the motion
        has no vertical component (every model then sees gravity g exactly). The models
        take gravity as g + a_z(t) (docs/equations.md, "Vertical ground motion").

    Notes
    -----
    Between samples the acceleration is linearly interpolated (the usual assumption of
    piecewise-linear records), which is also what the integrators use. A scale factor
    (:meth:`scaled`, an analysis' ``scale``) multiplies all three components; intensities
    (:attr:`pga`) stay horizontal.
    """

    ax: np.ndarray | None
    ay: np.ndarray | None
    dt: float
    name: str = "motion"
    metadata: dict[str, Any] = field(default_factory=dict)
    az: np.ndarray | None = None

    def __post_init__(self) -> None:
        dt = positive_finite("dt", self.dt)
        if self.ax is None and self.ay is None:
            raise ValueError("GroundMotion needs at least one of ax, ay")
        ax = None if self.ax is None else finite_array("ax", self.ax)
        ay = None if self.ay is None else finite_array("ay", self.ay)
        if ax is None:
            ax = np.zeros_like(ay)
        if ay is None:
            ay = np.zeros_like(ax)
        if ax.size != ay.size:
            raise ValueError(f"ax and ay must have equal lengths, got {ax.size} and {ay.size}")
        if ax.size < 2:
            raise ValueError(f"a ground motion needs at least 2 samples, got {ax.size}")
        az = None if self.az is None else finite_array("az", self.az)
        if az is not None and az.size != ax.size:
            raise ValueError(f"az must have the length of ax and ay ({ax.size}), got {az.size}")
        ax.setflags(write=False)
        ay.setflags(write=False)
        if az is not None:
            az.setflags(write=False)
        object.__setattr__(self, "az", az)
        object.__setattr__(self, "ax", ax)
        object.__setattr__(self, "ay", ay)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "metadata", dict(self.metadata))

    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.ax.size)

    @property
    def duration(self) -> float:
        """Time of the last sample [s]."""
        return (self.npts - 1) * self.dt

    @property
    def time(self) -> np.ndarray:
        """Sample times [s]."""
        return np.arange(self.npts) * self.dt

    @property
    def pga(self) -> float:
        """Vector peak ground acceleration max √(ax² + ay²) [m/s²]."""
        return float(np.max(np.hypot(self.ax, self.ay)))

    @property
    def pga_g(self) -> float:
        """Vector PGA in units of g [-]."""
        return self.pga / G

    @property
    def has_vertical(self) -> bool:
        """True when the motion carries a vertical component that is not identically zero
        (a zero one changes no answer: gravity stays g to the bit)."""
        return self.az is not None and bool(np.any(self.az))

    @property
    def pga_vertical(self) -> float:
        """Peak vertical acceleration max |a_z| [m/s²] (0 without a vertical component)."""
        return 0.0 if self.az is None else float(np.max(np.abs(self.az)))

    @property
    def samples_sha256(self) -> str:
        """sha256 (hex) of what an analysis reads: dt and the samples of every component, as
        float64. Equal digests are equal inputs to the bit; the answers of two motions that
        differ in the last bit may differ much more (rocking near a goal is chaotic in its
        input), so a comparison of answers across machines is exact only where this agrees."""
        import hashlib

        h = hashlib.sha256(np.float64(self.dt).tobytes())
        for a in (self.ax, self.ay) + (() if self.az is None else (self.az,)):
            h.update(np.ascontiguousarray(a, dtype="<f8").tobytes())
        return h.hexdigest()

    def horizontal(self) -> GroundMotion:
        """The motion without its vertical component."""
        if self.az is None:
            return self
        meta = dict(self.metadata)
        meta["vertical"] = "dropped"
        return GroundMotion(self.ax, self.ay, self.dt, self.name, meta)

    @property
    def is_unidirectional(self) -> bool:
        """True when one component is identically zero."""
        return not np.any(self.ax) or not np.any(self.ay)

    def scaled(self, factor: float) -> GroundMotion:
        """All components (x, y and z if present) multiplied by ``factor``."""
        f = float(factor)
        return GroundMotion(self.ax * f, self.ay * f, self.dt, self.name, self.metadata,
                            None if self.az is None else self.az * f)

    def component(self, which: str) -> GroundMotion:
        """A motion with only the ``"x"`` or ``"y"`` component, placed on x (for 2D runs); the
        vertical component, if any, is kept."""
        if which == "x":
            a = self.ax
        elif which == "y":
            a = self.ay
        else:
            raise ValueError(f"component must be 'x' or 'y', got {which!r}")
        return GroundMotion(a, None, self.dt, f"{self.name}:{which}", self.metadata, self.az)
