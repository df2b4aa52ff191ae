# Rules of the paper's figures, the fragility curves and the HTML report; helpers in
# figures_common.smk. Each rule is named after its figure: module rocking.plot.<name>,
# script ../scripts/<name>.py, caption rocking.plot.captions.CAPTIONS[<name>] (handed
# to ../report/figure.rst as params.caption; a function, so its braces are not wildcards).


rule fig03_wobbling_period:
    conda:
        "../envs/rocking.yaml"
    output:
        **_figure_output(f"{FIGURES_DIR}/fig03_wobbling_period", "Paper figures",
                         figure="Fig 3"),
    params:
        caption=lambda wildcards: caption("fig03_wobbling_period"),
    log:
        out_path("logs/figures/fig03_wobbling_period.log"),
    script:
        "../scripts/fig03_wobbling_period.py"


rule fig04_free_vibration:
    conda:
        "../envs/rocking.yaml"
    input:
        numba=ancient(NUMBA_CACHE),
    output:
        **_figure_output(f"{FIGURES_DIR}/fig04_free_vibration", "Paper figures",
                         figure="Fig 4"),
    params:
        caption=lambda wildcards: caption("fig04_free_vibration"),
        duration=FIG04_DURATION,
        # the study's contact parameters; the figure adds the paper's eight pairs
        model_options=lambda wildcards: damped_options(["3d-damped"]),
    log:
        out_path("logs/figures/fig04_free_vibration.log"),
    script:
        "../scripts/fig04_free_vibration.py"


rule fig06_theta_max_sensitivity:
    conda:
        "../envs/rocking.yaml"
    input:
        numba=ancient(NUMBA_CACHE),
    output:
        **_figure_output(global_stem("fig06_theta_max_sensitivity"), "Paper figures",
                         figure="Fig 6 (companion)"),
    params:
        caption=lambda wildcards: caption("fig06_theta_max_sensitivity"),
        spec=lambda wildcards: ensemble_spec(el_centro_ensemble()),
        model_options=lambda wildcards: damped_options(["3d-damped"]),
    log:
        global_log("fig06_theta_max_sensitivity"),
    script:
        "../scripts/fig06_theta_max_sensitivity.py"


rule fig06_el_centro:
    conda:
        "../envs/rocking.yaml"
    input:
        motions=lambda wildcards: ensemble_file(el_centro_ensemble()),
        sensitivity=rules.fig06_theta_max_sensitivity.output.notes,
        numba=ancient(NUMBA_CACHE),
    output:
        **_figure_output(global_stem("fig06_el_centro"), "Paper figures", figure="Fig 6"),
    params:
        caption=lambda wildcards: caption("fig06_el_centro"),
        model_options=lambda wildcards: damped_options(["3d-damped"]),
    log:
        global_log("fig06_el_centro"),
    script:
        "../scripts/fig06_el_centro.py"


rule fig07_tilt_map:
    conda:
        "../envs/rocking.yaml"
    input:
        complete=rules.tilt_map.output.done,
        motions=lambda wildcards: study_motions(wildcards.study),
    output:
        **_figure_output(out_path("{study}/figures/fig07_tilt_map"), "Paper figures",
                         figure="Fig 7", study="{study}"),
    params:
        caption=lambda wildcards: caption("fig07_tilt_map", reproduces_paper(wildcards.study)),
        store=lambda wildcards: product_store("tilt_map", wildcards.study),
    log:
        out_path("logs/{study}/fig07_tilt_map.log"),
    script:
        "../scripts/fig07_tilt_map.py"


rule fig08_motions:
    conda:
        "../envs/rocking.yaml"
    input:
        motions=lambda wildcards: ensemble_files(wildcards.ensemble),
        comparison=lambda wildcards: ensemble_files(wildcards.ensemble, "comparison"),
    output:
        **_figure_output(f"{FIGURES_DIR}/fig08_motions_{{ensemble}}", "Paper figures",
                         figure="Fig 8", ensemble="{ensemble}"),
    params:
        caption=lambda wildcards: caption("fig08_motions", reproduces_paper()),
        paper=lambda wildcards: reproduces_paper(),
    log:
        out_path("logs/figures/fig08_motions_{ensemble}.log"),
    script:
        "../scripts/fig08_motions.py"


