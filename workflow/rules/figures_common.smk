# The figures (rocking.plot.registry: one entry per figure module) and the HTML report:
# paths and helpers. Every figure is a PNG, a PDF and a JSON sidecar of the numbers it
# measured, which <root>/<study>/report.html sets against the paper's. A figure's entry says
# its scope, and so its file: <root>/figures/<name> (global), <root>/figures/<name>_<ensemble>
# (ensemble), <root>/figures/<name>_<study>+<study>... (studies: named after what it is
# drawn from, so that configurations sharing an output root but not their study names never
# write the same file), <root>/<study>/figures/<name> (study), with _<value> appended for a
# figure drawn once per value of a data() keyword (its entry's `per`: the stripe figure per
# mode); its logical inputs and parameters are resolved here (FIGURE_INPUTS, FIGURE_PARAMS)
# for the one rule loop of figures.smk, which draws every figure, the stripe, risk and
# portfolio figures included.

from rocking.plot.registry import Subject, figures, paper_record_ensemble

FIGURES_DIR = out_path("figures")


def figure_files(stem):
    """PNG, PDF and JSON notes of one figure."""
    return [f"{stem}.png", f"{stem}.pdf", f"{stem}.json"]


def subject(study=None, ensemble=None):
    """What a figure's entry is asked about (rocking.plot.registry.Subject)."""
    return Subject(config, study, ensemble, study_spec=study_spec)


def study_ensembles():
    """Ensembles used by some study, in configuration order."""
    return list(dict.fromkeys(ensemble_of(s) for s in config["studies"]))


def study_motions(study):
    """The ensemble file of a study (figures read the physical directions of x and y there)."""
    return ensemble_file(ensemble_of(study))


def reproduces_paper(study=None):
    """Whether ``study`` (default: any study) is declared a reproduction of the paper
    (``studies.<name>.reproduces``): only then are the paper's model figures drawn."""
    return subject(study).reproduces


def is_paper_record_study(study):
    """Whether ``study`` reproduces the paper on its El Centro ensemble: its report carries
    the paper's model figures (Figs 3, 4, 6) and the verdicts the paper states for El Centro
    only; another reproduction study (Loma Prieta) gets neither, once is enough."""
    return reproduces_paper(study) and ensemble_of(study) == paper_record_ensemble(config)


def figure_studies(fig):
    """The studies that want figure ``fig`` (its entry's ``wanted``)."""
    return [s for s in config["studies"]
            if fig.wanted(subject(s, ensemble_of(s) if fig.scope == "ensemble" else None))]


def figure_ensembles(fig):
    """The ensembles an ensemble-scope figure is drawn for: those of the studies that want
    it."""
    return list(dict.fromkeys(ensemble_of(s) for s in figure_studies(fig)))


def figure_pattern(fig):
    """The stem of figure ``fig``'s files, with the wildcards of its scope (and of its
    ``per`` keyword)."""
    per = f"_{{{fig.per}}}" if fig.per else ""
    if fig.scope == "study":
        return out_path(f"{{study}}/figures/{fig.name}{per}")
    if fig.scope == "ensemble":
        return f"{FIGURES_DIR}/{fig.name}_{{ensemble}}{per}"
    if fig.scope == "studies":
        return f"{FIGURES_DIR}/{fig.name}_{'+'.join(config['studies'])}{per}"
    return f"{FIGURES_DIR}/{fig.name}{per}"


def figure_log(fig):
    """The log of figure ``fig``: beside its study's logs, else under logs/figures/."""
    if fig.scope == "study":
        per = f"_{{{fig.per}}}" if fig.per else ""
        return out_path(f"logs/{{study}}/{fig.name}{per}.log")
    return out_path(f"logs/figures/{posixpath.basename(figure_pattern(fig))}.log")


def figure_wildcards(fig, study=None, ensemble=None):
    """The wildcards of each drawing of figure ``fig`` for ``study`` (or ``ensemble``):
    one, or one per value of its ``per`` keyword."""
    one = {"study": study} if fig.scope == "study" else \
        {"ensemble": ensemble} if fig.scope == "ensemble" else {}
    if not fig.per:
        return [one]
    study = study or next(s for s in figure_studies(fig) if ensemble_of(s) == ensemble)
    return [{**one, fig.per: v} for v in fig.per_values(subject(study, ensemble_of(study)))]


