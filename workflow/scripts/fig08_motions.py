"""Fig 8 (Snakemake script): traces and 5 %-damped PSA spectra of one ensemble, with the
pairs of the other identification method beside it."""

from rocking.motions.ensemble_io import load_ensemble
from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        render("fig08_motions", [out.png, out.pdf], out.notes,
               motions=load_ensemble(snakemake.input.motions),
               comparison=load_ensemble(snakemake.input.comparison),
               paper=bool(snakemake.params.get("paper", True)))


if __name__ == "__main__":
    main(snakemake)
