# Fig 7 data: peak tilt over (model, R, intensity) for one motion (default: the record),
# computed by the same chunked Dask machinery into results/<study>/tilt_map.zarr.
# The store is complete when results/<study>/tilt_map.done.json exists.


rule tilt_map_store:
    input:
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        directory("results/{study}/tilt_map.zarr"),
    params:
        spec=lambda wildcards: tilt_map_spec(wildcards.study),
        config_hash=lambda wildcards: tilt_map_hash(wildcards.study),
    conda:
        "../envs/rocking.yaml"
    log:
        "logs/{study}/tilt_map_store.log",
    script:
        "../scripts/tilt_map_store.py"


rule tilt_map:
    input:
        store="results/{study}/tilt_map.zarr",
        numba=ancient(NUMBA_CACHE),
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        "results/{study}/tilt_map.done.json",
    params:
        config_hash=lambda wildcards: tilt_map_hash(wildcards.study),
        dask=dask_options(),
    threads: compute_threads()
    conda:
        "../envs/rocking.yaml"
    log:
        "logs/{study}/tilt_map.log",
    script:
        "../scripts/tilt_map.py"
