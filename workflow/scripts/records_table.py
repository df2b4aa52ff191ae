"""The per-record table and the suite's fragility of a study: records.csv, suite_fragility.csv.

rocking.study.records.write_record_tables does the work; this script checks the store first.
"""

from rocking.execution.logs import job
from rocking.store.integrity import require_intact
from rocking.study.records import write_record_tables


def main(snakemake):
    store = snakemake.params.store
    with job(snakemake):
        require_intact(store, say=print)  # a damaged chunk is never tabulated
        n_rows, n_fits = write_record_tables(store, snakemake.input.motions,
                                             snakemake.params.measures,
                                             snakemake.output.records,
                                             snakemake.output.fragility,
                                             component=snakemake.params.component)
        print(f"wrote {snakemake.output.records} ({n_rows} rows) and "
              f"{snakemake.output.fragility} ({n_fits} fits)", flush=True)


if __name__ == "__main__":
    main(snakemake)
