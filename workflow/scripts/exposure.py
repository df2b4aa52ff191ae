"""A study's inventory as OpenQuake's exposure and fragility models and pelicun's inputs
(Snakemake script), from its portfolio.csv (rocking.risk.exposure.write_exposure)."""

from rocking.execution.logs import job
from rocking.risk.exposure import write_exposure


def main(snakemake):
    with job(snakemake):
        # read as written: ids as text (007 stays 007), positions with every digit
        export = write_exposure(snakemake.input.portfolio, snakemake.output.folder,
                                taxonomy_by=snakemake.params.taxonomy_by)
        for note in export.notes:
            print(note)
        print(f"{export.assets} assets, {len(export.taxonomies)} taxonomies: "
              f"{snakemake.output.folder}")


if __name__ == "__main__":
    main(snakemake)
