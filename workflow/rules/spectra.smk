# Performance spectra: the chunked critical-intensity searches of a study on Dask, written to
# its zarr store results/<study>/spectra.zarr. The store is prepared by the rule itself (made
# anew when the configuration changes, resumed after a killed run) and is not a Snakemake
# output, so that Snakemake never deletes finished chunks; the rule's output is the
# completion marker results/<study>/spectra.done.json, which later rules take as input.


# Compilation once per machine: the kernels are compiled (or loaded from numba's cache) here,
# before any rule that runs analyses starts worker processes, so they all load them from the
# cache instead of each compiling its own copy. Its output is an ancient() input of those
# rules: ordering only, a fresh marker never reruns finished results.
rule numba_cache:
    output:
        NUMBA_CACHE,
    threads: compute_threads()
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/numba_cache.log"),
    script:
        "../scripts/numba_cache.py"


rule spectra:
    input:
        numba=ancient(rules.numba_cache.output[0]),
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        done=out_path("{study}/spectra.done.json"),
    params:
        kind="spectra",
        store=lambda wildcards: spectra_store(wildcards.study),
        # a change of any result-affecting setting changes the hash: the rule reruns and
        # makes a fresh store instead of adding results of another configuration
        spec=lambda wildcards: spectra_spec(wildcards.study),
        config_hash=lambda wildcards: spectra_hash(wildcards.study),
        # no dask options here: they cannot change a number, and a changed param reruns the
        # rule; the script reads them from the config (rocking.study.cluster.dask_options)
    threads: compute_threads()
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/spectra.log"),
    script:
        "../scripts/compute_store.py"
