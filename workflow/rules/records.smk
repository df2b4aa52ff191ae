# Ground-motion ensembles: the record (rotated to principal axes and high-passed) first, then
# its synthetic RDK pairs, written by rocking.motions.ensemble_io to results/motions/<ensemble>.nc;
# the settings and fitted RDK parameters go to results/motions/<ensemble>.json.


rule motions:
    output:
        motions="results/motions/{ensemble}.nc",
        params="results/motions/{ensemble}.json",
    params:
        spec=lambda wildcards: ensemble_spec(wildcards.ensemble),
    conda:
        "../envs/rocking.yaml"
    log:
        "logs/motions/{ensemble}.log",
    script:
        "../scripts/motions.py"
