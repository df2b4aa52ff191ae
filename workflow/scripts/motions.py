"""Build a ground-motion ensemble: the processed record first, then its synthetic pairs.

rocking.motions.build.build_ensemble does the work (principal axes, Brune-corner
high-pass, RDK fit and simulation, optional cut to motions.max_duration); this rule only
maps the configuration onto it and writes the ensemble file and its parameters.
"""

import json
import logging

from rocking.motions.build import build_ensemble, read_motion
from rocking.motions.ensemble_io import save_ensemble
from rocking.study.cluster import log_to

ATTRS = ("record", "label", "stand_in", "stand_in_for", "rotation_deg", "highpass", "seed",
         "n_synthetic")


def main(snakemake):
    spec = snakemake.params.spec
    log = logging.getLogger("motions")
    with log_to(snakemake.log[0]):
        motion = read_motion(spec["record"], spec["paths"])
        build = build_ensemble(motion, spec["n_synthetic"], spec["seed"],
                               rotation=spec["rotation_deg"], mw=spec["mw"],
                               max_duration=spec["max_duration"], progress=log.info)
        params = build.parameters()
        params["ensemble"] = snakemake.wildcards.ensemble
        save_ensemble(snakemake.output.motions, build.motions,
                      attrs={"ensemble": snakemake.wildcards.ensemble,
                             **{k: params[k] for k in ATTRS}})
        with open(snakemake.output.params, "w") as fh:
            json.dump(params, fh, indent=2, sort_keys=True, default=str)
        log.info("wrote %d motions of %s to %s (stand-in: %s)", len(build.motions),
                 motion.name, snakemake.output.motions, params["stand_in"])


if __name__ == "__main__":
    main(snakemake)
