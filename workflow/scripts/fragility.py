"""Fragility of a study (Snakemake script): lognormal MLE per point with its bootstrap over
the motions, line fits of the mean spectra."""

import time

from rocking.execution.logs import job
from rocking.fragility import lognormal as fragility
from rocking.fragility.bootstrap import write_bootstrap
from rocking.plot import open_means, open_store


def main(snakemake):
    out = snakemake.output
    with job(snakemake):
        store = open_store(snakemake.params.store)
        upper = float(snakemake.params.upper)
        table = fragility.fragility_table(store, upper=upper)
        started = time.perf_counter()
        samples = fragility.fragility_bootstrap(store, table, upper=upper)
        print(f"bootstrap of the fragility over the motions: {samples.sizes['resample']} "
              f"resamples of {samples.sizes['row']} rows in "
              f"{time.perf_counter() - started:.1f} s")
        table = fragility.with_interval(table, samples)
        table.to_netcdf(out.fragility_nc)
        fragility.to_frame(table).to_csv(out.fragility_csv, index=False, float_format="%.10g")
        # after the table: the samples record that they belong to it
        write_bootstrap(samples, out.bootstrap, table=out.fragility_csv)
        lines = fragility.linear_fit_table(open_means(snakemake.input.means))
        lines.to_netcdf(out.linear_nc)
        fragility.to_frame(lines).to_csv(out.linear_csv, index=False, float_format="%.10g")


if __name__ == "__main__":
    main(snakemake)
