"""Fig 8 (Snakemake script): traces and 5 %-damped PSA spectra of one ensemble."""

from rocking.motions.ensemble_io import load_ensemble
from rocking.study.cluster import log_to
from rocking.study.figures import render


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0]):
        render("fig08", [out.png, out.pdf], out.notes,
               motions=load_ensemble(snakemake.input.motions))


if __name__ == "__main__":
    main(snakemake)