def figure_stems(fig):
    """Every stem figure ``fig`` is drawn to in this configuration."""
    pattern = figure_pattern(fig)
    if fig.scope == "study":
        return [pattern.format(**w) for s in figure_studies(fig)
                for w in figure_wildcards(fig, study=s)]
    if fig.scope == "ensemble":
        return [pattern.format(**w) for e in figure_ensembles(fig)
                for w in figure_wildcards(fig, ensemble=e)]
    if not figure_studies(fig):
        return []
    return [pattern.format(**w) for w in figure_wildcards(fig, figure_studies(fig)[0])]


def figure_output(fig):
    """Named outputs png (in the snakemake report), pdf and notes of figure ``fig``."""
    labels = {"figure": fig.label}
    labels.update({"study": "{study}"} if fig.scope == "study" else
                  {"ensemble": "{ensemble}"} if fig.scope == "ensemble" else {})
    if fig.per:
        labels[fig.per] = f"{{{fig.per}}}"
    return _figure_output(figure_pattern(fig), fig.category, **labels)


def _figure_output(stem, category, **labels):
    """Named outputs png (in the snakemake report), pdf and notes of one figure."""
    return {
        "png": report(f"{stem}.png", caption="../report/figure.rst", category=category,
                      labels=labels or None),
        "pdf": f"{stem}.pdf",
        "notes": f"{stem}.json",
    }


def _subject_studies(fig, wildcards):
    """The studies one job of figure ``fig`` reads: its study, the studies of its ensemble
    that want it, or (scope studies) every study that wants it."""
    if fig.scope == "study":
        return [wildcards.study]
    if fig.scope == "ensemble":
        return [s for s in figure_studies(fig) if ensemble_of(s) == wildcards.ensemble]
    return figure_studies(fig)


def _per_study(fig, wildcards, one):
    """``one(study)`` for the job's study, or the list over the studies of scope studies."""
    values = [one(s) for s in _subject_studies(fig, wildcards)]
    return values if fig.scope == "studies" else values[0]


FIGURE_INPUTS = {
    "motions": lambda fig, w: (ensemble_file(w.ensemble) if fig.scope == "ensemble" else
                               _per_study(fig, w, study_motions)),
    "comparison": lambda fig, w: ensemble_files(w.ensemble, "comparison"),
    "spectra": lambda fig, w: _per_study(fig, w, lambda s: product_complete("spectra", s)),
    "tilt_map": lambda fig, w: _per_study(fig, w, lambda s: product_complete("tilt_map", s)),
    "means": lambda fig, w: _per_study(fig, w, mean_spectra),
    "fragility_nc": lambda fig, w: _per_study(fig, w, lambda s: out_path(f"{s}/fragility.nc")),
    "fragility_csv": lambda fig, w: _per_study(
        fig, w, lambda s: out_path(f"{s}/fragility.csv")),
    "stripe_table": lambda fig, w: _per_study(
        fig, w, lambda s: rules.stripe_fragility.output.csv.format(study=s)),
    "stripe_refined": lambda fig, w: _per_study(
        fig, w, lambda s: rules.stripe_fragility.output.refined.format(study=s)),
    "risk": lambda fig, w: _per_study(fig, w, lambda s: rules.risk.output.table.format(study=s)),
    "portfolio": lambda fig, w: _per_study(
        fig, w, lambda s: rules.portfolio.output.table.format(study=s)),
    # headline.csv exists for the paper's El Centro study only (none elsewhere)
    "headline": lambda fig, w: [f for s in _subject_studies(fig, w)
                                if is_paper_record_study(s)
                                for f in [out_path(f"{s}/headline.csv")]],
}
"""How each logical input of a figure (rocking.plot.registry.INPUTS) is found for one job."""

