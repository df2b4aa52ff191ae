"""What decides the numbers of each store of a study: its spectra, tilt map and stripes.

- :class:`SpectraSpec`: the performance spectra (``results/<study>/spectra.zarr``);
- :class:`TiltMapSpec`: the Fig 7 tilt map (``tilt_map.zarr``), if the study has one;
- :class:`StripesSpec`: the multiple-stripe analyses (``stripes.zarr``), if any.

Each part has ``to_attrs()`` (the JSON-ready mapping a store records as its ``config``
attribute and hashes), ``from_attrs()`` (its exact inverse) and ``digest`` (the store's
``config_hash``). The mapping and hash are those the workflow has always written, so stores
made before this module are resumed, not recomputed. Only settings that decide the numbers (or
the chunking, for ``chunk_R: auto``) are in them: Dask addresses, progress intervals and worker
time-outs are not.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from dataclasses import field as dc_field
from typing import Any

from rocking._validate import positive_finite
from rocking.config.damping import Damping
from rocking.config.ensemble import EnsembleSpec
from rocking.config.fields import (
    DEFAULTS,
    checked_mapping,
    chunk_R_field,
    expand_grid,
    mode_list,
)
from rocking.config.plan import StudyPlan, plan_study
from rocking.motions.measures import DEFAULT_COMPONENT, VECTOR_PEAK
from rocking.spectra.accuracy import Accuracy
from rocking.store.attrs import config_hash

__all__ = ["SpectraSpec", "StripesSpec", "TiltMapSpec"]


class Hashed:
    """``digest``: the store's ``config_hash`` of :meth:`to_attrs`."""

    def to_attrs(self) -> dict[str, Any]:  # pragma: no cover - every subclass has its own
        raise NotImplementedError

    @property
    def digest(self) -> str:
        """Short sha256 of the canonical JSON of :meth:`to_attrs`."""
        return config_hash(self.to_attrs())


@dataclass(frozen=True, eq=False)
class SpectraSpec(Hashed):
    """The result-deciding description of a study's spectra store.

    Attributes
    ----------
    study : str
    ensemble : EnsembleSpec
    R : tuple of float
        Semi-diagonals [m].
    plan : StudyPlan
        The runs, their union grid (modes, tan α, limit states) and requested cells.
    chunk_R : int or "auto"
        Sizes R per task.
    min_task_seconds : float or None
        Least work per task for ``chunk_R: auto`` [s] (None otherwise: it cannot matter).
    accuracy : Accuracy
        The search's settings, resolved where the configuration entered
        (:meth:`rocking.spectra.accuracy.Accuracy.of`); the store records them as they were
        configured (:meth:`~rocking.spectra.accuracy.Accuracy.record`), so its digest is
        the one it always had.
    quantity : dict
        What a cell's critical intensity is (:meth:`rocking.spectra.quantity.Quantity.to_dict`:
        name, p, w): part of the digest, so a store of another quantity is another store.
    upper : float
        Highest PGA/(g tan α) searched [-].
    damping : Damping or None
        The contact model, when ``3d-damped`` runs.
    mu : float or None
        Support friction coefficient of every body [-]: the ``slides`` flag of each answer
        (None: the flags say nothing about sliding).

    Two specs are equal when their :meth:`to_attrs` are (run purposes are labels only).
    """

    study: str
    ensemble: EnsembleSpec
    R: tuple[float, ...]
    plan: StudyPlan
    chunk_R: int | str
    min_task_seconds: float | None
    accuracy: Accuracy
    quantity: dict[str, Any]
    upper: float
    damping: Damping | None
    mu: float | None = None

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SpectraSpec) and self.to_attrs() == other.to_attrs()

    __hash__ = None  # mutable-looking fields (the plan's mask): not hashable

    def search_options(self) -> dict[str, float]:
        """Keyword arguments of the searches: ``upper``, the contact model and ``mu`` (only
        when given, so that the stores of studies without it keep their digests)."""
        mu = {} if self.mu is None else {"mu": self.mu}
        return {"upper": self.upper, **Damping.options(self.damping), **mu}

    def to_attrs(self) -> dict[str, Any]:
        return {
            "study": self.study,
            "ensemble": self.ensemble.to_attrs(),
            "R": list(self.R),
            **self.plan.to_dict(),
            "tan_alpha": list(self.plan.tan_alpha),
            "limit_states": list(self.plan.limit_states),
            "modes": list(self.plan.modes),
            "chunk_R": self.chunk_R,
            "min_task_seconds": self.min_task_seconds,
            "accuracy": self.accuracy.record(),
            "quantity": dict(self.quantity),
            "search_options": self.search_options(),
        }

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> SpectraSpec:
        """Inverse of :meth:`to_attrs` (a store's ``config`` attribute)."""
        opts = attrs["search_options"]
        return cls(attrs["study"], EnsembleSpec.from_attrs(attrs["ensemble"]),
                   tuple(attrs["R"]), plan_study(attrs["runs"], "runs"), attrs["chunk_R"],
                   attrs["min_task_seconds"], Accuracy.of(attrs["accuracy"]),
                   dict(attrs["quantity"]),
                   opts["upper"],
                   Damping.from_options(opts), opts.get("mu"))


