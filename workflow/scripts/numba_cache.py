"""Compile the numba kernels once (or load them from the cache) before any worker starts."""

import json
import time

import numba

from rocking.study.logs import log_to
from rocking.study.warmup import warm_numba_cache


def main(snakemake):
    with log_to(snakemake.log[0], outputs=snakemake.output):
        t0 = time.perf_counter()
        seconds = warm_numba_cache(processes=snakemake.threads)
        summary = {"seconds_per_mode": seconds, "seconds": time.perf_counter() - t0,
                   "numba": numba.__version__}
    with open(snakemake.output[0], "w") as fh:
        json.dump(summary, fh, indent=2)


if __name__ == "__main__":
    main(snakemake)
