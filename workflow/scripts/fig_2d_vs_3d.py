"""Fig 12 (Snakemake script): 3D versus 2D mean spectra of every configured study."""

from rocking.study.cluster import log_to
from rocking.study.figures import render


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0]):
        studies = list(zip(snakemake.params.studies, snakemake.input.means, snakemake.input.stores,
                           strict=True))
        render("fig12", [out.png, out.pdf], out.notes, studies=studies)


if __name__ == "__main__":
    main(snakemake)
