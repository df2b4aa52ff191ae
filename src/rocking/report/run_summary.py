"""The report's "what was run" section: the configuration, grids, modes, accuracy and contact
parameters read from the stores' attributes, the ensembles' processing and seeds, the record's
PGA and the wall times of the main jobs (:func:`what_was_run`: rows of (item, value)).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from rocking.config.products import SpectraSpec, TiltMapSpec
from rocking.plot import _load
from rocking.plot.comparisons import fmt
from rocking.spectra.limit_states import limit_state_title
from rocking.store.attrs import decode_attrs
from rocking.study.aggregate import monitored

SHOWN = 10
"""Grids with at most this many values are listed in full, longer ones as a range."""


def grid_text(values: Sequence[float], unit: str = "") -> str:
    """``"0.5, 1, 2 m"`` for short grids, ``"20 values, 0.5–10 m (step 0.5)"`` for long."""
    v = [float(x) for x in values]
    if not v:
        return "none"
    u = f" {unit}" if unit else ""
    if len(v) <= SHOWN:
        return ", ".join(f"{x:g}" for x in v) + u
    steps = np.diff(v)
    step = f" (step {steps[0]:g})" if np.allclose(steps, steps[0], rtol=1e-6) else ""
    return f"{len(v)} values, {min(v):g}–{max(v):g}{u}{step}"


def _motions_text(motions: Sequence[Mapping], spec: SpectraSpec) -> str:
    """"<record> and n synthetic pairs (seed s)", or for a suite "k records and n pairs"."""
    records = [m for m in motions if _is_recorded(m)]
    n_pairs = len(motions) - max(len(records), 1)
    pairs = (f" and {n_pairs} synthetic pairs (seed {spec.ensemble.seed})" if n_pairs
             else ", no synthetic pairs")
    if len(records) > 1:
        return f"a suite of {len(records)} records{pairs}"
    return f"{motions[0]['label']}{pairs}"


def study_rows(path: str | Path) -> list[tuple[str, str]]:
    """What a spectra store says was run: ensemble, grids, limit states, modes per tan α,
    accuracy, contact parameters, version (its ``config`` read as a
    :class:`~rocking.config.products.SpectraSpec`)."""
    ds = _load.open_store(path)
    attrs = decode_attrs(ds.attrs)
    spec = SpectraSpec.from_attrs(attrs["config"])
    motions = attrs["ensemble"]["motions"]
    p = f"study {spec.study}"
    rows = [
        (f"{p}: motions", f"ensemble {spec.ensemble.name}: {_motions_text(motions, spec)}; "
                          + ", ".join(m["name"] for m in motions)),
        (f"{p}: sizes R", grid_text(spec.R, "m")),
        (f"{p}: slenderness tan α", grid_text(spec.plan.tan_alpha)),
        (f"{p}: limit states", ", ".join(limit_state_title(ls)
                                         for ls in spec.plan.limit_states)),
        (f"{p}: modes per tan α", modes_text(ds)),
        (f"{p}: accuracy", f"preset {spec.accuracy.preset or 'custom'}"
                           f": {tolerances_text(attrs['tolerances'])}; search up to "
                           f"PGA/(g tan α) = {fmt(spec.upper)}; "
                           + stated_error_text(spec.accuracy)),
    ]
    if spec.damping is not None:
        rows.append((f"{p}: damped contact (3d-damped)",
                     f"ωn = {fmt(spec.damping.omega_n)} rad/s, ζ = {fmt(spec.damping.zeta)} "
                     "(Fig 4 also overlays the paper's eight pairs ωn ∈ {200, 2000} rad/s × "
                     "ζ ∈ {0.05, 0.5, 5, 50})"))
    rows.append((f"{p}: the critical intensity", quantity_text(attrs)))
    rows.append((f"{p}: conditioning of the answers", plateau_text(ds)))
    if "lifts_off" in ds:
        rows.append((f"{p}: validity of the answers", validity_text(ds, spec.mu)))
        if spec.mu is not None:
            rows.append((f"{p}: sliding before overturning", sliding_text(ds, spec.mu)))
    rows.append((f"{p}: package version", f"rocking {attrs['rocking_version']}"))
    return rows


def stated_error_text(accuracy) -> str:
    """The one accuracy figure of the answers: the preset's stated error against the
    converged I10 (``rocking.spectra.accuracy.STATED``, docs/performance.md)."""
    from rocking.study.verify import stated_error

    e, q = stated_error(accuracy)
    return (f"{100 * q:g} % of the answers lie within {100 * e:g} % of the converged I10 "
            "(docs/performance.md)")


def tolerances_text(t: Mapping) -> str:
    """The accuracy settings of a store (:class:`rocking.spectra.accuracy.Accuracy` as
    attributes) in words: integration tolerance, scan grid, local sample."""
    parts = []
    if "rtol" in t:
        parts.append(f"time integration to a relative tolerance of {t['rtol']:g}"
                     + (f" ({t['rtol_damped']:g} for the damped model)"
                        if t.get("rtol_damped") not in (None, t["rtol"]) else ""))
    if t.get("scan_step") is not None:
        parts.append(f"intensity scanned upwards on a {100 * t['scan_step']:g} % grid "
                     "(its offset random per cell, seeded from the cell)")
    if t.get("local_step") is not None:
        reach = (f" from {100 * t['local_below']:g} % below to {100 * t['local_above']:g} % "
                 "above" if t.get("local_below") is not None and t.get("local_above")
                 is not None else "")
        parts.append(f"P(s) sampled around each first exceedance{reach} (in ln I), one "
                     f"analysis at a random place in each {100 * t['local_step']:g} % stratum")
    if t.get("rest_tilt") is not None:
        parts.append(f"an analysis ends early once the body is at rest (tilt below "
                     f"{t['rest_tilt']:g} rad)")
    known = {"name", "rtol", "rtol_damped", "scan_step", "local_step", "local_below",
             "local_above", "rest_tilt"}
    parts += [f"{k} = {v}" for k, v in t.items() if k not in known and v is not None]
    return "; ".join(parts) or "not recorded"


def quantity_text(attrs: Mapping) -> str:
    """What the store's answers are (its ``quantity`` attribute), in words."""
    from rocking.spectra.quantity import Quantity
    from rocking.study.aggregate import store_quantity

    q = Quantity.from_value(store_quantity(attrs))
    step = (attrs.get("tolerances") or {}).get("scan_step")
    if not q.is_quantile:
        return (q.describe(step) + ": the smallest exceeding intensity the scan saw, which "
                "moves with the grid (docs/models.md, \"The critical intensity\")")
    return (f"{q.describe(step)}: per motion, the lowest PGA/(g tan α) near which at least "
            f"{100 * q.p:g} % of the intensities exceed the goal (I50 beside it in the store); "
            "the means and fragilities are of these answers")


