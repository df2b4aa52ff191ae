"""Per-record answers of a study and the fragility over a suite of records.

For every recorded motion of a study (``kind == "record"`` in its ensemble file) and every
requested (mode, tan α, limit state, R) of its spectra store, :func:`record_table` gives what
an engineer asks of one record: its PGA as recorded and as processed, its PGV and Sa(T), the
critical PGA/(g tan α) and PGA [g], the factor the processed record must be scaled by to
exceed the limit state, and (:func:`as_recorded`) whether the processed record at scale 1
exceeds it: one analysis per (mode, tan α, R), not an inference from the scale factor, since
rocking is not monotonic in the intensity (a record may exceed at scale 1 although its
critical intensity, I10 by default, is above 1, or survive at 1 although it exceeds at a scale
below 1).

The critical intensity is searched on the scale of the record, and every intensity measure
of a scaled record is that scale times the record's measure (:mod:`rocking.motions.measures`),
so the critical PGV or Sa(T) is exactly the critical scale factor times the record's PGV or
Sa(T) — although the rocking response itself is not linear in the scale. The same holds in
every horizontal component (:data:`rocking.motions.measures.COMPONENTS`): the measures of
``records.csv`` are in the study's component (its ``component`` column).
:func:`suite_fragility` fits a lognormal fragility in each measure
(:func:`rocking.fragility.refit.fit_cells`, right-censored at the search bound where a motion
never exceeded the limit state), over the recorded motions and, separately, over the
synthetic pairs. Risk under a hazard of another measure or component refits the study's
fragility over all its motions (:mod:`rocking.fragility.refit`), not these per-group fits.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from rocking.motions.identity import identity
from rocking.motions.measures import (
    DEFAULT_COMPONENT,
    MEASURE_UNITS,
    intensity_measure,
    parse_measure,
)
from rocking.motions.motion import GroundMotion
from rocking.study.aggregate import (
    QUANTITY_COLUMNS,
    nullable_flag,
    quantity_values,
    requested_answers,
    unmonitored_empty,
)

__all__ = ["RECORD_COLUMNS", "as_recorded", "measure_column", "motion_measures",
           "record_table", "suite_fragilities", "suite_fragility", "write_record_tables"]

RECORD_COLUMNS = {
    "motion": ("", "the recorded motion (ensemble file, spectra store)"),
    "mode": ("", "analysis mode"),
    "tan_alpha": ("-", "slenderness b/h"),
    "limit_state": ("", "limit state"),
    "R": ("m", "semi-diagonal"),
    "pga_recorded_g": ("g", "vector PGA of the record as recorded (before any processing)"),
    "pga_g": ("g", "vector PGA of the record as processed (the motion that was scaled)"),
    "component": ("", "horizontal component of the intensity-measure columns (the study's "
                      "component); pga_recorded_g, pga_g, pga_crit, pga_crit_g are always "
                      "the vector peak, the spectra's own intensity"),
    "quantity": ("", "what pga_crit is: exceedance_quantile (I_p, the lowest intensity near "
                     "which a share p of the intensities within ±w in ln s exceed) or "
                     "first_exceedance (on the search's scan grid)"),
    "quantity_p": ("-", "the share p of I_p"),
    "quantity_w": ("-", "the half-width w of its window in ln s"),
    "scan_step": ("-", "relative step of the search's scan grid"),
    "pga_crit": ("g tan(alpha)", "critical PGA/(g tan alpha): the study's quantity"),
    "pga_crit_g": ("g", "critical PGA"),
    "scale_factor": ("-", "critical PGA / processed record PGA: the factor to exceed"),
    "exceeds_as_recorded": ("", "the processed record at scale 1 exceeds the limit state: "
                                "one analysis (empty where it failed)"),
    "as_recorded_disagrees": ("", "exceeds_as_recorded is not what the scale factor implies "
                                  "(exceeds although the scale factor is > 1 or not reached, "
                                  "or survives although it is <= 1)"),
    "as_recorded_note": ("", "the disagreement or failure in words"),
    "not_reached": ("", "not exceeded up to the search bound"),
    "plateau": ("", "the local exceedance probability rises near p below the answer without "
                    "crossing it: I_p is ill-conditioned there"),
    "non_monotonic": ("", "exceeded at one intensity and not at a higher one"),
    "failed": ("", "an analysis failed"),
    "slides": ("", "an analysis up to the answer that did not overturn needed more friction "
                   "than the study's mu while in contact (True/False; empty without mu)"),
    "lifts_off": ("", "an analysis up to the answer had a normal force N <= 0 (left the "
                      "support)"),
    "processing": ("", "source record and processing, in order"),
}
"""Columns of ``records.csv`` always present (``slides`` and ``lifts_off`` from a store that
has them): name → (unit, meaning)."""


def measure_column(measure: str, critical: bool = False,
                   component: str = DEFAULT_COMPONENT) -> tuple[str, str]:
    """Column name and unit of a measure (``"pga"`` → ``("pga_g", "g")``, ``"pgv"`` →
    ``("pgv", "m/s")``; ``"sa:1.0"`` → ``("sa_1s", "g")``); ``critical`` names the critical
    value (``"pga_crit_g"``, ``"pgv_crit"``). PGA in another component than the vector peak
    is ``pga_im_g`` (``pga_g`` is the spectra's vector PGA); the table's ``component`` column
    names the component."""
    kind, period = parse_measure(measure)
    if kind == "pga":
        base = "pga" if component == DEFAULT_COMPONENT else "pga_im"
        return (f"{base}_crit_g" if critical else f"{base}_g"), "g"
    name = kind if period is None else f"sa_{period:g}s"
    return (f"{name}_crit" if critical else name), MEASURE_UNITS[kind]


def motion_measures(motion: GroundMotion, measures: Sequence[str],
                    component: str = DEFAULT_COMPONENT) -> dict[str, float]:
    """Every measure of ``motion`` in ``component`` by its column name
    (:func:`measure_column`)."""
    return {measure_column(m, component=component)[0]: intensity_measure(motion, m, component)
            for m in measures}


def _table_measures(measures: Sequence[str], component: str) -> list[str]:
    """The measures with columns of their own: the vector-peak PGA is ``pga_g``."""
    return [m for m in measures
            if component != DEFAULT_COMPONENT or parse_measure(m)[0] != "pga"]


_FLAGS = ("not_reached", "plateau", "non_monotonic", "failed")
_VALIDITY = ("slides", "lifts_off")  # slides: True/False, empty without mu
_ORDER = ["motion", "kind", "source_record", "mode", "tan_alpha", "limit_state", "R",
          "pga_recorded_g", "pga_g", "component"]


def _motion_table(store, motions: Sequence[GroundMotion], measures: Sequence[str],
                  component: str = DEFAULT_COMPONENT):
    """One row per motion and requested (mode, tan α, limit state, R) of the store, in the
    store's order (motions as in the ensemble file)."""
    import pandas as pd

    by_name = {m.name: m for m in motions}
    stored = [str(v) for v in store["motion"].values]
    missing = [n for n in stored if n not in by_name]
    if missing:
        raise ValueError(f"motions {missing} of the store are not in the ensemble file given")
    ims = _table_measures(measures, component)
    per_motion = []
    for name in stored:
        motion, who = by_name[name], identity(by_name[name])
        per_motion.append({"motion": name, "kind": who["kind"],
                           "source_record": who["source_record"],
                           "pga_recorded_g": motion.metadata.get("recorded_pga_g", math.nan),
                           "pga_g": motion.pga_g, "component": component,
                           **motion_measures(motion, ims, component),
                           "processing": who["processing"]})
    info = pd.DataFrame(per_motion)
    validity = [f for f in _VALIDITY if f in store]
    table = requested_answers(store, ["pga_crit", "pga_crit_g", *_FLAGS, *validity])
    table = table.merge(info, on="motion", how="left", sort=False)
    # the store's order: motions as in the ensemble file, limit states by severity
    labels = {"motion": stored, "mode": [str(v) for v in store["mode"].values],
              "limit_state": [str(v) for v in store["limit_state"].values]}
    for column, order in labels.items():
        table[column] = pd.Categorical(table[column], categories=order, ordered=True)
    table = table.sort_values(["motion", "mode", "tan_alpha", "limit_state", "R"],
                              kind="stable").reset_index(drop=True)
    for column in labels:
        table[column] = table[column].astype(str)
    for flag in _FLAGS:
        table[flag] = table[flag].astype(bool)
    if "lifts_off" in table:  # True/False where the searches were monitored, else empty
        table["lifts_off"] = unmonitored_empty(store, table)
    if "slides" in table:  # True/False like the other flags, empty without the study's mu
        table["slides"] = nullable_flag(table["slides"])
    scale = table["pga_crit_g"] / table["pga_g"]  # NaN where not reached
    table["scale_factor"] = scale
    for m in ims:
        column = measure_column(m, component=component)[0]
        table[measure_column(m, True, component)[0]] = scale * table[column]
    for column, value in quantity_values(store.attrs).items():
        table[column] = value
    head = [*_ORDER, *(measure_column(m, component=component)[0] for m in ims),
            *QUANTITY_COLUMNS, "pga_crit", "pga_crit_g", "scale_factor", *_FLAGS, *validity,
            *(measure_column(m, True, component)[0] for m in ims), "processing"]
    return table[head]


def record_table(store, motions: Sequence[GroundMotion], measures: Sequence[str] = ("pga",),
                 *, kinds: Sequence[str] = ("record",), component: str = DEFAULT_COMPONENT):
    """The per-record table of a study.

    Parameters
    ----------
    store : xarray.Dataset
        The study's spectra store (``results/<study>/spectra.zarr``).
    motions : sequence of GroundMotion
        The motions of its ensemble file (:func:`rocking.motions.ensemble_io.load_ensemble`).
    measures : sequence of str
        Intensity measures beside the PGA (``"pgv"``, ``"sa:<T>"``; ``"pga"`` is always
        given).
    kinds : sequence of str
        ``"record"`` (default: the recorded motions) and/or ``"synthetic"``.
    component : str
        Horizontal component of the measures (:data:`rocking.motions.measures.COMPONENTS`).

    Returns
    -------
    pandas.DataFrame
        One row per motion and requested (mode, tan α, limit state, R): the columns of
        :data:`RECORD_COLUMNS`, ``kind``, ``source_record``, each measure of the motion and
        its critical value (``pgv``, ``pgv_crit`` [m/s]; ``sa_1s``, ``sa_1s_crit`` [g]).
    """
    table = _motion_table(store, motions, measures, component)
    return table[table["kind"].isin(list(kinds))].reset_index(drop=True)


_AS_RECORDED = ("exceeds_as_recorded", "as_recorded_disagrees", "as_recorded_note")


def as_recorded(table, motions: Sequence[GroundMotion], *, accuracy="default",
                omega_n: float | None = None, zeta: float | None = None):
    """Whether each processed record at scale 1 exceeds each limit state: one analysis.

    Every (motion, mode, tan α, R) of ``table`` is analysed once at the record's own
    intensity, PGA/(g tan α) = ``pga_g``/tan α, with the engine and tolerances of the
    spectra (:func:`rocking.fragility.stripes.stripe_outcomes`: a failed analysis is retried
    at a tighter tolerance), and every limit state of its rows is decided from that one
    response.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`record_table` (any rows of it).
    motions : sequence of GroundMotion
        The motions of the table (by name).
    accuracy : str, dict or Accuracy
        The store's tolerances (its ``tolerances`` attribute).
    omega_n, zeta : float, optional
        Contact model of "3d-damped" [rad/s], [-] (the store's ``search_options``).

    Returns
    -------
    pandas.DataFrame
        ``table`` with ``exceeds_as_recorded`` (nullable boolean: missing where the analysis
        failed), ``as_recorded_disagrees`` (the answer is not the one the scale factor
        implies: exceeding although the scale factor is > 1 or not reached, surviving
        although it is <= 1) and ``as_recorded_note`` (that in words) after
        ``scale_factor``.
    """
    import pandas as pd

    from rocking.dynamics.bodies import Cylinder
    from rocking.dynamics.contact import Contact
    from rocking.fragility.stripes import stripe_outcomes
    from rocking.spectra.accuracy import Accuracy
    from rocking.spectra.limit_states import parse_limit_states

    acc = Accuracy.of(accuracy)
    contact = Contact.of(omega_n, zeta)
    by_name = {m.name: m for m in motions}
    exceeds = pd.Series(pd.NA, index=table.index, dtype="boolean")
    for (name, mode, tan_alpha, R), rows in table.groupby(
            ["motion", "mode", "tan_alpha", "R"], sort=False):
        motion = by_name[name]
        states = parse_limit_states(list(rows["limit_state"]), sort=False)
        # the record's own intensity: the analysis runs at scale 1
        at_one = np.array([motion.pga_g / float(tan_alpha)])
        hit, failed, _ = stripe_outcomes(Cylinder(float(R), float(tan_alpha)), motion,
                                         states, at_one, str(mode), acc, contact=contact)
        if not failed[0]:  # one row per limit state, in the order of ``states``
            exceeds[rows.index] = hit[0]
    out = table.copy()
    implied = ~out["not_reached"] & (out["scale_factor"] <= 1.0)
    disagrees = (exceeds.fillna(implied) != implied).astype(bool)
    notes = [_note(e, s, nr, d) for e, s, nr, d in
             zip(exceeds, out["scale_factor"], out["not_reached"], disagrees, strict=True)]
    at = list(out.columns).index("scale_factor") + 1
    for k, (column, values) in enumerate(zip(_AS_RECORDED, (exceeds, disagrees, notes),
                                             strict=True)):
        out.insert(at + k, column, values)
    return out


def _note(exceeds, scale: float, not_reached: bool, disagrees: bool) -> str:
    """Why ``exceeds_as_recorded`` is not what the scale factor implies, in words."""
    import pandas as pd

    if pd.isna(exceeds):
        return "the analysis at scale 1 failed"
    if not disagrees:
        return ""
    if exceeds:
        first = "it is not exceeded up to the search bound" if not_reached else \
            f"its critical intensity is at scale {scale:.3g}"
        return f"exceeds at scale 1 although {first} (rocking is not monotonic in the intensity)"
    return (f"survives at scale 1 although it exceeds at scale {scale:.3g} "
            "(rocking is not monotonic in the intensity)")


def suite_fragility(table, measures: Sequence[str], upper: float | None,
                    component: str = DEFAULT_COMPONENT):
    """Lognormal fragility of every (mode, tan α, limit state, R) in each measure, per group
    of motions: the fits of :func:`rocking.fragility.refit.fit_cells` (each motion's
    critical measure, its critical vector-peak PGA times its ratio of the measure to it).

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`record_table` of every motion (``kinds=("record", "synthetic")``).
    measures : sequence of str
        ``"pga"`` [g], ``"pgv"`` [m/s], ``"sa:<T>"`` [g].
    upper : float or None
        Search bound PGA/(g tan α) [-]: a motion not reached is right-censored at the
        measure its record has when scaled to it (None: not-reached motions left out).
    component : str
        The component of ``table``'s measures (its ``component`` column), written in each
        row's ``component``.

    Returns
    -------
    pandas.DataFrame
        Per ``motions`` (``"records"``, and ``"synthetic"`` when there are any) and
        ``measure``: the columns of :func:`~rocking.fragility.refit.fit_cells`;
        ``attrs["bootstrap"]`` holds the resamples' θ and β, (rows, resamples) each.
    """
    import pandas as pd

    from rocking.fragility.refit import fit_cells

    frames, medians, betas = [], [], []
    for kind, group_name in (("record", "records"), ("synthetic", "synthetic")):
        part = table[table["kind"] == kind]
        if part.empty:
            continue
        critical = part.assign(pga_crit=part["pga_crit_g"] / part["tan_alpha"])
        if upper is None:  # not reached and no bound: left out, as said
            critical = critical[~critical["not_reached"].astype(bool)]
        for measure in measures:
            column = measure_column(measure, component=component)[0]
            info = part.drop_duplicates("motion")
            ratios = dict(zip(info["motion"].astype(str),
                              info[column].to_numpy(float) / info["pga_g"].to_numpy(float),
                              strict=True))
            fits, samples = fit_cells(critical, measure, component, ratios=ratios,
                                      bound=upper)
            fits.insert(0, "motions", group_name)
            fits["measure"] = measure  # the study's spelling (sa:1.0), as configured
            frames.append(fits)
            medians.append(samples.median)
            betas.append(samples.beta)
    frame = pd.concat(frames, ignore_index=True)
    frame.attrs["bootstrap"] = (np.concatenate(medians), np.concatenate(betas))
    return frame


def suite_fragilities(tables: dict, measures: Sequence[str], upper: float | None):
    """:func:`suite_fragility` of each component's :func:`record_table` (``tables``:
    component → table), stacked in that order; ``attrs["bootstrap"]`` the resamples of
    every row, in the same order."""
    import pandas as pd

    fits = [suite_fragility(t, measures, upper, c) for c, t in tables.items()]
    samples = tuple(np.concatenate([f.attrs["bootstrap"][i] for f in fits]) for i in (0, 1))
    for f in fits:  # pandas compares the attrs of the frames it joins: arrays cannot be
        f.attrs.clear()
    out = pd.concat(fits, ignore_index=True)
    out.attrs["bootstrap"] = samples
    return out


def _headers(columns: Sequence[str], measures: Sequence[str],
             component: str = DEFAULT_COMPONENT) -> dict[str, str]:
    units = {k: u for k, (u, _) in RECORD_COLUMNS.items()}
    for m in measures:
        for critical in (False, True):
            name, unit = measure_column(m, critical, component)
            units[name] = unit
    units["median"] = ""  # its unit is the row's
    return {c: f"{c} [{units[c]}]" if units.get(c) else c for c in columns}


def write_record_tables(store_path: str | Path, motions_path: str | Path,
                        measures: Sequence[str], records_csv: str | Path,
                        fragility_csv: str | Path, *,
                        component: str = DEFAULT_COMPONENT) -> tuple[int, int]:
    """Write ``records.csv`` (the recorded motions, with :func:`as_recorded`: one analysis
    per record and (mode, tan α, R)) and ``suite_fragility.csv``.

    Parameters
    ----------
    store_path : str or Path
        A finished spectra store.
    motions_path : str or Path
        Its ensemble file.
    measures : sequence of str
        The study's intensity measures (``studies.<name>.intensity_measures``).
    records_csv, fragility_csv : str or Path
        Output files (floats at :data:`rocking.units.CSV_FLOAT_FORMAT`).
    component : str
        The study's component (``studies.<name>.component``): that of ``records.csv`` and
        of ``suite_fragility.csv`` (risk refits the fragility in a hazard's own,
        :mod:`rocking.fragility.refit`).

    Returns
    -------
    (int, int)
        Rows written to each file.
    """
    import xarray as xr

    from rocking.fragility.lognormal import censoring_bound
    from rocking.fragility.table import CRITICAL_INTENSITY, quantity_of, write_fragilities
    from rocking.motions.ensemble_io import load_ensemble
    from rocking.store import read_attrs
    from rocking.units import CSV_FLOAT_FORMAT

    motions = load_ensemble(motions_path)
    with xr.open_zarr(store_path, consolidated=True) as store:
        tables = {component: record_table(store, motions, measures,
                                          kinds=("record", "synthetic"), component=component)}
        upper = censoring_bound(store)
        quantity = quantity_of(store.attrs)
    table = tables[component]
    attrs = read_attrs(store_path)  # the spectra's tolerances and contact model
    contact = {k: v for k, v in attrs.get("search_options", {}).items()
               if k in ("omega_n", "zeta")}
    records = as_recorded(table[table["kind"] == "record"].drop(columns=["kind"]), motions,
                          accuracy=attrs["tolerances"], **contact)
    fragility = suite_fragilities(tables, measures, upper)
    records.rename(columns=_headers(records.columns, measures, component)).to_csv(
        records_csv, index=False, float_format=CSV_FLOAT_FORMAT)
    write_fragilities(fragility, fragility_csv, estimator=CRITICAL_INTENSITY, quantity=quantity,
                      samples=_bootstrap_samples(fragility),
                      float_format=CSV_FLOAT_FORMAT)
    return len(records), len(fragility)


def _bootstrap_samples(fragility):
    """``suite_fragility_bootstrap.nc``'s content: θ [the row's unit] and β of every
    resample, rows in the table's order (:mod:`rocking.fragility.bootstrap`)."""
    import xarray as xr

    from rocking.fragility.lognormal import BOOTSTRAP_SEED
    from rocking.fragility.table import CRITICAL_INTENSITY

    med, beta = fragility.attrs["bootstrap"]
    ds = xr.Dataset({"median": (("row", "resample"), med.reshape(len(fragility), -1)),
                     "beta": (("row", "resample"), beta.reshape(len(fragility), -1))},
                    coords={"row": np.arange(len(fragility)),
                            "measure": ("row", fragility["measure"].astype(str).to_numpy()),
                            "component": ("row",
                                          fragility["component"].astype(str).to_numpy())})
    ds.attrs.update(fragility=CRITICAL_INTENSITY, seed=BOOTSTRAP_SEED,
                    unit="the row's measure unit (g for pga and sa, m/s for pgv)",
                    measures=" ".join(dict.fromkeys(fragility["measure"].astype(str))))
    return ds
