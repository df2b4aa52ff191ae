"""Figure 12: mean spectra of the bidirectional 3D model versus unidirectional 2D models.

For each ensemble (El Centro, black; Loma Prieta or its stand-in, red) the 3D model under both
components is compared with the 2D model under the x (major principal axis) and under the y
(minor) component alone; the intensity is the bidirectional PGA in all three (paper §5.4).
At the studies' common slenderness (tan α = 0.2 in the paper). The legend names each
ensemble by its record and the number of motions averaged; the note under the axes gives each
ensemble's axis azimuths, so the 2D curves can be matched with the paper's (whose x is E–W and
y N–S before its rotation). Open circles mark means over fewer motions than the ensemble;
means over answers flagged plateau are counted in a note. The means are of each motion's
critical intensity, the studies' quantity (I10 by default), which the legend names; studies
of different quantities are refused, never drawn side by side.
"""

from __future__ import annotations

import math
import re
import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from rocking.plot import _axes, _load, criteria
from rocking.plot._style import (
    MODE_STYLE,
    footnote,
    paper_tag,
    pga_g_axis,
    r_axis,
    styled,
    with_legend_row,
)
from rocking.plot.comparisons import DIFFERS, Comparison, finite, first_notes, fmt, judged
from rocking.spectra.limit_states import limit_state_title, parse_limit_state
from rocking.spectra.modes import MODE_2D_X, MODE_2D_Y, MODE_3D, PLANAR_MODES
from rocking.store.attrs import decode_attrs

MODES = (MODE_3D, *PLANAR_MODES)
REFERENCE_R = 10.0
"""Size of the paper's §5.4 statement (R = 10 m: ≈ 4 bidirectional, about twice 2D) [m]."""
ENSEMBLE_COLORS = ("black", "tab:red", "tab:blue", "tab:green")
MODE_LABELS = {MODE_3D: "3D, both components", MODE_2D_X: "2D, x (major axis) component only",
               MODE_2D_Y: "2D, y (minor axis) component only"}


def data(studies: Sequence[tuple], *, tan_alpha: float | None = None,
         modes: tuple[str, ...] = MODES, paper: bool = True) -> dict:
    """Mean spectra per ensemble and mode.

    ``tan_alpha`` defaults to the first study's (:func:`._load.main_tan_alpha` of its 3D and
    2D modes). Panels are the paper's overturning and excessive tilt in a reproduction of the
    paper (``paper``: absent ones and absent ensembles named), else the studies' own goals
    (:func:`._load.panel_limit_states`).

    Parameters
    ----------
    studies : sequence of (name, mean_spectra path, store path or None[, ensemble file or None])
        One entry per study; the store's attributes give the ensemble's label, motions and
        stand-in flag, the ensemble file the azimuths of x and y.

    Returns
    -------
    dict
        ``ensembles``: [{``name``, ``label``, ``stand_in``, ``n_motions``, ``axes``, ``R`` [m],
        ``panels``: {"overturning"/"excessive tilt"/goal title: {mode: mean PGA/(g tan α)
        (R,)}}}, ``titles``: the panel titles in order, ``missing``: notes; ``measured``: the
        means at R = 10 m.
    """
    ensembles = []
    missing: list[str] = []
    if tan_alpha is None and studies:
        agg = _load.open_means(studies[0][1])
        tan_alpha = (_load.main_tan_alpha(agg, list(modes))
                     or _load.main_tan_alpha(agg, list(modes[:1])))
    if tan_alpha is None:
        raise ValueError("no study of Fig 12 computed its 3D mode")
    for entry in studies:
        name, means, store = entry[:3]
        motions = entry[3] if len(entry) > 3 else None
        ens = _ensemble(name, means, store, motions, tan_alpha, modes, missing, paper)
        if ens is not None:
            ensembles.append(ens)
    names = " ".join(f"{e['name']} {e['label']}" for e in ensembles).lower()
    for wanted in ("El Centro", "Loma Prieta") if paper else ():
        if wanted.split()[0].lower() not in names:
            missing.append(f"no {wanted} ensemble in this run")
    titles = list(dict.fromkeys(t for e in ensembles for t in e["panels"]))
    answers = {e["answer"]: e["name"] for e in ensembles}
    if len(answers) > 1:  # two definitions of the answer are never set side by side
        raise ValueError("Fig 12: the studies hold different quantities ("
                         + ", ".join(f"{n}: {a}" for a, n in answers.items())
                         + "); give every study one quantity")
    measured = at_size(ensembles, REFERENCE_R)
    if ensembles:
        measured["answer"] = ensembles[0]["answer"]
    return {"ensembles": ensembles, "tan_alpha": tan_alpha, "missing": sorted(set(missing)),
            "titles": titles or ["overturning", "excessive tilt"],
            "answer": ensembles[0]["answer"] if ensembles else "critical",
            "answer_definition": ensembles[0]["answer_definition"] if ensembles else "",
            "reproduction": paper,
            "measured": measured,
            "axes": {e["name"]: e["axes"] for e in ensembles}}


