"""Refinement sample (Snakemake script): <root>/<study>/refinement_sample.csv, a stated
sample of the study's cells searched again with a fixed 0.05 % scan
(rocking.study.refinement)."""

import time

from rocking.execution.logs import job
from rocking.store.integrity import require_intact
from rocking.study.refinement import SampleSpec, write_refinement_sample


def main(snakemake):
    store = snakemake.params.store
    with job(snakemake):
        spec = SampleSpec.from_config(snakemake.params.refinement)
        require_intact(store, say=print)
        t0 = time.perf_counter()
        n = write_refinement_sample(store, snakemake.input.motions, snakemake.output.csv, spec,
                                    n_workers=snakemake.threads)
        print(f"wrote {snakemake.output.csv} ({n} cells refined with {spec}) in "
              f"{time.perf_counter() - t0:.0f} s", flush=True)


if __name__ == "__main__":
    main(snakemake)
