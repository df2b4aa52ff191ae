"""Risk of a study (Snakemake script): NRML and pelicun exports, risk table (first-exceedance
rows, and stripe rows when the study has stripes), risk figure."""

import json

from rocking.risk.exports import write_risk_outputs
from rocking.risk.hazard import parse_hazard
from rocking.study.figures import render
from rocking.study.logs import log_to


def main(snakemake):
    out, params = snakemake.output, snakemake.params
    with log_to(snakemake.log[0]):
        hazard = parse_hazard(params.hazard)
        stripes = snakemake.input.get("stripes") or None  # only studies with stripes:
        if stripes is not None and not isinstance(stripes, str):
            stripes = stripes[0]
        summary = write_risk_outputs(snakemake.input.fragility, hazard, nrml=out.nrml,
                                     pelicun=out.pelicun, table=out.table,
                                     search_upper=float(params.upper), study=params.study,
                                     stripes=stripes)
        print(json.dumps(summary, indent=1, ensure_ascii=False))
        render("risk", [out.png, out.pdf], out.notes, risk=out.table, hazard=hazard.source)


if __name__ == "__main__":
    main(snakemake)