def _panel_title(limit_state: str) -> str:
    """Key of a panel: the paper's "overturning" and "excessive tilt", else the goal's title."""
    if limit_state == "overturning":
        return "overturning"
    return "excessive tilt" if _load.excessive_tilt([limit_state]) else limit_state_title(
        limit_state)


def _ensemble(name: str, means, store, motions, tan_alpha: float, modes, missing: list[str],
              paper: bool = True):
    """One ensemble's curves, or None (with a note) when its tan α was not computed."""
    agg = _load.open_means(means)
    attrs = dict(agg.attrs)
    if store is not None and Path(store).exists():
        attrs = {**attrs, **_load.open_store(store).attrs}
    record, stand_in = _load.ensemble_label(attrs, name)
    n = len(_load.labels(agg, "motion")) or _count_motions(attrs)
    label = f"{record}: mean of {n} motions" if n else f"{record}: ensemble mean"
    if not _load.has_value(agg, "tan_alpha", tan_alpha):
        missing.append(f"{record}: tan α = {tan_alpha:g} not computed")
        return None
    agg = _load.select_value(agg, "tan_alpha", tan_alpha)
    states = _load.labels(agg, "limit_state")
    panels: dict[str, dict[str, np.ndarray]] = {}
    spread: dict[str, np.ndarray] = {}
    medians: dict[str, dict] = {}
    fits = fragility_table(Path(means).parent / "fragility.csv")
    chosen = (_load.paper_limit_states(states, missing, prefix=f"{record}: ") if paper else
              ((_panel_title(ls), ls) for ls in _load.panel_limit_states(states)))
    for title, ls in chosen:
        panels[title] = {}
        for mode in modes:
            y = _load.mean_curve(agg, mode, ls)
            if y is None:
                missing.append(f"{record}: mode {mode} not computed")
                continue
            panels[title][mode] = y
            fit = mle_medians(fits, tan_alpha, ls, mode)
            if fit is not None:
                medians[f"{title}|{mode}"] = fit
            for stat in ("std", "count", "n_not_reached", "censoring", "n_plateau"):
                if stat in agg and np.issubdtype(agg[stat].dtype, np.number):
                    spread[f"{title}|{mode}|{stat}"] = agg[stat].sel(
                        mode=mode, limit_state=ls).values.astype(float)
    return {"name": name, "label": label, "record": record, "stand_in": stand_in,
            "headline": headline_grids(Path(means).parent / "headline.csv"),
            "answer": _load.answer_label(agg.attrs),
            "answer_definition": _load.answer_definition(agg.attrs),
            "n_motions": n, "upper": _load.search_bound(attrs),
            "axes": _axes.from_ensemble(motions),
            "R": agg["R"].values.astype(float), "panels": panels, "spread": spread,
            "medians": medians}


def fragility_table(path: Path) -> pd.DataFrame | None:
    """The study's ``fragility.csv`` (the censoring-aware lognormal fits), None when absent."""
    return pd.read_csv(path) if Path(path).exists() else None


def mle_medians(df: pd.DataFrame | None, tan_alpha: float, limit_state: str,
                mode: str) -> dict | None:
    """The lognormal fit's medians over R of one (mode, limit state) at ``tan_alpha``.

    Returns
    -------
    dict or None
        ``R`` [m], ``median`` [PGA/(g tan α)], ``se_log`` (standard error of ln median from
        the bootstrap's 5–95 % interval, NaN without one), ``n``, ``n_censored`` (motions
        right-censored at the search bound); NaN medians where the fit failed. None when the
        table has no such row.
    """
    if df is None or df.empty:
        return None
    med = next((c for c in df.columns if c.startswith("median [")), None)
    ta = next((c for c in df.columns if c.startswith("tan_alpha")), None)
    r = next((c for c in df.columns if c.startswith("R")), None)
    if med is None or ta is None or r is None:
        return None
    names = df["limit_state"].map(lambda x: parse_limit_state(str(x)).name)
    sub = df[(df["mode"] == mode) & (names == parse_limit_state(limit_state).name)
             & np.isclose(df[ta].astype(float), tan_alpha, rtol=1e-6)].sort_values(r)
    if sub.empty:
        return None
    lo = next((c for c in sub.columns if c.startswith("median_p05")), None)
    hi = next((c for c in sub.columns if c.startswith("median_p95")), None)
    se = [criteria.se_log_from_interval(a, b) for a, b in zip(
        sub[lo] if lo else [np.nan] * len(sub), sub[hi] if hi else [np.nan] * len(sub),
        strict=True)]
    beta = next((c for c in sub.columns if c.startswith("beta")), None)
    return {"R": sub[r].astype(float).tolist(),
            "beta": pd.to_numeric(sub[beta], errors="coerce").astype(float).tolist()
            if beta else [float("nan")] * len(sub),
            "median": pd.to_numeric(sub[med], errors="coerce").astype(float).tolist(),
            "se_log": [float(x) for x in se],
            "n": sub["n"].astype(int).tolist() if "n" in sub else [],
            "n_censored": sub["n_censored"].astype(int).tolist() if "n_censored" in sub
            else [0] * len(sub)}


