"""Captions of the figures: what each shows and what the paper states about it.

A study that reproduces the paper gets :data:`CAPTIONS` (what a figure shows and what the
paper states of it), a study of one's own :data:`STUDY_CAPTIONS` (what it shows). The one
source of caption text: the HTML report (:mod:`rocking.plot.report`) prints them under
the figures and the workflow's Snakemake report renders them through
``workflow/report/figure.rst`` (``{{ snakemake.params.caption }}``). Keys are the figure names,
which are also the module, rule and script names.
"""

from __future__ import annotations

_PAPER_ONLY: dict[str, str] = {
    "fig03_wobbling_period": (
        "Fig 3. Period of pure wobbling T, normalized by the frequency parameter p, against the "
        "normalized tilt θ/α for tan α = 0.1, 0.2, 1 and 1000 (Euler's disk), with Housner's "
        "linearized 2D rocking period. Closed form of Eq (24) as corrected in "
        "docs/equations.md#eq-24-the-wobbling-period (the printed equation has a sign error "
        "under the root); no ground motion, so no x/y direction. The curves of tan α = 0.1 and "
        "0.2 lie within 1 % of each other; the inset magnifies them and gives their largest gap."
    ),
    "fig04_free_vibration": (
        "Fig 4. Free vibration of the R = 6 m, tan α = 0.2 cylinder released from θ0 = 0.1 rad "
        "towards +x (φ0 = 0) with three initial spins: quasi-rocking (φ̇0 = 1e-8 rad/s, the "
        "paper's value), pure wobbling (φ̇0 = the wobbling rate of Eq 24) and a mixed case (half "
        "that rate). Black: undamped; coloured: the damped model for the paper's eight contact "
        "parameters ωn ∈ {200, 2000} rad/s × ζ ∈ {0.05, 0.5, 5, 50} (§3). Left: orbit of the "
        "centre of mass in the horizontal x–y plane of Fig 1. The eight damped runs lie on one "
        "another (their largest gap is written above each θ panel); each is drawn with "
        "interleaved dashes so that every colour shows. The φ̇ panel of the quasi-rocking case "
        "has a symmetric log scale (linear below 1 rad/s): at each quasi-impact θ passes near "
        "0 and the contact point turns by about π almost at once, so φ̇ spikes to 1e8 rad/s "
        "between stretches of nearly zero spin."
    ),
    "fig06_el_centro": (
        "Fig 6. Response of the R = 6 m, tan α = 0.2 cylinder to the El Centro 1940 pair "
        "(NGA-West2 RSN 6), rotated to its principal axes and high-passed as in §4–5.1: tilt θ, "
        "θ̇, spin φ, φ̇, contact-spring w [µm], ẇ [mm/s] (damped model only) and the two ground "
        "components, undamped (black; open triangle at its peak) and damped (red), over the "
        "record's duration; the φ̇ axis is scaled to where the tilt is at least a tenth of its "
        "peak (near θ = 0 the spin is ill-defined and φ̇ spikes; the figure states how high). "
        "The paper reports peak "
        "tilts of 0.0838 rad (undamped) and 0.0668 rad (damped) and coinciding responses for "
        "the first 15 s; why ours differ is written in the figure and shown in the companion "
        "figure of θmax versus scale factor."
    ),
    "fig06_theta_max_sensitivity": (
        "Companion to Fig 6 (not in the paper): peak tilt θmax of the R = 6 m, tan α = 0.2 "
        "cylinder versus a scale factor on the El Centro pair, for the versions of the record "
        "available here (as recorded: x = E–W, y = N–S, unfiltered; on principal axes and "
        "high-passed, as this study uses it; rotated by the paper's 22.33° and high-passed, at "
        "scale 1 only, where it gives this study's θmax), undamped (filled markers) and damped "
        "(open), drawn as points without lines because θmax is chaotic in the scale. The "
        "horizontal lines are the paper's 0.0838 and 0.0668 rad. "
        "Scatter over a few per cent of scale is the chaotic sensitivity of a single-record "
        "peak: a match of θmax at scale 1 is not expected."
    ),
}
"""Captions of the paper's model figures, drawn only for a reproduction of the paper."""

NUMBERS = {"fig07_tilt_map": "Fig 7", "fig08_motions": "Fig 8", "fig09_spectra": "Fig 9",
           "fig10_goals": "Fig 10", "fig11_slenderness": "Fig 11", "fig12_2d_vs_3d": "Fig 12"}
"""The paper's number of each figure a study draws (named only in a reproduction)."""

