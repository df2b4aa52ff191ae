"""Stripe against first-exceedance fragility of one mode (Snakemake script)."""

from rocking.execution.logs import job
from rocking.plot import stripe_fragility as fig
from rocking.plot._style import save, write_notes


def main(snakemake):
    out = snakemake.output
    with job(snakemake):
        d = fig.data(snakemake.params.store, snakemake.input.fragility,
                     mode=snakemake.wildcards.mode, table=snakemake.input.table,
                     refined=snakemake.input.refined)
        save(fig.plot(d), [out.png, out.pdf])
        write_notes(out.notes, {"figure": "stripe_fragility",
                                **{k: d[k] for k in ("measured", "missing", "mode")}})


if __name__ == "__main__":
    main(snakemake)
