# From fragility to risk: paths and helpers of the risk rule (risk.smk). Pure functions of
# `config`; the hazard of every study is parsed once here, so a bad file or power law stops
# even a dry run with one line naming studies.<study>.hazard.

from functools import cache
from pathlib import Path

from rocking.motions.measures import same_measure
from rocking.risk.hazard import parse_hazard


def hazard_spec(study):
    """The study's `hazard:` entry, or None."""
    return study_spec(study).hazard


def hazard_file(study):
    """The hazard CSV of a study (relative to the working directory, else to the
    repository, as config/config.yaml is found), or None for a power law or no hazard."""
    spec = hazard_spec(study)
    name = spec.get("file") if isinstance(spec, dict) else spec
    if name is None or ("," in str(name) and not Path(name).exists()):
        return None
    for base in (Path("."), Path(workflow.basedir)):
        if (base / name).exists():
            return str(base / name)
    return str(name)


def hazard_param(study):
    """The hazard entry with its file resolved (what rocking.risk.parse_hazard reads)."""
    spec, path = hazard_spec(study), hazard_file(study)
    if path is None:
        return spec
    return {**spec, "file": path} if isinstance(spec, dict) else path


def study_preset(study):
    """The accuracy preset of the study's analyses ('' for custom tolerances): the risk table
    carries it, and a `fast` one is warned about."""
    accuracy = study_spec(study).spectra.accuracy
    return accuracy if isinstance(accuracy, str) else ""


def risk_studies():
    return [s for s in config["studies"] if hazard_spec(s) is not None]


def inventory_studies():
    return [s for s in config["studies"] if study_spec(s).inventory is not None]


def inventory_file(study):
    """The inventory CSV of a study (relative to the working directory, else to the
    repository); a missing file is refused at parse time, naming the key."""
    name = study_spec(study).inventory["file"]
    for base in (Path("."), Path(workflow.basedir)):
        if (base / name).is_file():
            return str(base / name)
    raise ValueError(f"studies.{study}.inventory.file: no such file: {name!r}")


def portfolio_targets():
    """portfolio.csv and its two figures of every study with an inventory, and the
    OpenQuake/pelicun export where it asks for one."""
    out = []
    for s in inventory_studies():
        out += [rules.portfolio.output.table.format(study=s),
                rules.portfolio.output.map.format(study=s),
                rules.portfolio.output.ranked.format(study=s)]
        if study_spec(s).inventory["export"] is not None:
            out.append(rules.exposure.output.folder.format(study=s))
    return out


def stripe_fragility_csv(study):
    """The stripe fragility table the risk rule adds to risk.csv ([] without stripes)."""
    if not has_product("stripes", study):
        return []
    return [rules.stripe_fragility.output.csv.format(study=study)]


def risk_targets():
    """Exports, risk table and figure of every study with a hazard (and the stripe
    fragility's exports where the study declares stripes in the vector-peak PGA: the NRML
    and pelicun exports are functions of it; stripes in Sa(T) or another component reach
    risk.csv only)."""
    out = []
    for s in risk_studies():
        out += [rules.risk.output.nrml.format(study=s),
                rules.risk.output.pelicun.format(study=s),
                rules.risk.output.table.format(study=s)]
        out += figure_files(out_path(f"{s}/figures/risk"))
        stripes = study_spec(s).stripes
        # the exports are of the vector-peak PGA (pelicun: Demand-Directional 1)
        if has_product("stripes", s) and stripes.measure == "pga" \
                and stripes.component == "vector_peak":
            out += [rules.stripe_risk_exports.output.nrml.format(study=s),
                    rules.stripe_risk_exports.output.pelicun.format(study=s)]
    return out


@cache
def hazard_curve(study):
    """The study's hazard curve, parsed once (a note on dropped levels is said once)."""
    return parse_hazard(hazard_param(study))


def hazard_measure(study):
    """The study's name of its hazard's intensity measure (pga, sa:1.0, ...), read from the
    hazard file (or the power law's measure)."""
    curve = hazard_curve(study)
    if same_measure(curve.measure, "pga"):
        return "pga"
    # the study's own spelling (sa:1.0), as suite_fragility.csv writes it
    return next(m for m in study_spec(study).intensity_measures
                if same_measure(m, curve.measure))


def hazard_component_of(study):
    """The horizontal component the study's hazard declares (its `component` key, or a
    `component=` comment in its file), None where unsaid (then taken as the study's): read
    off the one parsed curve (hazard_curve), so the file is read once at parse time."""
    return None if hazard_spec(study) is None else hazard_curve(study).component


def extra_components(study):
    """Components suite_fragility.csv fits beside the study's: the hazard's, if it differs."""
    c = hazard_component_of(study)
    return [] if c is None or c == study_spec(study).component else [c]


def suite_fragility_csv(study):
    """The suite's fragility table when the hazard is not PGA (its fits in Sa(T)) or not in
    the vector peak (the spectra's fragility.csv is the vector-peak PGA), else []."""
    component = hazard_component_of(study) or study_spec(study).component
    if hazard_measure(study) == "pga" and component == "vector_peak":
        return []
    return [out_path(f"{study}/suite_fragility.csv")]


def _check_hazards():
    """Every hazard parses, and its intensity measure is one the study fits, before any job
    runs (a dry run too); the error names the key."""
    for s in risk_studies():
        try:
            curve = hazard_curve(s)
        except (ValueError, OSError) as exc:
            raise ValueError(f"studies.{s}.hazard: {exc}") from None
        measures = list(study_spec(s).intensity_measures)
        if not any(same_measure(curve.measure, m) for m in ["pga", *measures]):
            raise ValueError(f"studies.{s}.hazard: {curve.source} is a hazard of "
                             f"{curve.imt} ({curve.measure}), which is not one of the study's "
                             f"intensity measures {measures}: add {curve.measure} to "
                             f"studies.{s}.intensity_measures")


_check_hazards()
