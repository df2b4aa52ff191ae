"""Create the empty spectra store of a study (layout, coordinates, attributes)."""

import logging
from pathlib import Path

from rocking import __version__
from rocking.spectra.accuracy import get_accuracy
from rocking.study import store
from rocking.study.cluster import log_to
from rocking.study.plan import plan_study


def main(snakemake):
    spec = snakemake.params.spec
    with log_to(snakemake.log[0]):
        ensemble = store.ensemble_attrs(snakemake.input.motions, spec["ensemble"]["name"])
        names = [m["name"] for m in ensemble["motions"]]
        chunk_R = spec["chunk_R"]
        if chunk_R == "auto":
            npts = min(m["npts"] for m in ensemble["motions"])
            chunk_R = store.auto_chunk_R(len(spec["R"]), npts, spec["min_task_seconds"])
        plan = plan_study(spec["runs"], f"studies.{spec['study']}.runs")
        layout = store.spectra_layout(plan.modes, plan.limit_states, names, plan.tan_alpha,
                                      spec["R"], chunk_R)
        attrs = {
            "title": f"Seismic performance rocking spectra, study {spec['study']}",
            "config": spec,
            "tolerances": get_accuracy(spec["accuracy"]).to_dict(),
            "search_options": spec["search_options"],
            "rocking_version": __version__,
            "ensemble": ensemble,
            "pga_crit_definition": "PGA/(g tan alpha), PGA = max sqrt(ax^2 + ay^2) of the pair; "
                                   "pga_crit_g = pga_crit * tan_alpha is the same PGA in g",
        }
        store.create_store(Path(snakemake.output[0]), layout, attrs,
                           snakemake.params.config_hash, coords=store.identity_coords(ensemble),
                           static={store.REQUESTED: plan.requested})
        skipped = len(store.regions_not_requested(layout, plan.requested))
        logging.getLogger("spectra_store").info(
            "created %s: %d chunks of %d sizes R (%d not requested by any run, marked done), "
            "motions %s; points per mode %s", snakemake.output[0], layout.n_regions, chunk_R,
            skipped, names, plan.points(len(names), len(spec["R"])))


if __name__ == "__main__":
    main(snakemake)
