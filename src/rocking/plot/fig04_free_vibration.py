"""Figure 4: free rocking and wobbling of the R = 6 m, tan α = 0.2 cylinder.

Three initial conditions, all released from tilt θ0 at rest in θ:

- quasi-rocking: a tiny spin φ̇0 = 1e-8 rad/s (the paper's value);
- pure wobbling: φ̇0 = the wobbling rate at θ0 (corrected Eq 24), so θ stays at θ0;
- mixed: half the wobbling rate, a combination of the two (the paper's Fig 4e–f shows a tilt
  that oscillates without coming close to zero, which a fraction of the wobbling spin gives).

θ0 = 0.1 rad reproduces the paper's first approach speed: θ̇ = −p √(2 (cos(α − θ0) − cos α))
= 0.190 rad/s, the 0.19 of its Eq (32). The undamped model is overlaid with the damped one for
the paper's eight contact parameters (§3: ωn ∈ {200, 2000} rad/s, ζ ∈ {0.05, 0.5, 5, 50}),
whose curves the paper reports to coincide; the figure measures how far apart they are. From
the same runs it measures the angle of turn of the contact point per quasi-impact (paper: 3.058;
asymptote π √(κo/κt) = 3.188) and the apparent coefficient of restitution of the damped model
over the first five quasi-impacts (paper Eq 32: 0.942).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from rocking.dynamics.names import (
    DAMPED_OMEGA_N,
    DAMPED_ZETA,
    MODEL_3D,
    MODEL_3D_DAMPED,
    PAPER_CONTACT_GRID,
)
from rocking.plot._style import styled
from rocking.plot.comparisons import (
    EQUATIONS,
    Comparison,
    close,
    finite,
    first_notes,
    fmt,
    judged,
    value_range,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from rocking.dynamics.bodies import Cylinder

R = 6.0
TAN_ALPHA = 0.2
THETA0 = 0.1
QUASI_ROCKING_SPIN = 1e-8
MIXED_FRACTION = 0.5
CASES = ("quasi-rocking", "wobbling", "mixed")
MODELS = (MODEL_3D, MODEL_3D_DAMPED)
PAIRS = PAPER_CONTACT_GRID
"""The paper's eight contact parameters (ωn [rad/s], ζ [-]) of the damped model (§3)."""


def initial_spin(body: Cylinder, case: str, theta0: float) -> float:
    """Initial spin φ̇0 [rad/s] of one of the three cases of Fig 4."""
    if case == "quasi-rocking":
        return QUASI_ROCKING_SPIN
    if case == "wobbling":
        return float(body.wobbling_rate(theta0))
    if case == "mixed":
        return MIXED_FRACTION * float(body.wobbling_rate(theta0))
    raise ValueError(f"case must be one of {CASES}, got {case!r}")


def centre_of_mass_orbit(body: Cylinder, theta, phi) -> tuple[np.ndarray, np.ndarray]:
    """Horizontal position of the centre of mass relative to the base centre at rest [m].

    From Eq (11) without ground displacement: the base centre moves by b(1 − cos θ) and the
    centre of mass sits h sin θ further, both along (cos φ, sin φ).
    """
    theta = np.asarray(theta, dtype=float)
    phi = np.asarray(phi, dtype=float)
    radius = body.b * (1.0 - np.cos(theta)) + body.h * np.sin(theta)
    return radius * np.cos(phi), radius * np.sin(phi)


def densify(t, theta, phi, n: int = 3000) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """θ and φ linearly interpolated onto the solver times plus ``n`` uniform times.

    Steady wobbling takes few, long solver steps; drawn point to point its circular orbit
    would be a polygon. φ is linear in t there, so interpolation restores the circle, and
    near quasi-impacts the solver's own dense steps dominate the merged grid.
    """
    t = np.asarray(t, dtype=float)
    grid = np.union1d(t, np.linspace(t[0], t[-1], n))
    return grid, np.interp(grid, t, theta), np.interp(grid, t, phi)


def tilt_maxima(theta) -> np.ndarray:
    """Indices of the tilt maxima, the initial sample included when it is one."""
    theta = np.asarray(theta, dtype=float)
    from scipy.signal import find_peaks  # scipy.signal costs 0.6 s to import: only when drawn

    peaks, _ = find_peaks(theta)
    if theta.size > 1 and theta[0] >= theta[1]:
        peaks = np.concatenate(([0], peaks))
    return peaks


