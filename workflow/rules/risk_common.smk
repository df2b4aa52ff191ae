# From fragility to risk: paths and helpers of the risk rule (risk.smk). Pure functions of
# `config`; the hazard of every study is parsed once here, so a bad file or power law stops
# even a dry run with one line naming studies.<study>.hazard.

from functools import cache

from rocking.config.checks import hazard_file_name, resolve_path, resolved_hazard
from rocking.risk.exports import exported
from rocking.risk.hazard import parse_hazard


def hazard_spec(study):
    """The study's `hazard:` entry, or None."""
    return study_spec(study).hazard


def hazard_param(study):
    """The study's hazard entry with its file resolved (rocking.config.checks.resolved_hazard:
    working directory, else the repository), as rocking.risk.parse_hazard reads it."""
    return resolved_hazard(hazard_spec(study), lambda name: resolve_path(name, workflow.basedir))


def hazard_file(study):
    """The hazard file a study reads, or None for a power law or no hazard."""
    return hazard_file_name(hazard_param(study))


def study_preset(study):
    """The accuracy preset of the study's analyses ('' for custom tolerances): the risk table
    carries it, and a `fast` one is warned about."""
    return study_spec(study).spectra.accuracy.preset or ""


def risk_studies():
    return [s for s in config["studies"] if hazard_spec(s) is not None]


def inventory_studies():
    return [s for s in config["studies"] if study_spec(s).inventory is not None]


def inventory_file(study):
    """The inventory CSV of a study (relative to the working directory, else to the
    repository; a missing file was refused with the configuration, naming the key)."""
    return resolve_path(study_spec(study).inventory["file"], workflow.basedir)


def portfolio_targets():
    """portfolio.csv of every study with an inventory (its two figures: figure_targets), and
    the OpenQuake/pelicun export where it asks for one."""
    out = []
    for s in inventory_studies():
        out += [rules.portfolio.output.table.format(study=s),
                rules.portfolio.output.site.format(study=s)]
        if study_spec(s).inventory["export"] is not None:
            out.append(rules.exposure.output.folder.format(study=s))
    return out


def stripe_fragility_csv(study):
    """The stripe fragility table the risk rule adds to risk.csv ([] without stripes)."""
    if not has_product("stripes", study):
        return []
    return [rules.stripe_fragility.output.csv.format(study=study)]


def risk_targets():
    """Exports and risk table of every study with a hazard (its figure: figure_targets),
    and the stripe fragility's exports where its measure and component have them
    (rocking.risk.exports.exported)."""
    out = []
    for s in risk_studies():
        out += [rules.risk.output.nrml.format(study=s),
                rules.risk.output.pelicun.format(study=s),
                rules.risk.output.table.format(study=s)]
        stripes = study_spec(s).stripes
        if stripes is not None and exported(stripes.measure, stripes.component):
            out += [rules.stripe_risk_exports.output.nrml.format(study=s),
                    rules.stripe_risk_exports.output.pelicun.format(study=s)]
    return out


@cache
def hazard_curve(study):
    """The study's hazard curve, parsed once (a note on dropped levels is said once)."""
    return parse_hazard(hazard_param(study))


def hazard_component_of(study):
    """The horizontal component of the study's hazard (declared, read from its file, or an
    OpenQuake file's default), None where unsaid: read off the one parsed curve."""
    return None if hazard_spec(study) is None else hazard_curve(study).component


def motion_measures_csv(study):
    """Every motion's measures in every component (the refits in the hazard's terms)."""
    return out_path(f"{study}/motion_measures.csv")


def motion_measure_names(study):
    """The measures motion_measures.csv gives: the study's and its hazard's."""
    names = list(study_spec(study).intensity_measures)
    if hazard_spec(study) is not None:
        names.append(hazard_curve(study).measure)
    return list(dict.fromkeys(names))
