"""Fig 6 (Snakemake script): El Centro response, the ensemble's first motion (the record)."""

from rocking.motions.ensemble_io import load_ensemble
from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        record = load_ensemble(snakemake.input.motions)[0]
        render("fig06_el_centro", [out.png, out.pdf], out.notes, motion=record,
               sensitivity=snakemake.input.sensitivity, **snakemake.params.model_options)


if __name__ == "__main__":
    main(snakemake)
