"""Figure 12: mean spectra under both ground-motion components against under one (paper §5.4).

The paper's comparison: "the same undamped 3D cylinder model" under both components
(bidirectional) and under each component alone (unidirectional: modes ``3d-x``, ``3d-y``),
the intensity the pair's vector PGA in every mode. Housner's 2D block under one component
(``2d-x``, ``2d-y``, restitution e = 0.942) is drawn beside them as a further, labelled
comparator: it changes the model as well as the excitation. One row per ensemble (El Centro,
black; Loma Prieta or its stand-in, red), each on its own intensity axis; one column per
limit state (overturning, θ > α/3), at the studies' common slenderness (tan α = 0.2 in the
paper). The ratios to the 3D model under both components are written at the largest R; the
note under the axes gives each ensemble's axis azimuths, so the one-component curves can be
matched with the paper's (whose x is E–W and y N–S before its rotation). Open circles mark
means over fewer motions than the ensemble; means over answers flagged plateau are counted in
a note. The means are of each motion's critical intensity, the studies' quantity (I10 by
default), which the legend names; studies of different quantities are refused, never drawn
side by side.
"""

from __future__ import annotations

import math
import re
import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.plot import _axes, _load, criteria
from rocking.plot._style import MODE_STYLE, footnote, paper_tag, pga_g_axis, r_axis, styled
from rocking.plot.comparisons import (
    DIFFERS,
    NOT_COMPUTED,
    NOT_IN_PAPER,
    Comparison,
    finite,
    first_notes,
    fmt,
    judged,
)
from rocking.spectra import modes as mode_registry
from rocking.spectra.limit_states import limit_state_title, parse_limit_state
from rocking.spectra.modes import (
    MODE_2D_X,
    MODE_2D_Y,
    MODE_3D,
    MODE_3D_X,
    MODE_3D_Y,
    PLANAR_MODES,
    UNIDIRECTIONAL_MODES,
)
from rocking.store.attrs import decode_attrs

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

PAPER_COMPARATORS = UNIDIRECTIONAL_MODES
"""The paper's unidirectional excitation: the same undamped 3D model under one component."""
HOUSNER_COMPARATORS = PLANAR_MODES
"""Housner's 2D block under one component: a further comparator, not the paper's."""
MODES = (MODE_3D, *PAPER_COMPARATORS, *HOUSNER_COMPARATORS)
REFERENCE_R = 10.0
"""Size of the paper's §5.4 statement (R = 10 m: ≈ 4 bidirectional, about twice under one
component) [m]."""
ENSEMBLE_COLORS = ("black", "tab:red", "tab:blue", "tab:green")
MODE_LABELS = {MODE_3D: "3D cylinder, both components",
               MODE_3D_X: "3D cylinder, x (major axis) component only",
               MODE_3D_Y: "3D cylinder, y (minor axis) component only",
               MODE_2D_X: "Housner 2D block (e = 0.942), x component only",
               MODE_2D_Y: "Housner 2D block (e = 0.942), y component only"}
SHORT = {MODE_3D: "3D", MODE_3D_X: "3D x", MODE_3D_Y: "3D y", MODE_2D_X: "2D x",
         MODE_2D_Y: "2D y"}
"""How a ratio and a count name each mode in the figure and the verdicts."""

PAPER_NOTE = ("the paper's comparison: the same undamped 3D model under one component against "
              "both, so the ratio is the effect of the second component alone")
"""What the ratios of the paper's comparator show (said in their verdicts)."""

HOUSNER_NOTE = ("Housner's 2D block with the restitution e = 0.942 of Eq 31 (tan α = 0.2) "
                "stays in its plane and loses (1 − e²) of its energy at every impact, where the "
                "undamped 3D model under one component leaves the plane at its first "
                "quasi-impact (the pivot turns by about 3.19 rad, not π) and loses none: its "
                "ratio to the 3D model under both mixes the second component with this change "
                "of model")
"""What the Housner ratios show (said in every row that quotes them)."""


