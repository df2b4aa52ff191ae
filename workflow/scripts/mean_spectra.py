"""Ensemble statistics of a study's spectra: mean_spectra.nc and mean_spectra.csv."""

import xarray as xr

from rocking.execution.logs import job
from rocking.store.integrity import require_intact
from rocking.study.aggregate import ensemble_statistics, write_statistics


def main(snakemake):
    store = snakemake.params.store
    with job(snakemake):
        require_intact(store, say=print)  # a damaged chunk is never aggregated into other numbers
        with xr.open_zarr(store, consolidated=True) as ds:
            stats = ensemble_statistics(ds)
        write_statistics(stats, snakemake.output.nc, snakemake.output.csv)
        print(f"wrote {snakemake.output.nc} and {snakemake.output.csv}: "
              f"{dict(stats.sizes)}", flush=True)


if __name__ == "__main__":
    main(snakemake)
