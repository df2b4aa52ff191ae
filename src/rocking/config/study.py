"""What a study is: its ensemble, grids, runs, accuracy, damping and search bound, typed.

A workflow configuration (``config/config.yaml``, ``config/paper.yaml``; schema
``workflow/schemas/config.schema.yaml``) is turned into a :class:`StudySpec` once, by
:meth:`StudySpec.from_config`: the values checked (errors name the key and the value), the
schema's defaults filled in where a configuration read without the workflow lacks them, and
every grid expanded (:func:`rocking.config.fields.expand_grid`). A study has up to three
stores, each described by its own part (:mod:`rocking.config.products`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from rocking._validate import positive_finite
from rocking.config.damping import Damping
from rocking.config.ensemble import EnsembleSpec
from rocking.config.fields import (
    DEFAULTS,
    accuracy_field,
    checked_mapping,
    chunk_R_field,
    config_section,
    expand_grid,
    number_field,
    quantity_field,
)
from rocking.config.plan import plan_study
from rocking.config.products import (
    Hashed,
    SpectraSpec,
    StripesSpec,
    TiltMapSpec,
    stripes_spec,
    tilt_map_spec,
)
from rocking.motions.measures import DEFAULT_COMPONENT

__all__ = ["CITATIONS", "PAPERS", "StudySpec"]

PAPERS = ("vassiliou2017",)
"""Papers a study can reproduce (``studies.<name>.reproduces``): Vassiliou et al. (2017)."""

CITATIONS = {
    "vassiliou2017": "Vassiliou, Burger, Egger, Bachmann, Broccardo & Stojadinović (2017), "
                     "“The three-dimensional behavior of inverted pendulum cylindrical "
                     "structures during earthquakes”, Earthquake Engineering & Structural "
                     "Dynamics 46:2261–2280",
}
"""The full reference of each paper of :data:`PAPERS` (authors, title, journal, year), as a
report of a reproduction names it."""


@dataclass(frozen=True)
class StudySpec(Hashed):
    """A study: its spectra and, if configured, its tilt map and stripes.

    Attributes
    ----------
    spectra : SpectraSpec
    tilt_map : TiltMapSpec or None
    stripes : StripesSpec or None
    hazard : str, dict or None
        The site's hazard as configured (``studies.<name>.hazard``: a hazard-curve file,
        ``{file, site, kind, unit, im_factor}`` or ``{k0, k, im_factor}``; read by
        :func:`rocking.risk.parse_hazard`), None without risk outputs. It decides no store.
    intensity_measures : tuple of str
        What the per-record table and the suite's fragility give beside the critical PGA
        (``studies.<name>.intensity_measures``): ``"pga"``, ``"pgv"``, ``"sa:<T>"`` (5 %
        damped pseudo-acceleration at period T [s]). It decides no store.
    reproduces : str or None
        The paper the study reproduces (one of :data:`PAPERS`), None for a study of one's
        own: it decides which figures and verdicts are drawn, no store.
    component : str
        Horizontal component of the intensity measures (``studies.<name>.component``,
        :data:`rocking.motions.measures.COMPONENTS`; default the vector peak,
        :data:`~rocking.motions.measures.DEFAULT_COMPONENT`, the spectra's own intensity),
        parsed once here. It decides no spectra store.
    """

    spectra: SpectraSpec
    tilt_map: TiltMapSpec | None = None
    stripes: StripesSpec | None = None
    hazard: str | dict[str, Any] | None = None
    intensity_measures: tuple[str, ...] = ("pga", "pgv")
    reproduces: str | None = None
    component: str = DEFAULT_COMPONENT
    inventory: dict[str, Any] | None = None

    @property
    def name(self) -> str:
        return self.spectra.study

    @property
    def ensemble(self) -> EnsembleSpec:
        return self.spectra.ensemble

    @classmethod
    def from_config(cls, config: Mapping[str, Any], name: str) -> StudySpec:
        """Study ``name`` of a workflow configuration, checked, defaults filled, grids expanded.

        Parameters
        ----------
        config : mapping
            The configuration (validated by the workflow, or read from YAML as it is).
        name : str
            Key of the study in ``studies``.

        Raises
        ------
        ValueError
            Naming the key and the value of the first bad setting.
        """
        from rocking.config.dimensions import resolve_dimensions

        config = resolve_dimensions(config)  # height/diameter -> R, tan_alpha
        studies = config.get("studies") or {}
        if name not in studies:
            raise ValueError(f"study {name!r} is not a key of studies {sorted(studies)}")
        field = f"studies.{name}"
        s = checked_mapping(studies[name], field, {**DEFAULTS["study"], "tilt_map": None,
                                            "stripes": None, "hazard": None,
                                            "reproduces": None, "inventory": None},
                     ["ensemble", "R", "runs"])
        ensemble = EnsembleSpec.from_config(config, s["ensemble"])
        quantity = quantity_field(config.get("quantity", DEFAULTS["quantity"]))
        accuracy = accuracy_field(config.get("accuracy", DEFAULTS["accuracy"]), quantity["w"])
        runs = s["runs"]
        if isinstance(runs, (list, tuple)):
            runs = [{**r, "tan_alpha": expand_grid(r["tan_alpha"], f"{field}.runs[{i}].tan_alpha")}
                    if isinstance(r, Mapping) and "tan_alpha" in r else r
                    for i, r in enumerate(runs)]
        plan = plan_study(runs, f"{field}.runs")
        chunk_R = chunk_R_field(s["chunk_R"], f"{field}.chunk_R", auto=True)
        min_task = config_section(config, "dask")["min_task_seconds"] if chunk_R == "auto" else None
        if min_task is not None:
            positive_finite("dask.min_task_seconds", min_task)
        upper = s["upper"] if s["upper"] is not None else config_section(config, "search")["upper"]
        where = f"{field}.upper" if s["upper"] is not None else "search.upper"
        if number_field(upper, where) <= 1.0:
            raise ValueError(f"{where} must be > 1 (the intensity that uplifts), got {upper!r}")
        mu = None if s["mu"] is None else positive_finite(f"{field}.mu", s["mu"])
        spectra = SpectraSpec(name, ensemble, tuple(expand_grid(s["R"], f"{field}.R")), plan,
                              chunk_R, min_task, accuracy, quantity, float(upper),
                              Damping.of_modes(config, plan.modes), mu)
        tilt_map = None if s["tilt_map"] is None else tilt_map_spec(
            config, s["tilt_map"], f"{field}.tilt_map", name, ensemble, accuracy)
        component = _component(s["component"], f"{field}.component")
        stripes = None if s["stripes"] is None else stripes_spec(
            config, s["stripes"], f"{field}.stripes", name, ensemble, accuracy, component)
        measures = _intensity_measures(s["intensity_measures"], f"{field}.intensity_measures")
        if stripes is not None and stripes.measure != "pga" and stripes.measure not in measures:
            raise ValueError(f"{field}.stripes.measure={stripes.measure!r} is not one of the "
                             f"study's intensity_measures {list(measures)} (or pga)")
        hazard = s["hazard"]
        if hazard is not None and not isinstance(hazard, (str, Mapping)):
            raise ValueError(f"{field}.hazard must be a file name or a mapping, got {hazard!r}")
        if isinstance(hazard, Mapping) and "component" in hazard:
            _component(hazard["component"], f"{field}.hazard.component")
        if s["reproduces"] is not None and s["reproduces"] not in PAPERS:
            raise ValueError(f"{field}.reproduces must be one of {list(PAPERS)} or null, got "
                             f"{s['reproduces']!r}")
        inventory = _inventory(s["inventory"], f"{field}.inventory", hazard)
        return cls(spectra, tilt_map, stripes,
                   dict(hazard) if isinstance(hazard, Mapping) else hazard,
                   measures, s["reproduces"], component, inventory)

    def to_attrs(self) -> dict[str, Any]:
        """``{"spectra", "tilt_map", "stripes", "hazard", "intensity_measures",
        "reproduces"}``: each part's mapping (None when absent)."""
        return {"spectra": self.spectra.to_attrs(),
                "tilt_map": None if self.tilt_map is None else self.tilt_map.to_attrs(),
                "stripes": None if self.stripes is None else self.stripes.to_attrs(),
                "hazard": self.hazard, "intensity_measures": list(self.intensity_measures),
                "reproduces": self.reproduces, "component": self.component}

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> StudySpec:
        """Inverse of :meth:`to_attrs`."""
        t, s = attrs.get("tilt_map"), attrs.get("stripes")
        return cls(SpectraSpec.from_attrs(attrs["spectra"]),
                   None if t is None else TiltMapSpec.from_attrs(t),
                   None if s is None else StripesSpec.from_attrs(s), attrs.get("hazard"),
                   tuple(attrs.get("intensity_measures", DEFAULTS["study"]
                                   ["intensity_measures"])),
                   attrs.get("reproduces"),
                   attrs.get("component", DEFAULTS["study"]["component"]))


INVENTORY_DEFAULTS: dict[str, Any] = {"export": None, "extrapolate": False,
                                      "resamples": 1000}
"""Defaults of a study's ``inventory:`` mapping (the schema's)."""

INVENTORY_EXPORTS = ("column", "size_class")
"""``inventory.export``: one OpenQuake taxonomy per column or per size class of (R, tan α)."""


def _inventory(value: Any, field: str, hazard: Any) -> dict[str, Any] | None:
    """A study's ``inventory:`` as ``{file, export, extrapolate, resamples}`` (None when
    absent); it needs the study's ``hazard:`` (λ is per the hazard's sites). It decides no
    store: only the portfolio rule reads it."""
    if value is None:
        return None
    entry = {"file": value} if isinstance(value, str) else value
    if not isinstance(entry, Mapping) or not isinstance(entry.get("file"), str) \
            or not entry["file"]:
        raise ValueError(f"{field} must be a file name or a mapping with file, got {value!r}")
    unknown = sorted(set(entry) - {"file", *INVENTORY_DEFAULTS})
    if unknown:
        raise ValueError(f"{field}: unknown key(s) {unknown} (known: file, "
                         f"{', '.join(INVENTORY_DEFAULTS)})")
    out = {"file": entry["file"], **INVENTORY_DEFAULTS,
           **{k: v for k, v in entry.items() if k != "file"}}
    if out["export"] is not None and out["export"] not in INVENTORY_EXPORTS:
        raise ValueError(f"{field}.export must be one of {list(INVENTORY_EXPORTS)} or null, "
                         f"got {out['export']!r}")
    if not isinstance(out["extrapolate"], bool):
        raise ValueError(f"{field}.extrapolate must be true or false, got "
                         f"{out['extrapolate']!r}")
    if isinstance(out["resamples"], bool) or not isinstance(out["resamples"], int) \
            or out["resamples"] < 0:
        raise ValueError(f"{field}.resamples must be an integer >= 0, got "
                         f"{out['resamples']!r}")
    if hazard is None:
        raise ValueError(f"{field} needs the study's hazard: (each column's λ integrates "
                         "its fragility against its site's hazard curve)")
    return out


def _component(value: Any, field: str) -> str:
    """A component of :data:`rocking.motions.measures.COMPONENTS` (one line naming the key
    and the value otherwise)."""
    from rocking.motions.measures import parse_component

    return parse_component(value, field)


def _intensity_measures(value: Any, field: str) -> tuple[str, ...]:
    """The study's intensity measures, checked by
    :func:`rocking.motions.measures.parse_measure`."""
    from rocking.motions.measures import parse_measure

    if not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"{field} must be a non-empty list such as [pga, pgv, 'sa:1.0'], "
                         f"got {value!r}")
    out = []
    for i, im in enumerate(value):
        try:
            parse_measure(im)
        except ValueError as exc:
            raise ValueError(f"{field}[{i}]={im!r}: {exc}") from None
        out.append(im)
    if len(set(out)) != len(out):
        raise ValueError(f"{field}: repeated measures {out!r}")
    return tuple(out)


def report_studies(config: Mapping[str, Any], study: str) -> list[str]:
    """The studies whose ensembles and stores the report of ``study`` describes: the study
    itself and, where it runs "3d" beside a 2D mode (its report shows Fig 12, which draws
    every such study), the other studies that do; in configuration order."""
    def compares(name: str) -> bool:
        return StudySpec.from_config(config, name).spectra.plan.compares_2d_with_3d()

    if not compares(study):
        return [study]
    return [s for s in config["studies"] if s == study or compares(s)]
