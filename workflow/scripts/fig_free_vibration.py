"""Fig 4 (Snakemake script): free vibration of the R = 6 m, tan α = 0.2 cylinder."""

from rocking.study.cluster import log_to
from rocking.study.figures import render


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0]):
        render("fig04", [out.png, out.pdf], out.notes, duration=float(snakemake.params.duration),
               **snakemake.params.model_options)


if __name__ == "__main__":
    main(snakemake)
