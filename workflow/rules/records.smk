# Ground-motion ensembles: the record (rotated to principal axes and high-passed) first, then
# its synthetic RDK pairs, written by rocking.motions.ensemble_io to
# results/motions/<ensemble>.nc;
# the settings, fitted RDK parameters and fit quality go to results/motions/<ensemble>.json.
# <ensemble>.compare.nc holds the pairs of the other identification method (Fig 8 only).


rule motions:
    output:
        motions=out_path("motions/{ensemble}.nc"),
        params=out_path("motions/{ensemble}.json"),
        comparison=out_path("motions/{ensemble}.compare.nc"),
    params:
        spec=lambda wildcards: ensemble_spec(wildcards.ensemble),
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/motions/{ensemble}.log"),
    script:
        "../scripts/motions.py"