def plateau_text(ds) -> str:
    """How many computed answers per mode carry the ``plateau`` flag, and what it means."""
    reached = ~ds["not_reached"].values.astype(bool)
    if "requested" in ds:
        reached &= ds["requested"].broadcast_like(ds["not_reached"]).transpose(
            *ds["not_reached"].dims).values.astype(bool)
    flag = ds["plateau"].values.astype(bool) & reached
    axis = ds["not_reached"].dims.index("mode")
    per = [f"{m}: {int(np.take(flag, i, axis).sum())} of {int(np.take(reached, i, axis).sum())}"
           for i, m in enumerate(_load.labels(ds, "mode"))]
    return ("answers flagged plateau (the local exceedance probability rises near p below "
            "the answer without crossing it, so a small change of the response could move "
            "the answer down) — " + "; ".join(per) + ".")


def validity_text(ds, mu: float | None) -> str:
    """How many computed answers per mode were reached by analyses that needed more friction
    than the study's μ (``slides``) or lifted off (``lifts_off``), and what that means."""
    requested = np.ones(ds["lifts_off"].shape, dtype=bool)
    if "requested" in ds:
        requested = ds["requested"].broadcast_like(ds["lifts_off"]).transpose(
            *ds["lifts_off"].dims).values.astype(bool)
    axis = ds["lifts_off"].dims.index("mode")
    seen = np.ones(requested.shape, dtype=bool) if mu is not None else monitored(
        ds).broadcast_like(ds["lifts_off"]).transpose(*ds["lifts_off"].dims).values.astype(bool)
    if not seen.any():
        return ("no support friction coefficient given and no sliding goal: the analyses "
                "ran without the support monitors (compiled in only where asked), so "
                "neither sliding nor lift-off was looked at; give mu: to check both "
                "(docs/models.md).")
    flags = {"lifts off": ds["lifts_off"].values.astype(bool) & requested & seen}
    if mu is not None and "slides" in ds:
        flags = {"slides": (ds["slides"].values == 1) & requested, **flags}
    per = [f"{m}: " + ", ".join(f"{name} {int(np.take(f, i, axis).sum())}"
                                for name, f in flags.items())
           + f" of {int(np.take(requested, i, axis).sum())}"
           for i, m in enumerate(_load.labels(ds, "mode"))]
    head = ("no support friction coefficient given (sliding not checked); "
            if mu is None else f"support friction coefficient μ = {fmt(mu)}; ")
    return (head + "answers whose analyses up to them " + (
        "slid while in contact (slides: an analysis that did not overturn needed more "
        "friction than μ) or " if mu is not None else "")
        + "left the support, N ≤ 0 (lifts off: nearly every overturning answer, a body "
        "falling over leaves its support) — " + "; ".join(per) + " (docs/models.md).")


