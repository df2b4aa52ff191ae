"""Stripe fragility table (Snakemake script): the binomial lognormal fit of every (mode, limit
state, R) of the stripes store beside the first-exceedance fit of the spectra."""

import xarray as xr

from rocking.study.logs import log_to
from rocking.study.stripes import stripe_table
from rocking.units import header


def main(snakemake):
    with log_to(snakemake.log[0]):
        with xr.open_dataset(snakemake.input.fragility) as f:
            first = f.load()
        table = stripe_table(xr.open_zarr(snakemake.params.store, consolidated=True), first)
        table.rename(columns=header).to_csv(snakemake.output.csv, index=False,
                                            float_format="%.10g")


if __name__ == "__main__":
    main(snakemake)
