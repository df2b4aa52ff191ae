"""Companion to Fig 6 (Snakemake script): θmax versus scale factor per version of the
El Centro record, read as recorded and processed like the ensemble."""

from rocking.motions.build import read_motion
from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        spec = snakemake.params.spec
        render("fig06_theta_max_sensitivity", [out.png, out.pdf], out.notes,
               record=read_motion(spec["record"], spec["paths"]), mw=spec["mw"],
               max_duration=spec["max_duration"],
               **snakemake.params.model_options)


if __name__ == "__main__":
    main(snakemake)
