"""The paper's statements and numbers per figure, set against a run's, each with a verdict.

Every figure writes what it measured into its JSON sidecar (:func:`rocking.study.figures.render`).
:func:`compare` turns those notes into :class:`Comparison` rows: the paper's words or number,
this run's number, and a verdict that follows from the two and a stated tolerance:

- ``reproduced``: within the tolerance;
- ``differs``: outside it, with the reason where the cause is known (and measured where the
  run can measure it);
- ``not reproducible``: the paper's number cannot be recomputed from what it states;
- ``not computed in this run``: a reduced run left the quantity out;
- ``not in the paper``: figures beyond the paper, shown for their own numbers.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from ._style import limit_state_title

EQUATIONS = "docs/equations.md"
"""The derivations the verdicts cite (the report links ``docs/equations.md#anchor``)."""

REPRODUCED = "reproduced"
DIFFERS = "differs"
NOT_REPRODUCIBLE = "not reproducible"
NOT_COMPUTED = "not computed in this run"
NOT_IN_PAPER = "not in the paper"
VERDICTS = (REPRODUCED, DIFFERS, NOT_REPRODUCIBLE, NOT_COMPUTED, NOT_IN_PAPER)

LINEAR_R2 = 0.95
"""Least R² of a straight line in R for "almost straight lines" (§5.2, §6) [-]."""


@dataclass(frozen=True)
class Comparison:
    """One statement of the paper set against this run.

    Attributes
    ----------
    figure : str
        Figure name (a key of :data:`rocking.study.figures.captions.CAPTIONS`).
    statement : str
        What is compared, with where the paper says it.
    paper : str
        The paper's number or words.
    ours : str
        This run's number(s).
    verdict : str
        One of :data:`VERDICTS`.
    reason : str
        The tolerance that was met, or why the numbers differ.
    """

    figure: str
    statement: str
    paper: str
    ours: str
    verdict: str
    reason: str = ""

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {VERDICTS}, got {self.verdict!r}")

    @property
    def verdict_text(self) -> str:
        """``"reproduced (within …)"``, ``"differs because …"`` and so on."""
        if not self.reason:
            return self.verdict
        if self.verdict == REPRODUCED:
            return f"{self.verdict} ({self.reason})"
        if self.verdict in (DIFFERS, NOT_REPRODUCIBLE):
            return f"{self.verdict} because {self.reason}"
        return f"{self.verdict}: {self.reason}"


def judged(figure: str, statement: str, paper: str, ours: str, ok: bool | None,
           tolerance: str, reason: str, missing: str = "") -> Comparison:
    """A comparison whose verdict follows from ``ok`` (None: not computed in this run).

    ``tolerance`` is quoted when reproduced, ``reason`` when it differs, ``missing`` (what the
    run left out) when nothing could be measured.
    """
    if ok is None:  # nothing was measured: the reason says what the run left out
        return Comparison(figure, statement, paper, "—", NOT_COMPUTED, missing)
    if ok:
        return Comparison(figure, statement, paper, ours, REPRODUCED, tolerance)
    return Comparison(figure, statement, paper, ours, DIFFERS, reason)


def fmt(value, digits: int = 4) -> str:
    """A number for a table; "not measured" for None/NaN."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "not measured"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


def _finite(*values) -> bool:
    return all(v is not None and isinstance(v, int | float) and math.isfinite(v) for v in values)


def _close(ours, paper: float, rtol: float) -> bool | None:
    return abs(ours - paper) <= rtol * abs(paper) if _finite(ours) else None


# ------------------------------------------------------------------------------ per figure


def fig03(notes: Mapping) -> list[Comparison]:
    m = notes.get("fig03_wobbling_period", {}).get("measured", {})
    ratios = {k.split("tan", 1)[1]: v for k, v in m.items() if k.startswith("ratio_to_housner")}
    rising = [v for k, v in m.items() if k.startswith("increasing_tan")]
    ok = (all(rising) and all(0.5 <= lo and hi <= 2.0 for lo, hi in ratios.values())
          if ratios else None)
    ours = "; ".join(f"tan α = {t}: {lo:.2f}–{hi:.2f}" for t, (lo, hi) in ratios.items())
    gap = m.get("max_rel_gap_slender_pair")
    rows = [judged(
        "fig03_wobbling_period", "Wobbling period versus tilt: 'the analogy between 2D rocking "
        "and 3D bounded wobbling is evident' (§2.2, Fig 3)",
        "both periods grow from 0 without bound as θ → α (qualitative)",
        f"every curve rises with θ/α: {all(rising)}; T_wobbling/T_Housner for 0.1 ≤ θ/α ≤ 0.9: "
        + ours, ok, "every curve rising and within a factor 2 of Housner's period",
        "a wobbling period departs from Housner's by more than a factor 2")]
    if _finite(gap):
        rows.append(Comparison(
            "fig03_wobbling_period", "Curves of tan α = 0.1 and 0.2 (Fig 3)",
            "drawn as nearly one curve", f"at most {100 * gap:.2f} % apart (inset)", REPRODUCED,
            "the slender limit: T·p depends on α only through small terms"))
    return rows


def fig04(notes: Mapping) -> list[Comparison]:
    d = notes.get("fig04_free_vibration", {})
    m, pred, body = d.get("measured", {}), d.get("predicted", {}), d.get("body", {})
    name = "fig04_free_vibration"
    turn = m.get("turn_angle_first")
    other = 2 * math.pi - turn if _finite(turn) else None
    rows = [
        judged(name, "Angle of turn of the contact point per quasi-impact, Eq (27)", "3.0952",
               f"{fmt(turn)} rad (asymptote π√(κo/κt) = {fmt(pred.get('turn_angle'), 6)}); "
               f"2π − it = {fmt(other)}", _close(turn, 3.0952, 1e-3), "|Δ| ≤ 0.1 %",
               "the printed Eq (27) inverts the inertia ratio (derivation: "
               f"{EQUATIONS}#eq-27-the-angle-of-turn): it gives the turn measured the other way "
               f"round, 2π − ours = {fmt(other)}"),
        judged(name, "Angle of turn measured numerically (§2.4)", "3.058",
               f"{fmt(turn)} rad (2π − it = {fmt(other)})", _close(turn, 3.058, 1e-3),
               "|Δ| ≤ 0.1 %", "the paper does not say how its 3.058 was read off; ours is φ "
               "between tilt maxima of a φ̇0 = 1e-8 rad/s run and equals the asymptote"),
        judged(name, "Coefficient of restitution of the damped model over five quasi-impacts, "
               "Eq (31)–(32)", "0.942",
               f"{fmt(m.get('restitution_damped'))} (ωn = {fmt(body.get('omega_n'))} rad/s, "
               f"ζ = {fmt(body.get('zeta'))}); over the eight (ωn, ζ): "
               + _range(m.get("restitution_damped_range")),
               _close(m.get("restitution_damped"), 0.942, 0.002 / 0.942), "|Δ| ≤ 0.002",
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
    found = {c: g for c, g in gaps.items() if _finite(g)}
    ours = f"{what}: " + "; ".join(f"{c} {fmt(g, 2)} rad" for c, g in found.items())
    ok = all(g <= tol for g in found.values()) if found else None
    return judged(name, statement, paper, ours, ok, f"max |Δθ| ≤ 2 % of θ0 = {tol:g} rad in "
                  "every case", reason, missing)


def _range(pair) -> str:
    return "not measured" if not pair else f"{pair[0]:.4f}–{pair[1]:.4f}"


def fig06(notes: Mapping) -> list[Comparison]:
    d = notes.get("fig06_el_centro", {})
    m = d.get("measured", {})
    sens = notes.get("fig06_theta_max_sensitivity", {}).get("measured", {})
    name = "fig06_el_centro"
    rows = []
    for model, paper, kind in (("3d", 0.0838, "undamped"), ("3d-damped", 0.0668, "damped")):
        ours = m.get(f"theta_max_{model}")
        rows.append(judged(
            name, f"Peak tilt θmax, {kind}, R = 6 m, tan α = 0.2, El Centro (§4)",
            f"{paper} rad", f"{fmt(ours)} rad", _close(ours, paper, 0.10), "|Δ| ≤ 10 %",
            _theta_reason(sens, model, paper), "model not run"))
    u, dmp = m.get("theta_max_3d"), m.get("theta_max_3d-damped")
    ratio = dmp / u if _finite(u, dmp) and u > 0 else None
    band = {k.split("|", 1)[1]: v for k, v in sens.items()
            if k.startswith("damped_over_undamped_band|")}
    why = "the ratio of two single-record peaks is as sensitive as the peaks"
    if band:
        why += (f"; within ±{100 * sens.get('band', 0.05):g} % of scale it ranges over "
                + "; ".join(f"{_range(b)} ({v})" for v, b in band.items()))
    rows.append(judged(
        name, "Damped against undamped peak tilt (§4: 'a 25 % difference')",
        "damped/undamped = 0.0668/0.0838 = 0.797", f"{fmt(ratio)}",
        abs(ratio - 0.797) <= 0.1 if ratio is not None else None, "|Δ| ≤ 0.1", why,
        "both models are needed"))
    t = m.get("t_part_theta")
    rows.append(judged(
        name, "Undamped and damped tilts coincide for the first 15 s (§4)", "≈ 15 s",
        f"tilts first differ by 5 % of θmax at t = {fmt(t, 3)} s",
        abs(t - 15.0) <= 4.0 if _finite(t) else None, "within ±4 s",
        "the first quasi-impact that separates the models comes at another time for this "
        "record version", "both models are needed"))
    return rows


def _theta_reason(sens: Mapping, model: str, paper: float) -> str:
    text = ("the record version (NGA-West2 RSN 6 here; the paper does not name its version), "
            "its processing (high-pass corner) and the chaotic sensitivity of a single-record "
            "peak; a rotation cannot matter (axisymmetric cylinder)")
    ranges = {k.split("|")[1]: v for k, v in sens.items()
              if k.startswith("band_range|") and k.endswith(f"|{model}")}
    if not ranges:
        return text
    inside = [v for v, (lo, hi) in ranges.items() if lo <= paper <= hi]
    parts = "; ".join(f"{v}: {lo:.4f}–{hi:.4f}" for v, (lo, hi) in ranges.items())
    where = (f"the paper's value lies inside the range of {', '.join(inside)}" if inside
             else "the paper's value lies outside these ranges")
    return (f"{text}. Evidence (companion figure): θmax within ±{100 * sens.get('band', 0.05):g} "
            f"% of scale spans {parts} rad; {where}")


def fig06_sensitivity(notes: Mapping) -> list[Comparison]:
    m = notes.get("fig06_theta_max_sensitivity", {}).get("measured", {})
    check = m.get("rotation_check") or {}
    worst = max(check.values()) if check else None
    return [Comparison(
        "fig06_theta_max_sensitivity", "θmax of the El Centro response versus scale factor and "
        "record version (evidence for Fig 6)", "—",
        f"a rotation by the paper's 22.33° changes θmax by {fmt(worst, 2)} rad; ranges per "
        "version in the Fig 6 rows", NOT_IN_PAPER,
        "a companion figure that explains Fig 6's difference")]


def fig07(notes: Mapping) -> list[Comparison]:
    m = notes.get("fig07_tilt_map", {}).get("measured", {})
    name = "fig07_tilt_map"
    firsts = {k.rsplit("_", 1)[1]: v for k, v in m.items()
              if k.startswith("first_intensity_theta_above_alpha_")}
    ours = "; ".join(f"{mod}: " + ", ".join(f"{fmt(v, 3)}" for v in vals)
                     for mod, vals in firsts.items())
    trend = {mod: _rank_correlation(m.get("R"), vals) for mod, vals in firsts.items()}
    ok = all(_finite(r) and r >= 0.7 for r in trend.values()) if trend else None
    gap = m.get("mean_abs_gap_below_alpha")
    corr = "; ".join(f"{mod} {fmt(r, 2)}" for mod, r in trend.items())
    return [
        judged(name, "Larger cylinders are harder to overturn (§5, Fig 7)",
               "intensity to reach θmax = α grows with R",
               f"lowest PGA/(g tan α) with θmax ≥ α at R = {m.get('R')} m: {ours}; rank "
               f"correlation with R: {corr}", ok,
               "Spearman rank correlation with R ≥ 0.7 (it rises overall; narrow windows of "
               "exceedance make single steps fall)",
               "the intensity to reach θmax = α does not rise with R on this grid",
               "no tilt map computed"),
        judged(name, "'The damped and undamped models give almost identical overturning "
               "spectra' (§5, Fig 7)", "almost identical maps",
               f"mean |Δ(θmax/α)| below α = {fmt(gap, 3)}; largest relative gap of the "
               f"intensity reaching θmax = α: {fmt(m.get('max_rel_gap_first_intensity'), 2)}",
               gap <= 0.05 if _finite(gap) else None, "mean |Δ(θmax/α)| ≤ 0.05",
               "the damped model's map departs from the undamped one",
               "both models are needed"),
    ]


def _is_el_centro(*names) -> bool:
    return any("centro" in str(n).lower() for n in names)


def fig08(notes: Mapping) -> list[Comparison]:
    found = {k: v for k, v in notes.items() if k.startswith("fig08_motions")}
    rows = []
    for key, d in found.items():
        m = d.get("measured", {})
        ens = key.removeprefix("fig08_motions").strip("_") or "ensemble"
        angle = m.get("principal_offset_deg")
        n = m.get("n_motions")
        pairs = f"; {n - 1} synthetic pairs (paper: 10)" if isinstance(n, int) else ""
        if _is_el_centro(ens, m.get("record")):
            rows.append(judged(
                "fig08_motions", f"Rotation of the record to uncorrelated axes (§5.1), {ens}",
                "22.33°", f"{fmt(angle)}° ({m.get('record')}){pairs}",
                abs(abs(angle) - 22.33) <= 0.5 if _finite(angle) else None, "|Δ| ≤ 0.5°",
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


def fig09(notes: Mapping) -> list[Comparison]:
    m = notes.get("fig09_spectra", {}).get("measured", {})
    rows = []
    for key, eff in m.items():
        if not key.startswith("damping|"):
            continue
        ls = key.split("|", 1)[1]
        rows.append(_damping_row(ls, eff, m.get("R")))
    if not rows:
        rows.append(Comparison("fig09_spectra", "Undamped and damped spectra essentially "
                               "identical (§5.2)", "essentially identical", "—", NOT_COMPUTED,
                               "the damped or the undamped model was not run at tan α = 0.2"))
    return rows


DAMPING_RTOL = 0.05
"""Difference of the means that is "essentially identical" whatever its scatter [-]."""


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

    ours = (f"largest |Δ| of the means {fmt(100 * worst, 3) if _finite(worst) else '—'} %"
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
                  ours, (not j["failed"]) if _finite(worst) else None, tolerance, reason)


def _rank_correlation(x, y) -> float | None:
    """Spearman rank correlation of two equal-length sequences (None values dropped)."""
    from scipy.stats import spearmanr

    if not x or not y:
        return None
    pairs = [(a, b) for a, b in zip(x, y, strict=False) if a is not None and b is not None]
    if len(pairs) < 3:
        return None
    return float(spearmanr(*zip(*pairs, strict=True)).statistic)


OVERTURNING_PHYSICS = (
    "At the smallest intensity that takes θ past α, no motion left the cylinder standing. "
    "Why: at θ = α the centre of mass is straight above the pivot (the contact point); beyond "
    "it, gravity's moment about the pivot turns from restoring to overturning and grows as "
    "θ grows, so only a reversal of the ground acceleration strong and long enough could "
    "bring the body back; at the threshold intensity, which just pushes θ past α, the "
    "motion has no such reserve. In numbers: gravity's moment about the pivot is "
    "m g ρ sin(α − θ), ρ the distance from the pivot to the centre of mass "
    "(geometry: {eq}#geometry-and-inertia); it changes sign at θ = α")


def fig10(notes: Mapping) -> list[Comparison]:
    m = notes.get("fig10_goals", {}).get("measured", {})
    name = "fig10_goals"
    rows = []
    absent = m.get("absent_goals", [])
    if absent:
        rows.append(Comparison(name, "Seven performance goals (Fig 10)", "7",
                               f"{m.get('n_goals', 0)}", NOT_COMPUTED,
                               "goals " + ", ".join(limit_state_title(g) for g in absent)))
    twins = {c["goals"][0]: c for c in m.get("coincide", [])}
    for c in m.get("coincide", []):
        a, b = (limit_state_title(g) for g in c["goals"])
        rows.append(Comparison(
            name, f"{a} and {b.lower()}: the same goal in this run", "seven distinct curves",
            f"identical mean, median and spread at all {c['n_R']} sizes "
            f"({c.get('n_motions')} motions each)", NOT_IN_PAPER,
            OVERTURNING_PHYSICS.format(eq=EQUATIONS)))
    for key, fit in m.items():
        if not key.startswith("line|"):
            continue
        ls = key.split("|", 1)[1]
        if ls in twins:  # said once, under the goal it coincides with
            continue
        r2 = fit.get("r_squared")
        rows.append(judged(
            name, f"Mean spectrum almost linear in R, {limit_state_title(ls)} (§5.2, §6: "
            "'increases almost linearly with cylinder size R')", "almost straight lines",
            f"slope {fmt(fit.get('slope'))} 1/m, intercept {fmt(fit.get('intercept'))}, "
            f"R² = {fmt(r2, 4)} (n = {fit.get('n')})", r2 >= LINEAR_R2 if _finite(r2) else None,
            f"R² ≥ {LINEAR_R2}", _bend_reason(fit), "fewer than three sizes R"))
    return rows


def _bend_reason(fit: Mapping) -> str:
    """Why a mean spectrum is not a straight line, in numbers: flat throughout (a low R² of
    a small variation), or flat, then rising (a bend)."""
    if "flat_to_R" not in fit:
        return "the mean spectrum bends in R (R² below the tolerance)"
    signs = fit.get("residual_signs", "")
    runs = 1 + sum(a != b for a, b in zip(signs, signs[1:], strict=False)) if signs else 0
    pattern = (f"residuals from the line by R: {signs} "
               + ("(a bend: few long runs of one sign, not scatter)" if runs <= 3
                  else f"({runs} runs of one sign)"))
    if fit["flat_to_R"] >= fit["end_R"]:
        return (f"the mean spectrum is nearly flat, within 10 % of {fit['flat_level']:.2f} at "
                f"every R (up to {fit['end_value']:.2f} at R = {fit['end_R']:g} m): the line "
                f"explains little of so small a variation; {pattern}")
    return (f"the mean spectrum is not straight but flat, then rising: within 10 % of "
            f"{fit['flat_level']:.2f} up to R = {fit['flat_to_R']:g} m, then up to "
            f"{fit['end_value']:.2f} at R = {fit['end_R']:g} m; {pattern}")


def fig11(notes: Mapping) -> list[Comparison]:
    m = notes.get("fig11_slenderness", {}).get("measured", {})
    rows = []
    for key, t in m.items():
        if not key.startswith("tan_alphas|"):
            continue
        ls = key.split("|", 1)[1]
        spread = m.get(f"max_rel_spread_{ls}")
        rows.append(judged(
            "fig11_slenderness", f"Slenderness has 'a very small influence' once the intensity "
            f"is normalized by g tan α, {limit_state_title(ls)} (§5.3)", "very small influence",
            f"largest spread among tan α = {', '.join(f'{v:g}' for v in t)}: "
            f"{fmt(100 * spread, 3) if _finite(spread) else '—'} % of the mean",
            spread <= 0.15 if _finite(spread) else None, "spread ≤ 15 % of the mean at every R",
            "slenderness changes the normalized spectra beyond the tolerance",
            f"only tan α = {', '.join(f'{v:g}' for v in t) or 'none'} computed"))
    return rows or [Comparison("fig11_slenderness", "Influence of slenderness (§5.3)",
                               "very small", "—", NOT_COMPUTED, "no mean spectra")]


def fig12(notes: Mapping) -> list[Comparison]:
    m = notes.get("fig12_2d_vs_3d", {}).get("measured", {})
    R = m.get("R", 10.0)
    names = sorted({k.split("|")[0] for k in m if k.count("|") >= 2})
    centro = next((n for n in names if "centro" in (n + m.get(f"{n}|label", "")).lower()), None)
    loma = next((n for n in names if "loma" in (n + m.get(f"{n}|label", "")).lower()), None)
    rows = [_r10_row(m, centro, R)]
    rows += _ratio_rows(m, centro, R, "El Centro", "overturning", (1.5, 2.5),
                        "'the intensities of unidirectional ground motion to overturn the same "
                        "cylinder are twice as high' (§5.4)", "about 2× the 3D value")
    rows += _ratio_rows(m, centro, R, "El Centro", "excessive tilt", (1.2, math.inf),
                        "'a similar trend holds for the excessive tilt' (§5.4)",
                        "2D above 3D")
    rows += _ratio_rows(m, loma, R, "Loma Prieta", "overturning", (1.2, math.inf),
                        "the same trend for the Loma Prieta ensemble (§5.4, red)",
                        "2D above 3D")
    rows += _ratio_rows(m, loma, R, "Loma Prieta", "excessive tilt", (1.2, math.inf),
                        "the same trend for the Loma Prieta ensemble (§5.4, red)",
                        "2D above 3D")
    return rows


def _r10_row(m: Mapping, ens: str | None, R: float) -> Comparison:
    v = m.get(f"{ens}|overturning|3d") if ens else None
    std, n = m.get(f"{ens}|overturning|3d|std"), m.get(f"{ens}|overturning|3d|count")
    se = std / math.sqrt(n) if _finite(std, n) and n > 0 else None
    return judged(
        "fig12_2d_vs_3d", f"Overturning of an R = {R:g} m cylinder by bidirectional motion, "
        "mean PGA/(g tan α) (§5.4; printed as 'PGA/tan α of about 4')", "about 4",
        f"{fmt(v)} (standard error of the mean {fmt(se, 2)}, {fmt(n, 3)} motions)",
        abs(v - 4.0) <= 1.0 if _finite(v) else None, "4 ± 1",
        "a different synthetic ensemble (own seeds, fewer motions in a reduced run) and record "
        "version; the mean of a few broadband motions scatters by its standard error, and the "
        "search bound and accuracy preset bound the values", "El Centro study not computed at "
        f"R = {R:g} m")


def _ratio_rows(m: Mapping, ens: str | None, R: float, who: str, title: str,
                bounds: tuple[float, float], statement: str, paper: str) -> list[Comparison]:
    v3 = m.get(f"{ens}|{title}|3d") if ens else None
    rows = []
    for mode, axis in (("2d-x", "x, major principal axis"), ("2d-y", "y, minor principal axis")):
        v2 = m.get(f"{ens}|{title}|{mode}") if ens else None
        ratio = v2 / v3 if _finite(v2, v3) and v3 > 0 else None
        lo, hi = bounds
        tol = f"ratio in [{lo:g}, {hi:g}]" if math.isfinite(hi) else f"ratio ≥ {lo:g}"
        stand_in = " (stand-in record)" if ens and m.get(f"{ens}|stand_in") else ""
        counts = _counts(m, ens, title, ("3d", mode))
        rows.append(judged(
            "fig12_2d_vs_3d", f"{who}{stand_in}, {title}, R = {R:g} m: 2D under the {axis} "
            f"component against 3D — {statement}", paper,
            (f"2D/3D = {fmt(ratio, 3)} ({fmt(v2, 3)} / {fmt(v3, 3)})" + counts)
            if ratio is not None else "—",
            lo <= ratio <= hi if ratio is not None else None, tol,
            _ratio_reason(m, ens, title, mode, who),
            f"{who} ensemble or its 2D modes not computed in this run"))
    return rows


def _n_motions(m: Mapping, ens: str | None) -> int | None:
    """Motions of an ensemble: its ``n_motions`` note, else the "mean of N motions" label."""
    n = m.get(f"{ens}|n_motions")
    if _finite(n):
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
        if _finite(v):
            out[mo] = int(round(v))
        elif _finite(c) and total is not None:
            out[mo] = int(round(total - c))
    return out


def _counts(m: Mapping, ens: str | None, title: str, modes) -> str:
    """``"; means over 7 (3D) and 4 (2D) of 11 motions"`` when a mean leaves motions out."""
    total = _n_motions(m, ens)
    got = {mo: m.get(f"{ens}|{title}|{mo}|count") for mo in modes}
    if total is None or all(not _finite(c) or c >= total for c in got.values()):
        return ""
    return ("; means over " + " and ".join(f"{int(c)} ({'3D' if mo == '3d' else '2D'})"
                                           for mo, c in got.items() if _finite(c))
            + f" of {int(total)} motions")


def _ratio_reason(m: Mapping, ens: str | None, title: str, mode: str, who: str) -> str:
    """Why a 2D/3D ratio differs: censored means when motions were not reached, else the
    ensemble and the direction of x."""
    short = _short(m, ens, title, ("3d", mode))
    if any(v > 0 for v in short.values()):
        upper = m.get(f"{ens}|upper")
        bound = f" PGA/(g tan α) = {fmt(upper)}" if _finite(upper) else ""
        left = " and ".join(f"{v} ({'3D' if mo == '3d' else '2D'})"
                            for mo, v in short.items() if v > 0)
        return (f"motions not reached at the search bound{bound}: {left} motions of the "
                f"{who} ensemble had not reached the limit state there and are left out of the "
                "means, which therefore understate the intensities, the 2D ones most (they are "
                "higher); the ratio of these censored means says little")
    return (f"a different {who} ensemble (own synthetic pairs, record version); our x is the "
            "record's major principal axis, the paper's x the E–W component before rotation")


def fragility(notes: Mapping) -> list[Comparison]:
    return [Comparison("fragility_curves", "Lognormal fragility curves per size R", "—",
                       "see the fragility table", NOT_IN_PAPER,
                       "an addition for performance-based design")]


COMPARISONS: dict[str, Callable[[Mapping], list[Comparison]]] = {
    "fig03_wobbling_period": fig03,
    "fig04_free_vibration": fig04,
    "fig06_el_centro": fig06,
    "fig06_theta_max_sensitivity": fig06_sensitivity,
    "fig07_tilt_map": fig07,
    "fig08_motions": fig08,
    "fig09_spectra": fig09,
    "fig10_goals": fig10,
    "fig11_slenderness": fig11,
    "fig12_2d_vs_3d": fig12,
    "fragility_curves": fragility,
}
"""The comparison function of every figure."""


def compare(notes: Mapping[str, Mapping], figures: list[str] | None = None) -> list[Comparison]:
    """Comparisons of the figures in ``figures`` (default all), from their sidecar notes.

    Parameters
    ----------
    notes : mapping
        Figure file stem (``fig08_motions_elcentro``) or name → its JSON notes. A figure
        without notes yields rows "not computed in this run".
    figures : list of str, optional
        Figure names to compare, in order.
    """
    out = []
    for name in figures or list(COMPARISONS):
        if name not in COMPARISONS:
            raise ValueError(f"figure must be one of {list(COMPARISONS)}, got {name!r}")
        out += COMPARISONS[name](notes)
    return out
