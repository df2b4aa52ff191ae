"""A study's risk outputs in one call: NRML, pelicun CSV and the risk table.

What the workflow's ``risk`` and ``stripe_risk_exports`` rules run
(``workflow/scripts/risk.py``) and what a user runs on a finished study's ``fragility.csv``
and ``stripe_fragility.csv``. Each export says which fragility it carries
(:data:`rocking.fragility.table.KINDS`): the NRML model id and description, the pelicun
component ids, the risk table's ``fragility`` column.
"""

from __future__ import annotations

from pathlib import Path

from rocking.fragility.table import Fragilities, read_fragilities
from rocking.motions.measures import DEFAULT_COMPONENT, VECTOR_PEAK
from rocking.risk.hazard import HazardCurve
from rocking.risk.nrml import nrml_model_id, write_nrml
from rocking.risk.pelicun import write_pelicun_csv
from rocking.risk.risk_table import risk_tables


def exported(measure: str, component: str) -> bool:
    """Whether a fragility in ``measure`` and ``component`` gets the NRML and pelicun
    exports: those of the vector-peak PGA only, the terms OpenQuake's PGA models and
    pelicun's ``Demand-Directional 1`` demand read it in (a stripe fragility in Sa(T) or
    another component reaches the study's risk table only)."""
    return measure == "pga" and component == VECTOR_PEAK


def _read(fragility) -> Fragilities:
    return fragility if isinstance(fragility, Fragilities) else read_fragilities(fragility)


def write_fragility_exports(fragility, *, nrml: str | Path, pelicun: str | Path,
                            search_upper: float | None = None, study: str = "") -> dict:
    """Write the NRML and pelicun exports of one fragility table (either kind).

    Parameters
    ----------
    fragility : Fragilities, path, DataFrame or Dataset
        ``results/<study>/fragility.csv`` or ``stripe_fragility.csv`` (the kind is read from
        its columns).
    nrml, pelicun : path
        Output files.
    search_upper : float, optional
        The study's search bound PGA/(g tan α) [-] (sets the NRML maxIML).
    study : str
        Study name: the NRML model id is ``<study>-<kind>`` and the description names it.

    Returns
    -------
    dict
        The kind, the NRML model id, limit states and functions (written, left out), the
        pelicun component count and the fragilities without a fit, for the rule's log. A
        table without any fit (a stripe fit can be undefined everywhere in a small study)
        gives a model without functions and a CSV without components, the log saying why.
    """
    frag = _read(fragility)
    desc = f"Study {study}." if study else ""
    model_id = nrml_model_id(study or "rocking", frag.kind)
    exp = write_nrml(frag, nrml, search_upper=search_upper, model_id=model_id,
                     description=desc)
    comps = write_pelicun_csv(frag, pelicun)
    off = exp.off_chain
    return {"fragility": frag.kind, "fitted": len(frag.rows), "skipped": frag.skipped_note(),
            "left_out_of_chain": (
                f"{', '.join(off)} left out of the NRML and pelicun exports: sliding in "
                "contact is not a damage state of the tilt-overturning chain (its fragility is "
                "in the study's fragility table)" if off else ""),
            "not_computed": frag.n_not_computed, "nrml_model_id": model_id,
            "nrml_limit_states": exp.limit_states, "nrml_functions": len(exp.functions),
            "nrml_left_out": exp.left_out, "pelicun_components": len(comps)}


def write_risk_outputs(fragility, hazard: HazardCurve, *, nrml: str | Path,
                       pelicun: str | Path, table: str | Path,
                       search_upper: float | None = None, study: str = "",
                       stripes=None, preset: str = "",
                       study_component: str = DEFAULT_COMPONENT) -> dict:
    """Write ``fragility.nrml.xml``, ``fragility.pelicun.csv`` and ``risk.csv`` of a study.

    One behaviour whatever the fits: every requested row is in ``risk.csv``, a row without a
    fit with its status (a study whose fragility cannot be fitted anywhere gets a table of
    statuses and exports without functions, never an error).

    Parameters
    ----------
    fragility : path
        The study's fragility table (``results/<study>/fragility.csv``, vector-peak PGA):
        always exported; in ``risk.csv`` in the hazard's measure and component
        (:func:`rocking.risk.reconcile.reconcile`: refitted from the study's
        ``critical.csv`` and ``motion_measures.csv`` beside it where the hazard's are
        others, refused where the study does not fit the hazard's measure).
    hazard : HazardCurve
        The site's hazard curve (PGA or Sa(T)), its component declared, read or an
        OpenQuake file's default.
    nrml, pelicun, table : path
        Output files (the exports of ``fragility``; the risk table of both fragilities).
    search_upper : float, optional
        The study's search bound PGA/(g tan α) [-] (sets the NRML maxIML).
    study : str
        Study name, for the NRML model id and description.
    stripes : path, DataFrame or Dataset, optional
        The study's stripe fragility (``stripe_fragility.csv``): its rows join the table,
        marked ``fragility = stripes``, where it is in the hazard's measure and component
        (stripes cannot be refitted in another: left out then, the summary says why).
    preset : str
        Accuracy preset of the study's analyses (the ``preset`` column).
    study_component : str
        The study's component (``studies.<name>.component``): taken where the hazard states
        none.

    Returns
    -------
    dict
        What was written: counts, the NRML limit states, the functions left out of the NRML,
        the rows without a fit (``skipped``), the hazard's site, kind, unit and component,
        what was assumed or refitted (``terms_note``), and the preset's and the hazard's
        first level's warnings, for the rule's log.
    """
    from rocking.risk.reconcile import reconcile
    from rocking.risk.risk_table import below_first_warning, preset_warning

    summary = write_fragility_exports(read_fragilities(fragility), nrml=nrml, pelicun=pelicun,
                                      search_upper=search_upper, study=study)
    assumed = (study_component, "the study's component")
    tables = [reconcile(fragility, hazard, assumed=assumed)]
    stripes_note = ""
    if stripes is not None:
        try:
            tables.append(reconcile(stripes, hazard, kind="stripes", assumed=assumed))
        except ValueError as exc:  # stripes in other terms: said, the first rows stand
            stripes_note = f"stripe rows left out of risk.csv: {exc}"
    risk = risk_tables(tables, hazard, preset=preset, assumed=assumed)
    risk.to_csv(table, index=False, float_format="%.6g")
    return {**summary, "risk_rows": len(risk), "risk_fragilities": [f.kind for f in tables],
            "risk_measure": tables[0].measure, "risk_component": tables[0].component,
            "terms_note": risk.attrs["note"], "stripes_note": stripes_note,
            "risk_skipped": risk.attrs["skipped"],
            "hazard": hazard.source, "hazard_note": hazard.note,
            "hazard_site": hazard.site, "hazard_kind": hazard.kind,
            "hazard_unit": hazard.unit, "below_first_warning": below_first_warning(risk),
            "preset_warning": preset_warning(preset)}


__all__ = ["write_fragility_exports", "write_risk_outputs"]
