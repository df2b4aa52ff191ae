"""A study's risk outputs in one call: NRML, pelicun CSV and the risk table.

What the workflow's ``risk`` rule runs (``workflow/scripts/risk.py``) and what a user runs on
a finished study's ``fragility.csv``.
"""

from __future__ import annotations

from pathlib import Path

from .fragilities import read_fragilities
from .hazard import HazardCurve
from .nrml import write_nrml
from .pelicun import write_pelicun_csv
from .table import risk_table


def write_risk_outputs(fragility, hazard: HazardCurve, *, nrml: str | Path,
                       pelicun: str | Path, table: str | Path,
                       search_upper: float | None = None, study: str = "") -> dict:
    """Write ``fragility.nrml.xml``, ``fragility.pelicun.csv`` and ``risk.csv`` of a study.

    Parameters
    ----------
    fragility : path, DataFrame or Dataset
        The study's fragility table (``results/<study>/fragility.csv``).
    hazard : HazardCurve
        The site's hazard curve.
    nrml, pelicun, table : path
        Output files.
    search_upper : float, optional
        The study's search bound PGA/(g tan α) [-] (sets the NRML maxIML).
    study : str
        Study name, for the NRML description.

    Returns
    -------
    dict
        What was written: counts, the NRML limit states, the functions left out of the NRML
        and the fragilities without a fit (``skipped``), for the rule's log.
    """
    frag = read_fragilities(fragility)
    if frag.rows.empty:
        raise ValueError("the fragility table has no fitted row (every median is NaN)")
    desc = f"Study {study}: lognormal fragilities of the critical PGA." if study else ""
    exp = write_nrml(frag, nrml, search_upper=search_upper, model_id=study or "rocking",
                     description=desc)
    comps = write_pelicun_csv(frag, pelicun)
    risk = risk_table(frag, hazard)
    risk.to_csv(table, index=False, float_format="%.6g")
    return {"fitted": len(frag.rows), "skipped": frag.skipped_note(),
            "not_computed": frag.n_not_computed, "nrml_limit_states": exp.limit_states,
            "nrml_functions": len(exp.functions), "nrml_left_out": exp.left_out,
            "pelicun_components": len(comps), "risk_rows": len(risk),
            "hazard": hazard.source}


__all__ = ["write_risk_outputs"]
