"""Stripe fragility exports of a study (Snakemake script): the NRML and pelicun files of
stripe_fragility.csv, ids saying they carry the multiple-stripe fragility."""

import json

from rocking.execution.logs import job
from rocking.risk.exports import write_fragility_exports


def main(snakemake):
    out, params = snakemake.output, snakemake.params
    with job(snakemake):
        summary = write_fragility_exports(snakemake.input.stripes, nrml=out.nrml,
                                          pelicun=out.pelicun, search_upper=float(params.upper),
                                          study=params.study)
        print(json.dumps(summary, indent=1, ensure_ascii=False))


if __name__ == "__main__":
    main(snakemake)