UNRESOLVED = ("Answers flagged unresolved (the response came close to the goal below the "
              "answer, so a narrower window of exceedance may lie lower) are counted per curve "
              "in the legend.")

STUDY_CAPTIONS: dict[str, str] = {
    "fig07_tilt_map": (
        "Contours of the peak normalized tilt θmax/α over cylinder size R and "
        "normalized intensity PGA/(g tan α) for the study's scaled record (principal axes, "
        "high-passed), at the slenderness in the title, one panel per model; PGA is the "
        "vector peak max √(ügx² + ügy²); right axis PGA in g. Contours are drawn on the grid "
        "the configuration gives (dots); the black line is θmax = α and the pale grey top "
        "class θmax > α, which includes overturning."
    ),
    "fig08_motions": (
        "Acceleration traces on the principal axes (x = major, y = minor) and 5 %-damped "
        "pseudo-acceleration spectra of the record (top, black) and its synthetic "
        "Rezaeian–Der Kiureghian pairs (the same colours as in the spectra per motion): per "
        "component the record (black), every synthetic "
        "motion (grey) and their median with the 16–84 % range (blue); left the count-based "
        "identification of RDK (2010), right the spectrum-matched one the study uses (fit "
        "quality in the table below the figure)."
    ),
    "fig09_spectra": (
        "Seismic performance rocking spectra per ground motion (one colour each, the "
        "same as in Fig 8: record black, synthetic pairs in colour; undamped solid, damped "
        "dashed) and their means over the motions (thick black), one panel per limit state "
        "(overturning, and excessive tilt θ > α/3 or the study's own tilt goal) at the "
        "slenderness in the title. Where the damped model ran, below: the relative difference "
        "damped − undamped per motion and of the means, with the band of ± 2 standard errors. "
        f"{UNRESOLVED} Right axis PGA in g."
    ),
    "fig10_goals": (
        "Mean performance spectra of the study's performance goals θ > r·α and "
        "overturning (the mode and slenderness in the title), each goal in its own colour in "
        "every figure; dashed lines are the least-squares lines (fitted over five sizes R or "
        "more) whose R² and largest departure from the mean the legend gives. Goals whose "
        "statistics coincide at every R (a cylinder tilted past α at the threshold intensity "
        "overturned) are drawn dotted over each other and said so in the figure. Means over "
        "answers flagged unresolved (they may lie lower) are counted per goal in the legend. "
        "Right axis PGA in g."
    ),
    "fig11_slenderness": (
        "Mean performance spectra (undamped 3D model) per slenderness tan α of the "
        "study, the intensity normalized by g tan α."
    ),
    "fig12_2d_vs_3d": (
        "Mean performance spectra of the 3D model under both components against the "
        "2D model under the major-axis (x) or the minor-axis (y) component alone, at the "
        "slenderness in the title; the intensity is the bidirectional PGA in all three (§5.4). "
        "Colours are ensembles, line styles modes; the ratios 2D/3D at the largest R are "
        "written at the right end of the curves; the note gives each ensemble's axis "
        "azimuths. Open circles: the mean covers fewer motions than the ensemble, the others "
        "not having reached the limit state at the search bound (such a mean understates the "
        "intensity). Means over answers flagged unresolved are counted per curve in the "
        "legend, and the legend says how far refinement moves the 3D overturning mean at the "
        "largest R (refinement_sample.csv). The verdicts read the 2D/3D ratios from the "
        "censoring-aware medians of the lognormal fits across every size, not from these "
        "means at one size. The 2D model is Housner's, with the restitution e = 0.942 "
        "(Eq 31) that dissipates energy at every impact; the undamped 3D model dissipates "
        "none."
    ),
    "fragility_curves": (
        "Fragility curves: lognormal maximum-likelihood fits of the "
        "ensemble's critical intensities PGA/(g tan α) per size R (motions that never reached "
        "the limit state are right-censored at the search bound); colour gives R on the colour "
        "bar, markers are the empirical fractions; the x axis runs a quarter beyond the "
        "largest intensity observed (or the largest median, at most three times that), never "
        "beyond the search bound. Medians IM₅₀ and dispersions β are tabulated in the report."
    ),
}
"""Captions of the figures a study draws, what they show and nothing of the paper (a study
of one's own gets these, adapted by :func:`caption` to what its notes say is drawn)."""

