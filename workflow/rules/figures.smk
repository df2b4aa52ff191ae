# Rules of the paper's figures, the fragility curves and the HTML report (issue 6);
# their helper functions are in figures_common.smk.

rule fig03_wobbling_period:
    conda:
        "../envs/rocking.yaml"
    output:
        **_figure_output(f"{FIGURES_DIR}/fig03_wobbling_period", "fig_03.rst", "Paper figures",
                         figure="Fig 3"),
    log:
        "logs/figures/fig03_wobbling_period.log",
    script:
        "../scripts/fig_wobbling_period.py"


rule fig04_free_vibration:
    conda:
        "../envs/rocking.yaml"
    output:
        **_figure_output(f"{FIGURES_DIR}/fig04_free_vibration", "fig_04.rst", "Paper figures",
                         figure="Fig 4"),
    params:
        duration=FIG04_DURATION,
        model_options=lambda wildcards: damped_options(["3d-damped"]),
    log:
        "logs/figures/fig04_free_vibration.log",
    script:
        "../scripts/fig_free_vibration.py"


rule fig06_el_centro:
    conda:
        "../envs/rocking.yaml"
    input:
        motions=lambda wildcards: ensemble_file(el_centro_ensemble()),
    output:
        **_figure_output(f"{FIGURES_DIR}/fig06_el_centro", "fig_06.rst", "Paper figures",
                         figure="Fig 6"),
    params:
        model_options=lambda wildcards: damped_options(["3d-damped"]),
    log:
        "logs/figures/fig06_el_centro.log",
    script:
        "../scripts/fig_el_centro.py"


rule fig08_motions:
    conda:
        "../envs/rocking.yaml"
    input:
        motions=lambda wildcards: ensemble_file(wildcards.ensemble),
    output:
        **_figure_output(f"{FIGURES_DIR}/fig08_motions_{{ensemble}}", "fig_08.rst",
                         "Paper figures", figure="Fig 8", ensemble="{ensemble}"),
    log:
        "logs/figures/fig08_motions_{ensemble}.log",
    script:
        "../scripts/fig_motions.py"


rule fig07_tilt_map:
    conda:
        "../envs/rocking.yaml"
    input:
        store=lambda wildcards: tilt_map_store(wildcards.study),
        complete=lambda wildcards: tilt_map_complete(wildcards.study),
    output:
        **_figure_output("results/{study}/figures/fig07_tilt_map", "fig_07.rst",
                         "Paper figures", figure="Fig 7", study="{study}"),
    log:
        "logs/{study}/fig07_tilt_map.log",
    script:
        "../scripts/fig_tilt_map.py"


rule fig09_spectra:
    conda:
        "../envs/rocking.yaml"
    input:
        store=lambda wildcards: spectra_store(wildcards.study),
        complete=lambda wildcards: spectra_complete(wildcards.study),
        means=lambda wildcards: mean_spectra(wildcards.study),
    output:
        **_figure_output("results/{study}/figures/fig09_spectra", "fig_09.rst",
                         "Paper figures", figure="Fig 9", study="{study}"),
    log:
        "logs/{study}/fig09_spectra.log",
    script:
        "../scripts/fig_spectra.py"


rule fig10_goals:
    conda:
        "../envs/rocking.yaml"
    input:
        means=lambda wildcards: mean_spectra(wildcards.study),
    output:
        **_figure_output("results/{study}/figures/fig10_goals", "fig_10.rst",
                         "Paper figures", figure="Fig 10", study="{study}"),
    log:
        "logs/{study}/fig10_goals.log",
    script:
        "../scripts/fig_goals.py"


rule fig11_slenderness:
    conda:
        "../envs/rocking.yaml"
    input:
        means=lambda wildcards: mean_spectra(wildcards.study),
    output:
        **_figure_output("results/{study}/figures/fig11_slenderness", "fig_11.rst",
                         "Paper figures", figure="Fig 11", study="{study}"),
    log:
        "logs/{study}/fig11_slenderness.log",
    script:
        "../scripts/fig_slenderness.py"


rule fig12_2d_vs_3d:
    conda:
        "../envs/rocking.yaml"
    input:
        means=[mean_spectra(s) for s in config["studies"]],
        stores=[spectra_store(s) for s in config["studies"]],
    output:
        **_figure_output(f"{FIGURES_DIR}/fig12_2d_vs_3d", "fig_12.rst", "Paper figures",
                         figure="Fig 12"),
    params:
        studies=list(config["studies"]),
    log:
        "logs/figures/fig12_2d_vs_3d.log",
    script:
        "../scripts/fig_2d_vs_3d.py"


rule fragility:
    conda:
        "../envs/rocking.yaml"
    input:
        store=lambda wildcards: spectra_store(wildcards.study),
        complete=lambda wildcards: spectra_complete(wildcards.study),
        means=lambda wildcards: mean_spectra(wildcards.study),
    output:
        fragility_nc="results/{study}/fragility.nc",
        fragility_csv=report("results/{study}/fragility.csv", caption="../report/fig_fragility_table.rst",
                             category="Beyond the paper", labels={"study": "{study}",
                                                                  "table": "fragility"}),
        linear_nc="results/{study}/linear_fit.nc",
        linear_csv=report("results/{study}/linear_fit.csv", caption="../report/fig_linear_fit.rst",
                          category="Beyond the paper", labels={"study": "{study}",
                                                               "table": "linear fits"}),
        **_figure_output("results/{study}/figures/fragility_curves", "fig_fragility.rst",
                         "Beyond the paper", figure="fragility", study="{study}"),
    params:
        upper=float(config["search"]["upper"]),
    log:
        "logs/{study}/fragility.log",
    script:
        "../scripts/fig_fragility.py"


rule report_html:
    conda:
        "../envs/rocking.yaml"
    input:
        lambda wildcards: report_inputs(wildcards.study),
    output:
        "results/{study}/report.html",
    params:
        study=lambda wildcards: wildcards.study,
        ensemble=lambda wildcards: ensemble_of(wildcards.study),
    log:
        "logs/{study}/report.log",
    script:
        "../scripts/report.py"
