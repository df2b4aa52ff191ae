# The paper's figures, the fragility curves and the HTML report: paths and helpers.
# Figures that need no study (Figs 3, 4, 6, 8, 12) go to results/figures/, the others to
# results/<study>/figures/; every figure is a PNG, a PDF and a JSON sidecar of the numbers it
# measured, which results/<study>/report.html sets against the paper's. A figure's name is its
# module in rocking.study.figures, its rule, its script and its caption key.

from rocking.study.figures.captions import caption

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


def study_motions(study):
    """The ensemble file of a study (figures read the physical directions of x and y there)."""
    return ensemble_file(ensemble_of(study))


def reproduces_paper(study=None):
    """Whether ``study`` (default: any study) is declared a reproduction of the paper
    (``studies.<name>.reproduces``): only then are the paper's model figures drawn."""
    studies = config["studies"] if study is None else [study]
    return any(study_spec(s).reproduces is not None for s in studies)


def fig12_studies():
    """Studies that run "3d" and a 2D mode at a common tan α (the curves of Fig 12)."""
    return [s for s in config["studies"] if study_plan(s).compares_2d_with_3d()]


PAPER_MODEL_FIGURES = ("fig03_wobbling_period", "fig04_free_vibration", "fig06_el_centro",
                       "fig06_theta_max_sensitivity")
"""The paper's figures of the model itself, drawn only for a reproduction of the paper."""


def global_figure_stems():
    """Figures beside the studies: the paper's model figures (Figs 3, 4, 6) for a
    reproduction of the paper, Fig 8 per ensemble, Fig 12 where some study has 3D and 2D."""
    stems = []
    if reproduces_paper():
        stems += [f"{FIGURES_DIR}/fig03_wobbling_period", f"{FIGURES_DIR}/fig04_free_vibration"]
        if el_centro_ensemble() is not None:
            stems += [f"{FIGURES_DIR}/fig06_el_centro",
                      f"{FIGURES_DIR}/fig06_theta_max_sensitivity"]
    stems += [f"{FIGURES_DIR}/fig08_motions_{e}" for e in study_ensembles()]
    if fig12_studies():
        stems.append(f"{FIGURES_DIR}/fig12_2d_vs_3d")
    return stems


def study_figure_stems(study):
    """The study's figures that its runs have data for (StudyPlan.figures), and Fig 7."""
    names = study_plan(study).figures()
    if has_tilt_map(study):
        names.insert(0, "fig07_tilt_map")
    return [f"results/{study}/figures/{n}" for n in names]


def report_figures(study):
    """Every figure (PNG + notes) the report of ``study`` shows."""
    def shown(stem):
        name = stem.rsplit("/", 1)[1]
        if name.startswith("fig08_motions_"):
            return name == f"fig08_motions_{ensemble_of(study)}"
        if name in PAPER_MODEL_FIGURES:
            return reproduces_paper(study)
        return name != "fig12_2d_vs_3d" or study in fig12_studies()

    stems = [s for s in global_figure_stems() if shown(s)]
    stems += study_figure_stems(study)
    return [f for s in stems for f in (f"{s}.png", f"{s}.json")]


def report_run_files(study):
    """What the report's "what was run" section reads: the completion summaries and the
    ensemble parameters of every study (Fig 12 uses them all)."""
    files = {"ensembles": expand(rules.motions.output.params, ensemble=study_ensembles()),
             "done": [spectra_complete(s) for s in config["studies"]]}
    if has_tilt_map(study):
        files["done"].append(tilt_map_complete(study))
    return files


def report_stores(study):
    """The stores the report reads (parameters: they are not Snakemake outputs)."""
    return {"stores": [spectra_store(s) for s in config["studies"]],
            "tilt_maps": [tilt_map_store(study)] if has_tilt_map(study) else []}


def report_inputs(study):
    """Named inputs of the report of ``study``."""
    return {"figures": report_figures(study),
            "linear_fit": rules.fragility_curves.output.linear_csv.format(study=study),
            "fragility": rules.fragility_curves.output.fragility_csv.format(study=study),
            **({"risk": rules.risk.output.table.format(study=study),
                "risk_png": rules.risk.output.png.format(study=study)}
               if hazard_spec(study) is not None else {}),
            **({"stripes": rules.stripe_fragility.output.csv.format(study=study)}
               if has_stripes(study) else {}),
            **report_run_files(study)}


def figure_targets():
    """All figure files and one report per study (asked for by the Snakefile's rule all)."""
    targets = [f for s in global_figure_stems() for f in figure_files(s)]
    for study in config["studies"]:
        targets += [f for s in study_figure_stems(study) for f in figure_files(s)]
        targets += [f"results/{study}/fragility.nc", f"results/{study}/fragility.csv",
                    f"results/{study}/linear_fit.nc", f"results/{study}/linear_fit.csv",
                    f"results/{study}/report.html"]
    return targets


def _figure_output(stem, category, **labels):
    """Named outputs png (in the snakemake report), pdf and notes of one figure."""
    return {
        "png": report(f"{stem}.png", caption="../report/figure.rst", category=category,
                      labels=labels or None),
        "pdf": f"{stem}.pdf",
        "notes": f"{stem}.json",
    }
