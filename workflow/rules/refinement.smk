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