@dataclass(frozen=True)
class _IntensityGrid(Hashed):
    """Analyses of every mode and size R at given intensities (a tilt map, stripes).

    Attributes
    ----------
    study : str
    ensemble : EnsembleSpec
    modes : tuple of str
    tan_alpha : float
        Slenderness [-].
    R : tuple of float
        Semi-diagonals [m].
    intensity : tuple of float
        PGA/(g tan α) [-].
    chunk_R : int
        Sizes R per task.
    accuracy : Accuracy
        As in :class:`SpectraSpec` (ODE tolerances and rest tilt of the analyses).
    damping : Damping or None
        When ``3d-damped`` is one of the modes.
    """

    study: str
    ensemble: EnsembleSpec
    modes: tuple[str, ...]
    tan_alpha: float
    R: tuple[float, ...]
    intensity: tuple[float, ...]
    chunk_R: int
    accuracy: Accuracy
    damping: Damping | None

    def to_attrs(self) -> dict[str, Any]:
        return {"study": self.study, "ensemble": self.ensemble.to_attrs(),
                "modes": list(self.modes), "tan_alpha": self.tan_alpha, "R": list(self.R),
                "intensity": list(self.intensity), "chunk_R": self.chunk_R,
                "accuracy": self.accuracy.record(), "model_options": Damping.options(self.damping)}

    @staticmethod
    def _common(attrs: Mapping[str, Any]) -> tuple:
        return (attrs["study"], EnsembleSpec.from_attrs(attrs["ensemble"]), tuple(attrs["modes"]),
                attrs["tan_alpha"], tuple(attrs["R"]), tuple(attrs["intensity"]),
                attrs["chunk_R"], Accuracy.of(attrs["accuracy"]),
                Damping.from_options(attrs["model_options"]))


@dataclass(frozen=True)
class TiltMapSpec(_IntensityGrid):
    """The Fig 7 tilt map of a study: peak tilt over (mode, R, intensity) for one motion.

    Besides the fields of every intensity grid (study, ensemble, modes, tan_alpha, R,
    intensity, chunk_R, accuracy, damping):

    Attributes
    ----------
    motion : str or None
        Motion of the ensemble (None: the record, its first motion).
    """

    motion: str | None = None

    def to_attrs(self) -> dict[str, Any]:
        return {**super().to_attrs(), "motion": self.motion}

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> TiltMapSpec:
        """Inverse of :meth:`to_attrs`."""
        return cls(*cls._common(attrs), motion=attrs["motion"])


