"""Fig 3 (Snakemake script): wobbling period versus tilt, closed forms only."""

from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        render("fig03_wobbling_period", [out.png, out.pdf], out.notes)


if __name__ == "__main__":
    main(snakemake)