def data(studies: Sequence[tuple], *, tan_alpha: float | None = None,
         modes: tuple[str, ...] = MODES, paper: bool = True) -> dict:
    """Mean spectra per ensemble and mode.

    ``tan_alpha`` defaults to the first study's (:func:`._load.main_tan_alpha` of its modes
    under both and under one component). Panels are the paper's overturning and excessive
    tilt in a reproduction of the paper (``paper``: absent ones and absent ensembles named),
    else the studies' own goals (:func:`._load.panel_limit_states`).

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
    import pandas as pd

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
    import pandas as pd

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
    import pandas as pd

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


MODE_MARKERS = {MODE_3D: "o", MODE_3D_X: "s", MODE_3D_Y: "^", MODE_2D_X: "s", MODE_2D_Y: "^"}
"""Small markers per mode (square: x, triangle: y), so that line styles stay readable where
curves cross; Housner's are drawn open, thinner and lighter (a further comparator)."""


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
    """Write each one-component mean over the 3D mean under both at the largest R where both
    are finite, at the right end of its curve (``×2.41 3D x``; Housner's ``2D x``, lighter),
    spread vertically so that labels never overlap.

    ``censored`` (mode → bool per R) marks means over fewer motions than the ensemble (the
    others not reached at the search bound, so the mean is too low): a censored
    one-component mean over a full 3D one makes the ratio a lower bound ("≥"), the reverse an
    upper bound ("≤"); both censored, neither can be said ("?").
    """
    base = curves.get(MODE_3D)
    if base is None:
        return
    censored = censored or {}
    labels = []
    for mode in (*PAPER_COMPARATORS, *HOUSNER_COMPARATORS):
        y = curves.get(mode)
        if y is None:
            continue
        ok = np.isfinite(y) & np.isfinite(base)
        if not ok.any():
            continue
        i = int(np.flatnonzero(ok)[-1])
        low1 = bool(np.asarray(censored.get(mode, np.zeros(len(y), bool)))[i])
        low3 = bool(np.asarray(censored.get(MODE_3D, np.zeros(len(y), bool)))[i])
        bound = {(True, False): "≥", (False, True): "≤", (True, True): "?"}.get((low1, low3), "")
        labels.append((float(y[i]), float(R[i]), f"{bound}×{y[i] / base[i]:.2f} {SHORT[mode]}",
                       mode in HOUSNER_COMPARATORS))
    # in axes fraction, in the order of the curves' ends, at least 5 % apart and inside
    lo, hi = ax.get_ylim()
    labels.sort()
    fracs = [(y - lo) / (hi - lo) if hi > lo else 0.5 for y, *_ in labels]
    for i in range(1, len(fracs)):
        fracs[i] = max(fracs[i], fracs[i - 1] + 0.05)
    for i in reversed(range(len(fracs))):
        fracs[i] = min(fracs[i], 0.97 if i == len(fracs) - 1 else fracs[i + 1] - 0.05)
    for frac, (_, r, text, housner) in zip(fracs, labels, strict=True):
        ax.annotate(text, (r, lo + frac * (hi - lo)), xytext=(4, 0), textcoords="offset points",
                    color=color, fontsize=6.5, va="center", alpha=0.6 if housner else 1.0,
                    annotation_clip=False)


def _curve(ax, R, y, mode: str, color) -> None:
    """One mean spectrum: the 3D model bold, under one component dashed, Housner's block
    thin, light and with open markers (a further comparator)."""
    housner = mode in HOUSNER_COMPARATORS
    ax.plot(R, y, color=color, ls=MODE_STYLE[mode]["linestyle"],
            lw=0.9 if housner else (1.8 if mode == MODE_3D else 1.4),
            alpha=0.55 if housner else 1.0, marker=MODE_MARKERS.get(mode, "o"),
            ms=3.0 if housner else 2.8, mfc="none" if housner else color, mec=color)


def _mode_handle(mode: str) -> Line2D:
    from matplotlib.lines import Line2D

    housner = mode in HOUSNER_COMPARATORS
    return Line2D([], [], color="dimgray", ls=MODE_STYLE[mode]["linestyle"],
                  lw=0.9 if housner else (1.8 if mode == MODE_3D else 1.4),
                  alpha=0.7 if housner else 1.0, marker=MODE_MARKERS.get(mode, "o"), ms=3.0,
                  mfc="none" if housner else "dimgray", mec="dimgray",
                  label=MODE_LABELS.get(mode, mode))


