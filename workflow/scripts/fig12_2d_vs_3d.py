"""Fig 12 (Snakemake script): 3D versus 2D mean spectra of every configured study."""

from rocking.study.figures import log_to_file, render


def main(snakemake):
    out = snakemake.output
    with log_to_file(snakemake.log[0]):
        studies = list(zip(snakemake.params.studies, snakemake.input.means, snakemake.params.stores,
                           snakemake.input.motions, strict=True))
        render("fig12_2d_vs_3d", [out.png, out.pdf], out.notes, studies=studies)


if __name__ == "__main__":
    main(snakemake)
