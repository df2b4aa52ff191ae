# The paper's figures, the fragility curves and the HTML report: paths and helpers.
# Figures not tied to one study (Figs 3, 4, 6, 8, 12) go to <root>/figures/ (named by
# global_stem), the others to <root>/<study>/figures/; every figure is a PNG, a PDF and a JSON
# sidecar of the numbers it measured, which <root>/<study>/report.html sets against the
# paper's. A figure's name is its
# module in rocking.plot, its rule, its script and its caption key.

from rocking.plot import figure_name
from rocking.plot.captions import caption

FIGURES_DIR = out_path("figures")
FIG04_DURATION = 15.0  # [s]: six quasi-impacts of the quasi-rocking case (Eq 32 needs five)


def figure_files(stem):
    """PNG, PDF and JSON notes of one figure."""
    return [f"{stem}.png", f"{stem}.pdf", f"{stem}.json"]


def el_centro_ensemble():
    """First ensemble built on the El Centro record (Fig 6 uses its first motion), or None."""
    for name, spec in config["ensembles"].items():
        if spec.get("record") == "el-centro-1940":  # a suite has records, not record
            return name
    return None


def study_ensembles():
    """Ensembles used by some study, in configuration order."""
    names = [study_config(s)["ensemble"] for s in config["studies"]]
    return list(dict.fromkeys(names))


def fig08_ensembles():
    """Ensembles of one record used by some study (one Fig 8 each: a record and its
    synthetic pairs; a suite of records is not that)."""
    return [e for e in study_ensembles() if not config["ensembles"][e].get("records")]


def study_motions(study):
    """The ensemble file of a study (figures read the physical directions of x and y there)."""
    return ensemble_file(ensemble_of(study))


def global_stem(name):
    """The stem of a figure not tied to one study, named after what it is drawn from (as
    Fig 8 after its ensemble), so that configurations sharing an output root but not their
    study and ensemble names never write the same file: Fig 6 after its El Centro ensemble,
    Fig 12 after the studies it sets side by side; Figs 3 and 4 after nothing (they depend on
    no study: only Fig 4 on the `damped` parameters)."""
    if name.startswith("fig06_"):
        return f"{FIGURES_DIR}/{name}_{el_centro_ensemble()}"
    if name == "fig12_2d_vs_3d":
        return f"{FIGURES_DIR}/{name}_{'+'.join(config['studies'])}"
    return f"{FIGURES_DIR}/{name}"


def global_log(name):
    """The log of the figure ``name`` not tied to one study."""
    return out_path(f"logs/figures/{posixpath.basename(global_stem(name))}.log")


def reproduces_paper(study=None):
    """Whether ``study`` (default: any study) is declared a reproduction of the paper
    (``studies.<name>.reproduces``): only then are the paper's model figures drawn."""
    studies = config["studies"] if study is None else [study]
    return any(study_spec(s).reproduces is not None for s in studies)


def is_paper_record_study(study):
    """Whether ``study`` reproduces the paper on its El Centro ensemble: its report carries
    the paper's model figures (Figs 3, 4, 6) and the verdicts the paper states for El Centro
    only; another reproduction study (Loma Prieta) gets neither, once is enough."""
    return reproduces_paper(study) and ensemble_of(study) == el_centro_ensemble()


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
        stems += [global_stem("fig03_wobbling_period"), global_stem("fig04_free_vibration")]
        if el_centro_ensemble() is not None:
            stems += [global_stem("fig06_el_centro"), global_stem("fig06_theta_max_sensitivity")]
    stems += [f"{FIGURES_DIR}/fig08_motions_{e}" for e in fig08_ensembles()]
    if fig12_studies():
        stems.append(global_stem("fig12_2d_vs_3d"))
    return stems


def study_figure_stems(study):
    """The study's figures that its runs have data for (StudyPlan.figures), and Fig 7."""
    names = study_plan(study).figures()
    if has_product("tilt_map", study):
        names.insert(0, "fig07_tilt_map")
    return [out_path(f"{study}/figures/{n}") for n in names]


def report_figures(study):
    """Every figure (PNG + notes) the report of ``study`` shows."""
    def shown(stem):
        name = stem.rsplit("/", 1)[1]
        kind = figure_name(name)  # the figure's kind, whatever its file is called
        if kind == "fig08_motions":
            return name == f"fig08_motions_{ensemble_of(study)}"
        if kind in PAPER_MODEL_FIGURES:
            return is_paper_record_study(study)
        return kind != "fig12_2d_vs_3d" or study in fig12_studies()

    stems = [s for s in global_figure_stems() if shown(s)]
    stems += study_figure_stems(study)
    return [f for s in stems for f in (f"{s}.png", f"{s}.json")]


def report_run_files(study):
    """What the report's "what was run" section reads: the completion summaries and the
    ensemble parameters of the studies it shows (report_studies: its own, and those of
    Fig 12 where it shows Fig 12)."""
    shown = report_studies(config, study)
    ensembles = list(dict.fromkeys(ensemble_of(s) for s in shown))
    files = {"ensembles": [ensemble_files(e, "params") for e in ensembles],
             "done": [product_complete("spectra", s) for s in shown]}
    if has_product("tilt_map", study):
        files["done"].append(product_complete("tilt_map", study))
    return files


def report_stores(study):
    """The stores the report reads (parameters: they are not Snakemake outputs)."""
    return {"stores": [product_store("spectra", s) for s in report_studies(config, study)],
            "tilt_maps": [product_store("tilt_map", study)]
            if has_product("tilt_map", study) else []}


def report_inputs(study):
    """Named inputs of the report of ``study``."""
    return {"figures": report_figures(study),
            "linear_fit": rules.fragility_curves.output.linear_csv.format(study=study),
            "fragility": rules.fragility_curves.output.fragility_csv.format(study=study),
            **({"risk": rules.risk.output.table.format(study=study),
                "risk_png": rules.risk.output.png.format(study=study),
                "refinement_risk": rules.refinement_risk.output.csv.format(study=study)}
               if hazard_spec(study) is not None else {}),
            **({"stripes": out_path(f"{study}/stripe_fragility.csv"),
                "stripe_figures": [out_path(f"{study}/figures/stripe_fragility_{mode}.png")
                                   for mode in study_spec(study).stripes.modes]}
               if has_product("stripes", study) else {}),
            "records": out_path(f"{study}/records.csv"),
            # the samples of every study the report quotes (Fig 12's finding), its own first
            "refinement": [out_path(f"{s}/refinement_sample.csv") for s in
                           dict.fromkeys([study, *report_studies(config, study)])],
            "suite_fragility": out_path(f"{study}/suite_fragility.csv"),
            **report_run_files(study)}


def figure_targets():
    """All figure files and one report per study (asked for by the Snakefile's rule all)."""
    targets = [f for s in global_figure_stems() for f in figure_files(s)]
    for study in config["studies"]:
        targets += [f for s in study_figure_stems(study) for f in figure_files(s)]
        targets += [out_path(f"{study}/{name}") for name in (
            "fragility.nc", "fragility.csv", "linear_fit.nc", "linear_fit.csv", "report.html")]
    return targets


def _figure_output(stem, category, **labels):
    """Named outputs png (in the snakemake report), pdf and notes of one figure."""
    return {
        "png": report(f"{stem}.png", caption="../report/figure.rst", category=category,
                      labels=labels or None),
        "pdf": f"{stem}.pdf",
        "notes": f"{stem}.json",
    }
