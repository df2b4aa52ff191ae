"""Build a ground-motion ensemble: the processed record first, then its synthetic pairs;
or a suite: the processed records first, then each record's synthetic pairs.

rocking.motions.build.build_ensemble (one record) and build_suite (a suite) do the work
(principal axes, high-pass, RDK fit and simulation, fit quality, optional cut to
motions.max_duration); this rule only maps the configuration onto them and writes the
ensemble file, its parameters, and the comparison ensemble of the other identification
method (Fig 8 only; a suite's holds its recorded motions).
"""

import logging

from rocking import _json
from rocking.execution.logs import heartbeat, job, terminal
from rocking.motions.build import (
    ENSEMBLE_ATTRS,
    SUITE_RECORD_KEYS,
    build_ensemble,
    build_suite,
    quality_lines,
    read_motion,
    recorded_entries,
)
from rocking.motions.ensemble_io import save_ensemble
from rocking.motions.stochastic.recorded import entries_for, write_params_file


def main(snakemake):
    spec = snakemake.params.spec
    log = logging.getLogger("motions")
    name = snakemake.wildcards.ensemble

    def say(message):
        # each stage on the terminal as well as in the log
        log.info("%s", message)
        print(f"motions {name}: {message}", file=terminal(), flush=True)

    # a line every progress interval between stages: the fit and the synthesis of many
    # pairs have no progress of their own
    interval = float(snakemake.config["dask"]["progress_interval"])
    with job(snakemake), \
            heartbeat(say, interval, f"building {name}") as stage:
        def said(message):
            stage[0] = f"after: {message}"
            say(message)

        settings = spec.get("records") or [spec]
        motions = [read_motion(r["record"], r["paths"], units=r["units"], dt=r["dt"],
                               vertical=r.get("vertical", False)) for r in settings]
        recorded = _recorded(spec, name, motions, settings)
        if spec.get("records"):
            records = [(m, {k: r[k] for k in SUITE_RECORD_KEYS})
                       for m, r in zip(motions, settings, strict=True)]
            build = build_suite(records, fit_method=spec["fit_method"],
                                max_duration=spec["max_duration"], recorded=recorded,
                                progress=said)
        else:
            build = build_ensemble(motions[0], spec["n_synthetic"], spec["seed"],
                                   rotation=spec["rotation_deg"], highpass=spec["highpass"],
                                   fc_hz=spec["fc_hz"], mw=spec["mw"],
                                   max_duration=spec["max_duration"],
                                   fit_method=spec["fit_method"], compare=True,
                                   recorded=(recorded or {}).get(motions[0].name),
                                   progress=said)
        params = build.parameters()
        params["ensemble"] = snakemake.wildcards.ensemble
        attrs = {"ensemble": snakemake.wildcards.ensemble,
                 **{k: params[k] for k in ENSEMBLE_ATTRS}}
        save_ensemble(snakemake.output.motions, build.motions, attrs=attrs)
        # The other identification's pairs (same seed), for Fig 8's side-by-side view.
        recorded = build.motions[:len(spec.get("records") or [None])]
        save_ensemble(snakemake.output.comparison, build.comparison or recorded,
                      attrs={**attrs, **(params["comparison"] or {})})
        for line in quality_lines(params):
            say(line)
        _json.write(snakemake.output.params, params, sort_keys=True)
        # the rounded fits and the digests of their pairs: commit this file as
        # config/ensembles/<name>.params.json and name it in ensembles.<name>.params
        entries = recorded_entries(build, [{**r, "fit_method": spec["fit_method"]}
                                           for r in settings])
        write_params_file(snakemake.output.recorded, name, entries)
        say(f"wrote {len(build.motions)} motions of {params['record']} to "
            f"{snakemake.output.motions} (stand-in: {params['stand_in']})")


def _recorded(spec, name, motions, settings):
    """Entries of the ensemble's parameters file by record name (None without ``params``),
    each checked against its record's settings."""
    if not spec.get("params"):
        return None
    return entries_for(spec["params"], [(m.name, {**r, "fit_method": spec["fit_method"]})
                                        for m, r in zip(motions, settings, strict=True)],
                       f"ensembles.{name}.params")


if __name__ == "__main__":
    main(snakemake)
