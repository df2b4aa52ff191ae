# The compute rule of every product of a study (rocking.execution.products.PRODUCTS: the
# performance spectra, the Fig 7 tilt map, the stripes), written once: the chunked analyses
# of a study on Dask, written to its zarr store <root>/<study>/<product>-<digest>.zarr
# (<product>.zarr links to the latest). The store is prepared by the rule itself (created for
# a new configuration, resumed after a killed run or when an earlier configuration comes
# back) and is not a Snakemake output, so that Snakemake never deletes finished chunks; the
# rule's output is the completion marker <root>/<study>/<product>.done.json, which later
# rules take as input.


# The order of the jobs when several are ready (Snakemake runs the highest priority first):
# the searches of the spectra are the run's longest chain, and a rule that takes every core
# waits until all are free, so the compute rules go before the figures and tables that can
# fill the gaps beside them. Scheduling only: no number depends on it.
COMPUTE_PRIORITY = {"numba_cache": 60, "spectra": 50, "stripes": 40, "tilt_map": 40,
                    "headline": 30}


# Compilation once per machine: the kernels are compiled (or loaded from numba's cache) here,
# before any rule that runs analyses starts worker processes, so they all load them from the
# cache instead of each compiling its own copy. Its output is an ancient() input of those
# rules: ordering only, a fresh marker never reruns finished results.
rule numba_cache:
    output:
        NUMBA_CACHE,
    threads: compute_threads()
    priority: COMPUTE_PRIORITY["numba_cache"]
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/numba_cache.log"),
    script:
        "../scripts/numba_cache.py"


for kind in PRODUCTS:

    rule:
        name:
            kind
        input:
            numba=ancient(rules.numba_cache.output[0]),
            motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
        output:
            done=out_path(f"{{study}}/{kind}.done.json"),
        params:
            kind=kind,
            store=product_param(product_store, kind),
            # a change of any result-affecting setting changes the hash and the store's name:
            # the rule reruns in another store (or resumes an earlier one) instead of mixing
            # results. Short parameters only (the script rebuilds the spec from the config and
            # checks its hash); no dask options: they cannot change a number, and a changed
            # param reruns
            config_hash=product_param(product_hash, kind),
        threads: compute_threads()
        priority: COMPUTE_PRIORITY.get(kind, 0)
        conda:
            "../envs/rocking.yaml"
        log:
            out_path(f"logs/{{study}}/{kind}.log"),
        script:
            "../scripts/compute_store.py"
