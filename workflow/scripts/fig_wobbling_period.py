"""Fig 3 (Snakemake script): wobbling period versus tilt, closed forms only."""

from rocking.study.cluster import log_to
from rocking.study.figures import render


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0]):
        render("fig03", [out.png, out.pdf], out.notes)


if __name__ == "__main__":
    main(snakemake)
