# Performance spectra: an empty zarr store per study (its own rule, so that a killed
# computation resumes in it), then the chunked critical-intensity searches on Dask.
# The store is complete when results/<study>/spectra.done.json exists.


rule spectra_store:
    input:
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        directory("results/{study}/spectra.zarr"),
    params:
        # a change of any result-affecting setting changes the hash, which reruns this rule
        # (a fresh store) instead of adding results of another configuration
        spec=lambda wildcards: spectra_spec(wildcards.study),
        config_hash=lambda wildcards: spectra_hash(wildcards.study),
    conda:
        "../envs/rocking.yaml"
    log:
        "logs/{study}/spectra_store.log",
    script:
        "../scripts/spectra_store.py"


rule spectra:
    input:
        store="results/{study}/spectra.zarr",
        numba=ancient(NUMBA_CACHE),
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        "results/{study}/spectra.done.json",
    params:
        config_hash=lambda wildcards: spectra_hash(wildcards.study),
        dask=dask_options(),
    threads: compute_threads()
    conda:
        "../envs/rocking.yaml"
    log:
        "logs/{study}/spectra.log",
    script:
        "../scripts/spectra.py"


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
        "logs/numba_cache.log",
    script:
        "../scripts/numba_cache.py"
