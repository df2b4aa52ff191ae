"""Fig 9 (Snakemake script): per-motion performance spectra and their mean."""

from rocking.study.cluster import log_to
from rocking.study.figures import render


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0]):
        render("fig09", [out.png, out.pdf], out.notes, store=snakemake.input.store,
               means=snakemake.input.means)


if __name__ == "__main__":
    main(snakemake)
