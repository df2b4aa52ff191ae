"""Write the run's configuration (defaults filled in) for the Snakemake report."""

import yaml

from rocking.execution.logs import job


def main(snakemake):
    with job(snakemake):
        with open(snakemake.output[0], "w") as fh:
            fh.write("# Configuration of this run, with the schema's defaults filled in\n"
                     "# (config/README.md explains every key; dask.* as of the run that\n"
                     "# wrote this file: a change of it alone reruns nothing).\n")
            yaml.safe_dump(dict(snakemake.config), fh, sort_keys=False)


if __name__ == "__main__":
    main(snakemake)
