"""Fig 10 (Snakemake script): mean spectra for every performance goal."""

from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        render("fig10_goals", [out.png, out.pdf], out.notes, means=snakemake.input.means,
               motions=snakemake.input.motions, paper=bool(snakemake.params.paper))


if __name__ == "__main__":
    main(snakemake)