def _count_motions(attrs: dict) -> int:
    """Number of motions listed in a store's ``ensemble`` attribute (0 if unknown)."""
    raw = decode_attrs({"ensemble": attrs.get("ensemble")})["ensemble"]
    return len(raw.get("motions", [])) if isinstance(raw, dict) else 0


def at_size(ensembles: list[dict], R: float) -> dict:
    """Mean intensities at size ``R`` [m] (linear interpolation in R; NaN outside the grid)."""
    out = {"R": R}
    for ens in ensembles:
        for title, curves in ens["panels"].items():
            for mode, y in curves.items():
                ok = np.isfinite(y)
                inside = ok.any() and ens["R"][ok].min() <= R <= ens["R"][ok].max()
                value = float(np.interp(R, ens["R"][ok], y[ok])) if inside else float("nan")
                out[f"{ens['name']}|{title}|{mode}"] = value
                for stat in ("std", "count", "n_not_reached"):
                    s = ens.get("spread", {}).get(f"{title}|{mode}|{stat}")
                    if s is not None and inside:
                        out[f"{ens['name']}|{title}|{mode}|{stat}"] = float(
                            np.interp(R, ens["R"][ok], s[ok]))
        for key, fit in ens.get("medians", {}).items():
            out[f"{ens['name']}|{key}|mle"] = fit
        out[f"{ens['name']}|label"] = ens["label"]
        out[f"{ens['name']}|n_motions"] = ens["n_motions"]
        out[f"{ens['name']}|upper"] = ens.get("upper")
        out[f"{ens['name']}|stand_in"] = bool(ens["stand_in"])
        grids = ens.get("headline")
        if grids and math.isclose(grids["R"], R):  # the same cells as the verdict's mean
            out[f"{ens['name']}|headline"] = grids
    return out


def headline_grids(path: Path) -> dict | None:
    """The study's ``headline.csv`` in numbers (:func:`rocking.study.headline.summary`: the
    mean first exceedance of the R = 10 m 3D overturning cells on each scan grid), None
    where the study has none."""
    from rocking.study.headline import summary

    if not Path(path).is_file():
        return None
    s = summary(pd.read_csv(path))
    return None if s is None else {**s, "grids": {f"{k:g}": v for k, v in s["grids"].items()}}


def fewer_motions(ens: dict, title: str, mode: str) -> np.ndarray:
    """Sizes R where the mean of (``title``, ``mode``) covers fewer motions than the ensemble.

    Uses the aggregate's ``censoring`` column when there is one, else ``n_not_reached`` > 0,
    else ``count`` below the ensemble's number of motions.
    """
    spread = ens.get("spread", {})
    y = ens["panels"].get(title, {}).get(mode)
    shape = np.shape(y) if y is not None else np.shape(ens["R"])
    for key, test in (("censoring", lambda v: np.nan_to_num(v) > 0),
                      ("n_not_reached", lambda v: np.nan_to_num(v) > 0),
                      ("count", lambda v: np.isfinite(v) & (v < ens["n_motions"]))):
        v = spread.get(f"{title}|{mode}|{key}")
        if v is not None:
            return np.asarray(test(np.asarray(v, float)), bool)
    return np.zeros(shape, bool)


MODE_MARKERS = {MODE_3D: "o", MODE_2D_X: "s", MODE_2D_Y: "^"}
"""Small markers per mode, so that line styles stay readable where curves cross."""


def _plateau_note(counts: list[tuple[str, str, int, int]]) -> str:
    """One line on the means that include answers flagged plateau (ill-conditioned): per
    record, each curve's count of such sizes out of its sizes, said once per record."""
    if all(k == n for _, _, k, n in counts):
        return ("Means that include answers on a plateau (ill-conditioned): every "
                f"size of all {len(counts)} curves.")
    per: dict[str, list[str]] = {}
    for record, curve, k, n in counts:
        per.setdefault(record, []).append(f"{curve} {k}/{n}")
    return ("Sizes whose mean includes answers on a plateau (ill-conditioned), per "
            "curve: " + "; ".join(f"{record}: {', '.join(items)}"
                                  for record, items in per.items()) + ".")


