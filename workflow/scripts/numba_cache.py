"""Compile the numba kernels once (or load them from the cache) before any worker starts."""

import json
import time

import numba

from rocking.execution.logs import job
from rocking.execution.warmup import histories_asked, variants_asked, warm_numba_cache


def main(snakemake):
    with job(snakemake):
        t0 = time.perf_counter()
        # the kernels' variants with the monitors or the vertical forcing only where asked
        monitors, vertical = variants_asked(snakemake.config)
        history = histories_asked(snakemake.config)  # Figs 4 and 6: compiled once, here
        seconds = warm_numba_cache(processes=snakemake.threads, monitors=monitors,
                                   vertical=vertical, history=history)
        summary = {"seconds_per_mode": seconds, "seconds": time.perf_counter() - t0,
                   "numba": numba.__version__, "monitors": monitors, "vertical": vertical,
                   "history": history}
        with open(snakemake.output[0], "w") as fh:  # inside the job: then recorded
            json.dump(summary, fh, indent=2)


if __name__ == "__main__":
    main(snakemake)