def turn_angles(theta, phi) -> np.ndarray:
    """Angle of turn of the contact point across each quasi-impact [rad], in [0, 2π).

    Between quasi-impacts of quasi-rocking the spin is negligible, so the change of φ from one
    tilt maximum to the next is the turn during the quasi-impact between them.
    """
    idx = tilt_maxima(theta)
    return np.mod(np.abs(np.diff(np.asarray(phi, dtype=float)[idx])), 2.0 * np.pi)


def approach_speeds(theta, theta_dot) -> np.ndarray:
    """Largest tilt-closing speed −θ̇ [rad/s] before each quasi-impact.

    Each window runs from a tilt maximum to the following tilt minimum, so the rebound after
    the quasi-impact never enters the window of the approach before it.
    """
    theta = np.asarray(theta, dtype=float)
    theta_dot = np.asarray(theta_dot, dtype=float)
    maxima = tilt_maxima(theta)
    speeds = []
    for start, stop in zip(maxima[:-1], maxima[1:], strict=True):
        minimum = start + int(np.argmin(theta[start:stop]))
        if minimum > start:
            speeds.append(float(np.max(-theta_dot[start : minimum + 1])))
    return np.asarray(speeds)


def restitution(theta, theta_dot, n_impacts: int = 5) -> float:
    """Mean coefficient of restitution over ``n_impacts`` quasi-impacts, (v_{n+1}/v_1)^(1/n).

    This is the paper's Eq (32) estimate; NaN with fewer than ``n_impacts + 1`` approaches is
    avoided by raising, so a too-short run cannot pass as a measurement.
    """
    v = approach_speeds(theta, theta_dot)
    if v.size < n_impacts + 1:
        raise ValueError(
            f"n_impacts={n_impacts} needs {n_impacts + 1} approaches, the history has {v.size}"
        )
    return float((v[n_impacts] / v[0]) ** (1.0 / n_impacts))


def damped_key(omega_n: float, zeta: float) -> str:
    """Name of a damped run in ``runs[case]``: ``"3d-damped ωn=2000 ζ=5"``."""
    return f"{MODEL_3D_DAMPED} ωn={omega_n:g} ζ={zeta:g}"


def data(
    *,
    R: float = R,
    tan_alpha: float = TAN_ALPHA,
    theta0: float = THETA0,
    duration: float = 15.0,
    cases: tuple[str, ...] = CASES,
    models: tuple[str, ...] = MODELS,
    pairs: tuple[tuple[float, float], ...] = PAIRS,
    omega_n: float = DAMPED_OMEGA_N,
    zeta: float = DAMPED_ZETA,
    rtol: float | None = None,
) -> dict:
    """Run the free-vibration analyses of Fig 4 and return the histories and measurements.

    Parameters
    ----------
    R : float
        Semi-diagonal [m].
    tan_alpha : float
        Slenderness [-].
    theta0 : float
        Initial tilt [rad].
    duration : float
        Length of each analysis [s].
    cases, models : tuple of str
        Subsets of :data:`CASES` and :data:`MODELS`.
    pairs : tuple of (float, float)
        Contact parameters (ωn [rad/s], ζ [-]) of the damped runs (default the paper's eight).
    omega_n, zeta : float
        The study's contact parameters [rad/s], [-]: added to ``pairs`` if absent; their run
        gives the damped restitution.
    rtol : float, optional
        Relative tolerance of the integrations (None: the models' defaults).

    Returns
    -------
    dict
        ``runs[case][key]`` (key ``"3d"`` or :func:`damped_key`) = dict of ``t, theta,
        theta_dot, phi, phi_dot, t_orbit, x, y`` arrays, ``theta_max``, ``status``,
        ``model``, ``omega_n``, ``zeta``; ``reference``: the key of the study's damped run;
        ``measured``: turn angle, restitutions and the spread among the damped runs;
        ``body``; ``predicted`` closed forms.
    """
    from rocking.dynamics.bodies import Cylinder

    body = Cylinder(R, tan_alpha)
    runs_pairs = list(pairs) + [(omega_n, zeta)] * ((omega_n, zeta) not in pairs)
    runs: dict[str, dict[str, dict]] = {}
    for case in cases:
        spin = initial_spin(body, case, theta0)
        runs[case] = {}
        if MODEL_3D in models:
            runs[case][MODEL_3D] = _run(body, theta0, spin, duration, MODEL_3D, rtol)
        if MODEL_3D_DAMPED in models:
            for wn, z in runs_pairs:
                runs[case][damped_key(wn, z)] = _run(body, theta0, spin, duration, MODEL_3D_DAMPED,
                                                     rtol, omega_n=wn, zeta=z)
    reference = damped_key(omega_n, zeta) if MODEL_3D_DAMPED in models else None
    return {
        "runs": runs,
        "reference": reference,
        "measured": measurements(runs, reference),
        "body": {"R": R, "tan_alpha": tan_alpha, "theta0": theta0, "duration": duration,
                 "omega_n": omega_n, "zeta": zeta, "pairs": [list(p) for p in runs_pairs]},
        "axes": {"text": "x, y: horizontal axes of Fig 1; released towards +x (φ0 = 0)"},
        "predicted": {
            "turn_angle": body.turn_angle,
            "restitution": body.e,
            "first_approach_speed": body.p * math.sqrt(
                2.0 * (math.cos(body.alpha - theta0) - math.cos(body.alpha))
            ),
        },
    }


