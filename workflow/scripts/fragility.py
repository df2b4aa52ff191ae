"""Fragility of a study (Snakemake script): lognormal MLE per point with its bootstrap over
the motions, line fits of the mean spectra."""

import time

from rocking.execution.logs import job
from rocking.fragility import lognormal as fragility
from rocking.fragility.table import CRITICAL_INTENSITY, quantity_of, write_fragilities
from rocking.motions.measures import DEFAULT_COMPONENT
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
        # the table with what it is in (estimator, measure, component, unit, quantity),
        # then its samples, whose record says they belong to it
        write_fragilities(fragility.to_frame(table), out.fragility_csv,
                          estimator=CRITICAL_INTENSITY, measure="pga", component=DEFAULT_COMPONENT,
                          quantity=quantity_of(store.attrs), samples=samples)
        lines = fragility.linear_fit_table(open_means(snakemake.input.means))
        lines.to_netcdf(out.linear_nc)
        fragility.to_frame(lines).to_csv(out.linear_csv, index=False, float_format="%.10g")


if __name__ == "__main__":
    main(snakemake)
