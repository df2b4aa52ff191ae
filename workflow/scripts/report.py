"""Report (Snakemake script): results/<study>/report.html with every figure and the headline
numbers of the paper against this run's."""

from rocking.study.cluster import log_to
from rocking.study.report import build


def main(snakemake):
    files = [str(f) for f in snakemake.input]
    with log_to(snakemake.log[0]):
        build(
            snakemake.output[0],
            title=f"rocking: study {snakemake.params.study} "
                  f"(ensemble {snakemake.params.ensemble})",
            figures=[f for f in files if f.endswith(".png")],
            linear_fit=next(f for f in files if f.endswith("linear_fit.csv")),
            fragility=next(f for f in files if f.endswith("fragility.csv")),
        )


if __name__ == "__main__":
    main(snakemake)
