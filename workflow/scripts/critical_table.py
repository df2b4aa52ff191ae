"""Every answer of a study's spectra store as one table (Snakemake script): critical.csv."""

from rocking.execution.logs import job
from rocking.study.aggregate import write_critical_table


def main(snakemake):
    with job(snakemake):
        write_critical_table(snakemake.params.store, snakemake.output[0])


if __name__ == "__main__":
    main(snakemake)
