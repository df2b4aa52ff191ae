"""Companion to Figure 6: peak tilt versus a scale factor on the record, per record version.

The paper's Fig 6 peak tilts (0.0838 rad undamped, 0.0668 rad damped) come from one response to
one record. This figure shows how much such a peak moves with the version of the record
available here (as recorded, unfiltered; on principal axes and high-passed, as the study uses
it) and with a few per cent of scale: the evidence behind the explanation Fig 6 carries. The
rotation itself cannot matter: the cylinder is axisymmetric, so a rotated pair gives a rotated
response with the same θmax; the data check this with the paper's 22.33°. Not a figure of the
paper.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from rocking.constants import G
from rocking.dynamics.names import MODEL_3D, MODEL_3D_DAMPED
from rocking.motions.motion import GroundMotion
from rocking.plot import _axes
from rocking.plot._style import footnote, styled, with_legend_row
from rocking.plot.comparisons import NOT_IN_PAPER, Comparison, first_notes, fmt

if TYPE_CHECKING:
    from matplotlib.figure import Figure

R = 6.0
TAN_ALPHA = 0.2
MODELS = (MODEL_3D, MODEL_3D_DAMPED)
SCALES = tuple(np.round(np.linspace(0.75, 1.25, 51), 4))
"""Scale factors on both components [-]."""
BAND = 0.05
"""Half-width of the scale band whose θmax range the report quotes [-]."""
PAPER_ANGLE_DEG = 22.33
"""The paper's rotation of El Centro to uncorrelated axes (§5.1) [deg]."""
PAPER_THETA_MAX = {MODEL_3D: 0.0838, MODEL_3D_DAMPED: 0.0668}
COMPONENT_PGA_NOTE = "component_pga_g|"
"""Prefix of the measured key of a record version's component peaks [g]."""
PGA_NOTE = "pga_g|"
"""Prefix of the measured key of a record version's vector peak [g]."""
"""Peak tilts printed in §4 [rad]."""

AS_RECORDED = "as recorded (x E–W, y N–S), unfiltered"
STUDY = "principal axes, high-passed (this study)"
PAPER_ROTATION = "rotated 22.33° (paper) + high-pass"
VERSION_STYLE = {AS_RECORDED: "tab:blue", STUDY: "black"}
MODEL_STYLE = {MODEL_3D: {"ls": "-", "marker": "o"},
               MODEL_3D_DAMPED: {"ls": "--", "marker": "s"}}


def record_versions(record: GroundMotion, *, mw: float | None = None, seed: int = 0,
                    max_duration: float | None = None) -> dict[str, GroundMotion]:
    """The versions of a recorded pair compared here, processed like the study's ensembles:
    as recorded, on principal axes + high-passed, and rotated by the paper's 22.33° +
    high-passed (the last only to check that a rotation leaves θmax unchanged).

    Parameters
    ----------
    record : GroundMotion
        The pair as recorded [m/s²].
    mw : float, optional
        Moment magnitude for the Brune corner of the high-pass (default from the record).
    seed : int
        Root seed (unused without synthetic pairs; kept for :func:`build_ensemble`).
    max_duration : float, optional
        Keep the first ``max_duration`` seconds, as a run with ``motions.max_duration`` does
        with every motion [s].
    """
    from rocking.motions.build import build_ensemble  # imported late: figures stay light to import

    def processed(rotation):
        return build_ensemble(record, 0, seed, rotation=rotation, mw=mw,
                              max_duration=max_duration).motions[0]

    raw = record
    if max_duration is not None and max_duration < record.duration:
        keep = int(round(max_duration / record.dt)) + 1
        raw = GroundMotion(record.ax[:keep], record.ay[:keep], record.dt, record.name,
                           record.metadata)
    return {AS_RECORDED: raw, STUDY: processed("auto"),
            PAPER_ROTATION: processed(PAPER_ANGLE_DEG)}


