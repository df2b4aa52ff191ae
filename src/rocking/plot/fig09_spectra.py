"""Figure 9: seismic performance rocking spectra per ground motion, with their mean.

One panel per limit state (overturning and excessive tilt θ > α/3 in the paper; a study's
own goals otherwise, :func:`._load.panel_limit_states`) at the study's slenderness (the paper's
tan α = 0.2; :func:`._load.main_tan_alpha`). Each motion has one colour; undamped solid,
damped dashed; the thick black line is the mean over the motions (from the study's aggregate
``mean_spectra.nc``). Points where the limit state was not reached within the search range,
or that were not computed, are not drawn. Where the damped model ran, a lower row quantifies
the paper's "essentially identical": the relative difference damped − undamped per motion and
of the means, with the spread of the per-motion differences.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.plot import _axes, _load, criteria
from rocking.plot._style import (
    MODE_STYLE,
    motion_styles,
    new_figure,
    paper_tag,
    pga_g_axis,
    plateau_suffix,
    r_axis,
    styled,
    suptitle_and_notes,
    validity_suffix,
)
from rocking.plot.comparisons import NOT_COMPUTED, Comparison, finite, first_notes, fmt, judged
from rocking.spectra.accuracy import STATED
from rocking.spectra.limit_states import limit_state_title
from rocking.spectra.modes import MODE_3D, MODE_3D_DAMPED

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

DAMPED = MODE_3D_DAMPED
"""The damped mode, drawn beside the undamped "3d" where the study ran it."""
LINESTYLES = {MODE_3D: "-", MODE_3D_DAMPED: "--"}
DAMPING_NOTE = "damping|"
"""Prefix of the measured key of the damped − undamped comparison of one limit state."""


def data(store: str | Path, means: str | Path, *, tan_alpha: float | None = None,
         modes: tuple[str, ...] | None = None, motions: str | Path | None = None,
         paper: bool = True) -> dict:
    """Arrays of Fig 9 from the store and the aggregate (``paper``: a reproduction of the
    paper, whose title names the paper's figure).

    Parameters
    ----------
    store, means : path
        The study's spectra store and ``mean_spectra.nc``.
    tan_alpha : float, optional
        Slenderness [-]; default the study's (:func:`._load.main_tan_alpha` of the modes).
    modes : tuple of str, optional
        Modes drawn; default the study's primary mode (:func:`._load.primary_mode`) and,
        with "3d", the damped model where the study ran it.
    motions : path, optional
        The ensemble file, for the physical directions of x and y.

    Returns
    -------
    dict
        ``R`` [m]; ``motions``; ``panels``: list of {``limit_state``, ``curves``:
        {mode: {motion: pga_crit (R,)}}, ``means``: {mode: mean (R,)}, ``damping``: the
        comparison of :func:`damping_effect` or None, ``plateau``: {mode: {motion: flag
        (R,)}}}; ``answer`` (the quantity's label, :func:`._load.answer_label`) and
        ``answer_definition``; ``missing``: notes. Intensities are PGA/(g tan α) [-], NaN
        where not reached or not computed.
    """
    ds = _load.open_store(store)
    agg = _load.open_means(means)
    if modes is None:
        primary = _load.primary_mode(ds)
        if primary is None:
            raise ValueError(f"the store {str(store)!r} holds no computed cell")
        damped = primary == MODE_3D and DAMPED in _load.labels(ds, "mode") and bool(
            _load.requested_cells(ds).sel(mode=DAMPED).any())
        modes = (primary, DAMPED) if damped else (primary,)
    if tan_alpha is None:
        tan_alpha = _load.main_tan_alpha(ds, list(modes)) or _load.main_tan_alpha(
            ds, list(modes[:1]))
    if tan_alpha is None or not _load.has_value(ds, "tan_alpha", tan_alpha):
        raise ValueError(f"tan_alpha={tan_alpha!r} is not in the store {str(store)!r}")
    ds = _load.select_value(ds, "tan_alpha", tan_alpha)
    agg = _load.select_value(agg, "tan_alpha", tan_alpha)
    states = _load.labels(ds, "limit_state")
    motion_names = _load.labels(ds, "motion")
    missing: list[str] = []
    panels = []
    cells = _load.requested_cells(ds)
    drawn = [ls for ls in states
             if any(m in _load.labels(ds, "mode") and bool(cells.sel(mode=m, limit_state=ls).any())
                    for m in modes)]
    for ls in _load.panel_limit_states(drawn or states):
        panels.append(_panel(ds, agg, ls, modes, motion_names, missing, tan_alpha))
    measured: dict = {"R": ds["R"].values.astype(float).tolist(),
                      "answer": _load.answer_label(ds.attrs)}
    for panel in panels:
        eff = panel["damping"]
        if eff is not None:
            measured[DAMPING_NOTE + panel["limit_state"]] = eff
            # kept for readers of older notes: the largest |Δ| of the means
            measured[f"max_rel_diff_damped_{panel['limit_state']}"] = eff["max_abs_rel_diff_means"]
    return {
        "measured": measured,
        "R": ds["R"].values.astype(float),
        "R_mean": agg["R"].values.astype(float),
        "motions": motion_names,
        "panels": panels,
        "tan_alpha": tan_alpha,
        "modes": list(modes),
        "colors": motion_styles(motion_names, _load.labels(ds, "source_record") or None),
        "axes": _axes.from_ensemble(motions),
        "motion_axes": _axes.of_records(motions),
        "missing": sorted(set(missing)),
        "paper": paper,
        "title": _load.ensemble_title(dict(ds.attrs), Path(str(store)).parent.name),
        "answer": _load.answer_label(ds.attrs),
        "answer_definition": _load.answer_definition(ds.attrs),
    }


def _panel(ds, agg, ls: str, modes, motion_names: list[str], missing: list[str],
           tan_alpha: float) -> dict:
    """Curves per motion and means per mode of one limit state."""
    curves: dict[str, dict[str, np.ndarray]] = {}
    plateau: dict[str, dict[str, np.ndarray]] = {}
    validity: dict[str, dict[str, dict[str, np.ndarray]]] = {"slides": {}}
    mean: dict[str, np.ndarray] = {}
    for mode in modes:
        if mode not in _load.labels(ds, "mode"):
            missing.append(f"mode {mode} not computed")
            continue
        sel = ds.sel(mode=mode, limit_state=ls)
        vals = sel["pga_crit"].transpose("motion", "R").values.astype(float)
        reached = ~sel["not_reached"].transpose("motion", "R").values.astype(bool)
        if not np.isfinite(vals).any():
            missing.append(f"mode {mode} not computed at tan α = {tan_alpha:g}")
            continue
        curves[mode] = {m: np.where(reached[i], vals[i], np.nan)
                        for i, m in enumerate(motion_names)}
        # answers where P rises near p without crossing it: ill-conditioned
        flag = sel["plateau"].transpose("motion", "R").values.astype(bool) & reached
        plateau[mode] = {m: flag[i] for i, m in enumerate(motion_names) if flag[i].any()}
        for name, per_mode in validity.items():  # the model's validity up to each answer
            if name in sel:  # slides is NaN (nothing said) without the study's mu: == 1
                flag = (sel[name].transpose("motion", "R").values == 1) & reached
                per_mode[mode] = {m: flag[i] for i, m in enumerate(motion_names)
                                  if flag[i].any()}
        m = _load.mean_curve(agg, mode, ls)
        if m is None:
            missing.append(f"mean of mode {mode} not aggregated")
        else:
            mean[mode] = m
    std = _load.mean_curve(agg, MODE_3D, ls, "std") if MODE_3D in modes else None
    effect = None
    if {MODE_3D, DAMPED} <= set(curves) and {MODE_3D, DAMPED} <= set(mean):
        effect = damping_effect(curves[MODE_3D], curves[DAMPED], mean[MODE_3D], mean[DAMPED],
                                std)
    return {"limit_state": ls, "curves": curves, "means": mean, "damping": effect,
            "plateau": plateau, **validity}


def damping_effect(undamped: dict, damped: dict, mean_u: np.ndarray, mean_d: np.ndarray,
                   std_u: np.ndarray | None = None) -> dict:
    """How far the damped spectra are from the undamped ones, per R.

    Parameters
    ----------
    undamped, damped : dict of str to ndarray
        Critical intensities per motion over R (NaN where not reached).
    mean_u, mean_d : ndarray
        Ensemble means over R.
    std_u : ndarray, optional
        Standard deviation among motions of the undamped intensities over R.

    Returns
    -------
    dict
        Lists over R: ``rel_diff_means`` (d − u)/u of the means; ``paired_mean``,
        ``paired_std``, ``paired_se``, ``paired_n``: the per-motion relative differences
        (motions reaching the limit state in both models); ``se_rel_diff_means``: the standard
        error of ``rel_diff_means`` (std of the paired differences d − u over √n, ÷ mean u);
        ``cov_undamped`` (std/mean among motions); and ``max_abs_rel_diff_means`` with
        ``R_index_of_max``.
    """
    rel = (np.asarray(mean_d) - np.asarray(mean_u)) / np.asarray(mean_u)
    per_motion = np.array([(damped[m] - undamped[m]) / undamped[m] for m in undamped])
    n = np.sum(np.isfinite(per_motion), axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        pm = np.nanmean(np.where(n > 0, per_motion, 0.0), axis=0)
        ps = np.nanstd(per_motion, axis=0, ddof=1) if per_motion.shape[0] > 1 else np.nan * pm
        se = ps / np.sqrt(n)
    pm = np.where(n > 0, pm, np.nan)
    ps = np.where(n > 1, ps, np.nan)
    se = np.where(n > 1, se, np.nan)
    # the difference of the means against its standard error: the paired differences d − u
    # scatter among motions, and their mean over n motions has SE = std/√n (relative to mean u)
    diff = np.array([damped[m] - undamped[m] for m in undamped])
    with np.errstate(invalid="ignore", divide="ignore"):
        se_means = (np.nanstd(diff, axis=0, ddof=1) / np.sqrt(n) / np.abs(np.asarray(mean_u))
                    if diff.shape[0] > 1 else np.full(rel.shape, np.nan))
    se_means = np.where(n > 1, se_means, np.nan)
    cov = (np.asarray(std_u) / np.asarray(mean_u)) if std_u is not None else np.full_like(rel,
                                                                                          np.nan)
    finite = np.isfinite(rel)
    k = int(np.nanargmax(np.abs(np.where(finite, rel, np.nan)))) if finite.any() else -1
    return {
        "rel_diff_means": rel.tolist(),
        "se_rel_diff_means": np.asarray(se_means, float).tolist(),
        "paired_mean": pm.tolist(),
        "paired_std": ps.tolist(),
        "paired_se": se.tolist(),
        "paired_n": n.astype(int).tolist(),
        "cov_undamped": np.asarray(cov, dtype=float).tolist(),
        "max_abs_rel_diff_means": float(abs(rel[k])) if k >= 0 else None,
        "R_index_of_max": k if k >= 0 else None,
        "per_motion": {m: ((damped[m] - undamped[m]) / undamped[m]).tolist() for m in undamped},
    }


@styled
def plot(d: dict) -> Figure:
    """One column per limit state: spectra above and, where the damped model ran,
    damped − undamped below."""
    panels = d["panels"]
    ncols = max(len(panels), 1)
    damped = DAMPED in d.get("modes", (MODE_3D, DAMPED))
    # wide enough for a two-column legend per panel (the record and ten pairs, each with its
    # count of answers on a plateau) beside the right-hand PGA [g] axis
    width = 12.5 if ncols > 1 else 7.0
    # the legend under each spectra panel: about 0.13 in per row of it
    rows = -(-(len(d["motions"]) + 2) // (2 if len(d["motions"]) > 4 else 1)) + 2
    extra = 0.13 * rows
    if damped:
        fig, axes = new_figure(width, 8.0 + extra, nrows=2, ncols=ncols, squeeze=False,
                               sharex="col", height_ratios=(2.2 + extra / 2.5, 1.0))
    else:
        fig, axes = new_figure(width, 6.0 + extra, ncols=ncols, squeeze=False)
    colors = {m: st["color"] for m, st in d["colors"].items()}
    for col, panel in enumerate(panels):
        _spectra_panel(axes[0][col], d, panel, colors)
        if damped:
            _difference_panel(axes[1][col], d, panel, colors)
    modes = d.get("modes", [MODE_3D, DAMPED])
    styles = "\nsolid undamped, dashed damped" if damped else (
        f"\n{MODE_STYLE.get(modes[0], {}).get('label', modes[0])} model")
    title = (f"Performance spectra per motion, {d.get('title', 'ensemble')}, tan α = "
             f"{d['tan_alpha']:g}{paper_tag(d, 'Fig 9')}{styles}")
    # a suite: every record's own principal axes, not the first record's alone
    axes_text = d.get("motion_axes", {}).get("text") or d["axes"]["text"]
    suptitle_and_notes(fig, {**d, "axes": {**d["axes"], "text": axes_text}}, title,
                       intensity=". Intensity: PGA = max √(ügx² + ügy²) (vector), "
                       "normalized by g tan α.")
    return fig


MEAN_STYLE = {"color": "0.55", "lw": 3.4, "alpha": 0.75, "zorder": 1.5}
"""The means: broad and grey under the motions' lines, so that the record (black, on top)
stays visible where it runs along them."""


def _spectra_panel(ax, d: dict, panel: dict, colors: dict) -> None:
    from matplotlib.lines import Line2D

    record = next(iter(d["motions"]), None)  # the ensemble's first motion, drawn last
    for mode, curves in panel["curves"].items():
        for motion, y in curves.items():
            ax.plot(d["R"], y, color=colors[motion], ls=LINESTYLES.get(mode, "-"), lw=0.8,
                    marker=".", ms=3, zorder=3 if motion == record else 2)
    lone = len(d["R_mean"]) == 1  # one size: a line of one point draws nothing, mark it
    for mode, y in panel["means"].items():
        ax.plot(d["R_mean"], y, ls=LINESTYLES.get(mode, "-"), marker="_" if lone else None,
                ms=18, mew=2.6, label=f"mean, {'damped' if mode == DAMPED else 'undamped'}",
                **MEAN_STYLE)
    # conditioning in the legend: per motion, how many of its answers are on a plateau
    counts = {m: sum(int(np.sum(f[m])) for f in panel.get("plateau", {}).values() if m in f)
              for m in d["motions"]}
    n_points = {m: sum(int(np.isfinite(c[m]).sum()) for c in panel["curves"].values() if m in c)
                for m in d["motions"]}
    slides = {m: sum(int(np.sum(v[m])) for v in panel.get("slides", {}).values() if m in v)
              for m in d["motions"]}
    ax.set_title(limit_state_title(panel["limit_state"]))
    ax.set_ylabel(f"{d.get('answer', 'critical')} PGA/(g tan α) [-]")
    r_axis(ax, d["R"], label=DAMPED not in d.get("modes", ()))
    pga_g_axis(ax, d["tan_alpha"])
    handles = [Line2D([], [], color=colors[m], lw=0.8, label=d["colors"][m]["label"]
                      + plateau_suffix(counts[m], n_points[m])
                      + validity_suffix(slides[m], n_points[m]))
               for m in d["motions"]]
    handles = ax.get_legend_handles_labels()[0] + handles
    ncols = 2 if len(handles) > 6 else 1
    # the axis follows the data (a little headroom); the legend goes below the panel, where
    # it covers no curve whatever their shape or number of sizes
    ys = [*(y for c in panel["curves"].values() for y in c.values()),
          *panel["means"].values()]
    top = max((float(np.nanmax(y)) for y in ys if np.isfinite(y).any()), default=1.0)
    ax.set_ylim(0.0, 1.06 * top)
    # the legend says what each curve is: the quantity, and what a plateau means
    title = "\n".join(t for t in (
        d.get("answer_definition", ""),
        "plateau: below the answer the share of exceeding intensities nears it unreached"
        if any(counts.values()) else "") if t) or None
    below = -0.03 if DAMPED in d.get("modes", ()) else -0.12  # under the R axis if it has one
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, below), ncols=ncols,
              fontsize=6.5, title=title, title_fontsize=6.5, frameon=False)


def _difference_panel(ax, d: dict, panel: dict, colors: dict) -> None:
    eff = panel["damping"]
    ax.set_xlabel("R [m]")
    ax.set_ylabel("damped − undamped [%]")
    ax.axhline(0.0, color="0.5", lw=0.8)
    if eff is None:
        ax.text(0.5, 0.5, "needs both models", ha="center", va="center", transform=ax.transAxes)
        return
    for motion, rel in eff["per_motion"].items():
        ax.plot(d["R"], 100 * np.asarray(rel, float), ".", color=colors[motion], ms=4)
    # the band the verdict uses: the difference of the means ± 2 of its standard errors
    rel = np.asarray(eff["rel_diff_means"], float)
    se = np.asarray(eff.get("se_rel_diff_means") or eff["paired_se"], float)
    ax.fill_between(d["R_mean"], 100 * (rel - 2 * se), 100 * (rel + 2 * se), color="0.8",
                    label="± 2 standard errors of the difference of the means")
    ax.plot(d["R_mean"], 100 * np.asarray(eff["rel_diff_means"], float), color="black", lw=2.0,
            label="difference of the means")
    ax.legend(loc="best", fontsize=6.5)


# ------------------------------------------------------ comparison with the paper


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    m = first_notes(notes, "fig09_spectra").get("measured", {})
    rows = []
    for key, eff in m.items():
        if not key.startswith(DAMPING_NOTE):
            continue
        ls = key.removeprefix(DAMPING_NOTE)
        if _load.excessive_tilt([ls]) is None:  # the paper's per-motion claim (overturning)
            rows.append(per_motion_row(ls, eff, m.get("R")))
        rows.append(_damping_row(ls, eff, m.get("R")))
    if not rows:
        rows.append(Comparison("fig09_spectra", "Undamped and damped spectra essentially "
                               "identical (§5.2)", "essentially identical", "—", NOT_COMPUTED,
                               "the damped or the undamped model was not run at tan α = 0.2"))
    return rows


def per_motion_row(ls: str, eff: Mapping, R: list | None = None) -> Comparison:
    """The paper's "essentially identical" judged per motion (:func:`.criteria.share_within`):
    the share of (motion, R) pairs whose damped and undamped answers differ by at most
    :data:`.criteria.PER_MOTION_TOL`, against :data:`.criteria.PER_MOTION_SHARE`."""
    per = eff.get("per_motion") or {}
    values = [v for rel in per.values() for v in rel if v is not None]
    within, total = criteria.share_within(values)
    tol, share = criteria.PER_MOTION_TOL, criteria.PER_MOTION_SHARE
    finite_values = [float(v) for v in values if finite(float(v))]
    span = (f"; differences {100 * min(finite_values):+.0f} % to "
            f"{100 * max(finite_values):+.0f} %") if finite_values else ""
    ours = (f"{within} of {total} (motion, R) pairs ({100 * within / total:.0f} %) within "
            f"±{100 * tol:g} %{span}") if total else "—"
    e, q = STATED["default"]
    rule = (f"at least {100 * share:g} % of the pairs within ±{100 * tol:g} %: a default "
            f"answer lies within {100 * e:g} % of the converged I10 in {100 * q:g} % of the "
            "cells (docs/performance.md), so identical models' answers differ by more than "
            f"twice that in up to {100 * (1 - share):g} % of the pairs")
    return judged("fig09_spectra", f"Undamped and damped spectra per motion, "
                  f"{limit_state_title(ls)} (§5.2: 'essentially identical'; Fig 9 draws "
                  "every motion)", "essentially identical per motion", ours,
                  (within >= share * total) if total else None, rule,
                  f"only {100 * within / max(total, 1):.0f} % of the pairs are within "
                  f"±{100 * tol:g} % (criterion: {rule})",
                  "the damped or the undamped model reached no answer")


DAMPING_RTOL = STATED["default"][0]
"""Difference of the means that is "essentially identical" whatever its scatter [-]: the
stated error e of a ``default`` answer against the converged I10
(``rocking.spectra.accuracy.STATED``); a mean of such answers carries an error up to e that
the two models need not share (docs/models.md, "Verdicts and their criteria")."""


def damping_judgement(eff: Mapping) -> dict:
    """Per R, is the damped mean "essentially identical" to the undamped one?

    A difference of the means is accepted when it is small (≤ :data:`DAMPING_RTOL`) or when
    it is within two standard errors of itself (``se_rel_diff_means``; older notes: the
    standard error of the per-motion differences): the ensemble's scatter explains it.

    Returns
    -------
    dict
        ``ok`` (list of bool per R), ``noise`` (indices accepted only through the scatter),
        ``small_systematic`` (indices with |Δ| ≤ 5 % but beyond 2 SE), ``failed`` (indices).
    """
    rel = [float("nan") if v is None else float(v) for v in eff.get("rel_diff_means", [])]
    se = eff.get("se_rel_diff_means") or eff.get("paired_se") or [None] * len(rel)
    se = [float("nan") if v is None else float(v) for v in se]
    ok, noise, small, failed = [], [], [], []
    for i, (d, e) in enumerate(zip(rel, se, strict=False)):
        if not math.isfinite(d):
            ok.append(True)
            continue
        within = math.isfinite(e) and abs(d) <= 2.0 * e
        good = abs(d) <= DAMPING_RTOL * (1 + 1e-9) or within
        ok.append(good)
        if not good:
            failed.append(i)
        elif abs(d) > DAMPING_RTOL:
            noise.append(i)
        elif not within:
            small.append(i)
    return {"ok": ok, "noise": noise, "small_systematic": small, "failed": failed,
            "rel": rel, "se": se}


def _damping_row(ls: str, eff: Mapping, R: list | None = None) -> Comparison:
    worst = eff.get("max_abs_rel_diff_means")
    k = eff.get("R_index_of_max")
    j = damping_judgement(eff)

    def at(idx):
        return ", ".join(f"{R[i]:g}" if R else str(i) for i in idx)

    def pm(i):
        return f"{fmt(100 * j['rel'][i], 2)} ± {fmt(200 * j['se'][i], 2)} %"

    ours = (f"largest |Δ| of the means {fmt(100 * worst, 3) if finite(worst) else '—'} %"
            + (f" at R = {R[k]:g} m, where Δ ± 2 SE = {pm(k)} (n = {eff['paired_n'][k]})"
               if k is not None and R else "")) if k is not None else "—"
    tolerance = "|Δ of the means| ≤ 5 % or within 2 standard errors of Δ, at every R"
    notes = []
    if j["noise"]:
        notes.append(f"at R = {at(j['noise'])} m Δ exceeds 5 % but lies within 2 SE (the "
                     "scatter among motions)")
    if j["small_systematic"]:
        notes.append(f"at R = {at(j['small_systematic'])} m a small systematic Δ (≤ 5 %, "
                     "beyond 2 SE)")
    if notes:
        tolerance += "; " + "; ".join(notes)
    reason = (f"at R = {at(j['failed'])} m the difference of the means exceeds both 5 % and 2 "
              "standard errors: " + "; ".join(f"R = {R[i]:g} m: {pm(i)}" if R else pm(i)
                                              for i in j["failed"]))
    return judged("fig09_spectra", f"Undamped and damped mean spectra, {limit_state_title(ls)} "
                  "(§5.2: 'essentially identical'; excessive tilt: 'differences ... practically "
                  "vanish when the average spectra are compared')", "essentially identical",
                  ours, (not j["failed"]) if finite(worst) else None, tolerance, reason)


def report_tables(notes: Mapping) -> list[tuple[str, pd.DataFrame]]:
    """Fig 9's damped against undamped means per size R, with the spread among motions."""
    import pandas as pd

    m = notes.get("measured", {})
    R = m.get("R")
    out = []
    for key, eff in m.items():
        if not key.startswith(DAMPING_NOTE) or not R:
            continue
        se = eff.get("se_rel_diff_means") or eff["paired_se"]
        judged = damping_judgement(eff)
        df = pd.DataFrame({
            "R [m]": R,
            "Δ of the means [%]": np.round(100 * np.asarray(eff["rel_diff_means"], float), 2),
            "± 2 SE of Δ [%]": np.round(200 * np.asarray(se, float), 2),
            "per-motion Δ, mean [%]": np.round(100 * np.asarray(eff["paired_mean"], float), 2),
            "motions": eff["paired_n"],
            "spread among motions, std/mean undamped [%]": np.round(100 * np.asarray(
                eff["cov_undamped"], float), 1),
            "essentially identical": ["yes" if ok else "no" for ok in judged["ok"]],
        })
        out.append((f"Damped − undamped, {limit_state_title(key.removeprefix(DAMPING_NOTE))}: "
                    "relative difference of the ensemble means with two standard errors "
                    "(std of the paired differences / √n), the mean of the per-motion "
                    "differences, and the spread among motions; identical = |Δ| ≤ 5 % or "
                    "within 2 SE", df))
    return out


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.captions import PLATEAU, QUANTITY  # noqa: E402
from rocking.plot.registry import FigureSpec  # noqa: E402


def _own_caption(notes: Mapping | None) -> str:
    """The caption from what is drawn: recorded motions and synthetic pairs, the damped
    model, answers on a plateau (without notes: :data:`CAPTION`)."""
    if notes is None:
        return FIGURE.caption
    labels = [str(c.get("label", "")) for c in (notes.get("colors") or {}).values()]
    synthetic = sum(lab.startswith("synthetic") for lab in labels)
    recorded = len(labels) - synthetic
    damped = any(str(k).startswith(DAMPING_NOTE) for k in (notes.get("measured") or {}))
    who = (f"the {recorded} recorded motions" if recorded > 1 else "the record") + (
        f" and {synthetic} synthetic pairs" if synthetic else "")
    text = (f"Seismic performance rocking spectra of each of {who} (one colour each, "
            "named in the legend) and their mean (thick black), one panel per limit state at "
            "the slenderness in the title.")
    if damped:
        text += (" Undamped solid, damped dashed; below, the relative difference damped − "
                 "undamped per motion and of the means, with the band of ± 2 standard errors.")
    return f"{text} {QUANTITY} {PLATEAU} Right axis PGA in g."


FIGURE = FigureSpec(
    name="fig09_spectra", module=__name__, number=9, label="Fig 9",
    caption=(
        "Seismic performance rocking spectra per ground motion (one colour each, the same "
        "as in Fig 8: record black, synthetic pairs in colour; undamped solid, damped "
        "dashed) and their means over the motions (thick black), one panel per limit state "
        "(overturning, and excessive tilt θ > α/3 or the study's own tilt goal) at the "
        "slenderness in the title. Where the damped model ran, below: the relative "
        "difference damped − undamped per motion and of the means, with the band of ± 2 "
        "standard errors. "
    ) + f"{QUANTITY} {PLATEAU} Right axis PGA in g.",
    paper=(
        "The paper's Fig 9: overturning and excessive tilt θ > α/3 at tan α = 0.2; it "
        "reports essentially identical undamped and damped overturning spectra, differences "
        "for excessive tilt that vanish in the mean, and mean spectra that are almost "
        "straight lines in R."
    ),
    scope="study", wanted=lambda s: bool(s.plan.modes),
    inputs={"complete": "spectra", "means": "means", "motions": "motions"},
    params={"store": "spectra_store", "paper": "paper"},
    el_centro_only=True, own_caption=_own_caption)
"""Fig 9, for every study (its primary mode at one tan α)."""
