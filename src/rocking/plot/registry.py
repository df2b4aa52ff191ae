"""The figures, each one self-describing entry (:class:`FigureSpec`) declared in its own module.

A figure module of :mod:`rocking.plot` (``fig09_spectra``, ``fragility_curves``, ``risk``, ...)
holds ``data(...)``, ``plot(data)``, optionally ``compare(notes)``, ``report_tables(notes)`` and
``run_rows(notes)``, and at module level ``FIGURE = FigureSpec(...)`` (a tuple of them for
figures drawn from one ``data``: the portfolio's map and ranking): its name, its number in the
paper's order, its caption, its scope (what one drawing is of), when a configuration wants it,
its logical inputs and where the report shows it. Everything else is written once over the
registry: the workflow's figure rules (one loop, ``workflow/rules/figures.smk``), their one
script (``workflow/scripts/figure.py``, :func:`rocking.plot.draw`), the report's order,
sections, captions and verdict filter, the gallery's captions. :func:`figures` finds the
entries: every module of this package that defines ``FIGURE``, and the modules other packages
name under the entry-point group ``rocking.figures`` (a figure added without editing this
package).
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache
from importlib.metadata import entry_points
from pathlib import Path
from typing import Any

SCOPES = ("global", "ensemble", "study", "studies")
"""What one drawing of a figure is of: the whole configuration (``global``: one file
``<root>/figures/<name>``), one ensemble (``<root>/figures/<name>_<ensemble>``), one study
(``<root>/<study>/figures/<name>``) or the studies that want it side by side (``studies``:
``<root>/figures/<name>_<study>+<study>...``, its inputs lists over those studies)."""

INPUTS = ("numba", "motions", "comparison", "spectra", "tilt_map", "means", "fragility_nc",
          "fragility_csv", "stripe_table", "stripe_refined", "risk", "portfolio", "headline")
"""Logical inputs a figure may declare (``FigureSpec.inputs`` values), resolved by the workflow
(``figure_inputs`` in ``workflow/rules/figures_common.smk``) for the figure's subject: the
compiled kernels, the ensemble file (and its comparison pairs), the completion marker of the
spectra or tilt-map store, the mean spectra, the fragility table, the stripe fragility table
and the refined analyses it used, the risk table, the portfolio table, the headline's first
exceedances on four grids (``headline.csv``, studies that have it; none elsewhere).
The name of another figure is that figure's JSON notes for the same subject."""

READ_BESIDE = ("numba", "spectra", "tilt_map", "headline")
"""Logical inputs declared for the order of the jobs and their reruns, not handed to
``data()`` (the compiled kernels, completion markers, tables read beside another input)."""

PARAMS = ("paper", "model_options", "ensemble_spec", "spectra_store", "tilt_map_store",
          "stripes_store", "studies", "study", "ensemble", "hazard", "hazard_file")
"""Logical parameters a figure may declare (``FigureSpec.params`` values): whether the paper is
reproduced, the damped model's contact parameters, the ensemble's settings, the spectra,
tilt-map or stripes store, the names of the studies (``studies`` scope), the study's name and
its ensemble's, its hazard entry (what :func:`rocking.risk.hazard.parse_hazard` reads) and its
hazard file (empty for a power law)."""

SECTIONS = ("", "stripes", "risk", "portfolio")
"""Where the report shows a figure (``FigureSpec.section``): among the figures (``""``, with
its verdicts), or under the tables of its own section."""

ENTRY_POINTS = "rocking.figures"
"""Entry-point group naming modules of other packages that declare a ``FIGURE``."""


@dataclass(frozen=True)
class Subject:
    """What a figure is asked about: the configuration, and a study and/or an ensemble.

    ``study_spec`` (default :meth:`rocking.config.study.StudySpec.from_config`) lets a
    caller hand in its own cached specs (the workflow's ``study_spec``).
    """

    config: Mapping
    study: str | None = None
    ensemble: str | None = None
    study_spec: Callable[[str], Any] | None = field(default=None, compare=False)

    def spec(self, study: str | None = None):
        """The :class:`~rocking.config.study.StudySpec` of ``study`` (default: this
        subject's)."""
        name = study or self.study
        if self.study_spec is not None:
            return self.study_spec(name)
        from rocking.config.study import StudySpec

        return StudySpec.from_config(self.config, name)

    @property
    def plan(self):
        """The study's :class:`~rocking.config.plan.StudyPlan`."""
        return self.spec().spectra.plan

    @property
    def reproduces(self) -> bool:
        """Whether the study (no study: any study) reproduces the paper
        (``studies.<name>.reproduces``)."""
        studies = list(self.config["studies"]) if self.study is None else [self.study]
        return any(self.spec(s).reproduces is not None for s in studies)

    @property
    def on_paper_record(self) -> bool:
        """Whether the subject's ensemble (or its study's) is the first ensemble built on
        the El Centro record, the one of the paper's Figs 6–11."""
        ensemble = self.ensemble or (self.spec().ensemble.name if self.study else None)
        return ensemble is not None and ensemble == paper_record_ensemble(self.config)


