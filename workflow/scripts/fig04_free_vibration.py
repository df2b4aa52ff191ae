"""Fig 4 (Snakemake script): free vibration of the R = 6 m, tan α = 0.2 cylinder,
undamped and damped for the paper's eight contact parameters."""

from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        render("fig04_free_vibration", [out.png, out.pdf], out.notes,
               duration=float(snakemake.params.duration), **snakemake.params.model_options)


if __name__ == "__main__":
    main(snakemake)
