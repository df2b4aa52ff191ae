"""Compute rule of a product (spectra, tilt map, stripes: rocking.execution.products): prepare the
study's store (resume in it, or make it anew for a new configuration), fill it on Dask, write
the completion marker (the rule's output)."""

from rocking import _json
from rocking.execution import logs, products
from rocking.execution.cluster import dask_options


def main(snakemake):
    p = snakemake.params
    study = snakemake.wildcards.study
    with logs.job(snakemake):
        spec = products.planned_spec(snakemake.config, study, p.kind, p.config_hash)
        summary = products.compute(
            p.kind, p.store, spec, p.config_hash, snakemake.input.motions,
            n_workers=snakemake.threads, key=f"{p.kind}-{study}",
            label=f"{p.kind.replace('_', ' ')} {study}", **dask_options(snakemake.config))
        _json.write(snakemake.output.done, {**summary, "store": str(p.store)})


if __name__ == "__main__":
    main(snakemake)
