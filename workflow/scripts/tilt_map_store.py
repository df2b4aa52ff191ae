"""Create the empty Fig 7 tilt-map store of a study."""

import logging
from pathlib import Path

from rocking import __version__
from rocking.spectra.accuracy import get_accuracy
from rocking.study import store
from rocking.study.cluster import log_to


def main(snakemake):
    spec = snakemake.params.spec
    with log_to(snakemake.log[0]):
        ensemble = store.ensemble_attrs(snakemake.input.motions, spec["ensemble"]["name"])
        names = [m["name"] for m in ensemble["motions"]]
        motion = spec["motion"] or names[0]  # the record comes first in an ensemble
        if motion not in names:
            raise ValueError(f"studies.{spec['study']}.tilt_map.motion={motion!r} is not a "
                             f"motion of ensemble {spec['ensemble']['name']!r}: {names}")
        layout = store.tilt_map_layout(spec["modes"], spec["R"], spec["intensity"],
                                       spec["chunk_R"])
        attrs = {
            "title": f"Peak tilt over size and intensity (Fig 7), study {spec['study']}",
            "config": spec,
            "motion": motion,
            "tan_alpha": spec["tan_alpha"],
            "tolerances": get_accuracy(spec["accuracy"]).to_dict(),
            "model_options": spec["model_options"],
            "rocking_version": __version__,
            "ensemble": ensemble,
        }
        who = next(m for m in ensemble["motions"] if m["name"] == motion)
        attrs["motion_processing"] = who["processing"]
        attrs["motion_PGA_g"] = who["PGA"]
        pga_g = ("intensity", [i * spec["tan_alpha"] for i in spec["intensity"]])
        store.create_store(Path(snakemake.output[0]), layout, attrs,
                           snakemake.params.config_hash, coords={"pga_g": pga_g})
        logging.getLogger("tilt_map_store").info(
            "created %s: %d chunks, motion %s", snakemake.output[0], layout.n_regions, motion)


if __name__ == "__main__":
    main(snakemake)