def _run(body: Cylinder, theta0: float, spin: float, duration: float, model: str,
         rtol: float | None, **contact) -> dict:
    """One free-vibration history with the densified centre-of-mass orbit."""
    from rocking.dynamics.analysis import (
        free_vibration,  # imported late: figures stay light to import
    )

    res = free_vibration(body, theta0, spin, duration=duration, model=model, rtol=rtol,
                         **contact)
    t_orbit, theta_orbit, phi_orbit = densify(res.t, res.theta, res.phi)
    x, y = centre_of_mass_orbit(body, theta_orbit, phi_orbit)
    return {
        "t": np.asarray(res.t),
        "theta": np.asarray(res.theta),
        "theta_dot": np.asarray(res.theta_dot),
        "phi": np.asarray(res.phi),
        "phi_dot": np.asarray(res.phi_dot),
        "t_orbit": t_orbit,
        "x": x,
        "y": y,
        "theta_max": float(res.theta_max),
        "status": str(res.status.value),
        "phi_dot0": spin,
        "model": model,
        **{k: float(v) for k, v in contact.items()},
    }


def max_gap(runs: list[dict], key: str = "theta") -> float:
    """Largest difference of ``key`` between any run and the first, over the first's times."""
    if len(runs) < 2:
        return float("nan")
    ref = runs[0]
    gaps = [np.max(np.abs(np.interp(ref["t"], r["t"], r[key]) - ref[key])) for r in runs[1:]]
    return float(max(gaps))


def measurements(runs: dict, reference: str | None = None) -> dict:
    """Turn angle (undamped quasi-rocking), restitutions, and how far apart the damped runs of
    different contact parameters and the undamped run are, per case [rad]."""
    out: dict = {}
    quasi = runs.get("quasi-rocking", {})
    if MODEL_3D in quasi:
        r = quasi[MODEL_3D]
        angles = turn_angles(r["theta"], r["phi"])
        if angles.size:
            out["turn_angle_first"] = float(angles[0])
            out["turn_angle_mean"] = float(np.mean(angles))
            out["n_turns"] = int(angles.size)
        out["restitution_undamped"] = _safe_restitution(r)
    damped_quasi = {k: r for k, r in quasi.items() if r["model"] == MODEL_3D_DAMPED}
    if damped_quasi:
        rest = {k: _safe_restitution(r) for k, r in damped_quasi.items()}
        found = [v for v in rest.values() if v is not None]
        out["restitution_damped_range"] = [min(found), max(found)] if found else None
        ref = damped_quasi.get(reference, next(iter(damped_quasi.values())))
        out["restitution_damped"] = _safe_restitution(ref)
        out["approach_speeds_damped"] = approach_speeds(ref["theta"], ref["theta_dot"])[:6].tolist()
    for case, models in runs.items():
        damped = [r for r in models.values() if r["model"] == MODEL_3D_DAMPED]
        if len(damped) > 1:
            out[f"max_gap_theta_damped_pairs_{case}"] = max_gap(damped)
        if damped and MODEL_3D in models:
            out[f"max_gap_theta_damped_undamped_{case}"] = max_gap([models[MODEL_3D], *damped])
    return out