FIGURE_PARAMS = {
    "paper": lambda fig, w: reproduces_paper(w.study if fig.scope == "study" else None),
    "model_options": lambda fig, w: damped_options(["3d-damped"]),
    "ensemble_spec": lambda fig, w: ensemble_spec(w.ensemble),
    "spectra_store": lambda fig, w: _per_study(fig, w, lambda s: product_store("spectra", s)),
    "tilt_map_store": lambda fig, w: _per_study(fig, w,
                                                lambda s: product_store("tilt_map", s)),
    "stripes_store": lambda fig, w: _per_study(fig, w,
                                               lambda s: product_store("stripes", s)),
    "studies": lambda fig, w: _subject_studies(fig, w),
    "study": lambda fig, w: _per_study(fig, w, lambda s: s),
    "ensemble": lambda fig, w: _per_study(fig, w, ensemble_of),
    "hazard": lambda fig, w: _per_study(fig, w, hazard_param),
    "hazard_file": lambda fig, w: _per_study(fig, w, lambda s: hazard_file(s) or ""),
}
"""How each logical parameter of a figure (rocking.plot.registry.PARAMS) is found."""


def _bound(how, fig):
    """``how(fig, wildcards)`` as a function of the wildcards alone (one per figure: a lambda
    in the loop of figures.smk would see only the last figure)."""
    return lambda wildcards: how(fig, wildcards)


def figure_inputs(fig):
    """Named inputs of figure ``fig``'s rule, from its entry's logical inputs: the compiled
    kernels (ancient: ordering only), another figure's notes for the same subject, or a
    function of the wildcards (FIGURE_INPUTS)."""
    out = {}
    for name, kind in fig.inputs.items():
        if kind == "numba":
            out[name] = ancient(NUMBA_CACHE)
        elif kind in FIGURE_INPUTS:
            out[name] = _bound(FIGURE_INPUTS[kind], fig)
        elif kind in figures():
            out[name] = f"{figure_pattern(figures()[kind])}.json"
        else:
            raise WorkflowError(f"figure {fig.name}: input {name}={kind!r} is neither a "
                                f"logical input {list(FIGURE_INPUTS)} nor a figure")
    return out


def figure_params(fig):
    """Parameters of figure ``fig``'s rule: its name, its caption (a function, so its braces
    are not wildcards; the paper's statements in a reproduction) and its logical params."""
    return {"figure": fig.name,
            "caption": _bound(lambda f, w: f.text(FIGURE_PARAMS["paper"](f, w)), fig),
            **{name: _bound(FIGURE_PARAMS[kind], fig) for name, kind in fig.params.items()},
            # a figure drawn per value of a data() keyword gets the value of its file
            **({fig.per: _bound(lambda f, w: getattr(w, f.per), fig)} if fig.per else {})}


def figure_stems_of(study):
    """Every figure (stem) the report of ``study`` shows: the figures of the study's own, of
    its ensemble and of the configuration its entry says it shows (FigureSpec.shown)."""
    stems = []
    for fig in figures().values():
        if not fig.shown(subject(study, ensemble_of(study))):
            continue
        stems += [figure_pattern(fig).format(**w)
                  for w in figure_wildcards(fig, study, ensemble_of(study))]
    return stems


def report_figures(study):
    """Every figure (PNG + notes) the report of ``study`` shows."""
    return [f for s in figure_stems_of(study) for f in (f"{s}.png", f"{s}.json")]


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
            "linear_fit": rules.fragility.output.linear_csv.format(study=study),
            "fragility": rules.fragility.output.fragility_csv.format(study=study),
            **({"risk": rules.risk.output.table.format(study=study)}
               if hazard_spec(study) is not None else {}),
            **({"stripes": out_path(f"{study}/stripe_fragility.csv")}
               if has_product("stripes", study) else {}),
            **({"portfolio": rules.portfolio.output.table.format(study=study)}
               if study_spec(study).inventory is not None else {}),
            "records": out_path(f"{study}/records.csv"),
            # the headline's first exceedances on four grids, of every study the findings
            # quote that has them (its own first)
            "headline": [out_path(f"{s}/headline.csv") for s in
                         dict.fromkeys([study, *report_studies(config, study)])
                         if is_paper_record_study(s)],
            "suite_fragility": out_path(f"{study}/suite_fragility.csv"),
            **report_run_files(study)}


def figure_targets():
    """All figure files and one report per study (asked for by the Snakefile's rule all)."""
    targets = [f for fig in figures().values() for s in figure_stems(fig)
               for f in figure_files(s)]
    for study in config["studies"]:
        targets += [out_path(f"{study}/{name}") for name in (
            "fragility.nc", "fragility.csv", "linear_fit.nc", "linear_fit.csv", "report.html")]
    return targets

