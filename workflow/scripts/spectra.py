"""Fill a study's spectra store on Dask (resuming after the chunks already done)."""

import json

from rocking.study import cluster, store


def main(snakemake):
    with cluster.log_to(snakemake.log[0]):
        summary = cluster.fill_store(
            snakemake.input.store, store.fill_spectra_region, snakemake.input.motions,
            config_digest=snakemake.params.config_hash, n_workers=snakemake.threads,
            key=f"spectra-{snakemake.wildcards.study}", **snakemake.params.dask)
    with open(snakemake.output[0], "w") as fh:
        json.dump(summary, fh, indent=2)


if __name__ == "__main__":
    main(snakemake)