def _safe_restitution(run: dict) -> float | None:
    # A short run has too few quasi-impacts; report None (shown as "not measured").
    try:
        return restitution(run["theta"], run["theta_dot"])
    except ValueError:
        return None


DASH = 2.0
"""Length of one dash of a damped run [pt]: the runs' dashes interleave (see run_style)."""


def run_style(key: str, run: dict, index: int = 0, count: int = 1) -> dict:
    """Line style of a run: undamped black solid; damped dashed, ωn = 200 blues, 2000 reds,
    darker for larger ζ.

    The damped runs coincide to plotting accuracy; each draws one dash of length
    :data:`DASH` per period of ``count`` dashes, shifted by its ``index``, so that where the
    curves lie on one another every run's colour still shows.
    """
    import matplotlib as mpl

    if run["model"] == MODEL_3D:
        return {"color": "black", "ls": "-", "lw": 1.6, "label": "undamped", "zorder": 1}
    shade = {0.05: 0.45, 0.5: 0.6, 5.0: 0.75, 50.0: 0.9}.get(run["zeta"], 0.7)
    cmap = mpl.colormaps["Blues" if run["omega_n"] < 1000.0 else "Reds"]
    n = max(int(count), 1)
    dashes = (DASH * index, (DASH, DASH * (n - 1))) if n > 1 else (0, (3.0, 2.0))
    return {"color": cmap(shade), "ls": dashes, "lw": 1.3, "zorder": 2,
            "label": f"ωn = {run['omega_n']:g}, ζ = {run['zeta']:g}"}


def symlog_ticks(ax, values, linthresh: float = 1.0, max_ticks: int = 5) -> None:
    """At most ``max_ticks`` decades labelled on a symmetric log axis, as 10^k."""
    from matplotlib import ticker

    values = np.asarray(values, dtype=float)
    top = float(np.nanmax(np.abs(values), initial=linthresh))
    k_max = max(1, math.ceil(math.log10(max(top, linthresh * 10.0))))
    step = max(1, math.ceil(k_max / (max_ticks - 1)))
    decades = [10.0**k for k in range(0, k_max + 1, step)]
    ticks = [0.0, *decades]
    if np.nanmin(values, initial=0.0) < -linthresh:
        ticks = [-v for v in decades[::-1]] + ticks
    ax.yaxis.set_major_locator(ticker.FixedLocator(ticks))
    ax.yaxis.set_major_formatter(ticker.FuncFormatter(_power_label))
    ax.yaxis.set_minor_locator(ticker.NullLocator())


def _power_label(value: float, _pos) -> str:
    if value == 0.0:
        return "0"
    k = round(math.log10(abs(value)))
    return f"{'−' if value < 0 else ''}10$^{{{k}}}$"


