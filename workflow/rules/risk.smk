# From fragility to risk (rocking.risk): for each study with a `hazard:` in its
# configuration, the OpenQuake NRML 0.5 and pelicun exports of its fragility table, the risk
# table (mean annual frequency, return period, probability in 50 years per mode, tan α, R and
# limit state) and the risk figure. A study that also declares `stripes:` gets the same
# exports of its stripe fragility (stripe_fragility.nrml.xml / .pelicun.csv), and its stripe
# rows in risk.csv (column `fragility`), set beside the first-exceedance ones in the figure
# and the report. Studies without `hazard:` get none of these. A hazard of SA(T) takes the
# first-exceedance rows from suite_fragility.csv (the suite's fits in Sa(T)). Every requested
# row is written, with its status where there is no fit. Helpers in risk_common.smk.

from rocking.plot.risk import CAPTION as RISK_CAPTION
from rocking.fragility.bootstrap import bootstrap_path


rule risk:
    conda:
        "../envs/rocking.yaml"
    input:
        fragility=rules.fragility.output.fragility_csv,
        bootstrap=rules.fragility.output.bootstrap,  # read beside fragility.csv
        hazard=lambda wildcards: [f] if (f := hazard_file(wildcards.study)) else [],
        stripes=lambda wildcards: stripe_fragility_csv(wildcards.study),
        suite=lambda wildcards: suite_fragility_csv(wildcards.study),
        # the bootstrap samples read beside those tables: declared, so a deleted one is
        # remade (never a silent blank interval)
        stripes_bootstrap=lambda wildcards: [str(bootstrap_path(f)) for f in
                                             stripe_fragility_csv(wildcards.study)],
        suite_bootstrap=lambda wildcards: [str(bootstrap_path(f)) for f in
                                           suite_fragility_csv(wildcards.study)],
    output:
        nrml=out_path("{study}/fragility.nrml.xml"),
        pelicun=out_path("{study}/fragility.pelicun.csv"),
        table=out_path("{study}/risk.csv"),
        **_figure_output(out_path("{study}/figures/risk"), "Beyond the paper", figure="risk",
                         study="{study}"),
    params:
        caption=RISK_CAPTION,
        hazard=lambda wildcards: hazard_param(wildcards.study),
        component=lambda wildcards: hazard_component_of(wildcards.study),
        study_component=lambda wildcards: study_spec(wildcards.study).component,
        upper=lambda wildcards: search_upper(wildcards.study),
        study=lambda wildcards: wildcards.study,
        preset=lambda wildcards: study_preset(wildcards.study),
        ensemble=lambda wildcards: ensemble_of(wildcards.study),
    log:
        out_path("logs/{study}/risk.log"),
    script:
        "../scripts/risk.py"


rule stripe_risk_exports:
    conda:
        "../envs/rocking.yaml"
    input:
        stripes=rules.stripe_fragility.output.csv,
    output:
        nrml=out_path("{study}/stripe_fragility.nrml.xml"),
        pelicun=out_path("{study}/stripe_fragility.pelicun.csv"),
    params:
        upper=lambda wildcards: search_upper(wildcards.study),
        study=lambda wildcards: wildcards.study,
    log:
        out_path("logs/{study}/stripe_risk_exports.log"),
    script:
        "../scripts/stripe_risk_exports.py"


# Every column of a site: a study with `inventory:` (and `hazard:`) interpolates its own
# fragility over its grid of R and tan α at each column of the inventory and integrates it
# against the hazard curve of the column's site (rocking.risk.portfolio). The searches are
# the study's: a changed inventory reruns only these rules. Helpers in risk_common.smk.


rule critical_table:
    conda:
        "../envs/rocking.yaml"
    input:
        complete=rules.spectra.output.done,
    output:
        out_path("{study}/critical.csv"),
    params:
        store=lambda wildcards: product_store("spectra", wildcards.study),
    log:
        out_path("logs/{study}/critical_table.log"),
    script:
        "../scripts/critical_table.py"


rule portfolio:
    conda:
        "../envs/rocking.yaml"
    input:
        fragility=rules.fragility.output.fragility_csv,
        critical=rules.critical_table.output[0],  # the bootstrap refits, read beside it
        records=rules.records_table.output[0],  # the study's component, read beside it
        inventory=lambda wildcards: inventory_file(wildcards.study),
        hazard=lambda wildcards: [f] if (f := hazard_file(wildcards.study)) else [],
    output:
        table=out_path("{study}/portfolio.csv"),
        map=out_path("{study}/figures/portfolio_map.png"),
        ranked=out_path("{study}/figures/portfolio_ranked.png"),
    params:
        hazard=lambda wildcards: hazard_param(wildcards.study),
        hazard_file=lambda wildcards: hazard_file(wildcards.study) or "",
        inventory=lambda wildcards: study_spec(wildcards.study).inventory,
        study=lambda wildcards: wildcards.study,
    log:
        out_path("logs/{study}/portfolio.log"),
    script:
        "../scripts/portfolio.py"


rule exposure:
    conda:
        "../envs/rocking.yaml"
    input:
        portfolio=rules.portfolio.output.table,
    output:
        folder=directory(out_path("{study}/exposure")),
    params:
        taxonomy_by=lambda wildcards: study_spec(wildcards.study).inventory["export"],
    log:
        out_path("logs/{study}/exposure.log"),
    script:
        "../scripts/exposure.py"