@dataclass(frozen=True)
class StripesSpec(_IntensityGrid):
    """The multiple-stripe analyses of a study (every motion at each stripe intensity).

    Besides the fields of every intensity grid (study, ensemble, modes, tan_alpha, R,
    intensity: the stripes, chunk_R, accuracy, damping):

    Attributes
    ----------
    limit_states : tuple of str
        As configured (the store canonicalises them).
    measure : str
        Intensity measure of the stripes (``"pga"``, or one of the study's
        ``intensity_measures`` such as ``"sa:1.0"``): ``intensity`` is it over g tan α.
    component : str
        The study's horizontal component of ``measure`` (``studies.<name>.component``):
        each motion is scaled so that its measure in it equals the stripe.
    refine : int
        Most stripes added per (mode, limit state, R) where the fit separates (decides no
        store: the refined analyses go beside it).
    bootstrap : int
        Resamples of the motions for the interval of the median (0: none; decides no store).
    jitter : float
        Half-width w in ln s of each analysis's jitter about its stripe
        (:func:`rocking.fragility.stripes.jittered`; 0: the stripes exactly).
    """

    limit_states: tuple[str, ...] = ()
    measure: str = "pga"
    refine: int = dc_field(default=8, compare=False)
    bootstrap: int = dc_field(default=1000, compare=False)
    component: str = DEFAULT_COMPONENT
    jitter: float = 0.0

    def to_attrs(self) -> dict[str, Any]:
        # the measure PGA is left out: stores made before stripes had a measure keep their hash
        extra = {} if self.measure == "pga" else {"measure": self.measure}
        if self.component != VECTOR_PEAK:  # likewise: the vector peak keeps the old hash
            extra["component"] = self.component
        if self.jitter:  # likewise: exact stripes keep the old hash
            extra["jitter"] = float(self.jitter)
        return {**super().to_attrs(), "limit_states": list(self.limit_states), **extra}

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> StripesSpec:
        """Inverse of :meth:`to_attrs` (``refine`` and ``bootstrap``, which decide no store,
        take their defaults)."""
        return cls(*cls._common(attrs), limit_states=tuple(attrs["limit_states"]),
                   measure=attrs.get("measure", "pga"),
                   component=attrs.get("component", VECTOR_PEAK),
                   jitter=float(attrs.get("jitter", 0.0)))


def _intensity_grid(config, t, field, study, ensemble, accuracy, part) -> tuple:
    """The settings every intensity grid has, checked; and the part's mapping."""
    t = checked_mapping(t, field, DEFAULTS[part], ["R", "intensity"])
    modes = mode_list(t["modes"], f"{field}.modes")
    return (study, ensemble, modes, positive_finite(f"{field}.tan_alpha", t["tan_alpha"]),
            tuple(expand_grid(t["R"], f"{field}.R")),
            tuple(expand_grid(t["intensity"], f"{field}.intensity")),
            chunk_R_field(t["chunk_R"], f"{field}.chunk_R", auto=False), accuracy,
            Damping.of_modes(config, modes)), t


def tilt_map_spec(config, t, field, study, ensemble, accuracy) -> TiltMapSpec:
    """The study's ``tilt_map:`` section ``t`` (at ``field``) as a checked spec."""
    common, t = _intensity_grid(config, t, field, study, ensemble, accuracy, "tilt_map")
    if t["motion"] is not None and not isinstance(t["motion"], str):
        raise ValueError(f"{field}.motion must be a motion name or null, got {t['motion']!r}")
    return TiltMapSpec(*common, motion=t["motion"])


def stripes_spec(config, t, field, study, ensemble, accuracy, component: str) -> StripesSpec:
    """The study's ``stripes:`` section ``t`` (at ``field``) as a checked spec; ``component``:
    the study's, parsed where the configuration entered (:meth:`StudySpec.from_config`)."""
    from rocking.spectra.limit_states import parse_limit_states

    common, t = _intensity_grid(config, t, field, study, ensemble, accuracy, "stripes")
    states = t["limit_states"]
    try:
        if not isinstance(states, (list, tuple)) or not states:
            raise ValueError("must be a non-empty list")
        parse_limit_states(list(states))
    except ValueError as exc:
        raise ValueError(f"{field}.limit_states={states!r}: {exc}") from None
    for key in ("refine", "bootstrap"):
        v = t[key]
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise ValueError(f"{field}.{key} must be an integer >= 0, got {v!r}")
    jitter = t["jitter"]
    if isinstance(jitter, bool) or not isinstance(jitter, int | float) or \
            not 0.0 <= jitter < 0.5:
        raise ValueError(f"{field}.jitter must be a number in [0, 0.5), got {jitter!r}")
    return StripesSpec(*common, limit_states=tuple(states), measure=t["measure"],
                       refine=t["refine"], bootstrap=t["bootstrap"], component=component,
                       jitter=float(jitter))
