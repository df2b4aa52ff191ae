"""Intensity measures of a two-component ground motion and the horizontal component they take.

A measure (:data:`MEASURES`) is a kind (PGA, PGV or Sa(T)) and a period where it needs one:
``"pga"``, ``"pgv"``, ``"sa:1.0"``. Each is the peak of one time series of the pair:

- PGA: the ground acceleration [g];
- PGV: the ground velocity, the trapezoidal integral of the acceleration from rest [m/s];
- Sa(T): ω² u/g, u the relative displacement of a linear oscillator of period T and 5 %
  damping driven by the component (exact recurrence,
  :func:`rocking.motions.response_spectrum.sdof_response`) [g].

The *component* (:data:`COMPONENTS`) says how the two horizontal series x(t), y(t) become one
number:

- ``vector_peak``: max_t √(x² + y²), the peak of the horizontal vector (the default, and the
  performance spectra's own intensity). For a linear system the response to the component
  along the unit vector n is n·(x, y), so this is the largest peak over every direction;
- ``rotd100``, ``rotd50``: the largest and the median over the angles θ = 0°, 1°, ..., 179° of
  max_t |x cos θ + y sin θ| (Boore 2010), by :func:`pyrotd.calc_rotated_percentiles`;
  rotd100 is the vector peak sampled at 1° (within a factor cos 0.5° below it);
- ``geometric_mean``: √(max|x| · max|y|) of the two as-recorded components;
- ``larger``: max(max|x|, max|y|) of the two as-recorded components.

Every measure and component here is linear in the scale of the motion
(:attr:`IntensityMeasure.scaling`): a record scaled by s has s times each, so the measure at
which a scaled record first exceeds a limit state is the critical scale factor times the
record's measure, exactly, and the ratio of two components of one record does not depend on
its scale.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from rocking.constants import G
from rocking.motions.motion import GroundMotion

__all__ = ["COMPONENTS", "DEFAULT_COMPONENT", "DEFAULT_DAMPING", "MEASURES", "MEASURE_PATTERN",
           "MEASURE_UNITS", "ROTD_ANGLES", "VECTOR_PEAK", "Component", "IntensityMeasure",
           "Measure", "component_peak", "component_ratio", "intensity_measure", "measure_imt",
           "measure_series", "parse_component", "parse_measure", "peak_vector_velocity",
           "same_measure", "vector_sa"]

DEFAULT_DAMPING = 0.05
"""Damping ratio of the Sa(T) oscillator [-]."""



@dataclass(frozen=True)
class IntensityMeasure:
    """One kind of intensity measure: how the configuration names it and what it is.

    Attributes
    ----------
    kind : str
        ``"pga"``, ``"pgv"`` or ``"sa"``; the configuration writes ``sa:<T>``.
    unit : str
        Unit of its values.
    description : str
        What it is, in words.
    scaling : str
        How it changes when the record is scaled by s: ``"linear"`` (s times the measure).
        Critical measures are the critical scale factor times the record's measure only for
        a linear measure.
    imt : str
        OpenQuake's intensity measure type (``"PGA"``, ``"PGV"``, ``"SA({period})"``).
    pattern : str
        Regular expression of its spellings in the configuration.
    """

    kind: str
    unit: str
    description: str
    scaling: str
    imt: str
    pattern: str

    @property
    def has_period(self) -> bool:
        """Whether the measure takes a period (``sa:<T>``)."""
        return "{period}" in self.imt


MEASURES = {m.kind: m for m in (
    IntensityMeasure("pga", "g", "peak ground acceleration", "linear", "PGA", "pga"),
    IntensityMeasure("pgv", "m/s", "peak ground velocity (integrated from rest)", "linear",
                     "PGV", "pgv"),
    IntensityMeasure("sa", "g", "5 % damped pseudo-spectral acceleration at period T [s]",
                     "linear", "SA({period})", "sa:[0-9]*\\.?[0-9]+"),
)}
"""The registry of intensity measures, by kind."""

MEASURE_PATTERN = "^(" + "|".join(m.pattern for m in MEASURES.values()) + ")$"
"""The configuration's spellings of a measure (the schema's ``intensity_measure`` pattern)."""

MEASURE_UNITS = {k: m.unit for k, m in MEASURES.items()}
"""Unit of each kind of measure."""


@dataclass(frozen=True)
class Component:
    """A definition of the horizontal component of a two-component measure.

    Attributes
    ----------
    name : str
        Its name in the configuration and the tables.
    description : str
        The definition in words.
    imt_component : str
        What OpenQuake (and the ground-motion models' papers) call it.
    """

    name: str
    description: str
    imt_component: str


VECTOR_PEAK = "vector_peak"
"""The vector peak's name, the one place it is spelled: the performance spectra's own
intensity (PGA = max_t √(ax² + ay²)), which a comparison names to take the spectra's own
numbers bit for bit."""

COMPONENTS = {c.name: c for c in (
    Component(VECTOR_PEAK, "peak over time of the horizontal vector sqrt(x^2 + y^2)",
              "maximum over all directions (the vector peak)"),
    Component("rotd100", "largest over 180 angles (1 deg) of the peak of the rotated component",
              "RotD100"),
    Component("rotd50", "median over 180 angles (1 deg) of the peak of the rotated component",
              "RotD50"),
    Component("geometric_mean", "sqrt(peak x * peak y) of the two as-recorded components",
              "Average Horizontal (geometric mean)"),
    Component("larger", "larger of the peaks of the two as-recorded components",
              "Greater of two horizontal"),
)}
"""The registry of horizontal components, by name."""

DEFAULT_COMPONENT = VECTOR_PEAK
"""A study's component when it names none: the performance spectra's own intensity."""

ROTD_ANGLES = np.arange(0.0, 180.0, 1.0)
"""Angles of the RotD components [deg]."""


def parse_component(name: str, field: str = "component") -> str:
    """The registry's name of a component (case-insensitive).

    Raises
    ------
    ValueError
        One line naming ``field``, the value and the known components.
    """
    text = name.strip().lower() if isinstance(name, str) else None
    if text not in COMPONENTS:
        raise ValueError(f"{field}: unknown component {name!r}; known: "
                         f"{', '.join(COMPONENTS)}")
    return text


SA_NAME = re.compile(r"^S[Aa]\(\s*([0-9.eE+-]+)\s*\)$")
"""OpenQuake's name of a spectral acceleration, ``SA(1.0)``: its period in group 1."""


@dataclass(frozen=True)
class Measure:
    """One intensity measure: a kind of :data:`MEASURES` and, for Sa, its period.

    The one object every part of the project asks what a measure is: its name in the
    configuration and the tables (:attr:`name`, ``"pga"``, ``"sa:1.0"``), its unit, how it
    scales with the record, OpenQuake's IMT (:attr:`imt`, ``"SA(1.0)"``), its label on an
    axis, the time series whose peaks it is (:meth:`series`), its value for a motion in a
    horizontal component (:meth:`of_motion`) and the factor from a normalized intensity
    (measure/(g tan α)) to its unit (:meth:`per_normalized`). Two spellings of one measure
    (``"sa:1"``, ``"SA(1.0)"``, ``"Sa:1.00"``) are one :class:`Measure` (equal, same hash).

    Build it with :meth:`of`.
    """

    kind: str
    period: float | None = None

    def __post_init__(self) -> None:
        info = MEASURES.get(self.kind)
        if info is None or info.has_period != (self.period is not None):
            raise ValueError(f"an intensity measure is {_SPELLED}, got kind {self.kind!r} "
                             f"with period {self.period!r}")
        if self.period is not None:
            if not (isinstance(self.period, int | float) and math.isfinite(self.period)
                    and self.period > 0):
                raise ValueError(f"the period of {self.kind} must be a number of seconds > 0, "
                                 f"got {self.period!r}")
            object.__setattr__(self, "period", float(self.period))

    @classmethod
    def of(cls, value) -> Measure:
        """The measure a name denotes: ``"pga"``, ``"pgv"``, ``"sa:<T>"`` (any case), or
        OpenQuake's ``"PGA"``, ``"PGV"``, ``"SA(<T>)"``; a :class:`Measure` is returned as it
        is.

        Raises
        ------
        ValueError
            Any other spelling, or a period that is not a finite number > 0.
        """
        if isinstance(value, Measure):
            return value
        if not isinstance(value, str):
            raise ValueError(f"an intensity measure is {_SPELLED}, got {value!r}")
        text = value.strip()
        hit = SA_NAME.match(text)
        if hit:
            text = f"sa:{hit.group(1)}"
        kind, colon, rest = text.lower().partition(":")
        info = MEASURES.get(kind)
        if info is not None and not info.has_period and not colon:
            return cls(kind)
        if info is not None and info.has_period and colon:
            try:
                period = float(rest)
            except ValueError:
                period = math.nan
            if not (math.isfinite(period) and period > 0):
                raise ValueError(f"the period of {value!r} must be a number of seconds > 0, "
                                 f"e.g. '{kind}:1.0'")
            return cls(kind, period)
        raise ValueError(f"an intensity measure is {_SPELLED}, got {value!r}")

    @property
    def info(self) -> IntensityMeasure:
        """Its kind's entry of :data:`MEASURES`."""
        return MEASURES[self.kind]

    @property
    def _period_text(self) -> str:
        p = self.period
        return f"{p:.1f}" if p == round(p, 1) else f"{p:g}"

    @property
    def name(self) -> str:
        """The configuration's and the tables' name: ``"pga"``, ``"pgv"``, ``"sa:1.0"``."""
        return self.kind if self.period is None else f"{self.kind}:{self._period_text}"

    @property
    def imt(self) -> str:
        """OpenQuake's intensity measure type: ``"PGA"``, ``"PGV"``, ``"SA(1.0)"``."""
        return self.info.imt.format(period=self._period_text if self.period else "")

    @property
    def label(self) -> str:
        """As an axis names it: ``"PGA"``, ``"PGV"``, ``"Sa(1 s)"``."""
        return self.kind.upper() if self.period is None else f"Sa({self.period:g} s)"

    @property
    def unit(self) -> str:
        """Unit of its values (:data:`MEASURE_UNITS`)."""
        return self.info.unit

    @property
    def scaling(self) -> str:
        """How it changes when the record is scaled (``"linear"``)."""
        return self.info.scaling

    @property
    def column(self) -> str:
        """A name fit for a column title: ``"pga"``, ``"pgv"``, ``"sa_1s"``."""
        return self.kind if self.period is None else f"sa_{self.period:g}s"

    def per_normalized(self, tan_alpha: float) -> float:
        """Factor from a normalized intensity, measure/(g tan α) [-], to the measure in its
        unit: tan α for measures in g, g tan α for PGV [m/s]."""
        return float(tan_alpha) * (G if self.unit == "m/s" else 1.0)

    def series(self, motion: GroundMotion,
               damping: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The pair of time series whose peaks are this measure, in its unit
        (:func:`measure_series`)."""
        return measure_series(motion, self, DEFAULT_DAMPING if damping is None else damping)

    def of_motion(self, motion: GroundMotion, component: str = DEFAULT_COMPONENT) -> float:
        """The measure of ``motion`` in ``component``, in its unit
        (:func:`intensity_measure`)."""
        return intensity_measure(motion, self, component)

    def __str__(self) -> str:
        return self.name


_SPELLED = "pga, pgv or 'sa:<T in s>' (OpenQuake's PGA, PGV, SA(<T>))"


def parse_measure(name) -> tuple[str, float | None]:
    """``"pga"``, ``"pgv"`` or ``"sa:<T>"`` (any spelling :meth:`Measure.of` takes) →
    (kind, period [s] or None)."""
    m = Measure.of(name)
    return m.kind, m.period


def measure_imt(name) -> str:
    """OpenQuake's IMT of a measure: ``"pga"`` → ``"PGA"``, ``"sa:1"`` → ``"SA(1.0)"``."""
    return Measure.of(name).imt


def same_measure(a, b) -> bool:
    """Whether two names (any spelling, ``SA(1.0)`` or ``sa:1.0``) denote the same
    intensity measure; False where either is none."""
    try:
        return Measure.of(a) == Measure.of(b)
    except ValueError:
        return False


def peak_vector_velocity(motion: GroundMotion) -> float:
    """PGV of the pair: max_t √(vx² + vy²), v integrated from rest (trapezoid) [m/s]."""
    from scipy.integrate import cumulative_trapezoid

    vx = cumulative_trapezoid(motion.ax, dx=motion.dt, initial=0.0)
    vy = cumulative_trapezoid(motion.ay, dx=motion.dt, initial=0.0)
    return float(np.max(np.hypot(vx, vy)))


def vector_sa(motion: GroundMotion, period: float, damping: float = DEFAULT_DAMPING) -> float:
    """Sa(T) of the pair: ω² max_t |u(t)| of the displacement vector, in g [-].

    Parameters
    ----------
    motion : GroundMotion
        Accelerations [m/s²].
    period : float
        Oscillator period T [s].
    damping : float
        Damping ratio ζ [-].
    """
    from rocking.motions.response_spectrum import sdof_response

    ux, _ = sdof_response(motion.ax, motion.dt, period, damping)
    uy, _ = sdof_response(motion.ay, motion.dt, period, damping)
    omega = 2.0 * math.pi / period
    return float(omega**2 * np.max(np.hypot(ux, uy)) / G)


def measure_series(motion: GroundMotion, name: str | Measure,
                   damping: float = DEFAULT_DAMPING) -> tuple[np.ndarray, np.ndarray]:
    """The pair of time series whose peaks are the measure ``name``, in its unit.

    PGA: the accelerations [g]; PGV: the velocities from rest (trapezoid) [m/s]; Sa(T):
    ω² u/g of the oscillator's relative displacements [g].
    """
    kind, period = parse_measure(name)
    if kind == "pga":
        return motion.ax / G, motion.ay / G
    if kind == "pgv":
        from scipy.integrate import cumulative_trapezoid

        return (cumulative_trapezoid(motion.ax, dx=motion.dt, initial=0.0),
                cumulative_trapezoid(motion.ay, dx=motion.dt, initial=0.0))
    from rocking.motions.response_spectrum import sdof_response

    w2 = (2.0 * math.pi / period) ** 2 / G
    ux, _ = sdof_response(motion.ax, motion.dt, period, damping)
    uy, _ = sdof_response(motion.ay, motion.dt, period, damping)
    return w2 * ux, w2 * uy


def component_peak(x: np.ndarray, y: np.ndarray, component: str) -> float:
    """The peak of the pair of series (x, y) in ``component`` (:data:`COMPONENTS`): a
    canonical name (:func:`parse_component` where it entered), taken as it is."""
    if component == VECTOR_PEAK:
        return float(np.max(np.hypot(x, y)))
    if component in ("rotd50", "rotd100"):
        import pyrotd

        pct = 50.0 if component == "rotd50" else 100.0
        # "rigorous": every sample is rotated (the "optimized" subset assumes the peak of
        # every direction is above 0.7 of the smaller component's peak)
        out = pyrotd.calc_rotated_percentiles([x, y], ROTD_ANGLES, [pct], method="rigorous")
        return float(out.spec_accel[0])
    px, py = float(np.max(np.abs(x))), float(np.max(np.abs(y)))
    return math.sqrt(px * py) if component == "geometric_mean" else max(px, py)


def intensity_measure(motion: GroundMotion, name: str | Measure,
                      component: str = DEFAULT_COMPONENT) -> float:
    """The measure ``name`` (:func:`parse_measure`) of a motion in ``component``, in
    :data:`MEASURE_UNITS`."""
    component = parse_component(component)
    kind, period = parse_measure(name)
    if component == VECTOR_PEAK:  # the spectra's own PGA, bit for bit
        if kind == "pga":
            return motion.pga_g
        if kind == "pgv":
            return peak_vector_velocity(motion)
        return vector_sa(motion, period)
    return component_peak(*measure_series(motion, name), component)


def component_ratio(motion: GroundMotion, name: str | Measure, to: str, frm: str) -> float:
    """Measure ``name`` of ``motion`` in component ``to`` over the same in ``frm`` [-]: the
    factor from one component to the other, the same at every scale of the motion."""
    return intensity_measure(motion, name, to) / intensity_measure(motion, name, frm)
