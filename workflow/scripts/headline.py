"""The headline cells' first exceedance on 1, 0.5, 0.2 and 0.1 % grids (Snakemake script):
<study>/headline.csv (rocking.study.headline)."""

import time

from rocking.execution.logs import job
from rocking.study.headline import summary, write_headline


def main(snakemake):
    with job(snakemake):
        t0 = time.perf_counter()
        table = write_headline(snakemake.params.store, snakemake.input.motions,
                               snakemake.output.csv, processes=snakemake.threads)
        s = summary(table)
        print(f"wrote {snakemake.output.csv}: {len(table)} searches, "
              + (f"{s['analyses']} analyses, {s['cpu_s']:.0f} CPU s, " if s else "")
              + f"{time.perf_counter() - t0:.0f} s", flush=True)


if __name__ == "__main__":
    main(snakemake)