@styled
def plot(d: dict) -> Figure:
    """Figure 4: orbits (left) and θ, θ̇, φ, φ̇ histories (right), one row per case."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    runs = d["runs"]
    cases = list(runs)
    fig = Figure(figsize=(10.5, 2.7 * len(cases) + 1.0), layout="constrained")
    grid = fig.add_gridspec(len(cases), 3, width_ratios=(1.2, 1.0, 1.0))
    names = (("theta", "θ [rad]"), ("theta_dot", "θ̇ [rad/s]"), ("phi", "φ [rad]"),
             ("phi_dot", "φ̇ [rad/s]"))
    for row, case in enumerate(cases):
        axes = _case_axes(fig, grid, row)
        damped = [k for k, r in runs[case].items() if r["model"] == MODEL_3D_DAMPED]
        for key, run in runs[case].items():
            k = damped.index(key) if key in damped else 0
            style = run_style(key, run, k, len(damped))
            axes[0].plot(run["x"], run["y"], **style)  # the densified orbit, see densify()
            for ax, (name, _) in zip(axes[1:], names, strict=True):
                ax.plot(run["t"], run[name], **{**style, "label": None})
        _label_case(axes, case, runs[case], names, d.get("measured", {}))
    handles, labels = fig.axes[0].get_legend_handles_labels()
    # the legend shows each damped run as a plain dashed line (interleaved dashes read as dots)
    handles = [handles[0]] + [Line2D([], [], color=h.get_color(), ls="--", lw=1.3)
                              for h in handles[1:]]
    title = "undamped (solid) and damped (dashed; ωn [rad/s], ζ [-])"
    if "quasi-rocking" in cases:  # said under the figure, not over the spikes it explains
        title += ("\nφ̇ of the quasi-rocking case (top right) on a symmetric log scale, linear "
                  "within ±1 rad/s: at each quasi-impact θ passes near 0\nand the contact point "
                  "turns by ≈ π almost at once, so φ̇ spikes")
    fig.legend(handles, labels, loc="outside lower center", ncols=5,
               fontsize=7, title=title, title_fontsize=7.5)
    b = d["body"]
    fig.suptitle(
        f"Free vibration, R = {b['R']:g} m, tan α = {b['tan_alpha']:g}, θ0 = {b['theta0']:g} rad "
        "(Fig 4); released towards +x"
    )
    return fig


def _case_axes(fig: Figure, grid, row: int) -> list:
    """Orbit axes and the four history axes (θ, θ̇ | φ, φ̇) of one row."""
    ax_orbit = fig.add_subplot(grid[row, 0])
    sub_a = grid[row, 1].subgridspec(2, 1, hspace=0.05)
    sub_b = grid[row, 2].subgridspec(2, 1, hspace=0.05)
    hist = [fig.add_subplot(sub_a[i]) for i in range(2)] + [fig.add_subplot(sub_b[i])
                                                            for i in range(2)]
    return [ax_orbit, *hist]


def _label_case(axes: list, case: str, models: dict, names, measured: dict) -> None:
    """Axis labels, scales and the measured gap between the damped runs of one case."""
    ax_orbit, hist = axes[0], axes[1:]
    ax_orbit.set_aspect("equal", adjustable="datalim")
    ax_orbit.set_xlabel("x of centre of mass [m]")
    ax_orbit.set_ylabel("y [m]")
    ax_orbit.set_title(f"{case}: φ̇0 = {_first(models)['phi_dot0']:.3g} rad/s")
    for ax, (key, label) in zip(hist, names, strict=True):
        ax.set_ylabel(label)
        if case != "quasi-rocking":
            _min_span(ax, [r[key] for r in models.values()])
    for ax in (hist[0], hist[2]):
        ax.tick_params(labelbottom=False)
    for ax in (hist[1], hist[3]):
        ax.set_xlabel("t [s]")
    if case == "quasi-rocking":
        # φ̇ spikes to ~1e8 rad/s in quasi-impacts: a symmetric log scale keeps them visible
        hist[3].set_yscale("symlog", linthresh=1.0)
        symlog_ticks(hist[3], np.concatenate([r["phi_dot"] for r in models.values()]))
    gap = measured.get(f"max_gap_theta_damped_pairs_{case}")
    if gap is not None and np.isfinite(gap):
        n = sum(r["model"] == MODEL_3D_DAMPED for r in models.values())
        hist[0].set_title(f"{n} damped runs (interleaved dashes) coincide: max |Δθ| = "
                          f"{gap:.2g} rad", fontsize=6.5, loc="right")


def _min_span(ax, series, span: float = 0.02) -> None:
    # A constant history (θ, θ̇, φ̇ of pure wobbling) would be drawn at round-off scale.
    values = np.concatenate([np.asarray(v, dtype=float) for v in series])
    if values.size and np.ptp(values) < span:
        mid = 0.5 * (values.max() + values.min())
        ax.set_ylim(mid - span, mid + span)
    ax.ticklabel_format(axis="y", useOffset=False)


def _first(models: dict) -> dict:
    return next(iter(models.values()))


# ------------------------------------------------------ comparison with the paper


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    d = first_notes(notes, "fig04_free_vibration")
    m, pred, body = d.get("measured", {}), d.get("predicted", {}), d.get("body", {})
    name = "fig04_free_vibration"
    turn = m.get("turn_angle_first")
    other = 2 * math.pi - turn if finite(turn) else None
    rows = [
        judged(name, "Angle of turn of the contact point per quasi-impact, Eq (27)", "3.0952",
               f"{fmt(turn)} rad (asymptote π√(κo/κt) = {fmt(pred.get('turn_angle'), 6)}); "
               f"2π − it = {fmt(other)}", close(turn, 3.0952, 1e-3), "|Δ| ≤ 0.1 %",
               "the printed Eq (27) inverts the inertia ratio (derivation: "
               f"{EQUATIONS}#eq-27-the-angle-of-turn): it gives the turn measured the other way "
               f"round, 2π − ours = {fmt(other)}"),
        judged(name, "Angle of turn measured numerically (§2.4)", "3.058",
               f"{fmt(turn)} rad (2π − it = {fmt(other)})", close(turn, 3.058, 1e-3),
               "|Δ| ≤ 0.1 %", "the paper does not say how its 3.058 was read off; ours is φ "
               "between tilt maxima of a φ̇0 = 1e-8 rad/s run and equals the asymptote"),
        judged(name, "Coefficient of restitution of the damped model over five quasi-impacts, "
               "Eq (31)–(32)", "0.942",
               f"{fmt(m.get('restitution_damped'))} (ωn = {fmt(body.get('omega_n'))} rad/s, "
               f"ζ = {fmt(body.get('zeta'))}); over the eight (ωn, ζ): "
               + value_range(m.get("restitution_damped_range")),
               close(m.get("restitution_damped"), 0.942, 0.002 / 0.942), "|Δ| ≤ 0.002",
               "the contact parameters or θ0 change the measured restitution"),
    ]
    theta0 = float(body.get("theta0", 0.1))
    tol = 0.02 * theta0
    cases = ("quasi-rocking", "wobbling", "mixed")
    rows.append(_gap_row(name, m, "damped_pairs", cases, tol,
                         "Damped responses for ωn ∈ {200, 2000} rad/s × ζ ∈ {0.05, 0.5, 5, 50} "
                         "(§3: 'the plots overlap')", "the eight curves overlap",
                         "max |Δθ| among the eight", "the contact parameters change the "
                         "response visibly", "damped model not run"))
    rows.append(_gap_row(name, m, "damped_undamped", cases[1:], tol,
                         "Damped and undamped responses without quasi-impacts (§2.4, §3: "
                         "indistinguishable)", "indistinguishable", "max |Δθ| damped − undamped",
                         "the damped model dissipates energy without quasi-impacts",
                         "undamped or damped model not run"))
    return rows


def _gap_row(name: str, m: Mapping, kind: str, cases, tol: float, statement: str, paper: str,
             what: str, reason: str, missing: str) -> Comparison:
    """One row for the largest |Δθ| of several free-vibration cases (each case listed)."""
    gaps = {c: m.get(f"max_gap_theta_{kind}_{c}") for c in cases}
    found = {c: g for c, g in gaps.items() if finite(g)}
    ours = f"{what}: " + "; ".join(f"{c} {fmt(g, 2)} rad" for c, g in found.items())
    ok = all(g <= tol for g in found.values()) if found else None
    return judged(name, statement, paper, ours, ok, f"max |Δθ| ≤ 2 % of θ0 = {tol:g} rad in "
                  "every case", reason, missing)


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="fig04_free_vibration", module=__name__, number=4, label="Fig 4",
    caption=(
        "Fig 4. Free vibration of the R = 6 m, tan α = 0.2 cylinder released from θ0 = 0.1 "
        "rad towards +x (φ0 = 0) with three initial spins: quasi-rocking (φ̇0 = 1e-8 rad/s, "
        "the paper's value), pure wobbling (φ̇0 = the wobbling rate of Eq 24) and a mixed "
        "case (half that rate). Black: undamped; coloured: the damped model for the paper's "
        "eight contact parameters ωn ∈ {200, 2000} rad/s × ζ ∈ {0.05, 0.5, 5, 50} (§3). "
        "Left: orbit of the centre of mass in the horizontal x–y plane of Fig 1. The eight "
        "damped runs lie on one another (their largest gap is written above each θ panel); "
        "each is drawn with interleaved dashes so that every colour shows. The φ̇ panel of "
        "the quasi-rocking case has a symmetric log scale (linear below 1 rad/s): at each "
        "quasi-impact θ passes near 0 and the contact point turns by about π almost at "
        "once, so φ̇ spikes to 1e8 rad/s between stretches of nearly zero spin."
    ),
    scope="global", wanted=lambda s: s.reproduces, paper_only=True, el_centro_only=True,
    inputs={"numba": "numba"},
    # the study's contact parameters; the figure adds the paper's eight pairs
    params={"model_options": "model_options"},
    arguments=lambda inputs, params: dict(params["model_options"]))
"""Fig 4: free vibration, drawn once for a reproduction of the paper."""