SLIDING_CELLS_SHOWN = 4
"""(mode, tan α, R) cells the sliding sentence names one by one; more are summed up."""


def sliding_text(ds, mu: float) -> str:
    """In words: does the column slide before it overturns at the study's μ, and at what
    intensity.

    Per motion and (mode, tan α, R) the sliding answer (``sliding:<μ>``, sliding in
    contact) is compared with the overturning answer: the motion slides first where its
    sliding answer is reached below its overturning answer (or overturning is not
    reached), overturns first where overturning is reached at or below its sliding answer.
    Without both limit states the ``slides`` flags of the overturning answers say whether an
    analysis below them slid (no intensity)."""
    from rocking.spectra.limit_states import OVERTURNING, match_limit_state

    states = _load.labels(ds, "limit_state")
    slide = match_limit_state(f"sliding:{mu!r}", states, missing_ok=True)
    over = match_limit_state(OVERTURNING, states, missing_ok=True)
    if over is None:
        return ("no overturning answer to compare with (add 'overturning' to the limit "
                "states)")
    if slide is None:
        flags = ds["slides"].sel(limit_state=over).values == 1
        req = _requested(ds, over)
        return (f"at μ = {fmt(mu)}: {int((flags & req).sum())} of {int(req.sum())} "
                "overturning answers had an analysis below them that slid while in contact; "
                f"add 'sliding:{fmt(mu)}' to the limit states for the intensity at which it "
                "slides")
    cells, n_first, n_over, n_none, n_all = [], 0, 0, 0, 0
    for mode in _load.labels(ds, "mode"):
        for ta in ds["tan_alpha"].values:
            for R in ds["R"].values:
                at = {"mode": mode, "tan_alpha": ta, "R": R}
                req = (_requested(ds, slide, at) & _requested(ds, over, at))
                if not req.any():
                    continue
                s_g = ds["pga_crit_g"].sel(limit_state=slide, **at).values[req]
                o_g = ds["pga_crit_g"].sel(limit_state=over, **at).values[req]
                first = np.isfinite(s_g) & ~(o_g <= s_g)  # NaN: not reached
                over_first = np.isfinite(o_g) & ~(s_g < o_g)
                n_first += int(first.sum())
                n_over += int(over_first.sum())
                n_none += int((~first & ~over_first).sum())
                n_all += int(req.sum())
                text = f"{mode}, tan α = {float(ta):g}, R = {float(R):.4g} m: "
                if first.any():
                    text += (f"slides first for {int(first.sum())} of {int(req.sum())} motions "
                             f"at PGA {_span(s_g[first])}")
                else:
                    text += f"slides first for none of {int(req.sum())} motions"
                if np.isfinite(o_g).any():
                    text += f" (overturning at PGA {_span(o_g[np.isfinite(o_g)])})"
                cells.append(text)
    if n_all == 0:
        return "no cell asked for both sliding and overturning"
    if n_first == 0:
        verdict = (f"at μ = {fmt(mu)} the column overturns before it slides for every motion "
                   f"that overturns ({n_over} of {n_all}"
                   + (f"; {n_none} do neither up to the search bound)" if n_none else ")"))
    elif n_over == 0 and n_none == 0:
        verdict = f"at μ = {fmt(mu)} the column slides before it overturns for every motion"
    else:
        verdict = (f"at μ = {fmt(mu)} the column slides before it overturns for {n_first} of "
                   f"{n_all} motion answers, overturns first for {n_over}"
                   + (f", neither up to the search bound for {n_none}" if n_none else ""))
    shown = cells[:SLIDING_CELLS_SHOWN]
    more = len(cells) - len(shown)
    return (verdict + " — " + "; ".join(shown) + (f"; {more} more cells" if more else "")
            + ". Sliding is μ_req > μ while in contact in an analysis that did not overturn "
            "(the fall of an overturning body needs unbounded friction and is not counted).")


