"""λ under refinement (Snakemake script): <root>/<study>/refinement_risk.csv, the fragility
of every point holding a refined cell fitted again with the refined answers substituted and
integrated with the study's hazard curve, as risk.csv is (rocking.study.refinement)."""

from rocking.execution.logs import job
from rocking.fragility.lognormal import censoring_bound
from rocking.plot import open_store
from rocking.risk.hazard import parse_hazard
from rocking.study.refinement import store_cells, write_refinement_risk


def main(snakemake):
    params = snakemake.params
    with job(snakemake):
        hazard = parse_hazard(params.hazard)
        component = params.component or params.study_component
        applies = hazard.measure == "pga" and component == params.study_component
        store = open_store(params.store)
        cells = store_cells(store, censoring_bound(store, float(params.upper)))
        n = write_refinement_risk(cells, snakemake.input.sample, hazard,
                                  snakemake.output.csv, applies=applies)
        print(f"wrote {snakemake.output.csv}: {n} points refitted"
              + ("" if applies else f" (none: the hazard is of {hazard.imt} in {component}, "
                 "risk.csv takes its fits from the suite)"), flush=True)


if __name__ == "__main__":
    main(snakemake)
