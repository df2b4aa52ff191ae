# From fragility to risk (rocking.risk): for each study with a `hazard:` in its
# configuration, the OpenQuake NRML 0.5 and pelicun exports of its fragility table, the risk
# table (mean annual frequency, return period, probability in 50 years per mode, tan α, R and
# limit state); the risk figure is drawn from it by the figure loop (figures.smk). A study that also declares `stripes:` gets the same
# exports of its stripe fragility (stripe_fragility.nrml.xml / .pelicun.csv), and its stripe
# rows in risk.csv (column `fragility`), set beside the critical-intensity ones in the figure
# and the report. Studies without `hazard:` get none of these. The fragility is taken in the
# hazard's measure and component (rocking.risk.reconcile): where they are not the vector-peak
# PGA it is refitted from each motion's critical PGA (critical.csv) and its measures
# (motion_measures.csv). Every requested row is written, with its status where there is no
# fit. Helpers in risk_common.smk.


# Every motion of a study in every intensity measure it needs, in every horizontal
# component: the ratios that refit its fragility in a hazard's terms.
rule motion_measures:
    conda:
        "../envs/rocking.yaml"
    input:
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
    output:
        out_path("{study}/motion_measures.csv"),
    params:
        measures=lambda wildcards: motion_measure_names(wildcards.study),
    log:
        out_path("logs/{study}/motion_measures.log"),
    script:
        "../scripts/motion_measures.py"

from rocking.fragility.bootstrap import bootstrap_path


rule risk:
    conda:
        "../envs/rocking.yaml"
    input:
        fragility=rules.fragility.output.fragility_csv,
        bootstrap=rules.fragility.output.bootstrap,  # read beside fragility.csv
        hazard=lambda wildcards: [f] if (f := hazard_file(wildcards.study)) else [],
        stripes=lambda wildcards: stripe_fragility_csv(wildcards.study),
        # the bootstrap samples read beside those tables: declared, so a deleted one is
        # remade (never a silent blank interval)
        stripes_bootstrap=lambda wildcards: [str(bootstrap_path(f)) for f in
                                             stripe_fragility_csv(wildcards.study)],
        # read beside fragility.csv to refit it in the hazard's measure and component
        critical=out_path("{study}/critical.csv"),
        motion_measures=out_path("{study}/motion_measures.csv"),
    output:
        nrml=out_path("{study}/fragility.nrml.xml"),
        pelicun=out_path("{study}/fragility.pelicun.csv"),
        table=out_path("{study}/risk.csv"),
    params:
        hazard=lambda wildcards: hazard_param(wildcards.study),
        study_component=lambda wildcards: study_spec(wildcards.study).component,
        upper=lambda wildcards: search_upper(wildcards.study),
        study=lambda wildcards: wildcards.study,
        preset=lambda wildcards: study_preset(wildcards.study),
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
        # the surface's nodes refitted from critical.csv in the hazard's measure and
        # component (motion_measures.csv), censored at fragility.csv's bound
        fragility=rules.fragility.output.fragility_csv,
        critical=rules.critical_table.output[0],
        motion_measures=rules.motion_measures.output[0],
        inventory=lambda wildcards: inventory_file(wildcards.study),
        hazard=lambda wildcards: [f] if (f := hazard_file(wildcards.study)) else [],
    output:
        table=out_path("{study}/portfolio.csv"),
        site=out_path("{study}/portfolio_site.csv"),
    params:
        hazard=lambda wildcards: hazard_param(wildcards.study),
        inventory=lambda wildcards: study_spec(wildcards.study).inventory,
        study_component=lambda wildcards: study_spec(wildcards.study).component,
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