def _requested(ds, limit_state: str, at: Mapping | None = None) -> np.ndarray:
    """Requested cells of ``limit_state`` (all where the store has no ``requested``)."""
    sel = {"limit_state": limit_state, **(at or {})}
    shape = ds["pga_crit_g"].sel(**sel).shape
    if "requested" not in ds:
        return np.ones(shape, dtype=bool)
    req = ds["requested"].broadcast_like(ds["pga_crit_g"]).sel(**sel)
    return req.values.astype(bool)


def _span(values: np.ndarray) -> str:
    """``"0.41 g"`` for one value, ``"0.38–0.52 g (median 0.44 g)"`` for several."""
    v = np.sort(np.asarray(values, dtype=float))
    if v.size == 1:
        return f"{v[0]:.3g} g"
    return f"{v[0]:.3g}–{v[-1]:.3g} g (median {float(np.median(v)):.3g} g)"


def modes_text(ds) -> str:
    """``"tan α = 0.2: 3d, 3d-damped; tan α = 0.1: 3d"`` plus the share of cells not computed."""
    per = _load.modes_per_tan_alpha(ds)
    text = "; ".join(f"tan α = {t:g}: {', '.join(m) or 'none'}" for t, m in per.items())
    done = _load.computed(ds).values
    if not done.all():
        text += (f" ({int((~done).sum())} of {done.size} cells not computed: not requested "
                 "or not run, left empty)")
    return text


def tilt_map_rows(path: str | Path) -> list[tuple[str, str]]:
    """Grid and models of a Fig 7 tilt-map store (its ``config`` read as a
    :class:`~rocking.config.products.TiltMapSpec`)."""
    ds = _load.open_store(path)
    attrs = decode_attrs(ds.attrs)
    spec = TiltMapSpec.from_attrs(attrs["config"])
    return [(f"study {spec.study}: Fig 7 tilt map",
             f"record {attrs['motion']}, tan α = {spec.tan_alpha:g}, models "
             f"{', '.join(spec.modes)}; R: {grid_text(spec.R, 'm')}; PGA/(g tan α): "
             f"{grid_text(spec.intensity)}")]


def _processing_text(e: Mapping) -> str:
    """How one record was processed and how many pairs were simulated from it."""
    hp = e.get("highpass") or {}
    stand_in = f" — stand-in for {e['stand_in_for']}" if e.get("stand_in") else ""
    if e.get("rotation_deg") is None:
        rotation = "recorded axes kept"
    else:
        rotation = (f"rotated by {fmt(e.get('rotation_deg'))}° to principal axes (x = major; "
                    f"offset {fmt(e.get('principal_offset_deg'))}° from the nearest recording "
                    "axis)")
    highpass = ("no high-pass" if not hp or hp.get("kind") in (None, "none") else
                f"high-pass {hp['kind']} at {fmt(hp.get('fc_hz'))} Hz (Mw {fmt(hp.get('mw'))})")
    pairs = (f"; {e['n_synthetic']} synthetic pairs, seed {e.get('seed', '?')}"
             if e.get("n_synthetic") else "")
    return f"{e.get('label', e.get('record'))}{stand_in}; {rotation}; {highpass}{pairs}"


def ensemble_rows(path: str | Path) -> list[tuple[str, str]]:
    """Processing of an ensemble's record and its synthetic pairs (``results/motions/*.json``);
    a suite: one row per record."""
    e = json.loads(Path(path).read_text())
    name = e.get("ensemble", Path(path).stem)
    if e.get("suite"):
        return [(f"ensemble {name}", str(e.get("label")))] + [
            (f"ensemble {name}: record {r.get('record')}", _processing_text(r))
            for r in e.get("records", [])]
    return [(f"ensemble {name}", _processing_text(e))]


