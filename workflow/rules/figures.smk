# The paper's figures, the fragility curves and the HTML report (issue 6).
# Figures that need no study (Figs 3, 4, 6, 8, 12) go to results/figures/, the others to
# results/<study>/figures/; every figure is a PNG, a PDF and a JSON sidecar of the numbers it
# measured, which results/<study>/report.html quotes next to the paper's.

FIGURES_DIR = "results/figures"
FIG04_DURATION = 15.0  # [s]: six quasi-impacts of the quasi-rocking case (Eq 32 needs five)


def figure_files(stem):
    """PNG, PDF and JSON notes of one figure."""
    return [f"{stem}.png", f"{stem}.pdf", f"{stem}.json"]


def el_centro_ensemble():
    """First ensemble built on the El Centro record (Fig 6 uses its first motion), or None."""
    for name, spec in config["ensembles"].items():
        if spec["record"] == "el-centro-1940":
            return name
    return None


def study_ensembles():
    """Ensembles used by some study, in configuration order (one Fig 8 each)."""
    names = [study_config(s)["ensemble"] for s in config["studies"]]
    return list(dict.fromkeys(names))


def global_figure_stems():
    stems = [f"{FIGURES_DIR}/fig03_wobbling_period", f"{FIGURES_DIR}/fig04_free_vibration"]
    if el_centro_ensemble() is not None:
        stems.append(f"{FIGURES_DIR}/fig06_el_centro")
    stems += [f"{FIGURES_DIR}/fig08_motions_{e}" for e in study_ensembles()]
    stems.append(f"{FIGURES_DIR}/fig12_2d_vs_3d")
    return stems


def study_figure_stems(study):
    names = ["fig09_spectra", "fig10_goals", "fig11_slenderness", "fragility_curves"]
    if has_tilt_map(study):
        names.insert(0, "fig07_tilt_map")
    return [f"results/{study}/figures/{n}" for n in names]


def report_inputs(study):
    """Every figure (PNG + notes) and table the report of ``study`` shows."""
    stems = [s for s in global_figure_stems()
             if "fig08_motions_" not in s or s.endswith(f"_{ensemble_of(study)}")]
    stems += study_figure_stems(study)
    files = [f for s in stems for f in (f"{s}.png", f"{s}.json")]
    return files + [f"results/{study}/linear_fit.csv", f"results/{study}/fragility.csv",
                    mean_spectra(study)]


def figure_targets():
    """All figure files and one report per study (asked for by the Snakefile's rule all)."""
    targets = [f for s in global_figure_stems() for f in figure_files(s)]
    for study in config["studies"]:
        targets += [f for s in study_figure_stems(study) for f in figure_files(s)]
        targets += [f"results/{study}/fragility.nc", f"results/{study}/fragility.csv",
                    f"results/{study}/linear_fit.nc", f"results/{study}/linear_fit.csv",
                    f"results/{study}/report.html"]
    return targets


def _figure_output(stem, caption, category, **labels):
    """Named outputs png (in the snakemake report), pdf and notes of one figure."""
    return {
        "png": report(f"{stem}.png", caption=f"../report/{caption}", category=category,
                      labels=labels or None),
        "pdf": f"{stem}.pdf",
        "notes": f"{stem}.json",
    }


rule fig03_wobbling_period:
    output:
        **_figure_output(f"{FIGURES_DIR}/fig03_wobbling_period", "fig_03.rst", "Paper figures",
                         figure="Fig 3"),
    log:
        "logs/figures/fig03_wobbling_period.log",
    script:
        "../scripts/fig_wobbling_period.py"


rule fig04_free_vibration:
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
