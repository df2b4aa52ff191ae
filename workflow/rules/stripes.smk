# Multiple-stripe fragility (beyond the paper): every motion of a study analysed once at each
# stripe intensity, chunked on Dask into <root>/<study>/stripes-<digest>.zarr (by the compute
# rule of every product, products.smk; the output is the completion marker), then
# fitted and set beside the critical-intensity fragility: stripe_fragility.csv (the figure
# loop of figures.smk draws one figure per mode from it). The stripes are in the study's `stripes.measure` (PGA by default); each analysis
# is jittered about its stripe by `stripes.jitter` in ln s (default 0.02), so the share of
# motions exceeding estimates the mean over motions of their local exceedance probability:
# stripe_exceedance.csv gives it at every stripe with its bootstrap interval.


# Separated fits are refined here, in-process (a few stripes: their analyses are kept in
# stripes-<digest>.refined.jsonl beside the store, so a killed job resumes; its first line
# records the store's config hash and the motions' sha256, checked on read), and every row is
# bootstrapped over the motions (stripe_fragility_bootstrap.nc, recording the table's sha256).
rule stripe_fragility:
    input:
        complete=rules.stripes.output.done,
        fragility=rules.fragility.output.fragility_nc,
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        csv=report(out_path("{study}/stripe_fragility.csv"),
                   caption="../report/stripe_fragility.rst", category="Beyond the paper",
                   labels={"study": "{study}", "table": "stripe fragility"}),
        samples=out_path("{study}/stripe_fragility_bootstrap.nc"),
        # the refined analyses the table used (the store's cache, copied whole): the figure
        # replays them from here, a declared input
        refined=out_path("{study}/stripe_fragility_refined.jsonl"),
        exceedance=out_path("{study}/stripe_exceedance.csv"),
    params:
        store=lambda wildcards: product_store("stripes", wildcards.study),
        refine=lambda wildcards: study_spec(wildcards.study).stripes.refine,
        bootstrap=lambda wildcards: study_spec(wildcards.study).stripes.bootstrap,
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/stripe_fragility.log"),
    script:
        "../scripts/stripe_fragility.py"

