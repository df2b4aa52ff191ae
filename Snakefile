# Seismic rocking spectra of Vassiliou et al. (2017): records -> ensembles -> chunked
# critical-intensity searches on Dask -> zarr stores -> ensemble statistics -> figures.
#
#   snakemake --cores 2                                # default, reduced study
#   snakemake --cores 2 --configfile config/paper.yaml # the paper's full study
#
# See docs/workflow.md for clusters (dask scheduler/worker, dask-jobqueue on SLURM).

from pathlib import Path

from snakemake.utils import min_version, validate

min_version("8.20")


# A --configfile replaces the default configuration instead of being merged into it: a
# study of the paper must not inherit keys of the reduced default run. The default is the
# working directory's config/config.yaml, else the one beside this Snakefile (--directory).
DEFAULT_CONFIG = next(
    p for p in (Path("config/config.yaml"), Path(workflow.basedir, "config/config.yaml"))
    if p.exists()
)

if not workflow.overwrite_configfiles:

    configfile: str(DEFAULT_CONFIG)


# Every check of the configuration, before any job is planned (a dry run too), each error
# one line naming the key and the value: the schema and its defaults, the cross-field checks
# (records and their files, tilt goals against every tan_alpha), every study's grids, the
# hazards and inventories against their studies. A relative file (recorded parameters,
# hazard, inventory) is read from the working directory, else from beside this Snakefile.
from rocking.config.checks import check_workflow_config

check_workflow_config(config, workflow.basedir, validate)


include: "workflow/rules/common.smk"
include: "workflow/rules/records.smk"
include: "workflow/rules/products.smk"
include: "workflow/rules/aggregate.smk"
include: "workflow/rules/records_table.smk"
include: "workflow/rules/figures_common.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/stripes.smk"
include: "workflow/rules/risk_common.smk"
include: "workflow/rules/risk.smk"
include: "workflow/rules/run_config.smk"
include: "workflow/rules/provenance.smk"  # last: it adds an input to every rule


report: "workflow/report/workflow.rst"


rule all:
    input:
        all_targets(),
        stripe_targets(),
        risk_targets(),
        portfolio_targets(),
        records_targets(),
    default_target: True
