"""Compile the numba kernels once (or load them from the cache) before any worker starts."""

import json
import time

import numba

from rocking.execution.logs import job
from rocking.execution.warmup import variants_asked, warm_numba_cache


def main(snakemake):
    with job(snakemake):
        t0 = time.perf_counter()
        # the kernels' variants with the monitors or the vertical forcing only where asked
        monitors, vertical = variants_asked(snakemake.config)
        seconds = warm_numba_cache(processes=snakemake.threads, monitors=monitors,
                                   vertical=vertical)
        summary = {"seconds_per_mode": seconds, "seconds": time.perf_counter() - t0,
                   "numba": numba.__version__, "monitors": monitors, "vertical": vertical}
        with open(snakemake.output[0], "w") as fh:
            json.dump(summary, fh, indent=2)


if __name__ == "__main__":
    main(snakemake)
