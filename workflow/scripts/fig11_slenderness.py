"""Fig 11 (Snakemake script): mean spectra for tan α = 0.1, 0.2, 0.3."""

from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        render("fig11_slenderness", [out.png, out.pdf], out.notes, means=snakemake.input.means,
               motions=snakemake.input.motions, paper=bool(snakemake.params.paper))


if __name__ == "__main__":
    main(snakemake)
