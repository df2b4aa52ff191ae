"""Build a ground-motion ensemble: the processed record first, then its synthetic pairs.

rocking.motions.build.build_ensemble does the work (principal axes, Brune-corner
high-pass, RDK fit and simulation, optional cut to motions.max_duration); this rule only
maps the configuration onto it and writes the ensemble file and its parameters.
"""

import logging

from rocking import _json
from rocking.motions.build import build_ensemble, read_motion
from rocking.motions.ensemble_io import save_ensemble
from rocking.study.cluster import log_to, terminal

ATTRS = ("record", "label", "stand_in", "stand_in_for", "rotation_deg", "highpass", "seed",
         "n_synthetic")


def main(snakemake):
    spec = snakemake.params.spec
    log = logging.getLogger("motions")
    name = snakemake.wildcards.ensemble

    def say(message):
        # each stage on the terminal as well as in the log
        log.info("%s", message)
        print(f"motions {name}: {message}", file=terminal(), flush=True)

    with log_to(snakemake.log[0]):
        motion = read_motion(spec["record"], spec["paths"])
        build = build_ensemble(motion, spec["n_synthetic"], spec["seed"],
                               rotation=spec["rotation_deg"], mw=spec["mw"],
                               max_duration=spec["max_duration"], progress=say)
        params = build.parameters()
        params["ensemble"] = snakemake.wildcards.ensemble
        save_ensemble(snakemake.output.motions, build.motions,
                      attrs={"ensemble": snakemake.wildcards.ensemble,
                             **{k: params[k] for k in ATTRS}})
        _json.write(snakemake.output.params, params, sort_keys=True)
        say(f"wrote {len(build.motions)} motions of {motion.name} to "
            f"{snakemake.output.motions} (stand-in: {params['stand_in']})")


if __name__ == "__main__":
    main(snakemake)
