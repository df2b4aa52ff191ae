# Multiple-stripe fragility (beyond the paper): every motion of a study analysed once at each
# stripe intensity, chunked on Dask into <root>/<study>/stripes-<digest>.zarr (by the compute
# rule of every product, products.smk; the output is the completion marker), then
# fitted and set beside the first-exceedance fragility: stripe_fragility.csv and one figure
# per mode. The stripes are in the study's `stripes.measure` (PGA by default).


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


rule stripe_fragility_figure:
    input:
        table=rules.stripe_fragility.output.csv,
        refined=rules.stripe_fragility.output.refined,
        fragility=rules.fragility.output.fragility_nc,
    output:
        png=report(out_path("{study}/figures/stripe_fragility_{mode}.png"),
                   caption="../report/stripe_fragility.rst", category="Beyond the paper",
                   labels={"study": "{study}", "figure": "stripe fragility {mode}"}),
        pdf=out_path("{study}/figures/stripe_fragility_{mode}.pdf"),
        notes=out_path("{study}/figures/stripe_fragility_{mode}.json"),
    wildcard_constraints:
        mode="3d|3d-damped|3d-x|3d-y|2d-x|2d-y",
    params:
        store=lambda wildcards: product_store("stripes", wildcards.study),
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/stripe_fragility_{mode}.log"),
    script:
        "../scripts/stripe_fragility_figure.py"