def _write_ratios(ax, R: np.ndarray, curves: dict, color, censored: dict | None = None) -> None:
    """Write 2D/3D at the largest R where both are finite, at the right end of each 2D curve.

    ``censored`` (mode → bool per R) marks means over fewer motions than the ensemble (the
    others not reached at the search bound, so the mean is too low): a censored 2D mean over
    a full 3D one makes the ratio a lower bound ("≥"), the reverse an upper bound ("≤");
    both censored, neither can be said ("?").
    """
    base = curves.get(MODE_3D)
    if base is None:
        return
    censored = censored or {}
    for mode in PLANAR_MODES:
        y = curves.get(mode)
        if y is None:
            continue
        ok = np.isfinite(y) & np.isfinite(base)
        if not ok.any():
            continue
        i = int(np.flatnonzero(ok)[-1])
        low2 = bool(np.asarray(censored.get(mode, np.zeros(len(y), bool)))[i])
        low3 = bool(np.asarray(censored.get(MODE_3D, np.zeros(len(y), bool)))[i])
        bound = {(True, False): "≥", (False, True): "≤", (True, True): "?"}.get((low2, low3), "")
        ax.annotate(f"{bound}×{y[i] / base[i]:.2f} ({mode[-1]})", (R[i], y[i]), xytext=(4, 0),
                    textcoords="offset points", color=color, fontsize=6.5, va="center")


@styled
def plot(d: dict) -> Figure:
    """Two panels (overturning, excessive tilt); colour = ensemble, line style = mode."""
    titles = d.get("titles", ("overturning", "excessive tilt"))
    fig, axes, legend_row = with_legend_row(10.0 if len(titles) > 1 else 6.4, 6.4,
                                            ncols=len(titles), legend_share=0.22)
    handles, modes_seen, notes = [], [], []
    partial = False  # any mean over fewer motions than the ensemble
    on_plateau: list[tuple] = []  # curves with means over answers flagged plateau
    for k, ens in enumerate(d["ensembles"]):
        color = ENSEMBLE_COLORS[k % len(ENSEMBLE_COLORS)]
        label = ens["label"]
        if ens["stand_in"] and "stand-in" not in label:
            label += " (stand-in)"
        handles.append(Line2D([], [], color=color, lw=1.6,
                              label="\n".join(textwrap.wrap(label, 48))))
        notes.append(f"{ens['record']}: {ens['axes']['text']}.")
        for ax, title in zip(axes, titles, strict=True):
            curves = ens["panels"].get(title, {})
            censored = {}
            for mode, y in curves.items():
                ax.plot(ens["R"], y, color=color, ls=MODE_STYLE[mode]["linestyle"], lw=1.4,
                        marker=MODE_MARKERS.get(mode, "o"), ms=2.5,
                        label=f"{label}: {MODE_LABELS.get(mode, mode)}")
                few = censored[mode] = fewer_motions(ens, title, mode)
                if few.any():  # the mean leaves out motions not reached at the search bound
                    partial = True
                    ax.plot(ens["R"][few], y[few], "o", ms=7, mfc="white", mec=color, mew=1.0,
                            zorder=1)
                flagged = ens.get("spread", {}).get(f"{title}|{mode}|n_plateau")
                if flagged is not None and (np.nan_to_num(flagged) > 0).any():
                    k = int((np.nan_to_num(flagged) > 0).sum())  # counted, not ringed
                    on_plateau.append((ens["record"], f"{MODE_STYLE[mode]['label']} {title}",
                                       k, int(np.isfinite(y).sum())))
                if mode not in modes_seen:
                    modes_seen.append(mode)
            _write_ratios(ax, ens["R"], curves, color, censored)
    handles += [Line2D([], [], color="gray", lw=1.4, ls=MODE_STYLE[m]["linestyle"],
                       marker=MODE_MARKERS.get(m, "o"), ms=2.5, label=MODE_LABELS.get(m, m))
                for m in modes_seen]
    if partial:
        handles.append(Line2D([], [], ls="", marker="o", ms=7, mfc="white", mec="gray",
                              label="open marker: mean over fewer motions than the ensemble\n"
                                    "(the others not reached at the search bound)"))
    handles.append(Line2D([], [], ls="", label="×k: 2D mean / 3D mean at the largest R"
                          + ("\n≥×k: the 2D mean there leaves out motions\n(open marker), "
                             "a lower bound; ≤: the 3D one" if partial else "")))
    if on_plateau:
        notes.append(_plateau_note(on_plateau))
    for ax, title in zip(axes, titles, strict=True):
        ax.set_title(limit_state_title("overturning" if title == "overturning" else "tilt:1/3")
                     if title in ("overturning", "excessive tilt") else title)
        ax.set_ylabel(f"mean {d.get('answer', 'critical')} PGA/(g tan α) [-] "
                      "(bidirectional PGA)")
        r_axis(ax, np.concatenate([e["R"] for e in d["ensembles"]] or [np.zeros(0)]))
        left, right = ax.get_xlim()
        ax.set_xlim(left, right + 0.1 * (right - left))  # room for the ratios written
        ax.set_ylim(0.0, ax.get_ylim()[1])  # the data's own top: the legend sits below
        pga_g_axis(ax, d["tan_alpha"])
    if handles:
        # One legend for both panels, in a row below them: colours are ensembles, styles are modes.
        legend_row.legend(handles=handles, loc="center", ncols=3, fontsize=7,
                          title=f"means of {d['answer_definition']}"
                          if d.get("answer_definition") else None, title_fontsize=7)
    title = (f"3D (bidirectional) versus 2D (one component), tan α = {d['tan_alpha']:g}"
             f"{paper_tag({'paper': d.get('reproduction', True)}, 'Fig 12')}")
    if d["missing"]:
        if d.get("reproduction", True):
            title += "\nreduced run: not everything the paper shows was computed (note below)"
        notes.insert(0, "Not computed in this run: " + "; ".join(d["missing"]) + ".")
    if d.get("reproduction", True):  # how to read the paper's 2D curves against ours
        notes.append(f"Axes: {_axes.PAPER_AXES}.")
    footnote(fig, notes)
    fig.suptitle(title)
    return fig


