# From fragility to risk (rocking.risk): for each study with a `hazard:` in its
# configuration, the OpenQuake NRML 0.5 and pelicun exports of its fragility table, the risk
# table (mean annual frequency, return period, probability in 50 years per mode, tan α, R and
# limit state) and the risk figure. Studies without `hazard:` get none of these. Helpers in
# risk_common.smk.

from rocking.study.figures.risk import CAPTION as RISK_CAPTION


rule risk:
    conda:
        "../envs/rocking.yaml"
    input:
        fragility=rules.fragility_curves.output.fragility_csv,
        hazard=lambda wildcards: [f] if (f := hazard_file(wildcards.study)) else [],
    output:
        nrml=out_path("{study}/fragility.nrml.xml"),
        pelicun=out_path("{study}/fragility.pelicun.csv"),
        table=out_path("{study}/risk.csv"),
        **_figure_output(out_path("{study}/figures/risk"), "Beyond the paper", figure="risk",
                         study="{study}"),
    params:
        caption=RISK_CAPTION,
        hazard=lambda wildcards: hazard_param(wildcards.study),
        upper=lambda wildcards: search_upper(wildcards.study),
        study=lambda wildcards: wildcards.study,
    log:
        out_path("logs/{study}/risk.log"),
    script:
        "../scripts/risk.py"
