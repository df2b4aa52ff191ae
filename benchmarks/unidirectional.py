"""Benchmark of the 3D model under one component (modes ``3d-x``, ``3d-y``): does the answer
depend on the spin that starts each uplift, or on round-off?

``python -m benchmarks unidirectional [--quick]`` writes ``results/benchmarks/unidirectional.csv``
/ ``.md``: on El Centro and the Loma Prieta (Corralitos) record rotated to principal axes and
one synthetic pair fitted to each, R ∈ {0.5, 2, 6, 10} m, tan α = 0.2, both modes, the
critical intensities of overturning and θ > α/3 (the "default" preset) with the spin at uplift
φ̇0 ∈ {1e-10, 1e-9, 1e-8, 1e-6, 1e-4 (the modes' own), 1e-2} rad/s, and at the modes' spin on
two motions that differ only by round-off from the one analysed: the mirrored motion (−a: the
same physics, the uplift direction φ0 = 0 where the original has −π, whose sine is 1.2e-16
rather than 0) and the motion with every sample of its exciting component moved by one unit in
the last place (seeded signs). Per answer: the intensity, its flags, analyses and CPU seconds,
and the relative difference from the modes' spin on the motion as it is; beside it the peak
tilt θmax at three intensities (1.5, 3 and 6 times uplift) per spin, whose spread shows the
sensitivity without the search's discreteness, and the analyses that fail at each spin, of
the undamped model and of the damped one.

``--damped`` writes ``unidirectional_damped.csv`` / ``.md`` instead: whether the damped 3D
model under one component "matches well" Housner's 2D block, as the paper's conclusions say
its damping was built to. On the same motions, R ∈ {2, 6, 10} m and both components, the
critical intensities of the undamped 3D model (the mode), the damped one (default contact,
the same spin at uplift) and Housner's block under that component, and their ratios.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import pandas as pd

from benchmarks._io import write_table
from benchmarks.inputs import benchmark_records, with_synthetic
from rocking.constants import G
from rocking.dynamics.analysis import ground_response
from rocking.dynamics.bodies import Cylinder
from rocking.motions.motion import GroundMotion
from rocking.motions.principal import to_principal_axes
from rocking.spectra.accuracy import PRESETS
from rocking.spectra.critical import make_analysis, uplift_intensity
from rocking.spectra.modes import MODES, UNIDIRECTIONAL_MODES, UNIDIRECTIONAL_SPIN, excitation
from rocking.spectra.search import search_critical

TAN_ALPHA = 0.2
LIMIT_STATES = ("overturning", "tilt:1/3")
SPINS = tuple(sorted({1e-10, 1e-9, 1e-8, 1e-6, UNIDIRECTIONAL_SPIN, 1e-2}))
R_VALUES = (0.5, 2.0, 6.0, 10.0)
PEAK_FACTORS = (1.5, 3.0, 6.0)
DEFAULT = PRESETS["default"]


def mirrored(motion: GroundMotion) -> GroundMotion:
    """The motion with both components negated: the same response of an axisymmetric body."""
    return GroundMotion(-motion.ax, -motion.ay, motion.dt, f"{motion.name} (−a)",
                        motion.metadata)


def last_bit(motion: GroundMotion, seed: int = 0) -> GroundMotion:
    """The motion with every sample moved by one unit in the last place, up or down (seeded)."""
    rng = np.random.default_rng(seed)
    moved = []
    for a in (motion.ax, motion.ay):
        up = rng.random(a.size) < 0.5
        moved.append(np.where(up, np.nextafter(a, np.inf), np.nextafter(a, -np.inf)))
    return GroundMotion(moved[0], moved[1], motion.dt, f"{motion.name} (±1 ulp)",
                        motion.metadata)


def answer_rows(motion: GroundMotion, R: float, mode: str, spin: float, variant: str) -> list:
    """One row per limit state of the search of one point at one spin."""
    body = Cylinder(R, TAN_ALPHA)
    analyze = make_analysis(body, motion, mode, rest_tilt=DEFAULT.rest_tilt, spin=spin)
    t0 = time.process_time()
    res = search_critical(analyze, list(LIMIT_STATES), body.alpha,
                          lower=uplift_intensity(motion, mode), accuracy=DEFAULT,
                          rtol=DEFAULT.rtol_for(MODES[mode].model))
    cpu = time.process_time() - t0
    rows = []
    for i, ls in enumerate(res.limit_states):
        rows.append({"motion": motion.name.split(" (")[0], "variant": variant, "mode": mode,
                     "R": R, "spin": spin, "limit_state": ls,
                     "intensity": float(res.intensity[i]),
                     "not_reached": bool(res.not_reached[i]), "failed": bool(res.failed[i]),
                     "n_analyses": int(res.n_analyses), "cpu_s": cpu})
    return rows


def peak_rows(motion: GroundMotion, R: float, mode: str) -> list:
    """θmax at :data:`PEAK_FACTORS` × uplift for every spin: its spread over the spins that
    ran (failures counted), and which spins the damped model (default contact) fails at."""
    body = Cylinder(R, TAN_ALPHA)
    excited, _ = excitation(mode, motion)
    lower = uplift_intensity(motion, mode)
    rows = []
    for factor in PEAK_FACTORS:
        scale = factor * lower * G * TAN_ALPHA / motion.pga
        peaks = {}
        for spin in SPINS:
            r = ground_response(body, excited, scale=scale, history=False, phi_dot0=spin)
            if r.status.value == "failed":
                continue
            peaks[spin] = 0.5 * math.pi if r.overturned else float(r.theta_max)
        ref = peaks.get(UNIDIRECTIONAL_SPIN, math.nan)
        spread = max(abs(v - ref) / ref for v in peaks.values()) if peaks else math.nan
        damped = {s: ground_response(body, excited, model="3d-damped", scale=scale,
                                     history=False, phi_dot0=s).status.value == "failed"
                  for s in SPINS}
        rows.append({"motion": motion.name, "mode": mode, "R": R,
                     "intensity_over_uplift": factor, "theta_max": ref,
                     "largest_relative_difference": spread,
                     **{f"failed_{s:g}": s not in peaks for s in SPINS},
                     **{f"damped_failed_{s:g}": damped[s] for s in SPINS}})
    return rows


def damped_rows(motion: GroundMotion, R: float, component: str) -> list:
    """The undamped and damped 3D model and Housner's block under ``component``: one row per
    limit state with the three critical intensities and the CPU seconds of each search."""
    from rocking.dynamics.result import Status
    from rocking.spectra.search import Outcome

    body = Cylinder(R, TAN_ALPHA)
    mode3, mode2 = f"3d-{component}", f"2d-{component}"
    excited, start = excitation(mode3, motion)
    unit = G * TAN_ALPHA / motion.pga

    def damped(intensity, stop_at, rtol):
        r = ground_response(body, excited, model="3d-damped", scale=intensity * unit,
                            stop_at=stop_at, rtol=rtol, history=False, monitors=False, **start)
        return Outcome(float(r.theta_max), bool(r.overturned), Status(r.status), r.reason, {})

    lower = uplift_intensity(motion, mode3)
    runs = {"3d": (make_analysis(body, motion, mode3, rest_tilt=DEFAULT.rest_tilt), lower,
                   DEFAULT.rtol_for(MODES[mode3].model)),
            "3d_damped": (damped, lower, DEFAULT.rtol_for("3d-damped")),
            "2d": (make_analysis(body, motion, mode2, rest_tilt=DEFAULT.rest_tilt),
                   uplift_intensity(motion, mode2), DEFAULT.rtol_for(MODES[mode2].model))}
    found, cpu = {}, {}
    for key, (analyze, low, rtol) in runs.items():
        t0 = time.process_time()
        found[key] = search_critical(analyze, list(LIMIT_STATES), body.alpha, lower=low,
                                     accuracy=DEFAULT, rtol=rtol)
        cpu[key] = time.process_time() - t0
    rows = []
    for i, ls in enumerate(found["3d"].limit_states):
        row = {"motion": motion.name, "component": component, "R": R, "limit_state": ls}
        for key, res in found.items():
            row[f"I_{key}"] = float(res.intensity[i])
            row[f"cpu_s_{key}"] = cpu[key]
        row["damped_over_undamped"] = row["I_3d_damped"] / row["I_3d"]
        row["damped_over_housner"] = row["I_3d_damped"] / row["I_2d"]
        rows.append(row)
    return rows


def damped_main(motions: list[GroundMotion], Rs) -> int:
    """The ``--damped`` table."""
    t0 = time.process_time()
    rows = []
    for motion in motions:
        for component in ("x", "y"):
            for R in Rs:
                rows += damped_rows(motion, R, component)
                print(f"  {motion.name} {component} R {R:g}", flush=True)
    df = pd.DataFrame(rows)
    lines = []
    for ls, g in df.groupby("limit_state", sort=False):
        for col, what in (("damped_over_undamped", "damped 3D / undamped 3D"),
                          ("damped_over_housner", "damped 3D / Housner 2D")):
            v = np.log(g[col].dropna())
            lines.append(f"- {ls}, {what}: geometric mean {math.exp(v.mean()):.2f}, "
                         f"{math.exp(v.min()):.2f}–{math.exp(v.max()):.2f} over {len(v)} "
                         "answers reached by both")
    notes = (f"Motions {', '.join(m.name for m in motions)} (principal axes); R "
             f"{', '.join(f'{r:g}' for r in Rs)} m; tan α {TAN_ALPHA:g}; both components; "
             f"the damped model with its default contact and the spin at uplift "
             f"{UNIDIRECTIONAL_SPIN:g} rad/s; preset default. {time.process_time() - t0:.0f} s "
             "of CPU (a shared machine).\n\n" + "\n".join(lines) + "\n\nEvery answer:")
    write_table("unidirectional_damped", df,
                "The damped 3D model under one component against the undamped and Housner's",
                notes)
    return 0


def _differences(ans: pd.DataFrame) -> pd.DataFrame:
    """Each answer with its relative difference from the modes' spin on the motion as it is."""
    key = ["motion", "mode", "R", "limit_state"]
    ref = ans[(ans["variant"] == "as is") & (ans["spin"] == UNIDIRECTIONAL_SPIN)]
    ref = ref[key + ["intensity", "not_reached"]].rename(
        columns={"intensity": "intensity_ref", "not_reached": "not_reached_ref"})
    out = ans.merge(ref, on=key, how="left")
    out["relative_difference"] = (out["intensity"] - out["intensity_ref"]) / out["intensity_ref"]
    out["reached_mismatch"] = out["not_reached"] != out["not_reached_ref"]
    return out.drop(columns=["intensity_ref", "not_reached_ref"])