# ------------------------------------------------------ comparison with the paper


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes (criteria:
    :mod:`.criteria`; the 2D/3D ratios from the censoring-aware medians across R where the
    notes have them, docs/models.md "Verdicts and their criteria")."""
    m = first_notes(notes, "fig12_2d_vs_3d").get("measured", {})
    R = m.get("R", 10.0)
    names = sorted({k.split("|")[0] for k in m if k.count("|") >= 2})
    centro = next((n for n in names if "centro" in (n + m.get(f"{n}|label", "")).lower()), None)
    loma = next((n for n in names if "loma" in (n + m.get(f"{n}|label", "")).lower()), None)
    rows = [_r10_row(m, centro, R)]
    rows += _ratio_rows(m, centro, R, "El Centro", "overturning", "about",
                        "'the intensities of unidirectional ground motion to overturn the same "
                        "cylinder are twice as high' (§5.4)", "about 2× the 3D value")
    rows += _ratio_rows(m, centro, R, "El Centro", "excessive tilt", "above",
                        "'a similar trend holds for the excessive tilt' (§5.4)",
                        "2D above 3D")
    rows += _ratio_rows(m, loma, R, "Loma Prieta", "overturning", "above",
                        "the same trend for the Loma Prieta ensemble (§5.4, red)",
                        "2D above 3D")
    rows += _ratio_rows(m, loma, R, "Loma Prieta", "excessive tilt", "above",
                        "the same trend for the Loma Prieta ensemble (§5.4, red)",
                        "2D above 3D")
    return rows


HOUSNER_NOTE = ("the 2D reference is Housner's model with the restitution e = 0.942 of "
                "Eq 31 (tan α = 0.2), which loses energy at every impact, where the undamped "
                "3D model loses none")
"""Why 2D and 3D differ beyond one component against two (said in every ratio verdict)."""


def _r10_row(m: Mapping, ens: str | None, R: float) -> Comparison:
    v = m.get(f"{ens}|overturning|3d") if ens else None
    std, n = m.get(f"{ens}|overturning|3d|std"), m.get(f"{ens}|overturning|3d|count")
    se = std / math.sqrt(n) if finite(std, n) and n > 0 else None
    statement = (f"Overturning of an R = {R:g} m cylinder by bidirectional motion, mean "
                 f"{m.get('answer', 'I10')} PGA/(g tan α) (§5.4; printed as 'PGA/tan α of "
                 "about 4')")
    ours = f"{fmt(v)} (standard error of the mean {fmt(se, 2)}, {fmt(n, 3)} motions)"
    short = _short(m, ens, "overturning", (MODE_3D,)).get(MODE_3D, 0) if ens else 0
    if finite(v) and short > 0:
        return Comparison("fig12_2d_vs_3d", statement, "about 4", ours, DIFFERS,
                          criteria.censored_note(short, _n_motions(m, ens)))
    grids = (m.get(f"{ens}|headline") or {}).get("grids") if ens else None
    if grids and finite(v):
        # the paper's number is a first exceedance on a grid it does not state: held against
        # every answer the same cells give, from the mean I10 to the coarsest grid's mean
        ok, low, high, tol = criteria.about_family([v, *grids.values()],
                                                   se if finite(se) else 0.0, 4.0)
        ours += "; mean first exceedance of the same cells " + ", ".join(
            f"{x:.2f} on the {100 * float(s):g} % grid" for s, x in grids.items())
        band = (f"4 within [{low:.2f} − {tol:.2f}, {high:.2f} + {tol:.2f}]: the answers the "
                "cells give, from the mean I10 to the coarsest grid's mean first exceedance "
                "(the paper's grid is not stated), widened by 2·√(2·SE² + (0.5/√3)²)")
        return judged("fig12_2d_vs_3d", statement, "about 4", ours, ok, band,
                      f"4 lies outside [{low - tol:.2f}, {high + tol:.2f}] ({band}): a "
                      "different synthetic ensemble (own seeds) and record version",
                      f"El Centro study not computed at R = {R:g} m")
    ok, tol = criteria.about_value(v, se if finite(se) else 0.0, 4.0) if finite(v) else (
        None, float("nan"))
    return judged(
        "fig12_2d_vs_3d", statement, "about 4", ours, ok,
        f"|mean − 4| ≤ {tol:.2f} = 2·√(2·SE² + (0.5/√3)²): the paper's mean of its own 11 "
        "motions scatters as ours does, and 'about 4' is rounded to the unit",
        f"|mean − 4| = {abs(v - 4.0) if finite(v) else float('nan'):.2f} exceeds "
        f"{tol:.2f} = 2·√(2·SE² + (0.5/√3)²) (the scatter of two ensembles' means and the "
        "rounding of 'about 4'): a different synthetic ensemble (own seeds) and record version",
        f"El Centro study not computed at R = {R:g} m")


def ratio_evidence(m: Mapping, ens: str | None, title: str, mode: str) -> dict | None:
    """2D/3D of the censoring-aware medians (``…|mle`` notes) at every size where both are
    fitted and at most :data:`.criteria.MAX_CENSORED_SHARE` of the motions are censored.

    Returns
    -------
    dict or None
        ``R`` [m], ``ratio``, ``se_log`` per size (the two medians' standard errors in
        quadrature; β/√n where the bootstrap gave none), ``pooled`` and ``pooled_se``
        (:func:`.criteria.pooled_ratio`), ``dropped`` (sizes left out for censoring).
        None without medians in the notes.
    """
    a = m.get(f"{ens}|{title}|{mode}|mle") if ens else None
    b = m.get(f"{ens}|{title}|{MODE_3D}|mle") if ens else None
    if not isinstance(a, Mapping) or not isinstance(b, Mapping):
        return None

    def per_size(fit: Mapping) -> dict:
        n = fit.get("n") or [None] * len(fit["R"])
        beta = fit.get("beta") or [float("nan")] * len(fit["R"])
        out = {}
        for i, r in enumerate(fit["R"]):
            se = fit["se_log"][i]
            if not finite(se) and finite(beta[i], n[i]) and n[i] > 0:
                se = beta[i] / math.sqrt(n[i])
            out[round(float(r), 9)] = (fit["median"][i], se, fit["n_censored"][i], n[i])
        return out

    two, three = per_size(a), per_size(b)
    sizes, ratio, se, dropped = [], [], [], []
    for r, (m2, s2, c2, n2) in two.items():
        if r not in three:
            continue
        m3, s3, c3, n3 = three[r]
        if not finite(m2, m3) or m3 <= 0:
            continue
        if any(finite(c, n) and n > 0 and c > criteria.MAX_CENSORED_SHARE * n
               for c, n in ((c2, n2), (c3, n3))):
            dropped.append(r)
            continue
        sizes.append(r)
        ratio.append(m2 / m3)
        se.append(math.sqrt(s2 ** 2 + s3 ** 2) if finite(s2, s3) else float("nan"))
    if not sizes:
        return None
    pooled, pooled_se = criteria.pooled_ratio(ratio, se)
    return {"R": sizes, "ratio": ratio, "se_log": se, "pooled": pooled,
            "pooled_se": pooled_se, "dropped": dropped}


def _judge_ratio(kind: str, ratio: float, se: float) -> tuple[bool | None, str, str]:
    """(ok, tolerance text, reason text) of a ratio with the ln standard error ``se``."""
    if not finite(ratio, se):
        return None, "", ""
    if kind == "about":
        ok, tol = criteria.ratio_about(ratio, se)
        rule = (f"|ln(ratio/2)| ≤ {tol:.2f} = 2·√(2·SE² + (ln 1.125/√3)²): the paper's ratio "
                "of its own 11 motions scatters as ours does, 'about twice' read to the "
                "nearest half")
        return ok, rule, f"|ln(ratio/2)| = {abs(math.log(ratio / 2)):.2f} exceeds {tol:.2f}"
    ok = criteria.ratio_above_one(ratio, se)
    rule = f"ln ratio > 2 SE = {2 * se:.2f}: 2D above 3D beyond the ensemble's scatter"
    return ok, rule, f"ln ratio = {math.log(ratio):.2f} is not above 2 SE = {2 * se:.2f}"


def _ratio_rows(m: Mapping, ens: str | None, R: float, who: str, title: str, kind: str,
                statement: str, paper: str) -> list[Comparison]:
    v3 = m.get(f"{ens}|{title}|3d") if ens else None
    rows = []
    stand_in = " (stand-in record)" if ens and m.get(f"{ens}|stand_in") else ""
    for mode, axis in ((MODE_2D_X, "x, major principal axis"),
                       (MODE_2D_Y, "y, minor principal axis")):
        v2 = m.get(f"{ens}|{title}|{mode}") if ens else None
        at_r = (f"at R = {R:g} m the means give {v2 / v3:.3g}×"
                + _counts(m, ens, title, (MODE_3D, mode))) if finite(v2, v3) and v3 > 0 else ""
        head = f"{who}{stand_in}, {title}: 2D under the {axis} component against 3D"
        ev = ratio_evidence(m, ens, title, mode)
        if ev is not None:
            ok, rule, why = _judge_ratio(kind, ev["pooled"], ev["pooled_se"])
            lo, hi = min(ev["ratio"]), max(ev["ratio"])
            ours = (f"2D/3D of the censoring-aware medians = {ev['pooled']:.3g} (geometric "
                    f"mean over {len(ev['R'])} sizes R = {min(ev['R']):g}–{max(ev['R']):g} m, "
                    f"ln SE {ev['pooled_se']:.2f}; {lo:.3g}–{hi:.3g} across R)"
                    + (f"; {at_r}" if at_r else ""))
            if ev["dropped"]:
                ours += (f"; sizes R = {', '.join(f'{r:g}' for r in ev['dropped'])} m left out "
                         "(more than half the motions censored)")
            rows.append(judged(
                "fig12_2d_vs_3d", f"{head}, across R — {statement}", paper, ours, ok,
                f"{rule}; {HOUSNER_NOTE}",
                f"{why}; {HOUSNER_NOTE}; " + _ratio_reason(m, ens, title, mode, who,
                                                          censored=False),
                f"{who} ensemble or its 2D modes not computed in this run"))
            continue
        # no fitted medians in the notes: the means at R alone, never "reproduced" if censored
        short = _short(m, ens, title, (MODE_3D, mode))
        statement_r = f"{head}, R = {R:g} m (means; no fragility table) — {statement}"
        ratio = v2 / v3 if finite(v2, v3) and v3 > 0 else None
        ours = f"2D/3D = {fmt(ratio, 3)} ({fmt(v2, 3)} / {fmt(v3, 3)})" + _counts(
            m, ens, title, (MODE_3D, mode)) if ratio is not None else "—"
        if ratio is not None and any(v > 0 for v in short.values()):
            rows.append(Comparison("fig12_2d_vs_3d", statement_r, paper, ours, DIFFERS,
                                   _ratio_reason(m, ens, title, mode, who)))
            continue
        se = _means_se_log(m, ens, title, mode)
        ok, rule, why = _judge_ratio(kind, ratio, se) if ratio is not None else (None, "", "")
        rows.append(judged(
            "fig12_2d_vs_3d", statement_r, paper, ours, ok, f"{rule}; {HOUSNER_NOTE}",
            f"{why}; {HOUSNER_NOTE}; " + _ratio_reason(m, ens, title, mode, who),
            f"{who} ensemble or its 2D modes not computed in this run"))
    return rows


def _means_se_log(m: Mapping, ens: str | None, title: str, mode: str) -> float | None:
    """Standard error of ln(mean 2D / mean 3D) from the means' standard errors (None when the
    notes have no spread)."""
    total = 0.0
    for mo in (mode, MODE_3D):
        v, std, n = (m.get(f"{ens}|{title}|{mo}{k}") for k in ("", "|std", "|count"))
        if not finite(v, std, n) or n <= 0 or v <= 0:
            return None
        total += (std / v) ** 2 / n
    return math.sqrt(total)


def _n_motions(m: Mapping, ens: str | None) -> int | None:
    """Motions of an ensemble: its ``n_motions`` note, else the "mean of N motions" label."""
    n = m.get(f"{ens}|n_motions")
    if finite(n):
        return int(n)
    found = re.search(r"mean of (\d+) motions", str(m.get(f"{ens}|label", "")))
    return int(found[1]) if found else None


def _short(m: Mapping, ens: str | None, title: str, modes) -> dict:
    """Motions left out of each mode's mean (not reached at the search bound)."""
    total = _n_motions(m, ens)
    out = {}
    for mo in modes:
        v = m.get(f"{ens}|{title}|{mo}|n_not_reached")
        c = m.get(f"{ens}|{title}|{mo}|count")
        if finite(v):
            out[mo] = int(round(v))
        elif finite(c) and total is not None:
            out[mo] = int(round(total - c))
    return out


