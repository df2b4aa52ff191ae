# The figures, written once over their registry (rocking.plot.registry.figures(): one
# entry per figure module, declared in it; the stripe, risk and portfolio figures among them),
# the fragility tables and the HTML report; helpers in figures_common.smk. Each figure's rule
# is named after it (its entry's `rule` where a table's rule has the name) and runs the one
# script ../scripts/figure.py; its inputs and parameters come from the logical inputs its
# entry declares, its caption from its entry (handed to ../report/figure.rst as
# params.caption). A figure no study wants plans no job (figure_targets asks for none).


for fig in figures().values():

    rule:
        name:
            fig.rule_name
        wildcard_constraints:
            **({fig.per: "[^/_]+"} if fig.per else {}),
        input:
            **figure_inputs(fig),
        output:
            **figure_output(fig),
        params:
            **figure_params(fig),
        conda:
            "../envs/rocking.yaml"
        log:
            figure_log(fig),
        script:
            "../scripts/figure.py"


# The fragility of a study: lognormal MLE per point with its bootstrap over the motions, and
# the line fits of the mean spectra (the fragility curves are drawn from these by the
# figure's rule).
rule fragility:
    conda:
        "../envs/rocking.yaml"
    input:
        complete=rules.spectra.output.done,
        means=rules.mean_spectra.output.nc,
    output:
        fragility_nc=out_path("{study}/fragility.nc"),
        fragility_csv=report(out_path("{study}/fragility.csv"),
                             caption="../report/fragility_table.rst",
                             category="Beyond the paper",
                             labels={"study": "{study}", "table": "fragility"}),
        bootstrap=out_path("{study}/fragility_bootstrap.nc"),
        linear_nc=out_path("{study}/linear_fit.nc"),
        linear_csv=report(out_path("{study}/linear_fit.csv"),
                          caption="../report/linear_fit.rst", category="Beyond the paper",
                          labels={"study": "{study}", "table": "linear fits"}),
    params:
        store=lambda wildcards: product_store("spectra", wildcards.study),
        upper=lambda wildcards: search_upper(wildcards.study),
    log:
        out_path("logs/{study}/fragility.log"),
    script:
        "../scripts/fragility.py"


rule report:
    conda:
        "../envs/rocking.yaml"
    input:
        unpack(lambda wildcards: report_inputs(wildcards.study)),
    output:
        page=out_path("{study}/report.html"),
        # its verdict table as data (what the documents quoting the gallery read)
        verdicts=out_path("{study}/verdicts.csv"),
    params:
        study=lambda wildcards: wildcards.study,
        ensemble=lambda wildcards: ensemble_of(wildcards.study),
        stores=lambda wildcards: report_stores(wildcards.study)["stores"],
        tilt_maps=lambda wildcards: report_stores(wildcards.study)["tilt_maps"],
        hazard=lambda wildcards: hazard_file(wildcards.study) or hazard_spec(wildcards.study),
        reproduces=lambda wildcards: study_spec(wildcards.study).reproduces,
        paper_record=lambda wildcards: is_paper_record_study(wildcards.study),
    log:
        out_path("logs/{study}/report.log"),
    script:
        "../scripts/report.py"


# The headline cells (the paper's §5.4 number: 3D overturning, R = 10 m, tan α 0.2, every
# motion) searched for their first exceedance on 1, 0.5, 0.2 and 0.1 % grids
# (rocking.study.headline), so that the report sets the mean I10 beside the classic answer on
# each grid. Studies that reproduce the paper on its El Centro ensemble only.
rule headline:
    conda:
        "../envs/rocking.yaml"
    input:
        complete=rules.spectra.output.done,
        motions=lambda wildcards: ensemble_file(ensemble_of(wildcards.study)),
        numba=ancient(NUMBA_CACHE),
    output:
        csv=out_path("{study}/headline.csv"),
    params:
        store=lambda wildcards: product_store("spectra", wildcards.study),
    # one core: it runs beside the tables and figures that follow the spectra instead of
    # waiting for both cores to be free
    threads: 1
    priority: COMPUTE_PRIORITY["headline"]
    log:
        out_path("logs/{study}/headline.log"),
    script:
        "../scripts/headline.py"
