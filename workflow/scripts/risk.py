"""Risk of a study (Snakemake script): NRML and pelicun exports, risk table (critical-intensity
rows in the hazard's measure, and stripe rows when the study has stripes); the risk figure is
drawn from the table by the figure loop."""

import json

from rocking.execution.logs import job
from rocking.risk.exports import write_risk_outputs
from rocking.risk.hazard import parse_hazard


def _one(files):
    """The single file of an optional input ([] → None)."""
    if not files:
        return None
    return files if isinstance(files, str) else files[0]


def main(snakemake):
    out, params = snakemake.output, snakemake.params
    with job(snakemake):
        hazard = parse_hazard(params.hazard)
        summary = write_risk_outputs(snakemake.input.fragility, hazard, nrml=out.nrml,
                                     pelicun=out.pelicun, table=out.table,
                                     search_upper=float(params.upper), study=params.study,
                                     stripes=_one(snakemake.input.get("stripes")),
                                     preset=params.preset,
                                     study_component=params.study_component)
        for note in ("preset_warning", "below_first_warning", "terms_note", "stripes_note"):
            if summary[note]:
                print(summary[note])
        print(json.dumps(summary, indent=1, ensure_ascii=False))


if __name__ == "__main__":
    main(snakemake)
