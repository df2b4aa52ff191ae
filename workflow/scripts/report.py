"""Report (Snakemake script): <root>/<study>/report.html with what was run, every figure and
the paper's statements against this run's numbers."""

from datetime import datetime
from pathlib import Path

from rocking.execution.logs import job
from rocking.report.html import build, report_title
from rocking.report.run_summary import what_was_run


def workflow_elapsed() -> float | None:
    """Seconds since the Snakemake run that writes this report started: its log file is named
    after its start time (``.snakemake/log/2026-11-23T104517.055836.snakemake.log``)."""
    starts = []
    for log in Path(".snakemake/log").glob("*.snakemake.log"):
        try:
            starts.append(datetime.strptime(log.name.split(".snakemake")[0], "%Y-%m-%dT%H%M%S.%f"))
        except ValueError:
            continue
    return (datetime.now() - max(starts)).total_seconds() if starts else None


def main(snakemake):
    inp = snakemake.input
    figures = [str(f) for f in inp.figures if str(f).endswith(".png")]
    with job(snakemake):
        run = what_was_run(stores=list(snakemake.params.stores),
                           tilt_maps=list(snakemake.params.tilt_maps),
                           ensembles=list(inp.ensembles), done=list(inp.done),
                           elapsed_seconds=workflow_elapsed())
        build(snakemake.output.page,
              title=report_title(str(snakemake.params.study), str(snakemake.params.ensemble),
                                 snakemake.params.reproduces),
              figures=figures, linear_fit=inp.linear_fit, fragility=inp.fragility, run=run,
              risk=inp.get("risk"), hazard=str(snakemake.params.get("hazard") or ""),
              stripes=inp.get("stripes"), paper=snakemake.params.reproduces is not None,
              records=inp.get("records"), suite_fragility=inp.get("suite_fragility"),
              paper_record=bool(snakemake.params.paper_record),
              study=str(snakemake.params.study), portfolio=inp.get("portfolio"),
              headline=list(inp.get("headline", [])), verdicts_csv=snakemake.output.verdicts)


if __name__ == "__main__":
    main(snakemake)
