"""Fig 9 (Snakemake script): per-motion performance spectra, their means, damped − undamped."""

from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        render("fig09_spectra", [out.png, out.pdf], out.notes, store=snakemake.params.store,
               means=snakemake.input.means, motions=snakemake.input.motions,
               paper=bool(snakemake.params.get("paper", True)))


if __name__ == "__main__":
    main(snakemake)
