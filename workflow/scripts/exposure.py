"""A study's inventory as OpenQuake's exposure and fragility models and pelicun's inputs
(Snakemake script), from its portfolio.csv (rocking.risk.exposure.write_exposure)."""

import pandas as pd

from rocking.execution.logs import job
from rocking.risk.exposure import write_exposure


def main(snakemake):
    with job(snakemake):
        table = pd.read_csv(snakemake.input.portfolio)
        export = write_exposure(table, snakemake.output.folder,
                                taxonomy_by=snakemake.params.taxonomy_by,
                                component=str(table["component"].iloc[0]))
        for note in export.notes:
            print(note)
        print(f"{export.assets} assets, {len(export.taxonomies)} taxonomies: "
              f"{snakemake.output.folder}")


if __name__ == "__main__":
    main(snakemake)