def _summary(ans: pd.DataFrame, peaks: pd.DataFrame) -> str:
    lines = []
    for (variant, spin), g in ans.groupby(["variant", "spin"], sort=False):
        d = g["relative_difference"].abs().dropna()
        ln = np.log1p(g["relative_difference"].dropna())
        bias = (f"{ln.mean():+.3f} ± {ln.std(ddof=1) / math.sqrt(len(ln)):.3f}"
                if len(ln) > 1 else "—")
        lines.append(
            f"| {variant} | {spin:g} | {len(g)} | {int(g['failed'].sum())} | "
            f"{int(g['reached_mismatch'].sum())} | {int((d == 0).sum())} | "
            f"{d.median():.2%} | {d.max():.2%} | {int((d > DEFAULT.bisection_tol).sum())} | "
            f"{bias} | {g.groupby(['motion', 'mode', 'R'])['cpu_s'].first().mean():.2f} |")
    head = ("| variant | spin [rad/s] | answers | failed | reached mismatch | identical | "
            "median \\|Δ\\| | largest \\|Δ\\| | \\|Δ\\| above the bisection tolerance | "
            "mean ln(1 + Δ) ± SE | CPU s per point |\n" + "|---" * 11 + "|")
    p = peaks["largest_relative_difference"]
    return (head + "\n" + "\n".join(lines) + "\n\n"
            f"Peak tilts at 1.5, 3 and 6 × uplift over the spins that ran: largest relative "
            f"difference from the modes' spin median {p.median():.1e}, largest {p.max():.1e} "
            f"({len(peaks)} (motion, mode, R, intensity)); analyses failed per spin: "
            + ", ".join(f"{s:g}: {int(peaks[f'failed_{s:g}'].sum())}" for s in SPINS)
            + f" of {len(peaks)}; the damped model's (default contact) at the same points: "
            + ", ".join(f"{s:g}: {int(peaks[f'damped_failed_{s:g}'].sum())}" for s in SPINS)
            + ".")


