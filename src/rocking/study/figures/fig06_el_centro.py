"""Figure 6: response of the R = 6 m, tan α = 0.2 cylinder to the El Centro 1940 pair.

The motion is the record as the ensemble stores it (first member: high-pass filtered and on
its principal axes, §4 and §5.1). Undamped and damped models are overlaid: θ, θ̇, φ, φ̇, the
contact-spring w, ẇ (damped model only) and, in the bottom two rows, the ground components.
The paper reports peak tilts of 0.0838 rad (undamped) and 0.0668 rad (damped).
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from ...dynamics.bodies import Cylinder
from ...motions.motion import GroundMotion
from ._style import new_figure, styled

R = 6.0
TAN_ALPHA = 0.2
MODELS = ("3d", "3d-damped")
PAPER_THETA_MAX = {"3d": 0.0838, "3d-damped": 0.0668}
"""Peak tilts printed in §4 [rad]."""

_KEYS = ("t", "theta", "theta_dot", "phi", "phi_dot", "w", "w_dot")


def data(
    motion: GroundMotion,
    *,
    R: float = R,
    tan_alpha: float = TAN_ALPHA,
    models: tuple[str, ...] = MODELS,
    **model_kw,
) -> dict:
    """Run the ground-motion analyses of Fig 6.

    Parameters
    ----------
    motion : GroundMotion
        The bidirectional record [m/s²] (x first component, y second).
    R : float
        Semi-diagonal [m].
    tan_alpha : float
        Slenderness [-].
    models : tuple of str
        Dynamics models to overlay.
    **model_kw
        Passed to :func:`rocking.ground_response`.

    Returns
    -------
    dict
        ``runs[model]``: history arrays (``w``, ``w_dot`` None for the undamped model),
        ``theta_max``, ``t_theta_max``, ``status``; ``ground``: ``t``, ``ax``, ``ay`` [m/s²];
        ``measured``: peak tilt per model [rad].
    """
    from ...dynamics.analysis import ground_response  # imported late: figures stay light to import

    if motion.is_unidirectional:
        raise ValueError(f"motion {motion.name!r} has a zero component; Fig 6 needs a pair")
    body = Cylinder(R, tan_alpha)
    runs = {}
    for model in models:
        res = ground_response(body, motion, model=model, **model_kw)
        run = {k: None if getattr(res, k) is None else np.asarray(getattr(res, k)) for k in _KEYS}
        run.update(
            theta_max=float(res.theta_max),
            t_theta_max=float(res.t_theta_max),
            status=str(res.status.value),
        )
        runs[model] = run
    return {
        "runs": runs,
        "ground": {"t": motion.time, "ax": np.asarray(motion.ax), "ay": np.asarray(motion.ay)},
        "motion": {"name": motion.name, "pga": motion.pga, "metadata": dict(motion.metadata)},
        "body": {"R": R, "tan_alpha": tan_alpha},
        "measured": {f"theta_max_{m}": runs[m]["theta_max"] for m in runs},
        "paper": {f"theta_max_{m}": v for m, v in PAPER_THETA_MAX.items()},
    }


@styled
def plot(d: dict) -> Figure:
    """Figure 6: eight stacked histories sharing the time axis."""
    rows = (
        ("theta", "θ [rad]"),
        ("theta_dot", "θ̇ [rad/s]"),
        ("phi", "φ [rad]"),
        ("phi_dot", "φ̇ [rad/s]"),
        ("w", "w [m]"),
        ("w_dot", "ẇ [m/s]"),
    )
    fig, axes = new_figure(7.5, 11.0, nrows=len(rows) + 2, sharex=True)
    colors = {"3d": "black", "3d-damped": "tab:red"}
    labels = {"3d": "undamped", "3d-damped": "damped"}
    for ax, (key, label) in zip(axes, rows, strict=False):
        for model, run in d["runs"].items():
            if run.get(key) is not None:
                ax.plot(run["t"], run[key], color=colors.get(model, None), lw=0.8,
                        label=f"{labels.get(model, model)} (θmax = {run['theta_max']:.4f} rad)")
        ax.set_ylabel(label)
    axes[0].legend(loc="upper left")
    if all(run.get("w") is None for run in d["runs"].values()):
        for ax in axes[4:6]:
            ax.text(0.5, 0.5, "damped model not run", ha="center", va="center",
                    transform=ax.transAxes)
    g = d["ground"]
    axes[-2].plot(g["t"], g["ax"], color="tab:blue", lw=0.6)
    axes[-2].set_ylabel("ü_gx [m/s²]")
    axes[-1].plot(g["t"], g["ay"], color="tab:blue", lw=0.6)
    axes[-1].set_ylabel("ü_gy [m/s²]")
    axes[-1].set_xlabel("t [s]")
    b = d["body"]
    fig.suptitle(
        f"{d['motion']['name']}: R = {b['R']:g} m, tan α = {b['tan_alpha']:g} (Fig 6)"
    )
    return fig
