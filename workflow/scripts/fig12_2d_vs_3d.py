"""Fig 12 (Snakemake script): 3D versus 2D mean spectra of every configured study."""

from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        studies = list(zip(snakemake.params.studies, snakemake.input.means, snakemake.params.stores,
                           snakemake.input.motions, strict=True))
        render("fig12_2d_vs_3d", [out.png, out.pdf], out.notes, studies=studies,
               paper=bool(snakemake.params.paper))


if __name__ == "__main__":
    main(snakemake)