def paper_record_ensemble(config: Mapping) -> str | None:
    """The first ensemble built on the El Centro record (a suite has ``records``), or None."""
    for name, spec in config["ensembles"].items():
        if spec.get("record") == "el-centro-1940":
            return name
    return None


@dataclass(frozen=True)
class FigureSpec:
    """One figure: everything the workflow and the report need to draw and show it.

    Attributes
    ----------
    name : str
        File stem (or its start: ``fig08_motions_<ensemble>``), workflow rule, the
        sidecar's ``"figure"``.
    module : str
        Dotted module holding ``data``, ``plot`` (and ``compare``, ``report_tables``,
        ``run_rows`` where it has them); ``__name__`` where it is declared.
    number : float
        Place in the paper's order (a companion takes a fraction, e.g. 6.5; a figure beyond
        the paper a number after the paper's last).
    label : str
        Short label: ``"Fig 9"`` (captions of a reproduction start with it), ``"Fig 6
        (companion)"``, ``"fragility"`` (beyond the paper); the Snakemake report's label.
    caption : str
        What the figure shows (a study of one's own reads this alone); a figure drawn only
        for a reproduction gives its whole caption here.
    scope : str
        One of :data:`SCOPES`.
    wanted : callable
        ``wanted(subject) -> bool`` (:class:`Subject`, always with a study; with the
        ensemble too for scope ``ensemble``): whether that study wants this figure drawn.
    inputs : mapping
        ``data()`` argument → logical input (:data:`INPUTS`, or another figure's name).
    params : mapping
        ``data()`` argument → logical parameter (:data:`PARAMS`).
    arguments : callable, optional
        ``arguments(inputs, params) -> dict``: the ``data()`` keywords from the resolved
        inputs and parameters, where they need reading first (default: both merged, the
        inputs of :data:`READ_BESIDE` left out).
    paper : str
        What the paper states of it (added to the caption in a reproduction).
    paper_only : bool
        Drawn only for a reproduction of the paper (no caption of a study of one's own).
    el_centro_only : bool
        The paper states its numbers for El Centro only: its verdicts belong to the report
        of the study on that record, and (scope other than ``study``) it is shown there only.
    general : callable, optional
        ``general(statement) -> bool``: statements of an ``el_centro_only`` figure that the
        paper makes of every record (judged in every study).
    own_caption : callable, optional
        ``own_caption(notes or None) -> str``: the caption of a study of one's own adapted to what
        the sidecar says is drawn (default: ``caption``).
    category : str
        Section of the Snakemake report.
    plot : str
        The module's drawing function (``plot``; ``plot_map`` and ``plot_ranked`` for the
        two portfolio figures drawn from one ``data``).
    section : str
        Where the report shows it (:data:`SECTIONS`): among the figures, or in its own
        section (the stripes, the risk, the portfolio) with its caption alone.
    per : str
        A ``data()`` keyword the figure is drawn once for each value of (``"mode"``: a
        stripe figure per mode), its files ``<name>_<value>``; with :attr:`per_values`.
    per_values : callable, optional
        ``per_values(subject) -> sequence of str``: the values of :attr:`per` a study draws.
    rule : str
        The workflow rule's name where the figure's name is taken by another rule (the risk
        table's ``risk``); default the name.
    """

    name: str
    module: str
    number: float
    label: str
    caption: str
    scope: str
    wanted: Callable[[Subject], bool]
    inputs: Mapping[str, str] = field(default_factory=dict)
    params: Mapping[str, str] = field(default_factory=dict)
    arguments: Callable[[Mapping, Mapping], dict] | None = None
    paper: str = ""
    paper_only: bool = False
    el_centro_only: bool = False
    general: Callable[[str], bool] | None = None
    own_caption: Callable[[Mapping], str] | None = None
    category: str = "Paper figures"
    plot: str = "plot"
    section: str = ""
    per: str = ""
    per_values: Callable[[Subject], Sequence[str]] | None = None
    rule: str = ""

    def __post_init__(self):
        if self.scope not in SCOPES:
            raise ValueError(f"figure {self.name!r}: scope must be one of {list(SCOPES)}, "
                             f"got {self.scope!r}")
        if self.section not in SECTIONS:
            raise ValueError(f"figure {self.name!r}: section must be one of {list(SECTIONS)}, "
                             f"got {self.section!r}")
        if bool(self.per) != (self.per_values is not None):
            raise ValueError(f"figure {self.name!r}: per and per_values go together")
        unknown = [v for v in self.params.values() if v not in PARAMS]
        if unknown:
            raise ValueError(f"figure {self.name!r}: params {unknown} are not among "
                             f"{list(PARAMS)}")

    @property
    def rule_name(self) -> str:
        """The name of the workflow rule that draws it."""
        return self.rule or self.name

    def text(self, paper: bool = True, notes: Mapping | None = None) -> str:
        """The caption: with the paper's statements for a reproduction (``paper``), else
        what the figure shows, adapted to its sidecar ``notes``; a figure of a report's own
        section has its caption alone.

        Raises
        ------
        ValueError
            For a figure drawn only for a reproduction asked without ``paper``.
        """
        if self.paper_only:
            if not paper:
                raise ValueError(f"figure {self.name!r} is drawn only for a reproduction of "
                                 "the paper")
            return self.caption
        if paper and not self.section:
            lead = f"{self.label}. " if self.label.startswith("Fig ") else "Beyond the paper: "
            return lead + f"{self.caption} {self.paper}".strip()
        if self.own_caption is not None:
            return self.own_caption(notes)
        return self.caption

    def data_kwargs(self, inputs: Mapping, params: Mapping) -> dict:
        """The ``data()`` keywords from the workflow's resolved ``inputs`` and ``params``
        (keyed by the argument names of :attr:`inputs` and :attr:`params`)."""
        if self.arguments is not None:
            return self.arguments(inputs, params)
        return {**{k: v for k, v in inputs.items() if self.inputs.get(k) not in READ_BESIDE},
                **params}

    def shown(self, subject: Subject) -> bool:
        """Whether the report of ``subject.study`` (its ensemble as ``subject.ensemble``)
        shows this figure: wanted there, and an El Centro-only figure not of the study's
        own (scope other than ``study``) only in the report of the study on that record."""
        if not self.wanted(subject):
            return False
        return self.scope == "study" or not self.el_centro_only or subject.on_paper_record


