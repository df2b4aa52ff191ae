"""One fragility with one hazard: the same intensity measure, component and unit, or refused.

A fragility and a hazard curve describe one intensity in three terms: its measure (PGA,
Sa(T)), its horizontal component (vector peak, RotD50, ...) and its unit (g). λ integrates
one against the other, so the three must be the same; :func:`decide` is the one place that
says how a study's fragility is brought into the hazard's terms, and every consumer goes
through it (the risk table and exports, :func:`reconcile`; the portfolio's surface,
:func:`reconcile_surface`; the configuration's dry run, :func:`rocking.config.checks`):

1. **Measure.** The hazard's measure must be one the study fits (``pga`` always, and each of
   its ``intensity_measures``); any other is refused, naming both and the key to add it.
2. **Component.** The hazard's component (declared, read from its file, or an OpenQuake
   file's default, :data:`rocking.risk.hazard.OPENQUAKE_COMPONENT`; a table or power law
   that says nothing is taken in the fragility's, and the output says so). A table that has
   its fits in it is used as it is; else the critical-intensity fragility is **refitted** in
   it from the study's own motions (:mod:`rocking.fragility.refit`: each motion's critical
   intensity times its ratio of the two components, exact because every measure is linear
   in the record's scale), never rescaled as a whole. A stripe fragility cannot be refitted
   (its motions were scaled in its own component): refused, saying how to run it in the
   hazard's.
3. **Unit.** The hazard's levels are read into g whatever the file's unit
   (:func:`rocking.risk.hazard.unit_factor`); the fragility's median is in its measure's
   unit, which must be g (PGA, Sa).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, replace
from pathlib import Path

from rocking.fragility.table import (
    CRITICAL_INTENSITY,
    STRIPES,
    Fragilities,
    fragility_kind,
    read_fragilities,
    renamed,
)
from rocking.motions.measures import DEFAULT_COMPONENT, Measure, parse_component

__all__ = ["Terms", "decide", "reconcile", "reconcile_surface", "study_terms", "table_terms"]


@dataclass(frozen=True)
class Terms:
    """What a fragility is taken in under a hazard.

    Attributes
    ----------
    measure : str
        The hazard's measure (the fragility's medians are in it).
    component : str
        The component used: the hazard's (or the fragility's, where the hazard says none).
    refit : bool
        The fragility is refitted from the study's motions in it (no table has it).
    note : str
        What the output says: where the component comes from, what was refitted ('' when
        nothing needs saying).
    """

    measure: str
    component: str
    refit: bool
    note: str


def decide(hazard_measure, hazard_component: str | None, *, have: Iterable[tuple[str, str]],
           refittable: Iterable[tuple[str, str]] = (), kind: str = CRITICAL_INTENSITY,
           where: str = "the fragility", hazard: str = "the hazard",
           hazard_note: str = "", assumed: tuple[str, str] | None = None) -> Terms:
    """The one decision: the terms a fragility is taken in under a hazard, or a one-line
    refusal (module docstring).

    Parameters
    ----------
    hazard_measure : str
        The hazard's intensity measure (any spelling).
    hazard_component : str or None
        Its horizontal component; None where the hazard states none (taken in the
        fragility's).
    have : iterable of (measure, component)
        The fits the fragility table holds.
    refittable : iterable of (measure, component)
        What the study's motions can refit the fragility in (a critical-intensity fragility
        with ``critical.csv`` and ``motion_measures.csv``, or the workflow, which writes
        them: every component of the study's measures).
    kind : str
        The estimator (a stripe fragility is never refitted).
    where, hazard : str
        The fragility and the hazard, for the messages.
    hazard_note : str
        What the hazard says of its component (an OpenQuake default), carried into the note.
    assumed : (str, str), optional
        The component taken where the hazard states none, and whose it is (``("rotd50",
        "the study's")``); default the fragility's own.

    Raises
    ------
    ValueError
        The hazard's measure is none the study fits; no fit in the hazard's component and
        none can be refitted; a measure not in g.
    """
    measure = Measure.of(hazard_measure)
    have = [(Measure.of(m).name, parse_component(c)) for m, c in have]
    refittable = ([] if kind == STRIPES else
                  [(Measure.of(m).name, parse_component(c)) for m, c in refittable])
    measures = list(dict.fromkeys([m for m, _ in have] + [m for m, _ in refittable]))
    if measure.name not in measures:
        raise ValueError(f"{hazard} is of {measure.imt}, {where} of {', '.join(measures)} "
                         f"only: add {measure.name} to the study's intensity_measures (a "
                         "fragility in another measure is never used for it)")
    if measure.unit != "g":
        raise ValueError(f"{hazard}: a hazard in {measure} [{measure.unit}] cannot be "
                         "integrated: its levels are read in g")
    notes = [hazard_note] if hazard_note else []
    own = [c for m, c in have if m == measure.name] or [DEFAULT_COMPONENT]
    if hazard_component is None:
        component, whose = ((parse_component(assumed[0]), assumed[1]) if assumed
                            else (own[0], f"{where}'s"))
        notes.append(hazard_note or (
            f"{hazard} does not state its horizontal component: taken as {whose} "
            f"({component}); declare it (hazard.component, --component)"))
        notes = list(dict.fromkeys(notes))
    else:
        component = parse_component(hazard_component)
    if (measure.name, component) in have:
        return Terms(measure.name, component, False, "; ".join(notes))
    if (measure.name, component) in refittable:
        notes.append(f"{where} refitted in {measure.name} {component} (the hazard's) from "
                     "each motion's critical PGA (critical.csv) and its ratio of "
                     f"{measure.name} {component} to it (motion_measures.csv)")
        return Terms(measure.name, component, True, "; ".join(notes))
    theirs = sorted({c for m, c in have if m == measure.name})
    if kind == STRIPES:
        raise ValueError(f"{hazard} is in the component {component}, {where} in "
                         f"{', '.join(theirs)}: stripes scale each motion in their own "
                         f"component, so they cannot be refitted in another: run them in "
                         f"{component} (studies.<name>.component: {component}), or declare "
                         f"the hazard's component if it is {theirs[0]}")
    raise ValueError(f"{hazard} is in the component {component}, {where} has {measure.name} "
                     f"in {', '.join(theirs) or 'no component'} only and no motion measures "
                     f"to refit it (motion_measures.csv beside it: the workflow writes it "
                     f"for a study with a hazard:); or declare the hazard's component "
                     f"(hazard.component, --component) if it is {', '.join(theirs) or 'that'}")


def table_terms(source) -> tuple[list[tuple[str, str]], list[tuple[str, str]], str, Path | None]:
    """What a fragility table holds and what its study can refit: ``(have, refittable,
    kind, folder)`` (refittable empty for a table not in a study folder or of stripes)."""
    from rocking.fragility.refit import MOTION_MEASURES, available, read_motion_measures
    from rocking.units import read_table

    if isinstance(source, Fragilities):
        return [(source.measure, source.component)], [], source.kind, None
    frame = read_table(source) if isinstance(source, str | Path) else source
    frame = renamed(frame.rename(columns=lambda c: str(c).split(" [", 1)[0]))
    kind = (str(frame["estimator"].iloc[0]) if "estimator" in frame.columns and len(frame)
            else fragility_kind(frame))
    measures = frame["measure"].astype(str) if "measure" in frame.columns else ["pga"] * len(
        frame)
    components = (frame["component"].astype(str) if "component" in frame.columns
                  else [DEFAULT_COMPONENT] * len(frame))
    have = list(dict.fromkeys(zip(measures, components, strict=True))) or [
        ("pga", DEFAULT_COMPONENT)]
    folder = Path(source).parent if isinstance(source, str | Path) else None
    refittable: list[tuple[str, str]] = []
    if folder is not None and kind == CRITICAL_INTENSITY and (folder / "critical.csv").is_file():
        path = folder / MOTION_MEASURES
        refittable = sorted(available(read_motion_measures(path) if path.is_file() else None))
    return have, refittable, kind, folder


def reconcile(fragility, hazard, *, kind: str | None = None,
              assumed: tuple[str, str] | None = None) -> Fragilities:
    """A fragility in the hazard's measure, component and unit (:func:`decide`).

    Parameters
    ----------
    fragility : Fragilities, path, DataFrame or Dataset
        A fragility table (``fragility.csv``, ``suite_fragility.csv``,
        ``stripe_fragility.csv``) or one already read; a table in a study's folder can be
        refitted in the hazard's component from the study's motions.
    hazard : rocking.risk.hazard.HazardCurve
        The hazard curve (its ``measure``, ``component``, ``component_note``).
    kind : str, optional
        The estimator of the table (default: the table's).
    assumed : (str, str), optional
        As :func:`decide` (the workflow: the study's component).

    Returns
    -------
    Fragilities
        Its ``note`` says what was assumed or refitted ('' when nothing).
    """
    have, refittable, own_kind, folder = table_terms(fragility)
    kind = kind or own_kind
    where = (f"the {kind} fragility ({fragility})" if isinstance(fragility, str | Path)
             else f"the {kind} fragility")
    hazard_note = hazard.component_note if hazard.component_source in ("default",
                                                                      "im_factor") else ""
    terms = decide(hazard.measure, hazard.component, have=have, refittable=refittable,
                   kind=kind, where=where, hazard=f"the hazard ({hazard.source})",
                   hazard_note=hazard_note, assumed=assumed)
    if terms.refit:
        from rocking.fragility.refit import refit_study

        frag = replace(refit_study(folder, terms.measure, terms.component), note="")
    elif isinstance(fragility, Fragilities):
        frag = fragility
    else:
        frag = read_fragilities(fragility, kind, measure=terms.measure,
                                component=terms.component)
    return replace(frag, note="; ".join(n for n in (terms.note, frag.note) if n))


def reconcile_surface(study, hazard_measure, hazard_component: str | None, *,
                      hazard: str = "the hazard", hazard_note: str = "", mode: str = "3d",
                      limit_states=None, n_resamples: int | None = None,
                      assumed: tuple[str, str] | None = None):
    """The fragility surface of a study's folder in the hazard's measure and component
    (:func:`decide`; the surface's nodes refitted there, :meth:`rocking.fragility.surface.
    FragilitySurface.from_study`)."""
    from rocking.fragility.lognormal import BOOTSTRAP_RESAMPLES
    from rocking.fragility.refit import study_folder
    from rocking.fragility.surface import FragilitySurface

    folder = study_folder(study)
    have, refittable, kind, _ = table_terms(folder / "fragility.csv") \
        if (folder / "fragility.csv").is_file() else ([("pga", DEFAULT_COMPONENT)], [],
                                                      CRITICAL_INTENSITY, None)
    refittable = refittable or ([] if not (folder / "critical.csv").is_file()
                                else [("pga", DEFAULT_COMPONENT)])
    terms = decide(hazard_measure, hazard_component, have=have, refittable=refittable,
                   kind=kind, where=f"the study's fragility ({folder})", hazard=hazard,
                   hazard_note=hazard_note, assumed=assumed)
    surface = FragilitySurface.from_study(
        folder, mode=mode, limit_states=limit_states,
        n_resamples=BOOTSTRAP_RESAMPLES if n_resamples is None else n_resamples,
        measure=terms.measure, component=terms.component)
    return replace(surface, note=terms.note)  # the refit's own note says it again


def study_terms(hazard_measure, hazard_component: str | None, measures: Iterable[str], *,
                study: str, hazard: str, hazard_note: str = "",
                study_component: str = DEFAULT_COMPONENT) -> Terms:
    """:func:`decide` for a configured study before anything is computed: the workflow
    fits ``pga`` and each of the study's ``measures`` (``intensity_measures``), and writes
    every motion's measures in every component (rule ``motion_measures``), so any
    component of those measures can be refitted; a hazard that states no component is
    taken in the study's ``component``."""
    from rocking.motions.measures import COMPONENTS

    names = list(dict.fromkeys(["pga", *(Measure.of(m).name for m in measures)]))
    return decide(hazard_measure, hazard_component, have=[("pga", DEFAULT_COMPONENT)],
                  refittable=[(m, c) for m in names for c in COMPONENTS],
                  where=f"study {study}", hazard=hazard, hazard_note=hazard_note,
                  assumed=(study_component, "the study's component"))
