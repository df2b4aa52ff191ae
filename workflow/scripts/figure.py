"""One figure (Snakemake script for every figure rule, workflow/rules/figures.smk): the
figure named by ``params.figure`` drawn by its module from the rule's inputs and parameters
(rocking.plot.draw)."""

from rocking.execution.logs import job
from rocking.plot import draw


def _plain(value):
    """A Snakemake named list as a plain list, anything else as it is."""
    return list(value) if isinstance(value, list) else value


def main(snakemake):
    params = {k: _plain(v) for k, v in snakemake.params.items()
              if k not in ("figure", "caption")}
    # every input but the planning's (workflow/rules/provenance.smk), which holds no file
    inputs = {k: _plain(v) for k, v in snakemake.input.items() if k != "provenance"}
    with job(snakemake):
        draw(snakemake.params.figure, inputs, params, dict(snakemake.output.items()))


if __name__ == "__main__":
    main(snakemake)
