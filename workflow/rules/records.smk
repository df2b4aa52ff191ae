# Ground-motion ensembles: the record (rotated to principal axes and high-passed) first, then
# its synthetic RDK pairs; or a suite (ensembles.<name>.records): every record processed with
# its own settings first, then each record's synthetic pairs. Written by
# rocking.motions.ensemble_io to results/motions/<ensemble>.nc (per motion: source_record,
# kind);
# the settings, fitted RDK parameters and fit quality go to results/motions/<ensemble>.json.
# <ensemble>.compare.nc holds the pairs of the other identification method (Fig 8 only).


rule motions:
    output:
        motions="results/motions/{ensemble}.nc",
        params="results/motions/{ensemble}.json",
        comparison="results/motions/{ensemble}.compare.nc",
    params:
        spec=lambda wildcards: ensemble_spec(wildcards.ensemble),
    conda:
        "../envs/rocking.yaml"
    log:
        "logs/motions/{ensemble}.log",
    script:
        "../scripts/motions.py"
