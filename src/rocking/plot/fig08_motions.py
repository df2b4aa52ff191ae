"""Figure 8: the ensemble's acceleration traces and 5 %-damped pseudo-acceleration spectra.

Left, the traces: top row the record on its principal axes (first member of the ensemble
file), then the synthetic pairs; x (major) and y (minor) components. Right, per component,
the response spectra: the record's (thick black), every synthetic motion's (thin grey), and
the ensemble's median (geometric mean) with its 16–84 % range, log–log over 0.05–5 s. With a
comparison ensemble (the other identification method, same seed) both methods are shown side
by side, each panel with its fit quality (median ÷ record per period band). Synthetic pairs
match the record only through linear-oscillator statistics, which is why their rocking
spectra scatter (paper §5.1–5.2).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from rocking.constants import G
from rocking.motions.motion import GroundMotion
from rocking.plot._style import motion_styles, paper_tag, styled
from rocking.plot.comparisons import (
    NOT_COMPUTED,
    NOT_IN_PAPER,
    Comparison,
    finite,
    fmt,
    judged,
    notes_of,
)

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

PERIODS = np.geomspace(0.05, 5.0, 100)
"""Oscillator periods of the drawn spectra [s], log-spaced."""

METHOD_TITLES = {
    "spectrum": "spectrum-matched fit",
    "counts": "count-based fit (RDK 2010)",
}
"""Panel title of each identification method."""

COMPONENTS = (("x", "ax", "major"), ("y", "ay", "minor"))


def bearing(azimuth: float | None) -> str:
    """Quadrant bearing of an azimuth [deg clockwise from north], e.g. ``"N 19.5° W"``."""
    if azimuth is None:
        return "direction unknown"
    az = float(azimuth) % 360.0
    if az <= 90.0:
        return f"N {az:.1f}° E"
    if az <= 180.0:
        return f"S {180.0 - az:.1f}° E"
    if az <= 270.0:
        return f"S {az - 180.0:.1f}° W"
    return f"N {360.0 - az:.1f}° W"


def _spectra(motions: Sequence[GroundMotion], periods: np.ndarray, attr: str) -> np.ndarray:
    """(n, p) PSA [g] of one component of every motion."""
    from rocking.motions.response_spectrum import pseudo_acceleration
    from rocking.motions.stochastic.quality import DAMPING

    return np.vstack([pseudo_acceleration(getattr(m, attr), m.dt, periods, DAMPING) / G
                      for m in motions])


def _method(motions: Sequence[GroundMotion]) -> str:
    """Identification method of an ensemble's synthetic motions (``"counts"`` if unstated)."""
    return str(motions[1].metadata.get("fit_method", "counts")) if len(motions) > 1 else "none"


def _group(motions: Sequence[GroundMotion], periods: np.ndarray) -> dict:
    """Spectra, percentiles and fit quality of one ensemble's synthetic motions."""
    from rocking.motions.stochastic import quality

    out: dict = {"method": _method(motions), "n": len(motions) - 1}
    syn = motions[1:]
    for key, attr, _ in COMPONENTS:
        if not syn:
            continue
        psa = _spectra(syn, periods, attr)
        out[f"psa_{key}"] = psa
        out[f"median_{key}"] = np.exp(np.log(psa).mean(axis=0))
        out[f"p16_{key}"], out[f"p84_{key}"] = np.percentile(psa, [16.0, 84.0], axis=0)
    out["fit_quality"] = quality.ensemble_quality(motions) if len(syn) >= 2 else None
    return out