def _is_recorded(m: Mapping) -> bool:
    """A motion of a store's ensemble that is a record (its own source), not a pair."""
    return m.get("name") is not None and m.get("name") == m.get("source_record")


def pga_row(store: str | Path) -> tuple[str, str]:
    """The record's PGA (a suite: every record's): one number each and what it is (a figure
    may add the unprocessed record's through its ``run_rows`` hook,
    :func:`.entries.figure_run_rows`)."""
    motions = decode_attrs(_load.open_store(store).attrs)["ensemble"]["motions"]
    if not motions:
        return ("record PGA", "not recorded in the store")
    from rocking.constants import G

    def pga_g(m: Mapping) -> float:
        # stores record the motion's identity "PGA" [g]; older ones its "pga" [m/s²]
        return m["PGA"] if "PGA" in m else m["pga"] / G

    records = [m for m in motions if _is_recorded(m)]
    if len(records) > 1:  # a suite
        values = ", ".join(f"{m['label']} {pga_g(m):.3f} g" for m in records)
        return ("records' PGA", f"{values}: vector peaks max √(ax² + ay²) after each record's "
                "processing, as every spectrum is scaled")
    first = motions[0]
    return ("record PGA", f"{pga_g(first):.3f} g: vector peak max √(ax² + ay²) of "
            f"{first['label']} after rotation to principal axes and high-pass, as every "
            "spectrum is scaled (a vector peak does not depend on the rotation)")


def timing_rows(done: Sequence[str | Path] = (), ensembles: Sequence[str | Path] = (),
                elapsed_seconds: float | None = None) -> list[tuple[str, str]]:
    """Wall times of the main jobs (from their completion summaries) and of the workflow."""
    rows = []
    for path in ensembles:
        t = json.loads(Path(path).read_text()).get("timings", {})
        if t:
            rows.append((f"run time: ensemble {Path(path).stem}",
                         ", ".join(f"{k.removesuffix('_s')} {v:.1f} s" for k, v in t.items())))
    for path in done:
        s = json.loads(Path(path).read_text())
        if "wall_seconds" in s:
            before = s.get("done_before", 0)
            if s.get("store_state") in ("created", "replaced"):
                # a new store marks the chunks that hold no requested cell done at once
                origin = f"new store; {before} chunks hold no requested cell" if before else \
                    "new store"
            else:
                origin = f"resumed: {before} chunks were already done"
            points = s.get("points_computed")
            what = f" ({points} spectrum points)" if points else ""
            rows.append((f"run time: {Path(path).parent.name}/{Path(path).name.split('.')[0]}",
                         f"{s['wall_seconds']:.0f} s wall for {s.get('computed', '?')} of "
                         f"{s.get('chunks', '?')} chunks{what} on {s.get('cluster', '?')} "
                         f"({origin})"))
    if elapsed_seconds is not None and math.isfinite(elapsed_seconds):
        rows.append(("run time: workflow", f"{elapsed_seconds / 60:.1f} min from the start of "
                                           "the Snakemake invocation that wrote this report "
                                           "(jobs done by earlier invocations not counted)"))
    return rows


def what_was_run(*, stores: Sequence[str | Path] = (), tilt_maps: Sequence[str | Path] = (),
                 ensembles: Sequence[str | Path] = (), done: Sequence[str | Path] = (),
                 elapsed_seconds: float | None = None) -> list[tuple[str, str]]:
    """Rows (item, value) of the report's "what was run" section.

    Parameters
    ----------
    stores : sequence of path
        Spectra stores of the studies (configuration, grids, modes per tan α, accuracy, contact
        parameters, version).
    tilt_maps : sequence of path
        Fig 7 tilt-map stores.
    ensembles : sequence of path
        ``results/motions/<ensemble>.json`` (rotation, high-pass, seeds, timings).
    done : sequence of path
        Completion summaries ``*.done.json`` (wall times).
    elapsed_seconds : float, optional
        Time from the start of the workflow to the report [s].
    """
    rows = []
    for path in ensembles:
        rows += ensemble_rows(path)
    if stores:
        rows.append(pga_row(stores[0]))
    for path in stores:
        rows += study_rows(path)
    for path in tilt_maps:
        rows += tilt_map_rows(path)
    return rows + timing_rows(done, ensembles, elapsed_seconds)
