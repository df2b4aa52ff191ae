# From fragility to risk (rocking.risk): for each study with a `hazard:` in its
# configuration, the OpenQuake NRML 0.5 and pelicun exports of its fragility table, the risk
# table (mean annual frequency, return period, probability in 50 years per mode, tan α, R and
# limit state) and the risk figure. Studies without `hazard:` get none of these.

from pathlib import Path

from rocking.risk.hazard import parse_hazard
from rocking.study.figures.risk import CAPTION as RISK_CAPTION


def hazard_spec(study):
    """The study's `hazard:` entry, or None."""
    return study_config(study).get("hazard")


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


def risk_studies():
    return [s for s in config["studies"] if hazard_spec(s) is not None]


def risk_targets():
    """Exports, risk table and figure of every study with a hazard."""
    out = []
    for s in risk_studies():
        out += [f"results/{s}/fragility.nrml.xml", f"results/{s}/fragility.pelicun.csv",
                f"results/{s}/risk.csv"]
        out += figure_files(f"results/{s}/figures/risk")
    return out


def _check_hazards():
    """Every hazard parses before any job runs; the error names the key."""
    for s in risk_studies():
        try:
            parse_hazard(hazard_param(s))
        except (ValueError, OSError) as exc:
            raise ValueError(f"studies.{s}.hazard: {exc}") from None


_check_hazards()


rule risk:
    conda:
        "../envs/rocking.yaml"
    input:
        fragility=rules.fragility_curves.output.fragility_csv,
        hazard=lambda wildcards: [f] if (f := hazard_file(wildcards.study)) else [],
    output:
        nrml="results/{study}/fragility.nrml.xml",
        pelicun="results/{study}/fragility.pelicun.csv",
        table="results/{study}/risk.csv",
        **_figure_output("results/{study}/figures/risk", "Beyond the paper", figure="risk",
                         study="{study}"),
    params:
        caption=RISK_CAPTION,
        hazard=lambda wildcards: hazard_param(wildcards.study),
        upper=float(config["search"]["upper"]),
        study=lambda wildcards: wildcards.study,
    log:
        "logs/{study}/risk.log",
    script:
        "../scripts/risk.py"
