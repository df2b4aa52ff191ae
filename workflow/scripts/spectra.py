"""Fill a study's spectra store on Dask (resuming after the chunks already done)."""

from rocking import _json
from rocking.study import cluster, store


def main(snakemake):
    study = snakemake.wildcards.study
    with cluster.log_to(snakemake.log[0]):
        summary = cluster.fill_store(
            snakemake.input.store, store.fill_spectra_region, snakemake.input.motions,
            config_digest=snakemake.params.config_hash, n_workers=snakemake.threads,
            key=f"spectra-{study}", label=f"spectra {study}", **snakemake.params.dask)
        _json.write(snakemake.output[0], summary)


if __name__ == "__main__":
    main(snakemake)
