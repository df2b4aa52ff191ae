"""Fig 9 (Snakemake script): per-motion performance spectra, their means, damped − undamped."""

from rocking.study.figures import log_to_file, render


def main(snakemake):
    out = snakemake.output
    with log_to_file(snakemake.log[0]):
        render("fig09_spectra", [out.png, out.pdf], out.notes, store=snakemake.params.store,
               means=snakemake.input.means, motions=snakemake.input.motions)


if __name__ == "__main__":
    main(snakemake)
