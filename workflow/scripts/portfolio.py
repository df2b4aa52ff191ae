"""Every column of a study's inventory (Snakemake script): portfolio.csv and its two figures,
from the study's fragility surface and its hazard (rocking.risk.portfolio.site_portfolio)."""

from pathlib import Path

from rocking.execution.logs import job
from rocking.plot.portfolio import render_figures
from rocking.risk.portfolio import site_portfolio, write_portfolio


def main(snakemake):
    out, params = snakemake.output, snakemake.params
    with job(snakemake):
        inventory = params.inventory
        result = site_portfolio(Path(snakemake.input.fragility).parent,
                                snakemake.input.inventory, params.hazard,
                                extrapolate=inventory["extrapolate"],
                                resamples=inventory["resamples"])
        for note in result.notes:
            print(note)
        write_portfolio(result.table, Path(out.table).parent, result.inventory.skipped)
        render_figures(result.table, Path(out.map).parent, hazard=str(params.hazard_file),
                       study=f"study {params.study}")
        print(f"{result.table['id'].nunique()} columns: {out.table}")


if __name__ == "__main__":
    main(snakemake)
