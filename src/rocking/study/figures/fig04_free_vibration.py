"""Figure 4: free rocking and wobbling of the R = 6 m, tan α = 0.2 cylinder.

Three initial conditions, all released from tilt θ0 at rest in θ:

- quasi-rocking: a tiny spin φ̇0 = 1e-8 rad/s (the paper's value);
- pure wobbling: φ̇0 = the wobbling rate at θ0 (corrected Eq 24), so θ stays at θ0;
- mixed: half the wobbling rate, a combination of the two (the paper's Fig 4e–f shows a tilt
  that oscillates without coming close to zero, which a fraction of the wobbling spin gives).

θ0 = 0.1 rad reproduces the paper's first approach speed: θ̇ = −p √(2 (cos(α − θ0) − cos α))
= 0.190 rad/s, the 0.19 of its Eq (32). Undamped and damped models are overlaid. From the same
runs the figure measures the angle of turn of the contact point per quasi-impact (paper: 3.058;
asymptote π √(κo/κt) = 3.188) and the apparent coefficient of restitution of the damped model
over the first five quasi-impacts (paper Eq 32: 0.942).
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure
from scipy.signal import find_peaks

from ...dynamics.bodies import Cylinder
from ._style import MODE_STYLE, styled

R = 6.0
TAN_ALPHA = 0.2
THETA0 = 0.1
QUASI_ROCKING_SPIN = 1e-8
MIXED_FRACTION = 0.5
CASES = ("quasi-rocking", "wobbling", "mixed")
MODELS = ("3d", "3d-damped")


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


def data(
    *,
    R: float = R,
    tan_alpha: float = TAN_ALPHA,
    theta0: float = THETA0,
    duration: float = 15.0,
    cases: tuple[str, ...] = CASES,
    models: tuple[str, ...] = MODELS,
    **model_kw,
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
    **model_kw
        Passed to :func:`rocking.free_vibration` (``rtol``, ``omega_n``, ``zeta``).

    Returns
    -------
    dict
        ``runs[case][model]`` = dict of ``t, theta, theta_dot, phi, phi_dot, x, y`` arrays,
        ``theta_max``, ``status``; ``measured`` = turn angle and restitution when the
        quasi-rocking runs exist; ``body`` parameters.
    """
    from ...dynamics.analysis import free_vibration  # imported late: figures stay light to import

    body = Cylinder(R, tan_alpha)
    runs: dict[str, dict[str, dict]] = {}
    for case in cases:
        spin = initial_spin(body, case, theta0)
        runs[case] = {}
        for model in models:
            res = free_vibration(body, theta0, spin, duration=duration, model=model, **model_kw)
            t_orbit, theta_orbit, phi_orbit = densify(res.t, res.theta, res.phi)
            x, y = centre_of_mass_orbit(body, theta_orbit, phi_orbit)
            runs[case][model] = {
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
            }
    return {
        "runs": runs,
        "measured": measurements(runs),
        "body": {"R": R, "tan_alpha": tan_alpha, "theta0": theta0, "duration": duration},
        "predicted": {
            "turn_angle": body.turn_angle,
            "restitution": body.e,
            "first_approach_speed": body.p * math.sqrt(
                2.0 * (math.cos(body.alpha - theta0) - math.cos(body.alpha))
            ),
        },
    }


def measurements(runs: dict) -> dict:
    """Turn angle (undamped quasi-rocking) and restitution (both models) from the runs."""
    out: dict[str, float] = {}
    quasi = runs.get("quasi-rocking", {})
    if "3d" in quasi:
        r = quasi["3d"]
        angles = turn_angles(r["theta"], r["phi"])
        if angles.size:
            out["turn_angle_first"] = float(angles[0])
            out["turn_angle_mean"] = float(np.mean(angles))
            out["n_turns"] = int(angles.size)
        out["restitution_undamped"] = _safe_restitution(r)
    if "3d-damped" in quasi:
        r = quasi["3d-damped"]
        out["restitution_damped"] = _safe_restitution(r)
        v = approach_speeds(r["theta"], r["theta_dot"])
        out["approach_speeds_damped"] = v[:6].tolist()
    return out


def _safe_restitution(run: dict) -> float | None:
    # A short run has too few quasi-impacts; report None (shown as "not measured").
    try:
        return restitution(run["theta"], run["theta_dot"])
    except ValueError:
        return None


@styled
def plot(d: dict) -> Figure:
    """Figure 4: orbits (left) and θ, θ̇, φ, φ̇ histories (right), one row per case."""
    runs = d["runs"]
    cases = list(runs)
    fig = Figure(figsize=(10.0, 2.6 * len(cases) + 0.4), layout="constrained")
    grid = fig.add_gridspec(len(cases), 3, width_ratios=(1.2, 1.0, 1.0))
    names = (("theta", "θ [rad]"), ("theta_dot", "θ̇ [rad/s]"))
    names2 = (("phi", "φ [rad]"), ("phi_dot", "φ̇ [rad/s]"))
    for row, case in enumerate(cases):
        ax_orbit = fig.add_subplot(grid[row, 0])
        sub_a = grid[row, 1].subgridspec(2, 1, hspace=0.05)
        sub_b = grid[row, 2].subgridspec(2, 1, hspace=0.05)
        ax_hist = [fig.add_subplot(sub_a[i]) for i in range(2)]
        ax_hist += [fig.add_subplot(sub_b[i]) for i in range(2)]
        for model, r in runs[case].items():
            style = dict(MODE_STYLE[model])
            style["color"] = "black" if model == "3d" else "tab:red"
            ax_orbit.plot(r["x"], r["y"], **style)  # the densified orbit, see densify()
            for ax, (key, _) in zip(ax_hist, names + names2, strict=True):
                ax.plot(r["t"], r[key], **style)
        ax_orbit.set_aspect("equal", adjustable="datalim")
        ax_orbit.set_xlabel("x of centre of mass [m]")
        ax_orbit.set_ylabel("y [m]")
        ax_orbit.set_title(f"{case}: φ̇0 = {_first(runs[case])['phi_dot0']:.3g} rad/s")
        ax_orbit.legend(loc="upper right")
        for ax, (key, label) in zip(ax_hist, names + names2, strict=True):
            ax.set_ylabel(label)
            if case != "quasi-rocking":
                _min_span(ax, [r[key] for r in runs[case].values()])
        for ax in (ax_hist[0], ax_hist[2]):
            ax.tick_params(labelbottom=False)
        for ax in (ax_hist[1], ax_hist[3]):
            ax.set_xlabel("t [s]")
        if case == "quasi-rocking":
            # φ̇ spikes to ~1e8 rad/s in quasi-impacts: a symmetric log scale keeps them visible
            ax_hist[3].set_yscale("symlog", linthresh=1.0)
    b = d["body"]
    fig.suptitle(
        f"Free vibration, R = {b['R']:g} m, tan α = {b['tan_alpha']:g}, θ0 = {b['theta0']:g} rad"
        " (Fig 4; black undamped, red damped)"
    )
    return fig


def _min_span(ax, series, span: float = 0.02) -> None:
    # A constant history (θ, θ̇, φ̇ of pure wobbling) would be drawn at round-off scale.
    values = np.concatenate([np.asarray(v, dtype=float) for v in series])
    if values.size and np.ptp(values) < span:
        mid = 0.5 * (values.max() + values.min())
        ax.set_ylim(mid - span, mid + span)
    ax.ticklabel_format(axis="y", useOffset=False)


def _first(models: dict) -> dict:
    return next(iter(models.values()))