@cache
def _registry() -> dict[str, FigureSpec]:
    found = []
    # this package's modules, found on disk (importing the package here would be a circle)
    names = [f"{__package__}.{m.name}" for m in pkgutil.iter_modules([str(Path(__file__).parent)])
             if not m.name.startswith("_")]
    names += [ep.value for ep in entry_points(group=ENTRY_POINTS)]
    for name in names:
        entry = getattr(importlib.import_module(name), "FIGURE", None)
        for one in entry if isinstance(entry, tuple) else (entry,):
            if isinstance(one, FigureSpec):
                found.append(one)
    out: dict[str, FigureSpec] = {}
    for entry in sorted(found, key=lambda f: (f.number, f.name)):
        if entry.name in out:
            raise ValueError(f"figure {entry.name!r} is declared twice ({out[entry.name].module}"
                             f", {entry.module})")
        out[entry.name] = entry
    return out


def figures() -> dict[str, FigureSpec]:
    """Every figure by name, in the paper's order (by ``number``)."""
    return dict(_registry())


def refresh() -> None:
    """Find the figures again (after a module or entry point was added at run time)."""
    importlib.invalidate_caches()
    _registry.cache_clear()


def figure(name: str) -> FigureSpec:
    """The entry of figure ``name``.

    Raises
    ------
    ValueError
        Naming the figure and the known ones.
    """
    known = _registry()
    if name not in known:
        raise ValueError(f"figure must be one of {list(known)}, got {name!r}")
    return known[name]


def caption(name: str, paper: bool = True, notes: Mapping | None = None) -> str:
    """The caption of figure ``name`` (:meth:`FigureSpec.text`)."""
    return figure(name).text(paper, notes)


__all__ = ["ENTRY_POINTS", "INPUTS", "PARAMS", "READ_BESIDE", "SCOPES", "SECTIONS", "FigureSpec",
           "Subject",
           "caption", "figure", "figures", "paper_record_ensemble", "refresh"]