def data(record: GroundMotion | None = None, *,
         versions: dict[str, GroundMotion] | None = None, mw: float | None = None,
         max_duration: float | None = None,
         scales: Sequence[float] = SCALES, R: float = R, tan_alpha: float = TAN_ALPHA,
         models: tuple[str, ...] = MODELS, **model_kw) -> dict:
    """Peak tilt per (version, model, scale).

    Parameters
    ----------
    record : GroundMotion, optional
        The pair as recorded; its versions come from :func:`record_versions`.
    versions : dict of str to GroundMotion, optional
        Ready versions instead of ``record``.
    mw, max_duration : float, optional
        Passed to :func:`record_versions`.
    scales : sequence of float
        Scale factors on both components [-].
    R : float
        Semi-diagonal [m].
    tan_alpha : float
        Slenderness [-].
    models : tuple of str
        Dynamics models.
    **model_kw
        Passed to :func:`rocking.dynamics.analysis.ground_response` (``omega_n``, ``zeta``).

    Returns
    -------
    dict
        ``scales``; ``theta_max[version][model]`` (n_scales,) [rad]; ``pga_g[version]`` (vector
        PGA at scale 1) [g]; ``measured``: θmax at scale 1 and its range within ±:data:`BAND`
        of scale per version and model; ``paper``.
    """
    from rocking.dynamics.analysis import ground_response  # imported late: figures stay light
    from rocking.dynamics.bodies import Cylinder

    if versions is None:
        if record is None:
            raise ValueError("give record (the pair as recorded) or versions")
        versions = record_versions(record, mw=mw, max_duration=max_duration)
    scales = np.asarray(scales, dtype=float)
    if scales.ndim != 1 or scales.size < 2 or np.any(scales <= 0):
        raise ValueError(f"scales must hold at least two factors > 0, got {scales!r}")
    body = Cylinder(R, tan_alpha)
    versions = dict(versions)
    rotated = versions.pop(PAPER_ROTATION, None)
    theta = {v: {m: np.array([ground_response(body, motion, model=m, scale=s, history=False,
                                              **model_kw).theta_max for s in scales])
                 for m in models}
             for v, motion in versions.items()}
    measured = measurements(scales, theta, {v: m.pga_g for v, m in versions.items()})
    for v, m in versions.items():  # component peaks: the numbers record tables quote
        measured[COMPONENT_PGA_NOTE + v] = [float(np.max(np.abs(m.ax))) / G,
                                            float(np.max(np.abs(m.ay))) / G]
    rotated_theta = {}
    if rotated is not None and STUDY in versions:
        # Axisymmetry: the paper's rotation gives the study version's θmax (to the tolerance).
        rotated_theta = {m: ground_response(body, rotated, model=m, history=False,
                                            **model_kw).theta_max for m in models}
        measured["rotation_check"] = {m: abs(
            rotated_theta[m] - ground_response(body, versions[STUDY], model=m, history=False,
                                               **model_kw).theta_max) for m in models}
    return {
        "scales": scales,
        "theta_max": theta,
        "rotated_theta_max": rotated_theta,
        "pga_g": {v: m.pga_g for v, m in versions.items()},
        "axes": {v: _axes.describe(m.metadata)["text"] for v, m in versions.items()},
        "body": {"R": R, "tan_alpha": tan_alpha},
        "measured": measured,
        "paper": {f"theta_max_{m}": v for m, v in PAPER_THETA_MAX.items()},
    }


def measurements(scales: np.ndarray, theta: dict, pga_g: dict) -> dict:
    """θmax at scale 1 and its range within the ±:data:`BAND` scale band, per version/model."""
    out: dict = {"band": BAND, "versions": list(theta)}
    near = np.abs(scales - 1.0) <= BAND + 1e-9
    at_one = int(np.argmin(np.abs(scales - 1.0)))
    for version, models in theta.items():
        out[PGA_NOTE + version] = float(pga_g[version])
        for model, values in models.items():
            band = values[near]
            out[f"theta_max|{version}|{model}"] = float(values[at_one])
            out[f"band_range|{version}|{model}"] = [float(np.min(band)), float(np.max(band))]
            out[f"full_range|{version}|{model}"] = [float(np.min(values)), float(np.max(values))]
        if MODEL_3D in models and MODEL_3D_DAMPED in models:
            ratio = models[MODEL_3D_DAMPED][near] / models[MODEL_3D][near]
            out[f"damped_over_undamped_band|{version}"] = [float(np.min(ratio)),
                                                           float(np.max(ratio))]
    return out


