"""Every answer of a study's spectra store as one table (Snakemake script): critical.csv."""

from rocking.execution.logs import log_to
from rocking.study.aggregate import write_critical_table


def main(snakemake):
    with log_to(snakemake.log[0], outputs=snakemake.output):
        write_critical_table(snakemake.params.store, snakemake.output[0])


if __name__ == "__main__":
    main(snakemake)
