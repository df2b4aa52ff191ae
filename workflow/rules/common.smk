# Shared helpers: the validated configuration turned into store specifications (one
# rocking.config.study.StudySpec per study: grids, runs, hashes) and target paths. Pure
# functions of `config`; no work happens here.

import posixpath
import re
from functools import cache

from rocking.execution.prepare import keyed
from rocking.execution.products import PRODUCTS
from rocking.config.damping import Damping
from rocking.config.ensemble import EnsembleSpec
from rocking.store.attrs import config_hash
from rocking.config.study import StudySpec, report_studies
from snakemake.exceptions import WorkflowError


OUTPUT = posixpath.normpath(config["output"])
"""The output root (config key ``output``, default ``results``): every file a rule writes,
its log included, lies under it, so two configurations with different roots never share one."""


def out_path(path):
    """``path`` (relative, may hold wildcards) under the output root: the one place paths of
    outputs and logs are made."""
    return posixpath.join(OUTPUT, path)


def study_config(study):
    return config["studies"][study]


def ensemble_of(study):
    return study_spec(study).ensemble.name


def ensemble_spec(name):
    """Everything that decides the motions of an ensemble (also hashed into stores)."""
    return EnsembleSpec.from_config(config, name).settings()


def ensemble_files(name, kind="motions"):
    """The file ``kind`` (motions, params, comparison) of ensemble ``name``, keyed by the
    digest of its settings."""
    digest = EnsembleSpec.from_config(config, name).digest
    return expand(getattr(rules.motions.output, kind), ensemble=name, digest=digest)[0]


def ensemble_file(name):
    return ensemble_files(name)


def planned_ensemble(name, digest):
    """The settings of ensemble ``name``, if ``digest`` is theirs (a file asked for by name
    with another digest belongs to other settings: it is not made from these)."""
    spec = EnsembleSpec.from_config(config, name)
    if spec.digest != digest:
        raise WorkflowError(f"ensembles.{name}: the settings of this configuration hash to "
                            f"{spec.digest}, not {digest}")
    return spec.settings()


@cache
def study_spec(study):
    """The study as one checked object (rocking.config.study.StudySpec)."""
    return StudySpec.from_config(config, study)


def damped_options(modes):
    """Contact-model parameters, only when a damped model runs (else they cannot matter)."""
    return Damping.options(Damping.of_modes(config, modes))


def study_plan(study):
    """The study's runs checked and united (rocking.config.plan): modes, tan α, limit states
    and which of their cells are requested."""
    return study_spec(study).spectra.plan


def search_upper(study):
    """Highest PGA/(g tan α) searched in a study: its own ``upper``, else ``search.upper``."""
    return study_spec(study).spectra.upper


# A study's products (rocking.execution.products.PRODUCTS: spectra, tilt_map, stripes) by name:
# each is a part of the study (None when not configured) with its own store and compute rule.
def has_product(kind, study):
    return getattr(study_spec(study), kind) is not None


def product_spec(kind, study):
    """The result-affecting description of a product's store (its hash names the store).

    For the spectra, ``runs`` say what is computed; ``modes``, ``tan_alpha`` and
    ``limit_states`` are their union, the store's grid (cells of the grid no run asks for
    stay NaN, requested = false).
    """
    return getattr(study_spec(study), kind).to_attrs()


def product_hash(kind, study):
    return getattr(study_spec(study), kind).digest


def compute_threads():
    """Worker processes of an embedded LocalCluster: all cores given to snakemake (--cores)."""
    try:
        return max(1, int(workflow.cores))
    except WorkflowError:  # no --cores (e.g. a dry run): the value is not used
        return 1


NUMBA_CACHE = out_path("numba_cache.json")
"""Marker of the numba_cache step (the kernels compiled into numba's on-disk cache)."""


# The stores are prepared and filled by their compute rule and are not Snakemake outputs (see
# products.smk); other rules take the rule's completion marker as input and the store path as
# a parameter. Everything else is named by the rule that writes it (rules.<name>.output).
# A store's name holds the digest of what decides its numbers (rocking.execution.prepare.keyed):
# a changed setting adds a store, changing it back finds the earlier one.
def product_store(kind, study):
    return str(keyed(out_path(f"{study}/{kind}.zarr"), product_hash(kind, study)))


def product_complete(kind, study):
    """The completion marker of a product's compute rule (its output)."""
    return expand(getattr(rules, kind).output.done, study=study)[0]


def product_param(helper, kind):
    """A rule parameter ``helper(kind, study)`` of the product ``kind`` (one function per
    product: a lambda in the loop of products.smk would see only the last kind)."""
    return lambda wildcards: helper(kind, wildcards.study)


def mean_spectra(study):
    return expand(rules.mean_spectra.output.nc, study=study)[0]


def run_config_file(study):
    """This run's configuration, defaults filled in, in the study's folder (report)."""
    return out_path(f"{study}/config.yaml")


def all_targets():
    targets = []
    for study in config["studies"]:
        targets += expand(rules.mean_spectra.output, study=study)
        targets.append(run_config_file(study))
        if has_product("tilt_map", study):
            targets.append(product_complete("tilt_map", study))
    targets += list(figure_targets())
    return targets


def stripe_targets():
    """The table of every study that declares stripes (its figures: figure_targets)."""
    return [out_path(f"{study}/stripe_fragility.csv") for study in config["studies"]
            if has_product("stripes", study)]


wildcard_constraints:
    study="|".join(map(re.escape, config["studies"])),
    ensemble="|".join(map(re.escape, config["ensembles"])),
    digest="[0-9a-f]{16}",


def records_targets():
    """The per-record table and the suite's fragility of every study."""
    return [out_path(f"{study}/{name}") for study in config["studies"]
            for name in ("records.csv", "suite_fragility.csv")]

