# Shared helpers: the validated configuration turned into grids, store specifications,
# their hashes and target paths. Pure functions of `config`; no work happens here.

import re

import numpy as np

from rocking.study.plan import plan_study
from rocking.study.store import config_hash
from snakemake.exceptions import WorkflowError


def expand_grid(spec, field):
    """Values of a grid given as a list or {start, stop, num[, spacing]} (checked)."""
    if isinstance(spec, list):
        values = [float(v) for v in spec]
    else:
        start, stop, num = float(spec["start"]), float(spec["stop"]), int(spec["num"])
        if stop < start:
            raise ValueError(f"{field}: stop={stop!r} is below start={start!r}")
        if spec.get("spacing", "linear") == "log":
            values = np.geomspace(start, stop, num)
        else:
            values = np.linspace(start, stop, num)
        # 12 significant digits: 0.5 + 3 * 0.95 is stored as 3.35, not 3.3499999999999996
        values = [float(f"{v:.12g}") for v in values]
    if len(set(values)) != len(values):
        raise ValueError(f"{field}: repeated values {values!r}")
    return values


def study_config(study):
    return config["studies"][study]


def ensemble_of(study):
    return study_config(study)["ensemble"]


def ensemble_spec(name):
    """Everything that decides the motions of an ensemble (also hashed into stores)."""
    spec = dict(config["ensembles"][name])
    spec["max_duration"] = config["motions"]["max_duration"]
    return spec


def ensemble_file(name):
    return expand(rules.motions.output.motions, ensemble=name)[0]


def accuracy_config():
    return config["accuracy"]


def damped_options(modes):
    """Contact-model parameters, only when a damped model runs (else they cannot matter)."""
    if "3d-damped" not in modes:
        return {}
    return {"omega_n": float(config["damped"]["omega_n"]), "zeta": float(config["damped"]["zeta"])}


def study_plan(study):
    """The study's runs checked and united (rocking.study.plan): modes, tan α, limit states
    and which of their cells are requested."""
    runs = []
    for i, run in enumerate(study_config(study)["runs"]):
        field = f"studies.{study}.runs[{i}]"
        runs.append({**run, "tan_alpha": expand_grid(run["tan_alpha"], f"{field}.tan_alpha")})
    return plan_study(runs, f"studies.{study}.runs")


def spectra_spec(study):
    """The result-affecting description of a spectra store (its hash invalidates the store).

    ``runs`` say what is computed; ``modes``, ``tan_alpha`` and ``limit_states`` are their
    union, the store's grid (cells of the grid no run asks for stay NaN, requested = false).
    """
    s = study_config(study)
    plan = study_plan(study)
    return {
        "study": study,
        "ensemble": {"name": ensemble_of(study), **ensemble_spec(ensemble_of(study))},
        "R": expand_grid(s["R"], f"studies.{study}.R"),
        **plan.to_dict(),
        "tan_alpha": list(plan.tan_alpha),
        "limit_states": list(plan.limit_states),
        "modes": list(plan.modes),
        "chunk_R": s["chunk_R"],
        "min_task_seconds": config["dask"]["min_task_seconds"] if s["chunk_R"] == "auto" else None,
        "accuracy": accuracy_config(),
        "search_options": {"upper": search_upper(study),
                           **damped_options(plan.modes)},
    }


def search_upper(study):
    """Highest PGA/(g tan α) searched in a study: its own ``upper``, else ``search.upper``."""
    own = study_config(study).get("upper")
    return float(config["search"]["upper"] if own is None else own)


def spectra_hash(study):
    return config_hash(spectra_spec(study))


def has_tilt_map(study):
    return study_config(study).get("tilt_map") is not None


def tilt_map_spec(study):
    """The result-affecting description of a Fig 7 tilt-map store."""
    t = study_config(study)["tilt_map"]
    return {
        "study": study,
        "ensemble": {"name": ensemble_of(study), **ensemble_spec(ensemble_of(study))},
        "motion": t["motion"],
        "modes": list(t["modes"]),
        "tan_alpha": float(t["tan_alpha"]),
        "R": expand_grid(t["R"], f"studies.{study}.tilt_map.R"),
        "intensity": expand_grid(t["intensity"], f"studies.{study}.tilt_map.intensity"),
        "chunk_R": int(t["chunk_R"]),
        "accuracy": accuracy_config(),
        "model_options": damped_options(t["modes"]),
    }


def tilt_map_hash(study):
    return config_hash(tilt_map_spec(study))


def has_stripes(study):
    return study_config(study).get("stripes") is not None


def stripes_spec(study):
    """The result-affecting description of a study's stripes store."""
    t = study_config(study)["stripes"]
    return {
        "study": study,
        "ensemble": {"name": ensemble_of(study), **ensemble_spec(ensemble_of(study))},
        "modes": list(t["modes"]),
        "tan_alpha": float(t["tan_alpha"]),
        "limit_states": list(t["limit_states"]),
        "R": expand_grid(t["R"], f"studies.{study}.stripes.R"),
        "intensity": expand_grid(t["intensity"], f"studies.{study}.stripes.intensity"),
        "chunk_R": int(t["chunk_R"]),
        "accuracy": accuracy_config(),
        "model_options": damped_options(t["modes"]),
    }


def stripes_hash(study):
    return config_hash(stripes_spec(study))


def dask_options():
    d = config["dask"]
    return {"scheduler_address": d["scheduler_address"], "scheduler_file": d["scheduler_file"],
            "progress_interval": float(d["progress_interval"]),
            "worker_timeout": float(d["worker_timeout"])}


def compute_threads():
    """Worker processes of an embedded LocalCluster: all cores given to snakemake (--cores)."""
    try:
        return max(1, int(workflow.cores))
    except WorkflowError:  # no --cores (e.g. a dry run): the value is not used
        return 1


NUMBA_CACHE = "results/numba_cache.json"
"""Marker of the numba_cache step (the kernels compiled into numba's on-disk cache)."""


# The stores are prepared and filled by their compute rule and are not Snakemake outputs (see
# spectra.smk); other rules take the rule's completion marker as input and the store path as
# a parameter. Everything else is named by the rule that writes it (rules.<name>.output).
def spectra_store(study):
    return f"results/{study}/spectra.zarr"


def tilt_map_store(study):
    return f"results/{study}/tilt_map.zarr"


def spectra_complete(study):
    return expand(rules.spectra.output.done, study=study)[0]


def tilt_map_complete(study):
    return expand(rules.tilt_map.output.done, study=study)[0]


def mean_spectra(study):
    return expand(rules.mean_spectra.output.nc, study=study)[0]


RUN_CONFIG = "results/config.yaml"  # this run's configuration, defaults filled in (report)


def all_targets():
    targets = []
    for study in config["studies"]:
        targets += expand(rules.mean_spectra.output, study=study)
        if has_tilt_map(study):
            targets.append(tilt_map_complete(study))
    targets += list(figure_targets())
    targets.append(RUN_CONFIG)
    return targets


def _check_config():
    """Grids and specs build without error (the cross-field checks of
    rocking.study.config_checks ran in the Snakefile); each error names the key and value."""
    for study in config["studies"]:
        spectra_spec(study)
        if has_tilt_map(study):
            tilt_map_spec(study)
    if config["dask"]["scheduler_address"] and config["dask"]["scheduler_file"]:
        raise ValueError("dask.scheduler_address and dask.scheduler_file are both set; "
                         "give one")


_check_config()


wildcard_constraints:
    study="|".join(map(re.escape, config["studies"])),
    ensemble="|".join(map(re.escape, config["ensembles"])),
