"""Fig 7 (Snakemake script): θmax/α contours from results/<study>/tilt_map.zarr."""

from rocking.study.cluster import log_to
from rocking.study.figures import render


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0]):
        render("fig07", [out.png, out.pdf], out.notes, path=snakemake.input.store)


if __name__ == "__main__":
    main(snakemake)