def main(argv: list[str] | None = None) -> int:
    """Run the comparison and write the tables."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks unidirectional")
    parser.add_argument("--quick", action="store_true", help="one motion, two sizes")
    parser.add_argument("--damped", action="store_true",
                        help="the damped 3D model under one component against the undamped "
                             "one and Housner's block (unidirectional_damped.*)")
    args = parser.parse_args(argv)
    motions = []
    for record, _ in benchmark_records().values():
        rotated = to_principal_axes(record)[0]
        motions += [rotated] if args.quick else with_synthetic(rotated)
    motions = motions[:1] if args.quick else motions
    Rs = (2.0, 10.0) if args.quick else R_VALUES
    if args.damped:
        return damped_main(motions, Rs[-3:])
    t0 = time.process_time()
    answers, peaks = [], []
    for motion in motions:
        variants = {"as is": motion, "mirrored (−a)": mirrored(motion),
                    "±1 ulp per sample": last_bit(motion)}
        for mode in UNIDIRECTIONAL_MODES:
            for R in Rs:
                for spin in SPINS:
                    answers += answer_rows(motion, R, mode, spin, "as is")
                for variant in list(variants)[1:]:
                    answers += answer_rows(variants[variant], R, mode, UNIDIRECTIONAL_SPIN,
                                           variant)
                peaks += peak_rows(motion, R, mode)
                last = answers[-1]
                print(f"  {motion.name} {mode} R {R:g}: {last['cpu_s']:.2f} s per search",
                      flush=True)
    ans = _differences(pd.DataFrame(answers))
    pk = pd.DataFrame(peaks)
    notes = (
        f"Modes {', '.join(UNIDIRECTIONAL_MODES)} (spin at uplift {UNIDIRECTIONAL_SPIN:g} "
        f"rad/s); motions {', '.join(m.name for m in motions)} (principal axes); R "
        f"{', '.join(f'{r:g}' for r in Rs)} m; tan α {TAN_ALPHA:g}; limit states "
        f"{', '.join(LIMIT_STATES)}; preset default (bisection tolerance "
        f"{DEFAULT.bisection_tol:.1%}). Δ: relative difference from the modes' spin on the "
        f"motion as it is. {time.process_time() - t0:.0f} s of CPU in all (a shared "
        f"machine: CPU seconds, not wall time).\n\n" + _summary(ans, pk)
        + f"\n\nPeak tilts:\n\n{pk.to_markdown(index=False)}\n\nEvery answer:")
    write_table("unidirectional", ans, "The 3D model under one component: spin and round-off",
                notes)
    return 0