def data(motions: Sequence[GroundMotion], comparison: Sequence[GroundMotion] | None = None,
         *, periods=PERIODS, paper: bool = True) -> dict:
    """Traces [g] and PSA spectra [g] of the ensemble and, optionally, of a comparison.

    Parameters
    ----------
    motions : sequence of GroundMotion
        The ensemble: the record on its principal axes, then the synthetic pairs [m/s²].
    comparison : sequence of GroundMotion, optional
        The same record, then the pairs of the other identification method.
    periods : array_like
        Periods of the drawn spectra [s].

    Returns
    -------
    dict
        ``motions``: [{``name``, ``t`` [s], ``ax``, ``ay`` [g], ``psa_x``, ``psa_y`` [g],
        ``stand_in``}] of the ensemble; ``groups``: per ensemble (this one first) its
        method, synthetic spectra, median and 16/84 % percentiles [g] and fit quality;
        ``record``: azimuths [deg] and label; ``measured``, ``missing`` (what the run left
        out) and ``remarks`` (a stand-in record, few pairs) notes.
    """
    from rocking.motions.response_spectrum import pseudo_acceleration
    from rocking.motions.stochastic.quality import DAMPING

    if not motions:
        raise ValueError("motions must hold at least one GroundMotion, got an empty list")
    periods = np.asarray(periods, dtype=float)
    out = []
    for m in motions:
        psa = pseudo_acceleration(np.vstack([m.ax, m.ay]), m.dt, periods, DAMPING) / G
        out.append({
            "name": m.name,
            "t": m.time,
            "ax": np.asarray(m.ax) / G,
            "ay": np.asarray(m.ay) / G,
            "psa_x": psa[0],
            "psa_y": psa[1],
            "stand_in": bool(m.metadata.get("stand_in", False)),
        })
    groups = [_group(motions, periods)]
    if comparison is not None and len(comparison) > 1:
        groups.append(_group(comparison, periods))
    first = motions[0].metadata
    measured = {
        "record": motions[0].name,
        "record_pga_g": motions[0].pga_g,
        "principal_offset_deg": first.get("principal_offset_deg"),
        "rotation_deg": first.get("rotation_deg"),
        "n_motions": len(motions),
        "fit_method": groups[0]["method"],
        "fit_quality": {g["method"]: g["fit_quality"] for g in groups},
    }
    # what the figure says of what it drew (a report shows them as remarks), apart from what
    # the run left out (``missing``: "not computed in this run")
    remarks = [f"{m['name']} is a stand-in" for m in out if m["stand_in"]]
    if 1 < len(motions) < 11:
        remarks.append(f"only {len(motions) - 1} synthetic pairs: medians, 16–84 % ranges and "
                       "fit quality rest on few motions")
    missing = [] if len(groups) > 1 else [
        "no comparison ensemble of the other identification method"]
    record = {"x_azimuth": first.get("x_azimuth"), "y_azimuth": first.get("y_azimuth"),
              "label": first.get("label", motions[0].name)}
    return {"paper": paper, "motions": out, "groups": groups, "periods": periods,
            "damping": DAMPING,
            "record": record, "measured": measured, "missing": missing, "remarks": remarks,
            "colors": motion_styles([m["name"] for m in out])}


QUIET = 0.01
"""A trace has ended when it stays below this share of its peak [-]."""


def motion_end(t: np.ndarray, *traces: np.ndarray) -> float:
    """Time after which every trace stays below :data:`QUIET` of its peak [s] (drops the
    zero padding that makes a record look longer than its motion)."""
    end = float(t[0])
    for a in traces:
        a = np.abs(np.asarray(a, float))
        loud = np.flatnonzero(a > QUIET * a.max()) if a.size and a.max() > 0 else []
        if len(loud):
            end = max(end, float(t[min(loud[-1] + 1, t.size - 1)]))
    return end


def _traces(fig: Figure, grid, motions: list[dict], colors: dict) -> None:
    n = len(motions)
    peak = max(float(np.max(np.abs(np.r_[m["ax"], m["ay"]]))) for m in motions)
    # to the end of the longest motion, rounded up to 5 s
    t_end = 5.0 * np.ceil(max(motion_end(m["t"], m["ax"], m["ay"]) for m in motions) / 5.0)
    first_x = None
    for i, m in enumerate(motions):
        color = colors[m["name"]]["color"]
        ax_x = fig.add_subplot(grid[i, 0], sharex=first_x, sharey=first_x)
        ax_y = fig.add_subplot(grid[i, 1], sharex=first_x, sharey=first_x)
        first_x = first_x or ax_x
        ax_x.plot(m["t"], m["ax"], color=color, lw=0.5)
        ax_y.plot(m["t"], m["ay"], color=color, lw=0.5)
        label = colors[m["name"]]["label"] + (" (stand-in)" if m["stand_in"] else "")
        ax_x.set_ylabel(label, rotation=0, ha="right", va="center", fontsize=7, color=color)
        for ax in (ax_x, ax_y):
            ax.set_ylim(-1.1 * peak, 1.1 * peak)
            ax.set_xlim(0.0, t_end)
            ax.tick_params(labelsize=6)
            if i < n - 1:
                ax.tick_params(labelbottom=False)
        if i == 0:
            ax_x.set_title("x (major) acceleration [g]")
            ax_y.set_title("y (minor) acceleration [g]")
    for ax in (ax_x, ax_y):  # the bottom row carries the time axis
        ax.set_xlabel("t [s]")


