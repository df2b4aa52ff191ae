"""Spectra or tilt-map rule: prepare the study's store (resume in it, or make it anew for a
new configuration), fill it on Dask, write the completion marker (the rule's output)."""

from rocking import _json
from rocking.study import logs, prepare
from rocking.study.cluster import dask_options


def main(snakemake):
    p = snakemake.params
    with logs.log_to(snakemake.log[0]):
        summary = prepare.compute(
            p.kind, p.store, p.spec, p.config_hash, snakemake.input.motions,
            n_workers=snakemake.threads, key=f"{p.kind}-{snakemake.wildcards.study}",
            label=f"{p.kind.replace('_', ' ')} {snakemake.wildcards.study}",
            **dask_options(snakemake.config))
        _json.write(snakemake.output.done, summary)


if __name__ == "__main__":
    main(snakemake)
