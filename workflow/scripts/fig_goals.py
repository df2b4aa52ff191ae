"""Fig 10 (Snakemake script): mean spectra for every performance goal."""

from rocking.study.cluster import log_to
from rocking.study.figures import render


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0]):
        render("fig10", [out.png, out.pdf], out.notes, means=snakemake.input.means)


if __name__ == "__main__":
    main(snakemake)
