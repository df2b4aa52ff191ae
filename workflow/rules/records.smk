# Ground-motion ensembles: the record (rotated to principal axes and high-passed) first, then
# its synthetic RDK pairs, written by rocking.ensemble_io to results/motions/<ensemble>.nc.


rule motions:
    output:
        "results/motions/{ensemble}.nc",
    params:
        spec=lambda wildcards: ensemble_spec(wildcards.ensemble),
    conda:
        "../envs/rocking.yaml"
    log:
        "logs/motions/{ensemble}.log",
    script:
        "../scripts/motions.py"
