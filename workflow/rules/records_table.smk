# The per-record table of a study (its recorded motions: PGA as recorded and processed, PGV,
# Sa(T), and per mode, tan α, limit state and R the critical PGA, the scale factor to exceed
# it, whether the record exceeds it at scale 1: one analysis) and the lognormal fragility
# over the suite in each of the study's intensity measures (recorded motions; synthetic
# pairs separately).
# rocking.study.records does the work.


rule records_table:
    input:
        complete=rules.spectra.output.done,
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        records=report(
            out_path("{study}/records.csv"),
            caption="../report/records_table.rst",
            category="Records",
            labels={"study": "{study}", "table": "per-record answers"},
        ),
        fragility=report(
            out_path("{study}/suite_fragility.csv"),
            caption="../report/records_table.rst",
            category="Records",
            labels={"study": "{study}", "table": "fragility over the suite"},
        ),
        bootstrap=out_path("{study}/suite_fragility_bootstrap.nc"),
    params:
        store=lambda wildcards: product_store("spectra", wildcards.study),
        measures=lambda wildcards: list(study_spec(wildcards.study).intensity_measures),
        component=lambda wildcards: study_spec(wildcards.study).component,
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/records_table.log"),
    script:
        "../scripts/records_table.py"