@styled
def plot(d: dict) -> Figure:
    """One row per ensemble, each on its own axis of intensity; one column per limit state.

    Colour = ensemble (the paper's black and red), line style and marker = mode: the 3D model
    under both components solid, under one component dashed (the paper's comparison, §5.4),
    Housner's 2D block thin and light (a further comparator).
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    titles = list(d.get("titles", ("overturning", "excessive tilt")))
    ensembles = d["ensembles"] or [{"label": "", "record": "", "stand_in": False, "panels": {},
                                    "R": np.zeros(0), "axes": {"text": ""}, "n_motions": 0}]
    nrows, ncols = len(ensembles), len(titles)
    fig = Figure(figsize=(10.0 if ncols > 1 else 6.4, 3.2 * nrows + 1.9), layout="constrained")
    grid = fig.add_gridspec(nrows + 1, ncols, height_ratios=(*([1.0] * nrows), 0.5))
    legend_row = fig.add_subplot(grid[nrows, :])
    legend_row.axis("off")
    handles, modes_seen, notes = [], [], []
    partial = False  # any mean over fewer motions than the ensemble
    on_plateau: list[tuple] = []  # curves with means over answers flagged plateau
    R_all = np.concatenate([np.asarray(e["R"], float) for e in ensembles])
    first = None
    for k, ens in enumerate(ensembles):
        color = ENSEMBLE_COLORS[k % len(ENSEMBLE_COLORS)]
        label = ens["label"]
        if ens["stand_in"] and "stand-in" not in label:
            label += " (stand-in)"
        if label:
            handles.append(Line2D([], [], color=color, lw=1.8,
                                  label="\n".join(textwrap.wrap(label, 48))))
            notes.append(f"{ens['record']}: {ens['axes']['text']}.")
        for j, title in enumerate(titles):
            ax = fig.add_subplot(grid[k, j], sharex=first)
            first = first or ax
            curves = ens["panels"].get(title, {})
            censored = {}
            for mode in MODES:
                if mode not in curves:
                    continue
                y = curves[mode]
                _curve(ax, ens["R"], y, mode, color)
                few = censored[mode] = fewer_motions(ens, title, mode)
                if few.any():  # the mean leaves out motions not reached at the search bound
                    partial = True
                    ax.plot(ens["R"][few], y[few], "o", ms=7, mfc="none", mec=color, mew=1.0,
                            alpha=0.55 if mode in HOUSNER_COMPARATORS else 1.0, zorder=1)
                flagged = ens.get("spread", {}).get(f"{title}|{mode}|n_plateau")
                if flagged is not None and (np.nan_to_num(flagged) > 0).any():
                    n_flag = int((np.nan_to_num(flagged) > 0).sum())  # counted, not ringed
                    on_plateau.append((ens["record"], f"{SHORT[mode]} {title}", n_flag,
                                       int(np.isfinite(y).sum())))
                if mode not in modes_seen:
                    modes_seen.append(mode)
            ls_title = (limit_state_title("overturning" if title == "overturning" else "tilt:1/3")
                        if title in ("overturning", "excessive tilt") else title)
            record = ens.get("record") or ""
            ax.set_title("\n".join([ls_title, *textwrap.wrap(record, 75)]), color=color)
            ax.set_ylabel(f"mean {d.get('answer', 'critical')} PGA/(g tan α) [-]\n"
                          "(bidirectional PGA)")
            r_axis(ax, R_all, label=k == nrows - 1)
            left, right = ax.get_xlim()
            ax.set_xlim(left, right + 0.14 * (right - left))  # room for the ratios written
            ax.set_ylim(0.0, ax.get_ylim()[1] * 1.06)  # each ensemble on its own scale
            pga_g_axis(ax, d["tan_alpha"])
            _write_ratios(ax, ens["R"], curves, color, censored)
    handles += [_mode_handle(m) for m in MODES if m in modes_seen]
    if partial:
        handles.append(Line2D([], [], ls="", marker="o", ms=7, mfc="white", mec="gray",
                              label="open circle: mean over fewer motions than the ensemble\n"
                                    "(the others not reached at the search bound)"))
    handles.append(Line2D([], [], ls="", label="×k: one-component mean / 3D mean under both\n"
                          "at the largest R" + ("; ≥×k: the one-component mean there\nleaves "
                                                "out motions (a lower bound); ≤: the 3D one"
                                                if partial else "")))
    if on_plateau:
        notes.append(_plateau_note(on_plateau))
    if handles:
        legend_row.legend(handles=handles, loc="center", ncols=3, fontsize=7,
                          title=f"means of {d['answer_definition']}"
                          if d.get("answer_definition") else None, title_fontsize=7)
    title = (f"Both ground-motion components against one, tan α = {d['tan_alpha']:g}"
             f"{paper_tag({'paper': d.get('reproduction', True)}, 'Fig 12')}")
    paper = " (the paper's comparison, §5.4)" if d.get("reproduction", True) else ""
    notes.insert(0, f"Dashed: the same undamped 3D model under one component{paper}; thin "
                 "and light: Housner's 2D block under one component, a further comparator "
                 "that also changes the model (planar, e = 0.942 per impact).")
    if d["missing"]:
        if d.get("reproduction", True):
            title += "\nreduced run: not everything the paper shows was computed (note below)"
        notes.insert(0, "Not computed in this run: " + "; ".join(d["missing"]) + ".")
    if d.get("reproduction", True):  # how to read the paper's one-component curves against ours
        notes.append(f"Axes: {_axes.PAPER_AXES}.")
    footnote(fig, notes)
    fig.suptitle(title)
    return fig


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes (criteria:
    :mod:`.criteria`; the ratios of one component to both from the censoring-aware medians
    across R where the
    notes have them, docs/models.md "Verdicts and their criteria")."""
    m = first_notes(notes, "fig12_2d_vs_3d").get("measured", {})
    R = m.get("R", 10.0)
    names = sorted({k.split("|")[0] for k in m if k.count("|") >= 2})
    centro = next((n for n in names if "centro" in (n + m.get(f"{n}|label", "")).lower()), None)
    loma = next((n for n in names if "loma" in (n + m.get(f"{n}|label", "")).lower()), None)
    statements = (
        (centro, "El Centro", "overturning", "about",
         "'the intensities of unidirectional ground motion to overturn the same cylinder are "
         "twice as high' (§5.4)", "about 2× the bidirectional value"),
        (centro, "El Centro", "excessive tilt", "above",
         "'a similar trend holds for the excessive tilt' (§5.4)", "one component above both"),
        (loma, "Loma Prieta", "overturning", "above",
         "the same trend for the Loma Prieta ensemble (§5.4, red)", "one component above both"),
        (loma, "Loma Prieta", "excessive tilt", "above",
         "the same trend for the Loma Prieta ensemble (§5.4, red)", "one component above both"),
    )
    rows = [_r10_row(m, centro, R)]
    for ens, who, title, kind, statement, paper in statements:
        rows += _ratio_rows(m, ens, R, who, title, kind, statement, paper, PAPER_COMPARATORS)
    for ens, who, title, kind, statement, paper in statements:  # named, not judged
        rows += _ratio_rows(m, ens, R, who, title, kind, statement, paper,
                            HOUSNER_COMPARATORS)
    return rows


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
    """``mode``/3D of the censoring-aware medians (``…|mle`` notes; ``mode`` under one
    component, 3D under both) at every size where both are
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
    rule = (f"ln ratio > 2 SE = {2 * se:.2f}: one component above both beyond the ensemble's "
            "scatter")
    return ok, rule, f"ln ratio = {math.log(ratio):.2f} is not above 2 SE = {2 * se:.2f}"


AXIS = {"x": "x, major principal axis", "y": "y, minor principal axis"}


def _ratio_rows(m: Mapping, ens: str | None, R: float, who: str, title: str, kind: str,
                statement: str, paper: str, modes: tuple[str, ...]) -> list[Comparison]:
    """One row per comparator of ``modes`` against the 3D model under both components: the
    paper's comparator (:data:`PAPER_COMPARATORS`) judged against the paper's statement,
    Housner's (:data:`HOUSNER_COMPARATORS`) quoted with what it shows ("not in the paper":
    the paper compares the 3D model with itself)."""
    v3 = m.get(f"{ens}|{title}|3d") if ens else None
    rows = []
    stand_in = " (stand-in record)" if ens and m.get(f"{ens}|stand_in") else ""
    for mode in modes:
        housner = mode in HOUSNER_COMPARATORS
        what = ("Housner's 2D block (a further comparator)" if housner
                else "the 3D model")
        axis = AXIS[mode_registry.MODES[mode].component]
        v1 = m.get(f"{ens}|{title}|{mode}") if ens else None
        at_r = (f"at R = {R:g} m the means give {v1 / v3:.3g}×"
                + _counts(m, ens, title, (MODE_3D, mode))) if finite(v1, v3) and v3 > 0 else ""
        head = (f"{who}{stand_in}, {title}: {what} under the {axis} component alone against "
                "the 3D model under both")
        note = HOUSNER_NOTE if housner else PAPER_NOTE
        ratio_name = f"{SHORT[mode]}/3D"
        missing = f"{who} ensemble or its mode {mode} not computed in this run"
        ev = ratio_evidence(m, ens, title, mode)
        if ev is not None:
            ok, rule, why = _judge_ratio(kind, ev["pooled"], ev["pooled_se"])
            lo, hi = min(ev["ratio"]), max(ev["ratio"])
            ours = (f"{ratio_name} of the censoring-aware medians = {ev['pooled']:.3g} "
                    f"(geometric mean over {len(ev['R'])} sizes R = {min(ev['R']):g}–"
                    f"{max(ev['R']):g} m, ln SE {ev['pooled_se']:.2f}; {lo:.3g}–{hi:.3g} "
                    "across R)" + (f"; {at_r}" if at_r else ""))
            if ev["dropped"]:
                ours += (f"; sizes R = {', '.join(f'{r:g}' for r in ev['dropped'])} m left out "
                         "(more than half the motions censored)")
            statement_r = f"{head}, across R — {statement}"
            if housner:
                rows.append(Comparison("fig12_2d_vs_3d", statement_r, "—", ours, NOT_IN_PAPER,
                                       note))
                continue
            rows.append(judged(
                "fig12_2d_vs_3d", statement_r, paper, ours, ok, f"{rule}; {note}",
                f"{why}; " + _ratio_reason(m, ens, title, mode, who, censored=False), missing))
            continue
        # no fitted medians in the notes: the means at R alone, never "reproduced" if censored
        short = _short(m, ens, title, (MODE_3D, mode))
        statement_r = f"{head}, R = {R:g} m (means; no fragility table) — {statement}"
        ratio = v1 / v3 if finite(v1, v3) and v3 > 0 else None
        ours = f"{ratio_name} = {fmt(ratio, 3)} ({fmt(v1, 3)} / {fmt(v3, 3)})" + _counts(
            m, ens, title, (MODE_3D, mode)) if ratio is not None else "—"
        if housner:
            censored = "; " + _ratio_reason(m, ens, title, mode, who) if any(
                v > 0 for v in short.values()) else ""
            rows.append(Comparison("fig12_2d_vs_3d", statement_r, "—", ours, NOT_IN_PAPER,
                                   note + censored) if ratio is not None else
                        Comparison("fig12_2d_vs_3d", statement_r, "—", "—", NOT_COMPUTED,
                                   missing))
            continue
        if ratio is not None and any(v > 0 for v in short.values()):
            rows.append(Comparison("fig12_2d_vs_3d", statement_r, paper, ours, DIFFERS,
                                   _ratio_reason(m, ens, title, mode, who)))
            continue
        se = _means_se_log(m, ens, title, mode)
        ok, rule, why = _judge_ratio(kind, ratio, se) if ratio is not None else (None, "", "")
        rows.append(judged(
            "fig12_2d_vs_3d", statement_r, paper, ours, ok, f"{rule}; {note}",
            f"{why}; " + _ratio_reason(m, ens, title, mode, who), missing))
    return rows


def _means_se_log(m: Mapping, ens: str | None, title: str, mode: str) -> float | None:
    """Standard error of ln(mean under one component / mean under both) from the means'
    standard errors (None when the notes have no spread)."""
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
    """``"; means over 7 (3D) and 4 (2D x) of 11 motions"`` when a mean leaves motions out."""
    total = _n_motions(m, ens)
    got = {mo: m.get(f"{ens}|{title}|{mo}|count") for mo in modes}
    if total is None or all(not finite(c) or c >= total for c in got.values()):
        return ""
    return ("; means over " + " and ".join(f"{int(c)} ({SHORT.get(mo, mo)})"
                                           for mo, c in got.items() if finite(c))
            + f" of {int(total)} motions")


def _ratio_reason(m: Mapping, ens: str | None, title: str, mode: str, who: str,
                  censored: bool = True) -> str:
    """Why a ratio of one component to both differs: censored means when motions were not
    reached (``censored``:
    the ratio is one of means), else the ensemble and the direction of x."""
    short = _short(m, ens, title, (MODE_3D, mode))
    if censored and any(v > 0 for v in short.values()):
        upper = m.get(f"{ens}|upper")
        bound = f" PGA/(g tan α) = {fmt(upper)}" if finite(upper) else ""
        left = " and ".join(f"{v} ({SHORT.get(mo, mo)})"
                            for mo, v in short.items() if v > 0)
        return (f"motions not reached at the search bound{bound}: {left} motions of the "
                f"{who} ensemble had not reached the limit state there and are left out of the "
                "means, which therefore understate the intensities, those under one component "
                "most (they are higher); the ratio of these censored means says little")
    return (f"a different {who} ensemble (own synthetic pairs, record version); our x is the "
            "record's major principal axis, the paper's x the E–W component before rotation")


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="fig12_2d_vs_3d", module=__name__, number=12, label="Fig 12",
    caption=(
        "Mean performance spectra under both ground-motion components against under one, at "
        "the slenderness in the title, one row per ensemble (each on its own scale), the "
        "intensity the bidirectional PGA in every curve (§5.4). Solid: the undamped 3D "
        "model under both components; dashed: the same model under the major-axis (x) or "
        "the minor-axis (y) component alone, started with a spin of 1e-4 rad/s at each uplift "
        "(the paper's comparison); thin and light: Housner's 2D block under one component "
        "(restitution e = 0.942, Eq 31), a further comparator that also changes the model. "
        "The ratios to the 3D model under both at the largest R are written at the right end "
        "of the curves (≥ where the one-component mean is censored, so the ratio is a lower "
        "bound; ≤ where the 3D mean is); the note gives each ensemble's axis azimuths. Open "
        "circles: the mean covers fewer motions than the ensemble, the others not having "
        "reached the limit state at the search bound (such a mean understates the "
        "intensity). The means are of each motion's I10 (the lowest PGA/(g tan α) near which "
        "10 % of the intensities exceed) unless the study chose another quantity, as the "
        "legend says; means over answers flagged plateau are counted per curve in the note. "
        "The verdicts read the ratios from the "
        "censoring-aware medians of the lognormal fits across every size, not from these "
        "means at one size; they judge the paper's comparator, and quote Housner's."
    ),
    paper=(
        "The paper's Fig 12 (tan α = 0.2) reports that overturning an R = 10 m cylinder "
        "needs PGA/(g tan α) of about 4 under both components and about twice that under "
        "one (the same undamped 3D model; El Centro black, Loma Prieta red)."
    ),
    scope="studies", wanted=lambda s: s.plan.compares_2d_with_3d(),
    # read beside the means: the censoring-aware medians of the ratio verdicts and the
    # headline's first exceedances on four grids (the R = 10 m verdict)
    inputs={"means": "means", "complete": "spectra", "motions": "motions",
            "fragility": "fragility_csv", "headline": "headline"},
    params={"studies": "studies", "stores": "spectra_store", "paper": "paper"},
    arguments=lambda inputs, params: {
        "studies": list(zip(params["studies"], inputs["means"], params["stores"],
                            inputs["motions"], strict=True)),
        "paper": bool(params["paper"])})
"""Fig 12, over the studies that run "3d" and a mode under one component at a common tan α."""