rule fig09_spectra:
    conda:
        "../envs/rocking.yaml"
    input:
        complete=rules.spectra.output.done,
        means=rules.mean_spectra.output.nc,
        motions=lambda wildcards: study_motions(wildcards.study),
        # read beside the means: the legend says how far refinement moves the answers
        refinement=rules.refinement_sample.output.csv,
    output:
        **_figure_output(out_path("{study}/figures/fig09_spectra"), "Paper figures",
                         figure="Fig 9", study="{study}"),
    params:
        caption=lambda wildcards: caption("fig09_spectra", reproduces_paper(wildcards.study)),
        store=lambda wildcards: product_store("spectra", wildcards.study),
        paper=lambda wildcards: reproduces_paper(wildcards.study),
    log:
        out_path("logs/{study}/fig09_spectra.log"),
    script:
        "../scripts/fig09_spectra.py"


rule fig10_goals:
    conda:
        "../envs/rocking.yaml"
    input:
        means=rules.mean_spectra.output.nc,
        motions=lambda wildcards: study_motions(wildcards.study),
        refinement=rules.refinement_sample.output.csv,  # read beside the means (legend)
    output:
        **_figure_output(out_path("{study}/figures/fig10_goals"), "Paper figures",
                         figure="Fig 10", study="{study}"),
    params:
        caption=lambda wildcards: caption("fig10_goals", reproduces_paper(wildcards.study)),
        paper=lambda wildcards: reproduces_paper(wildcards.study),
    log:
        out_path("logs/{study}/fig10_goals.log"),
    script:
        "../scripts/fig10_goals.py"


rule fig11_slenderness:
    conda:
        "../envs/rocking.yaml"
    input:
        means=rules.mean_spectra.output.nc,
        motions=lambda wildcards: study_motions(wildcards.study),
    output:
        **_figure_output(out_path("{study}/figures/fig11_slenderness"), "Paper figures",
                         figure="Fig 11", study="{study}"),
    params:
        caption=lambda wildcards: caption("fig11_slenderness", reproduces_paper(wildcards.study)),
        paper=lambda wildcards: reproduces_paper(wildcards.study),
    log:
        out_path("logs/{study}/fig11_slenderness.log"),
    script:
        "../scripts/fig11_slenderness.py"


rule fig12_2d_vs_3d:
    conda:
        "../envs/rocking.yaml"
    input:
        means=[mean_spectra(s) for s in fig12_studies()],
        complete=[product_complete("spectra", s) for s in fig12_studies()],
        motions=[study_motions(s) for s in fig12_studies()],
        # read beside the means: the censoring-aware medians of the 2D/3D verdicts and the
        # refinement sample of the legend
        fragility=[out_path(f"{s}/fragility.csv") for s in fig12_studies()],
        refinement=[out_path(f"{s}/refinement_sample.csv") for s in fig12_studies()],
    output:
        **_figure_output(global_stem("fig12_2d_vs_3d"), "Paper figures", figure="Fig 12"),
    params:
        caption=lambda wildcards: caption("fig12_2d_vs_3d", reproduces_paper()),
        studies=fig12_studies(),
        stores=[product_store("spectra", s) for s in fig12_studies()],
        paper=reproduces_paper(),
    log:
        global_log("fig12_2d_vs_3d"),
    script:
        "../scripts/fig12_2d_vs_3d.py"


rule fragility_curves:
    conda:
        "../envs/rocking.yaml"
    input:
        complete=rules.spectra.output.done,
        means=rules.mean_spectra.output.nc,
        motions=lambda wildcards: study_motions(wildcards.study),
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
        **_figure_output(out_path("{study}/figures/fragility_curves"), "Beyond the paper",
                         figure="fragility", study="{study}"),
    params:
        caption=lambda wildcards: caption("fragility_curves", reproduces_paper(wildcards.study)),
        store=lambda wildcards: product_store("spectra", wildcards.study),
        upper=lambda wildcards: search_upper(wildcards.study),
    log:
        out_path("logs/{study}/fragility_curves.log"),
    script:
        "../scripts/fragility_curves.py"


rule report:
    conda:
        "../envs/rocking.yaml"
    input:
        unpack(lambda wildcards: report_inputs(wildcards.study)),
    output:
        out_path("{study}/report.html"),
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
