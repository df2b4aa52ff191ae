"""Stripe against first-exceedance fragility of one mode (Snakemake script)."""

from rocking.execution.logs import log_to
from rocking.plot import stripe_fragility as fig
from rocking.plot._style import save, write_notes


def main(snakemake):
    out = snakemake.output
    with log_to(snakemake.log[0], outputs=snakemake.output):
        d = fig.data(snakemake.params.store, snakemake.input.fragility,
                     mode=snakemake.wildcards.mode, table=snakemake.input.table,
                     refined=snakemake.input.refined)
        save(fig.plot(d), [out.png, out.pdf])
        write_notes(out.notes, {"figure": "stripe_fragility",
                                **{k: d[k] for k in ("measured", "missing", "mode")}})


if __name__ == "__main__":
    main(snakemake)