def _spectrum_panel(ax, d: dict, group: dict, key: str, in_use: bool) -> None:
    T = d["periods"]
    record = d["motions"][0][f"psa_{key}"]
    for psa in group.get(f"psa_{key}", []):
        ax.plot(T, psa, color="0.6", lw=0.4, alpha=0.7)
    if f"median_{key}" in group:
        ax.fill_between(T, group[f"p16_{key}"], group[f"p84_{key}"], color="tab:blue",
                        alpha=0.25, lw=0, label="16–84 %")
        ax.plot(T, group[f"median_{key}"], color="tab:blue", lw=1.8,
                label=f"median (geometric mean), n = {group['n']}")
    ax.plot(T, record, color="black", lw=1.8, label="record")
    ax.plot([], [], color="0.6", lw=0.4, label="each synthetic")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(float(T[0]), float(T[-1]))
    ax.set_xlabel("T [s]")
    ax.set_ylabel(f"PSA, ζ = {100 * d['damping']:g} % [g]")
    q = group.get("fit_quality")
    if q is not None:
        text = "median/record: " + ", ".join(
            f"{b.replace(' s', '')} s {r:.2f}" for b, r in q[key]["band_ratio"].items())
        text += f"\nrecord inside 5–95 %: {100 * q[key]['inside_5_95']:.0f} % of 0.1–4 s"
        ax.text(0.02, 0.03, text, transform=ax.transAxes, fontsize=6.5, va="bottom",
                bbox={"facecolor": "white", "alpha": 0.8, "lw": 0})
    method = METHOD_TITLES.get(group["method"], group["method"])
    ax.set_title(f"{method}{' (this ensemble)' if in_use else ' (comparison)'}", fontsize=8)


@styled
def plot(d: dict) -> Figure:
    """Traces in stacked rows (x, y), spectra per component and method on the right."""
    from matplotlib.figure import Figure

    motions = d["motions"]
    n = len(motions)
    # Counts left, spectrum right: the repair reads left to right.
    groups = sorted(d["groups"], key=lambda g: g["method"] != "counts")
    fig = Figure(figsize=(7.0 + 3.6 * len(groups), max(0.6 * n + 1.8, 6.5)),
                 layout="constrained")
    outer = fig.add_gridspec(1, 2, width_ratios=(2.0, 1.8 * len(groups)))
    _traces(fig, outer[0].subgridspec(n, 2), motions, d["colors"])
    right = outer[1].subgridspec(2, len(groups))
    rec = d["record"]
    for row, (key, _, name) in enumerate(COMPONENTS):
        share = None
        for col, group in enumerate(groups):
            ax = fig.add_subplot(right[row, col], sharey=share)
            share = share or ax
            _spectrum_panel(ax, d, group, key, group is d["groups"][0])
            if col == 0:
                az = rec.get(f"{key}_azimuth")
                ax.annotate(f"{key}: {name} principal axis, azimuth "
                            f"{'?' if az is None else f'{az:.1f}°'} ({bearing(az)})",
                            (0.0, 1.13), xycoords="axes fraction", fontsize=8.5,
                            fontweight="bold", annotation_clip=False)
    # one legend below the spectra: inside a panel it covers the curves somewhere
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower right", ncols=4, fontsize=7)
    fig.suptitle(f"Ground motions of the ensemble{paper_tag(d, 'Fig 8')}: {rec['label']} and "
                 "its synthetic RDK pairs")
    return fig


# ------------------------------------------------------ comparison with the paper


