"""Every column of a study's inventory (Snakemake script): portfolio.csv from the study's
fragility surface and its hazard (rocking.risk.portfolio.site_portfolio); its two figures are
drawn by the figure loop."""

from pathlib import Path

from rocking.execution.logs import job
from rocking.risk.portfolio import site_lines, site_portfolio, write_portfolio


def main(snakemake):
    out, params = snakemake.output, snakemake.params
    with job(snakemake):
        inventory = params.inventory
        result = site_portfolio(Path(snakemake.input.fragility).parent,
                                snakemake.input.inventory, params.hazard,
                                extrapolate=inventory["extrapolate"],
                                resamples=inventory["resamples"],
                                study_component=params.study_component)
        for note in [*result.inventory.notes, *result.notes, *site_lines(result.site)]:
            print(note)
        write_portfolio(result.table, Path(out.table).parent, result.inventory.skipped)
        print(f"{result.table['id'].nunique()} columns: {out.table}")


if __name__ == "__main__":
    main(snakemake)
