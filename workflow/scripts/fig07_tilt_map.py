"""Fig 7 (Snakemake script): θmax/α contours from results/<study>/tilt_map.zarr."""

from rocking.plot import render
from rocking.study.logs import log_to


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        render("fig07_tilt_map", [out.png, out.pdf], out.notes, path=snakemake.params.store,
               motions=snakemake.input.motions)


if __name__ == "__main__":
    main(snakemake)
