"""Every motion of a study in every measure it needs and every horizontal component
(Snakemake script): motion_measures.csv (rocking.fragility.refit.write_motion_measures)."""

from rocking.execution.logs import job
from rocking.fragility.refit import write_motion_measures


def main(snakemake):
    with job(snakemake):
        path = write_motion_measures(snakemake.input.motions, snakemake.params.measures,
                                     snakemake.output[0])
        print(f"wrote {path}")


if __name__ == "__main__":
    main(snakemake)
