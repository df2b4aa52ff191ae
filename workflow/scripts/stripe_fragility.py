"""Stripe fragility table (Snakemake script): the binomial lognormal fit of every (mode, limit
state, R) of the stripes store, refined where separated and bootstrapped over the motions,
beside the critical-intensity fit of the spectra; and the bootstrap samples."""

from rocking.execution.logs import job
from rocking.execution.stripes import write_stripe_fragility


def main(snakemake):
    p = snakemake.params
    with job(snakemake):
        write_stripe_fragility(p.store, snakemake.output.csv, snakemake.output.samples,
                               fragility=snakemake.input.fragility,
                               motions=snakemake.input.motions, refine=int(p.refine),
                               resamples=int(p.bootstrap), study=snakemake.wildcards.study,
                               refined=snakemake.output.refined,
                               exceedance=snakemake.output.exceedance)


if __name__ == "__main__":
    main(snakemake)