def _counts(m: Mapping, ens: str | None, title: str, modes) -> str:
    """``"; means over 7 (3D) and 4 (2D) of 11 motions"`` when a mean leaves motions out."""
    total = _n_motions(m, ens)
    got = {mo: m.get(f"{ens}|{title}|{mo}|count") for mo in modes}
    if total is None or all(not finite(c) or c >= total for c in got.values()):
        return ""
    return ("; means over " + " and ".join(f"{int(c)} ({'3D' if mo == '3d' else '2D'})"
                                           for mo, c in got.items() if finite(c))
            + f" of {int(total)} motions")


def _ratio_reason(m: Mapping, ens: str | None, title: str, mode: str, who: str,
                  censored: bool = True) -> str:
    """Why a 2D/3D ratio differs: censored means when motions were not reached (``censored``:
    the ratio is one of means), else the ensemble and the direction of x."""
    short = _short(m, ens, title, (MODE_3D, mode))
    if censored and any(v > 0 for v in short.values()):
        upper = m.get(f"{ens}|upper")
        bound = f" PGA/(g tan α) = {fmt(upper)}" if finite(upper) else ""
        left = " and ".join(f"{v} ({'3D' if mo == '3d' else '2D'})"
                            for mo, v in short.items() if v > 0)
        return (f"motions not reached at the search bound{bound}: {left} motions of the "
                f"{who} ensemble had not reached the limit state there and are left out of the "
                "means, which therefore understate the intensities, the 2D ones most (they are "
                "higher); the ratio of these censored means says little")
    return (f"a different {who} ensemble (own synthetic pairs, record version); our x is the "
            "record's major principal axis, the paper's x the E–W component before rotation")


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="fig12_2d_vs_3d", module=__name__, number=12, label="Fig 12",
    caption=(
        "Mean performance spectra of the 3D model under both components against the 2D "
        "model under the major-axis (x) or the minor-axis (y) component alone, at the "
        "slenderness in the title; the intensity is the bidirectional PGA in all three "
        "(§5.4). Colours are ensembles, line styles modes; the ratios 2D/3D at the largest "
        "R are written at the right end of the curves (≥ where the 2D mean is censored, so "
        "the ratio is a lower bound; ≤ where the 3D mean is); the note gives each ensemble's axis "
        "azimuths. Open circles: the mean covers fewer motions than the ensemble, the "
        "others not having reached the limit state at the search bound (such a mean "
        "understates the intensity). The means are of each motion's I10 (the lowest PGA/(g "
        "tan α) near which 10 % of the intensities exceed) unless the study chose another "
        "quantity, as the legend says; means over answers flagged plateau are counted in a "
        "note. The verdicts read the "
        "2D/3D ratios from the censoring-aware medians of the lognormal fits across every "
        "size, not from these means at one size. The 2D model is Housner's, with the "
        "restitution e = 0.942 (Eq 31) that dissipates energy at every impact; the undamped "
        "3D model dissipates none."
    ),
    paper=(
        "The paper's Fig 12 (tan α = 0.2) reports that overturning an R = 10 m cylinder "
        "needs PGA/(g tan α) of about 4 bidirectionally and about twice that "
        "unidirectionally (El Centro black, Loma Prieta red)."
    ),
    scope="studies", wanted=lambda s: s.plan.compares_2d_with_3d(),
    # read beside the means: the censoring-aware medians of the 2D/3D verdicts and the
    # headline's first exceedances on four grids (the R = 10 m verdict)
    inputs={"means": "means", "complete": "spectra", "motions": "motions",
            "fragility": "fragility_csv", "headline": "headline"},
    params={"studies": "studies", "stores": "spectra_store", "paper": "paper"},
    arguments=lambda inputs, params: {
        "studies": list(zip(params["studies"], inputs["means"], params["stores"],
                            inputs["motions"], strict=True)),
        "paper": bool(params["paper"])})
"""Fig 12, over the studies that run "3d" and a 2D mode at a common tan α."""