PAPER_STATEMENTS: dict[str, str] = {
    "fig07_tilt_map": (
        "The paper's Fig 7: the El Centro record at tan α = 0.2, undamped (left) and damped "
        "(right); it reports that larger cylinders are harder to overturn and that both "
        "models give almost identical maps."
    ),
    "fig08_motions": (
        "The paper rotates El Centro by 22.33° to uncorrelated axes and simulates 10 pairs; "
        "the seeds are not the paper's, so individual synthetic motions differ from its Fig 8."
    ),
    "fig09_spectra": (
        "The paper's Fig 9: overturning and excessive tilt θ > α/3 at tan α = 0.2; it reports "
        "essentially identical undamped and damped overturning spectra, differences for "
        "excessive tilt that vanish in the mean, and mean spectra that are almost straight "
        "lines in R."
    ),
    "fig10_goals": (
        "The paper's Fig 10: the undamped 3D model at tan α = 0.2 and seven goals, "
        "r ∈ {0.1, 0.2, 1/3, 0.5, 0.75, 1} and overturning, all almost linear in R (θ > α and "
        "overturning coincide in the paper run); goals a reduced run did not compute are named "
        "in the figure."
    ),
    "fig11_slenderness": (
        "The paper's Fig 11: tan α = 0.1, 0.2 and 0.3; it reports that, once the intensity is "
        "normalized by g tan α, slenderness has a very small influence. Slendernesses this run "
        "did not compute are named in the figure."
    ),
    "fig12_2d_vs_3d": (
        "The paper's Fig 12 (tan α = 0.2) reports that overturning an R = 10 m cylinder needs "
        "PGA/(g tan α) of about 4 bidirectionally and about twice that unidirectionally "
        "(El Centro black, Loma Prieta red)."
    ),
    "fragility_curves": "",
}
"""What the paper shows and states of each figure a study draws (added for a reproduction)."""

CAPTIONS: dict[str, str] = {
    **_PAPER_ONLY,
    **{name: (f"{NUMBERS[name]}. " if name in NUMBERS else "Beyond the paper: ")
       + f"{text} {PAPER_STATEMENTS[name]}".strip() for name, text in STUDY_CAPTIONS.items()},
}
"""Caption of every figure in a reproduction of the paper, keyed by figure name, in the
paper's order."""


EXTRA_CAPTIONS: dict[str, str] = {
    "stripe_fragility": (
        "Multiple-stripe against first-exceedance fragility (beyond the paper), one panel per "
        "limit state and size R of the study's stripes: markers the share of the motions "
        "exceeding the limit state at each stripe intensity, the solid line its binomial "
        "maximum-likelihood lognormal, the dashed line the lognormal of the motions' first "
        "exceedances; medians IM₅₀ and dispersions β in the legend and in the table below."
    ),
    "risk": "",
}
"""Captions of figures drawn beyond :data:`CAPTIONS` (the stripe and the risk figures),
used by the report where the figure's sidecar or module gives none."""


def caption(name: str, paper: bool = True, notes: dict | None = None) -> str:
    """The caption of figure ``name`` (a key of :data:`CAPTIONS`): with the paper's
    statements for a reproduction of the paper (``paper``), else what the figure shows,
    adapted to what its sidecar ``notes`` say is drawn (no synthetic pairs, no damped model:
    no words for them)."""
    if name not in CAPTIONS:
        raise ValueError(f"figure must be one of {list(CAPTIONS)}, got {name!r}")
    if not paper and name in _PAPER_ONLY:
        raise ValueError(f"figure {name!r} is drawn only for a reproduction of the paper")
    if paper:
        return CAPTIONS[name]
    if name == "fig09_spectra" and notes is not None:
        return _spectra_caption(notes)
    return STUDY_CAPTIONS[name].replace(" (the same colours as in the spectra per motion)", "")


def _spectra_caption(notes: dict) -> str:
    """The caption of the spectra per motion from what is drawn: recorded motions and
    synthetic pairs, the damped model, unresolved answers."""
    labels = [str(c.get("label", "")) for c in (notes.get("colors") or {}).values()]
    synthetic = sum(lab.startswith("synthetic") for lab in labels)
    recorded = len(labels) - synthetic
    damped = any(str(k).startswith("damping|") for k in (notes.get("measured") or {}))
    who = (f"the {recorded} recorded motions" if recorded > 1 else "the record") + (
        f" and {synthetic} synthetic pairs" if synthetic else "")
    text = (f"Seismic performance rocking spectra of each of {who} (one colour each, "
            "named in the legend) and their mean (thick black), one panel per limit state at "
            "the slenderness in the title.")
    if damped:
        text += (" Undamped solid, damped dashed; below, the relative difference damped − "
                 "undamped per motion and of the means, with the band of ± 2 standard errors.")
    return f"{text} {UNRESOLVED} Right axis PGA in g."