@styled
def plot(d: dict) -> Figure:
    """One panel: θmax against scale factor, colour = record version, line style = model;
    overturned runs (θmax = π/2) are drawn as triangles on the upper edge."""
    fig, (ax,), legend_row = with_legend_row(7.5, 6.0, legend_share=0.28)
    s = d["scales"]
    every = np.concatenate([v for models in d["theta_max"].values() for v in models.values()])
    standing = every[every < 0.5 * np.pi * 0.999]
    top = 1.15 * max(float(np.max(standing, initial=0.0)), *PAPER_THETA_MAX.values())
    for version, models in d["theta_max"].items():
        color = VERSION_STYLE.get(version, None)
        for model, values in models.items():
            style = MODEL_STYLE.get(model, {})
            kind = "damped" if model == MODEL_3D_DAMPED else "undamped"
            # markers only: θmax is chaotic in the scale, a line between points would
            # suggest values in between that no run computed
            ax.plot(s, np.where(values < top, values, np.nan), color=color, ls="none",
                    marker=style.get("marker", "o"), ms=3.5 if kind == "undamped" else 3.0,
                    mfc=color if kind == "undamped" else "none",
                    label=f"{kind}, {version}, PGA {d['pga_g'][version]:.3f} g")
            over = values >= top
            if over.any():  # an empty unclipped line would stretch the layout to (0, 0)
                ax.plot(s[over], np.full(over.sum(), 0.985 * top), "^", color=color, ms=6,
                        clip_on=False)
    for model, value in d.get("rotated_theta_max", {}).items():
        kind = "damped" if model == MODEL_3D_DAMPED else "undamped"
        ax.plot([1.0], [value], ls="none", marker="+" if kind == "undamped" else "x", ms=11,
                mew=1.6, color="tab:orange", zorder=5,
                label=f"{kind}, {PAPER_ROTATION} (scale 1 only): {value:.4f} rad")
    for model, value in PAPER_THETA_MAX.items():
        kind = "damped" if model == MODEL_3D_DAMPED else "undamped"
        ax.axhline(value, color="tab:red", lw=1.2, ls=MODEL_STYLE[model]["ls"],
                   label=f"paper, {kind}: {value} rad")
    ax.axvspan(1.0 - BAND, 1.0 + BAND, color="0.88", zorder=0)
    ax.axvline(1.0, color="0.5", lw=0.8)
    ax.set_xlabel("Scale factor on both components [-] (1 = the record's own PGA; "
                  f"shaded: ±{100 * BAND:g} %)")
    ax.set_ylabel("Peak tilt θmax [rad]")
    ax.set_xlim(float(s[0]), float(s[-1]))
    ax.set_ylim(0.0, top)
    # below the axes: inside, the legend would hide points (θmax is scattered everywhere)
    legend_row.legend(*ax.get_legend_handles_labels(), loc="center", ncols=2,
               fontsize=6.5)
    notes = ["▲: θmax above the axis (overturned). Filled markers undamped, open damped."]
    check = d["measured"].get("rotation_check")
    if check:
        notes.append("rotating the pair by the paper's 22.33° changes θmax by "
                     f"≤ {max(check.values()):.1g} rad (axisymmetric cylinder)")
    footnote(fig, notes)
    b = d["body"]
    fig.suptitle(f"El Centro 1940: peak tilt versus scale factor and record version\n"
                 f"R = {b['R']:g} m, tan α = {b['tan_alpha']:g} (companion to Fig 6, "
                 "not in the paper)")
    return fig


# ------------------------------------------------------ comparison with the paper


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    m = first_notes(notes, "fig06_theta_max_sensitivity").get("measured", {})
    check = m.get("rotation_check") or {}
    worst = max(check.values()) if check else None
    return [Comparison(
        "fig06_theta_max_sensitivity", "θmax of the El Centro response versus scale factor and "
        "record version (evidence for Fig 6)", "—",
        f"a rotation by the paper's 22.33° changes θmax by {fmt(worst, 2)} rad; ranges per "
        "version in the Fig 6 rows", NOT_IN_PAPER,
        "a companion figure that explains Fig 6's difference")]


def run_rows(notes: Mapping) -> list[tuple[str, str]]:
    """The report's "what was run" row of the unprocessed record's peaks (for reference:
    the study scales the processed record)."""
    m = notes.get("measured", {})
    raw = [k.removeprefix(COMPONENT_PGA_NOTE) for k in m
           if k.startswith(COMPONENT_PGA_NOTE + "as recorded")]
    if not raw:
        return []
    cx, cy = m[COMPONENT_PGA_NOTE + raw[0]]
    return [("record PGA, unprocessed", f"vector {m[PGA_NOTE + raw[0]]:.3f} g, components "
             f"x (E–W) {cx:.3f} g and y (N–S) {cy:.3f} g (the larger one is the PGA record "
             "tables quote); for reference: the study scales the processed record")]


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402


def _arguments(inputs: Mapping, params: Mapping) -> dict:
    """The record as recorded (the ensemble's files), processed like the ensemble."""
    from rocking.motions.build import read_motion

    spec = params["spec"]
    return {"record": read_motion(spec["record"], spec["paths"]), "mw": spec["mw"],
            "max_duration": spec["max_duration"], **params["model_options"]}


FIGURE = FigureSpec(
    name="fig06_theta_max_sensitivity", module=__name__, number=6.5,
    label="Fig 6 (companion)",
    caption=(
        "Companion to Fig 6 (not in the paper): peak tilt θmax of the R = 6 m, tan α = 0.2 "
        "cylinder versus a scale factor on the El Centro pair, for the versions of the "
        "record available here (as recorded: x = E–W, y = N–S, unfiltered; on principal "
        "axes and high-passed, as this study uses it; rotated by the paper's 22.33° and "
        "high-passed, at scale 1 only, where it gives this study's θmax), undamped (filled "
        "markers) and damped (open), drawn as points without lines because θmax is chaotic "
        "in the scale. The horizontal lines are the paper's 0.0838 and 0.0668 rad. Scatter "
        "over a few per cent of scale is the chaotic sensitivity of a single-record peak: a "
        "match of θmax at scale 1 is not expected."
    ),
    scope="ensemble", wanted=lambda s: s.reproduces and s.on_paper_record, paper_only=True,
    el_centro_only=True, inputs={"numba": "numba"},
    params={"spec": "ensemble_spec", "model_options": "model_options"},
    arguments=_arguments)
"""Companion to Fig 6, drawn for the El Centro ensemble of a reproduction of the paper."""
