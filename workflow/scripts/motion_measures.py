"""Every motion of a study in every measure it needs and every horizontal component
(Snakemake script): motion_measures.csv (rocking.fragility.refit.write_motion_measures)."""

from rocking.execution.logs import log_to
from rocking.fragility.refit import write_motion_measures


def main(snakemake):
    with log_to(snakemake.log[0], outputs=snakemake.output):
        path = write_motion_measures(snakemake.input.motions, snakemake.params.measures,
                                     snakemake.output[0])
        print(f"wrote {path}")


if __name__ == "__main__":
    main(snakemake)
