# How far a study's answers move under refinement (rocking.study.refinement): a stated sample
# of its answered cells (k per mode and limit state, seeded, and every cell of the headline
# mean) searched again with a fixed 0.05 % scan from uplift to the answer, with the study's
# own tolerances; cost capped per point (config `refinement:`). The report's findings and
# Figs 9, 10 and 12 quote the shifts beside their numbers.


rule refinement_sample:
    input:
        complete=rules.spectra.output.done,
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
        numba=ancient(NUMBA_CACHE),
    output:
        csv=out_path("{study}/refinement_sample.csv"),
    params:
        store=lambda wildcards: product_store("spectra", wildcards.study),
        refinement=lambda wildcards: dict(config.get("refinement") or {}),
    threads: compute_threads()
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/refinement_sample.log"),
    script:
        "../scripts/refinement_sample.py"


# λ under refinement: the fragility of every point holding a refined cell fitted again with
# the refined answers substituted (the study's fit) and integrated with the study's hazard
# curve (risk.csv's function). Studies with a `hazard:` only; the report quotes the shift.
rule refinement_risk:
    input:
        complete=rules.spectra.output.done,
        sample=rules.refinement_sample.output.csv,
        hazard=lambda wildcards: [f] if (f := hazard_file(wildcards.study)) else [],
    output:
        csv=out_path("{study}/refinement_risk.csv"),
    params:
        store=lambda wildcards: product_store("spectra", wildcards.study),
        hazard=lambda wildcards: hazard_param(wildcards.study),
        component=lambda wildcards: hazard_component_of(wildcards.study),
        study_component=lambda wildcards: study_spec(wildcards.study).component,
        upper=lambda wildcards: search_upper(wildcards.study),
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/refinement_risk.log"),
    script:
        "../scripts/refinement_risk.py"
