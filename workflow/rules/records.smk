# Ground-motion ensembles: the record (rotated to principal axes and high-passed) first, then
# Ground-motion ensembles: the record (rotated to principal axes and high-passed) first, then
# its synthetic RDK pairs; or a suite (ensembles.<name>.records): every record processed with
# its own settings first, then each record's synthetic pairs (per motion: source_record,
# kind). Written by rocking.motions.ensemble_io to
# <root>/motions/<ensemble>-<digest>.nc, the digest that of every setting of the ensemble
# (EnsembleSpec.digest): two configurations that give one ensemble name different settings
# write different files, and no study reads motions made with other settings.
# The settings, fitted RDK parameters and fit quality go to <ensemble>-<digest>.json;
# <ensemble>-<digest>.compare.nc holds the pairs of the other identification method (Fig 8);
# <ensemble>-<digest>.params.json the rounded RDK fit of every record with its digest and the
# digests of its pairs: committed as config/ensembles/<ensemble>.params.json and named by
# ensembles.<ensemble>.params, it is used instead of fitting (docs/motions.md).


rule motions:
    input:
        # recorded RDK parameters (ensembles.<name>.params): a new file makes new motions
        recorded=lambda wildcards: planned_ensemble(wildcards.ensemble, wildcards.digest)
        .get("params") or [],
    output:
        motions=out_path("motions/{ensemble}-{digest}.nc"),
        params=out_path("motions/{ensemble}-{digest}.json"),
        comparison=out_path("motions/{ensemble}-{digest}.compare.nc"),
        # the rounded RDK fits and their digests (docs/motions.md, "Recorded parameters")
        recorded=out_path("motions/{ensemble}-{digest}.params.json"),
    params:
        spec=lambda wildcards: planned_ensemble(wildcards.ensemble, wildcards.digest),
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/motions/{ensemble}-{digest}.log"),
    script:
        "../scripts/motions.py"