def _is_el_centro(*names) -> bool:
    return any("centro" in str(n).lower() for n in names)


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    rows = []
    for key, d in notes_of(notes, "fig08_motions"):
        m = d.get("measured", {})
        ens = key.removeprefix("fig08_motions").strip("_") or "ensemble"
        angle = m.get("principal_offset_deg")
        n = m.get("n_motions")
        pairs = f"; {n - 1} synthetic pairs (paper: 10)" if isinstance(n, int) else ""
        if _is_el_centro(ens, m.get("record")):
            rows.append(judged(
                "fig08_motions", f"Rotation of the record to uncorrelated axes (§5.1), {ens}",
                "22.33°", f"{fmt(angle)}° ({m.get('record')}){pairs}",
                abs(abs(angle) - 22.33) <= 0.5 if finite(angle) else None, "|Δ| ≤ 0.5°",
                "the record version differs (NGA-West2 RSN 6 here; the paper does not name its "
                "version or processing); the angle is computed from this version's two "
                "components"))
        else:  # the paper gives the angle of El Centro only
            rows.append(Comparison(
                "fig08_motions", f"Rotation of the record to uncorrelated axes, {ens}",
                "no angle given", f"{fmt(angle)}° ({m.get('record')}){pairs}", NOT_IN_PAPER,
                "the paper states the angle for its other record only"))
        if isinstance(n, int) and n - 1 != 10:  # the paper's ten pairs: a row only if not
            rows.append(judged(
                "fig08_motions", f"Synthetic pairs simulated (§5.1), {ens}", "10", f"{n - 1}",
                False, "the same number", f"this run's configuration asks for {n - 1} "
                "(a reduced run)"))
    return rows or [Comparison("fig08_motions", "Ground motions of the ensemble (Fig 8)", "—",
                               "—", NOT_COMPUTED, "figure not built")]


# ------------------------------------------------------------ extra table of the report


def fit_quality_table(notes: Mapping) -> pd.DataFrame:
    """Fit quality of the ensemble (and its comparison), one row per method and component.

    Columns: record, identification method (``*`` marks the one the study uses), component,
    the median ÷ record PSA ratio per period band, its range over 0.1–4 s, and the share of
    periods with the record inside the ensemble's 5–95 % range.
    """
    import pandas as pd

    m = notes.get("measured", {})
    used = m.get("fit_method")
    rows = []
    for method, fit in (m.get("fit_quality") or {}).items():
        if not fit:
            continue
        for key, name in (("x", "x (major)"), ("y", "y (minor)")):
            q = fit[key]
            row = {"record": m.get("record"),
                   "identification": method + (" *" if method == used else ""),
                   "component": name}
            row.update({f"median/record {b}": round(r, 2) for b, r in q["band_ratio"].items()})
            row["range 0.1-4 s"] = f"{q['ratio_min']:.2f}–{q['ratio_max']:.2f}"
            row["record inside 5–95 %"] = f"{100 * q['inside_5_95']:.0f} % of periods"
            row["pairs"] = q["n"]
            rows.append(row)
    return pd.DataFrame(rows)


def report_tables(notes: Mapping) -> list[tuple[str, pd.DataFrame]]:
    """The report's table under this figure: the fit quality of the synthetic ensemble."""
    return [("Fit quality of the synthetic ensembles (5 % PSA, geometric mean of the synthetic "
             "motions ÷ record; * = the ensemble the study uses)", fit_quality_table(notes))]


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402


def _arguments(inputs: Mapping, params: Mapping) -> dict:
    """The ensemble and the pairs of the other identification method, read."""
    from rocking.motions.ensemble_io import load_ensemble

    return {"motions": load_ensemble(inputs["motions"]),
            "comparison": load_ensemble(inputs["comparison"]),
            "paper": bool(params["paper"])}


FIGURE = FigureSpec(
    name="fig08_motions", module=__name__, number=8, label="Fig 8",
    caption=(
        "Acceleration traces on the principal axes (x = major, y = minor) and 5 %-damped "
        "pseudo-acceleration spectra of the record (top, black) and its synthetic "
        "Rezaeian–Der Kiureghian pairs (the same colours as in the spectra per motion): per "
        "component the record (black), every synthetic motion (grey) and their median with "
        "the 16–84 % range (blue); left the count-based identification of RDK (2010), right "
        "the spectrum-matched one the study uses (fit quality in the table below the "
        "figure)."
    ),
    paper=(
        "The paper rotates El Centro by 22.33° to uncorrelated axes and simulates 10 pairs; "
        "the seeds are not the paper's, so individual synthetic motions differ from its Fig "
        "8."
    ),
    # a suite of records is not a record with its synthetic pairs
    scope="ensemble", wanted=lambda s: not s.config["ensembles"][s.ensemble].get("records"),
    inputs={"motions": "motions", "comparison": "comparison"}, params={"paper": "paper"},
    arguments=_arguments,
    own_caption=lambda notes: FIGURE.caption.replace(
        " (the same colours as in the spectra per motion)", ""))
"""Fig 8, for every ensemble of one record that some study uses."""
