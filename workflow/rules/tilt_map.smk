# Fig 7 data: peak tilt over (mode, R, intensity) for one motion (default: the record),
# computed by the same chunked Dask machinery into <root>/<study>/tilt_map-<digest>.zarr,
# prepared and resumed like the spectra store (spectra.smk); the output is the completion
# marker.


rule tilt_map:
    input:
        numba=ancient(rules.numba_cache.output[0]),
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        done=out_path("{study}/tilt_map.done.json"),
    params:
        kind="tilt_map",
        store=lambda wildcards: tilt_map_store(wildcards.study),
        config_hash=lambda wildcards: tilt_map_hash(wildcards.study),
    threads: compute_threads()
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/tilt_map.log"),
    script:
        "../scripts/compute_store.py"
