"""The numbers documents quote from the committed gallery, written from the gallery itself: a
maintainer's tool beside ``workflow/gallery.py`` (which runs it after copying a run), not
part of the library.

A document (README.md, docs/*.md) that quotes the gallery (``results/paper/``: its reports'
verdicts, its tables) marks each quotation as a block::

    <!-- BEGIN gallery:verdict-counts -->24 reproduced, …<!-- END gallery:verdict-counts -->

and :func:`render` rewrites the text between the markers from the gallery with the block's
function in :data:`BLOCKS` (inline for a number in a sentence, on lines of their own for a
table). The workflow's gallery script rewrites every marked document after it copies a run,
and tests/test_docs_numbers.py fails when a committed document differs from what its gallery
gives: a verdict or number that moves in the gallery cannot leave a document behind.

The verdicts are read from each report's verdict table as data (``<study>/verdicts.csv``,
written by the report beside its page, row for row as the page shows it); the numbers from the
study tables (``<study>/*.csv``), the ensembles' parameters (``motions/*.json``) and the
manifest. Nothing here reads HTML.

    python workflow/gallery_quotes.py [--gallery results/paper] [--check] [FILE ...]
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import re
import sys
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from rocking.fragility.table import CRITICAL_INTENSITY, STRIPES
from rocking.plot.comparisons import DIFFERS, REPRODUCED, VERDICTS
from rocking.report.entries import VERDICT_COLUMNS

BLOCK = re.compile(r"(?P<begin><!-- BEGIN gallery:(?P<name>[\w-]+) -->)(?P<body>.*?)"
                   r"(?P<end><!-- END gallery:(?P=name) -->)", re.DOTALL)
"""A marked quotation: its name, the generated text, and the markers around it."""

STUDY_TITLES = {"elcentro": "El Centro", "lomaprieta": "Loma Prieta"}
"""How the documents name the gallery's studies (another study is named by its folder)."""


@dataclass(frozen=True)
class VerdictRow:
    """One row of a report's verdict table (a row of its ``verdicts.csv``).

    ``verdict`` is one of :data:`rocking.plot.comparisons.VERDICTS`; ``reason`` the tolerance
    met or why the numbers differ, as the report gives it.
    """

    figure: str
    statement: str
    paper: str
    ours: str
    verdict: str
    reason: str

    @property
    def first_reason(self) -> str:
        """The reason up to its first "; " outside brackets."""
        return _first_clause(self.reason)


def _first_clause(text: str) -> str:
    """``text`` up to its first "; " outside brackets."""
    depth = 0
    for i, ch in enumerate(text):
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        elif ch == ";" and depth == 0:
            return text[:i]
    return text


def verdict_rows(table: str | Path) -> list[VerdictRow]:
    """The verdict table of a study (its ``verdicts.csv``), row by row.

    Raises
    ------
    ValueError
        The file lacks a column of :data:`~rocking.report.entries.VERDICT_COLUMNS`, or a row
        names no verdict of :data:`~rocking.plot.comparisons.VERDICTS` (naming the file and
        the row).
    """
    with open(table, newline="", encoding="utf-8") as fh:
        reader = csv.DictReader(fh)
        missing = [c for c in VERDICT_COLUMNS if c not in (reader.fieldnames or ())]
        if missing:
            raise ValueError(f"verdict table {table}: no column {missing} "
                             f"(columns {reader.fieldnames})")
        rows = list(reader)
    out = []
    for i, r in enumerate(rows, start=2):
        if r["verdict"] not in VERDICTS:
            raise ValueError(f"verdict table {table}, line {i}: verdict {r['verdict']!r} is "
                             f"none of {VERDICTS}")
        out.append(VerdictRow(*(r[c] for c in VERDICT_COLUMNS)))
    return out


def _reports(gallery: Path) -> dict[str, Path]:
    """Each study folder of the gallery with a report's verdict table, by name (sorted)."""
    return {p.parent.name: p for p in sorted(Path(gallery).glob("*/verdicts.csv"))}


def _title(study: str) -> str:
    return STUDY_TITLES.get(study, study)


def verdict_counts(gallery: Path) -> str:
    """"El Centro report: 24 reproduced, 10 differ, 3 not in the paper; Loma Prieta …":
    the verdicts of each report of the gallery, counted."""
    words = {DIFFERS: "differ"}
    parts = []
    for study, page in _reports(gallery).items():
        rows = verdict_rows(page)
        counts = [(v, sum(r.verdict == v for r in rows)) for v in VERDICTS]
        parts.append(f"{_title(study)} report: "
                     + ", ".join(f"{n} {words.get(v, v)}" for v, n in counts if n))
    if not parts:
        raise ValueError(f"gallery {gallery}: no <study>/verdicts.csv")
    return "; ".join(parts)


@dataclass(frozen=True)
class Headline:
    """A row of the headline table: a report's verdict row, picked by figure and the start of
    its statement, under a name of the quantity for the reader."""

    study: str
    figure: str
    statement: str
    quantity: str

    def pick(self, rows: Sequence[VerdictRow]) -> VerdictRow:
        """The one row of ``rows`` of this figure whose statement starts so."""
        found = [r for r in rows if r.figure == self.figure
                 and r.statement.startswith(self.statement)]
        if len(found) != 1:
            raise ValueError(f"{self.study}/verdicts.csv: {len(found)} verdict rows of "
                             f"{self.figure} start with {self.statement!r} (need one)")
        return found[0]


HEADLINES = (
    Headline("elcentro", "fig04_free_vibration", "Angle of turn of the contact point",
             "angle of turn per quasi-impact, tan α = 0.2, printed Eq (27)"),
    Headline("elcentro", "fig04_free_vibration", "Angle of turn measured numerically",
             "the same angle, measured numerically (§2.4)"),
    Headline("elcentro", "fig04_free_vibration", "Coefficient of restitution",
             "damped restitution over five quasi-impacts"),
    Headline("elcentro", "fig08_motions", "Rotation of the record to uncorrelated axes (§5.1)",
             "El Centro principal angle"),
    Headline("elcentro", "fig06_el_centro", "Peak tilt θmax, undamped",
             "Fig 6 peak tilt, undamped (R = 6 m)"),
    Headline("elcentro", "fig06_el_centro", "Peak tilt θmax, damped",
             "Fig 6 peak tilt, damped (R = 6 m)"),
    Headline("elcentro", "fig09_spectra", "Undamped and damped spectra per motion, Overturning",
             "Fig 9: damped and undamped spectra \"essentially identical\", per motion "
             "(overturning)"),
    Headline("elcentro", "fig09_spectra", "Undamped and damped mean spectra, Overturning",
             "Fig 9: the same, mean spectra (overturning)"),
    Headline("elcentro", "fig09_spectra", "Undamped and damped mean spectra, Tilt θ > α/3",
             "Fig 9: the same, mean spectra (θ > α/3)"),
    Headline("elcentro", "fig10_goals", "Mean spectrum almost linear in R, Overturning",
             "Fig 10: mean spectrum \"almost linear in R\", El Centro (overturning)"),
    Headline("lomaprieta", "fig10_goals", "Mean spectrum almost linear in R, Overturning",
             "Fig 10: the same, Loma Prieta (overturning)"),
    Headline("elcentro", "fig11_slenderness", "Slenderness has 'a very small influence' "
             "once the intensity is normalized by g tan α, Overturning",
             "Fig 11: slenderness has \"a very small influence\" (overturning)"),
    Headline("elcentro", "fig11_slenderness", "Slenderness has 'a very small influence' "
             "once the intensity is normalized by g tan α, Tilt θ > α/3",
             "Fig 11: the same (θ > α/3)"),
    Headline("elcentro", "fig12_2d_vs_3d", "Overturning of an R = 10 m cylinder",
             "Fig 12: R = 10 m, 3D overturning"),
    Headline("elcentro", "fig12_2d_vs_3d", "El Centro, overturning: the 3D model under the x",
             "Fig 12: 3D under x alone \"twice as high\" (El Centro, overturning)"),
    Headline("elcentro", "fig12_2d_vs_3d", "El Centro, overturning: the 3D model under the y",
             "Fig 12: 3D under y alone \"twice as high\" (El Centro, overturning)"),
    Headline("elcentro", "fig12_2d_vs_3d", "Loma Prieta (stand-in record), overturning: the 3D "
             "model under the x", "Fig 12: Loma Prieta, 3D under x alone above both (overturning)"),
    Headline("elcentro", "fig12_2d_vs_3d", "Loma Prieta (stand-in record), overturning: the 3D "
             "model under the y", "Fig 12: Loma Prieta, 3D under y alone above both (overturning)"),
    Headline("elcentro", "fig12_2d_vs_3d", "El Centro, overturning: Housner's 2D block (a "
             "further comparator) under the x", "Fig 12: Housner's 2D block under x against 3D "
             "(El Centro, overturning)"),
    Headline("elcentro", "fig12_2d_vs_3d", "El Centro, overturning: Housner's 2D block (a "
             "further comparator) under the y", "Fig 12: Housner's 2D block under y against 3D "
             "(El Centro, overturning)"),
)
"""The rows of docs/models.md's headline table, in order."""


def _cell(text: str) -> str:
    """A markdown table cell: pipes escaped."""
    return text.replace("|", "\\|")


def headline_table(gallery: Path, headlines: Iterable[Headline] = HEADLINES) -> str:
    """The headline table (quantity, paper, this run, verdict) from the reports' verdict
    rows: the paper's and this run's cells as the report gives them, the verdict with the
    first clause of its reason where it is not "reproduced" (the tolerances are in
    docs/models.md's criteria table)."""
    reports = _reports(gallery)
    rows: dict[str, list[VerdictRow]] = {}
    lines = ["| quantity | paper | this run | verdict |", "|---|---|---|---|"]
    for h in headlines:
        if h.study not in reports:
            raise ValueError(f"gallery {gallery}: no {h.study}/verdicts.csv")
        if h.study not in rows:
            rows[h.study] = verdict_rows(reports[h.study])
        r = h.pick(rows[h.study])
        verdict = r.verdict if r.verdict == REPRODUCED or not r.first_reason else \
            f"{r.verdict}: {r.first_reason}"
        lines.append("| " + " | ".join(_cell(c) for c in (h.quantity, r.paper, r.ours,
                                                              verdict)) + " |")
    return "\n\n" + "\n".join(lines) + "\n\n"


def _table_row(gallery: Path, study: str, table: str, **where: str) -> dict[str, str]:
    """The one row of ``<study>/<table>.csv`` whose columns equal ``where``."""
    path = Path(gallery) / study / f"{table}.csv"
    with open(path, newline="", encoding="utf-8") as fh:
        rows = [r for r in csv.DictReader(fh) if all(r.get(k) == v for k, v in where.items())]
    if len(rows) != 1:
        raise ValueError(f"{path}: {len(rows)} rows with {where} (need one)")
    return rows[0]


_R10 = {"limit_state": "overturning", "tan_alpha [-]": "0.2", "R [m]": "10"}


def _r10_means(gallery: Path, one: Sequence[str] = ()
               ) -> tuple[float, float, int, dict[str, float]]:
    """El Centro, overturning, tan α 0.2, R = 10 m: the 3D mean under both components, its
    standard error, the number of motions, and the means of the modes ``one`` under one
    component (mean_spectra.csv)."""
    rows = {m: _table_row(gallery, "elcentro", "mean_spectra", mode=m, **_R10)
            for m in ("3d", *one)}
    n = int(rows["3d"]["count"])
    mean = float(rows["3d"]["mean [g tan(alpha)]"])
    sem = float(rows["3d"]["std [g tan(alpha)]"]) / math.sqrt(n)
    return mean, sem, n, {m: float(r["mean [g tan(alpha)]"]) for m, r in rows.items()}


def r10_means(gallery: Path) -> str:
    """"4.75 ± 0.41 at R = 10 m in 3D, under one component 3D-x/3D 2.1×, 3D-y/3D 1.9×
    (Housner's 2D block: 2D-x/3D 2.43×, 2D-y/3D 1.84×)" (El Centro, overturning, tan α 0.2;
    mean ± its standard error)."""
    mean, sem, _, one = _r10_means(gallery, ("3d-x", "3d-y", "2d-x", "2d-y"))
    return (f"{mean:.2f} ± {sem:.2f} at R = 10 m in 3D, under one component "
            f"3D-x/3D {one['3d-x'] / mean:.2f}×, 3D-y/3D {one['3d-y'] / mean:.2f}× "
            f"(Housner's 2D block: 2D-x/3D {one['2d-x'] / mean:.2f}×, "
            f"2D-y/3D {one['2d-y'] / mean:.2f}×)")


def r10_band(gallery: Path) -> str:
    """"≈ 1.3 with SE 0.41": Fig 12's "about 4" band 2·√(2 SE² + (0.5/√3)²) at this run's
    standard error of the R = 10 m 3D mean."""
    _, sem, *_ = _r10_means(gallery)
    return f"≈ {2 * math.sqrt(2 * sem**2 + 0.25 / 3):.1f} with SE {sem:.2f}"


def fragility_r6(gallery: Path) -> str:
    """"median 2.284 (PGA 0.457 g), β = 0.238, from 11 motions": El Centro, 3d, overturning,
    tan α 0.2, R = 6 m (fragility.csv)."""
    row = _table_row(gallery, "elcentro", "fragility", mode="3d", limit_state="overturning",
                     **{"tan_alpha [-]": "0.2", "R [m]": "6"})
    return (f"median {float(row['median [g tan(alpha)]']):.3f} "
            f"(PGA {float(row['median_pga_g [g]']):.3f} g), "
            f"β = {float(row['beta [-]']):.3f}, from {row['n']} motions")


def record_r6(gallery: Path) -> str:
    """"2.206": El Centro as the workflow processes it, 3d overturning, tan α 0.2, R = 6 m
    (critical.csv; the README's command line gives the same with the workflow's processing)."""
    row = _table_row(gallery, "elcentro", "critical", mode="3d", limit_state="overturning",
                     motion="el-centro-1940", **{"tan_alpha [-]": "0.2", "R [m]": "6"})
    return f"{float(row['pga_crit [g tan(alpha)]']):.3f}"


def stripe_ratio_r6(gallery: Path) -> str:
    """"1.5×": the stripe median over the critical-intensity median, El Centro, 3d,
    overturning, R = 6 m (stripe_fragility.csv)."""
    row = _table_row(gallery, "elcentro", "stripe_fragility", mode="3d",
                     limit_state="overturning", **{"R [m]": "6"})
    return f"{float(row['ratio']):.1f}×"


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _power(value: float) -> str:
    """``1.74·10⁻³``: three significant digits times a power of ten."""
    mantissa, exponent = f"{value:.2e}".split("e")
    return f"{mantissa}·10{str(int(exponent)).translate(_SUPERSCRIPT)}"


def risk_stripe_critical(gallery: Path) -> str:
    """The stripe λ against the critical-intensity λ of El Centro under the example hazard,
    3d, tan α 0.2, R = 2, 6, 10 m (risk.csv): ratios with both λ for overturning, ratios for
    excessive tilt (θ > α/3)."""
    path = Path(gallery) / "elcentro" / "risk.csv"
    with open(path, newline="", encoding="utf-8") as fh:
        maf = {(r["fragility"], r["limit_state"], r["R [m]"]): float(r["maf [1/yr]"])
               for r in csv.DictReader(fh)
               if r["mode"] == "3d" and r["tan_alpha [-]"] == "0.2"}

    def pair(ls: str, R: str) -> tuple[float, float]:
        try:
            return maf[(STRIPES, ls, R)], maf[(CRITICAL_INTENSITY, ls, R)]
        except KeyError as err:
            raise ValueError(f"{path}: no 3d, tan α 0.2 row {err.args[0]}") from None

    sizes = ("2", "6", "10")
    over = [pair("overturning", R) for R in sizes]
    tilt = [a / b for a, b in (pair("tilt:1/3", R) for R in sizes)]
    (s2, c2), (s6, c6), (s10, c10) = over
    return (f"{s2 / c2:.2f}× the critical-intensity λ at R = 2 m ({_power(s2)} against "
            f"{_power(c2)} per year), {s6 / c6:.2f}× at R = 6 m ({_power(s6)} against "
            f"{_power(c6)}) and {s10 / c10:.2f}× at R = 10 m ({_power(s10)} against "
            f"{_power(c10)}); of excessive tilt {tilt[0]:.2f}×, {tilt[1]:.2f}× and "
            f"{tilt[2]:.2f}×")


RECORD_TITLES = {"el-centro-1940": "El Centro", "loma-prieta-corralitos": "Corralitos"}
"""How the documents name the gallery's records (another record is named as it is)."""

_PARAMETERS = (("Ia", "Ia [m/s]", ".3f"), ("D5_95", "D5-95 [s]", ".2f"),
               ("t_mid", "t_mid [s]", ".2f"), ("f_mid", "f_mid [Hz]", ".2f"),
               ("f_slope", "f′ [Hz/s]", ".3f"), ("zeta_f", "ζ_f", ".2f"),
               ("f_mid2", "f_mid2 [Hz]", ".2f"), ("zeta_f2", "ζ_f2", ".2f"),
               ("share2", "share2", ".2f"), ("f_low", "f_low [Hz]", ".2f"),
               ("zeta_low", "ζ_low", ".2f"))
"""The fitted RDK parameters of an ensemble as the documents show them: key, column, format."""


def ensemble_parameters(gallery: Path) -> str:
    """The fitted parameters of each ensemble of the gallery (``motions/<name>.json``), one
    row per record and component."""
    lines = ["| record, component | " + " | ".join(c for _, c, _ in _PARAMETERS) + " |",
             "|---|" + "---|" * len(_PARAMETERS)]
    files = sorted((Path(gallery) / "motions").glob("*.json"))
    if not files:
        raise ValueError(f"gallery {gallery}: no motions/*.json")
    for path in files:
        notes = json.loads(path.read_text(encoding="utf-8"))
        title = RECORD_TITLES.get(notes["record"], notes["record"])
        for component in ("major", "minor"):
            fit = notes["fit"][component]
            cells = [format(float(fit[k]), f).replace("-", "−") for k, _, f in _PARAMETERS]
            lines.append(f"| {title}, {component} | " + " | ".join(cells) + " |")
    return "\n\n" + "\n".join(lines) + "\n\n"


def _records(gallery: Path) -> list[dict[str, str]]:
    """Loma Prieta's ``records.csv`` (the record analysed once at scale 1)."""
    path = Path(gallery) / "lomaprieta" / "records.csv"
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def records_rows(gallery: Path) -> str:
    """"120 rows": the rows of Loma Prieta's records.csv."""
    return f"{len(_records(gallery))} rows"


def records_as_recorded(gallery: Path) -> str:
    """What the analyses at scale 1 changed in Loma Prieta's records.csv: of the rows whose
    scale factor (≤ 1) says the record exceeds as recorded, those it survives, the range of
    their scale factors, what they are; and the rows whose scale factor says it survives
    that exceed at scale 1."""
    rows = _records(gallery)
    exceed = [r for r in rows if float(r["scale_factor [-]"]) <= 1]
    changed = [r for r in exceed if r["as_recorded_disagrees"] == "True"]
    other = sum(r["as_recorded_disagrees"] == "True" for r in rows) - len(changed)
    survivors = "no row" if not other else f"{other} row" + ("s" if other > 1 else "")
    tail = f"; {survivors} that the scale factor said survives exceeds at scale 1"
    if not changed:
        return f"changed none of the {len(exceed)} rows that the scale factor said exceed" + tail
    scales = [float(r["scale_factor [-]"]) for r in changed]
    kinds: dict[str, int] = {}
    singles = []
    for r in changed:
        if r["non_monotonic"] == "True":
            key = f"`{r['limit_state']}`"
            kinds[key] = kinds.get(key, 0) + 1
        else:
            singles.append(f"one {r['mode']} {r['limit_state']} at R = {r['R [m]']} m")
    what = [f"{n} of them {k} rows the search had flagged `non_monotonic`"
            for k, n in kinds.items()] + singles
    return (f"changed {len(changed)} of the {len(exceed)} rows that the scale factor said "
            "exceed: the record survives at scale 1 although the search found an exceedance "
            f"at scale {min(scales):.2f}–{max(scales):.2f} ({', '.join(what)})" + tail)


def portfolio_example(gallery: Path) -> str:
    """The worked example of docs/risk.md: El Centro's portfolio.csv (the example inventory
    under the example hazard), overturning, ranked: one markdown row per column."""
    import pandas as pd

    table = pd.read_csv(Path(gallery) / "elcentro" / "portfolio.csv")
    rows = table[table["limit_state"] == "overturning"].sort_values("rank", kind="stable")
    lines = ["| rank | column | height [m] | diameter [m] | R [m] | tan α | overturning θ [g] "
             "(90 %) | β | λ [1/yr] (90 %) | return period [yr] | P(50 yr) |",
             "|---:|---|---:|---:|---:|---:|---|---:|---|---:|---:|"]
    for r in rows.to_dict(orient="records"):
        lines.append(
            f"| {r['rank']} | {r['id']} | {r['height']:g} | {r['diameter']:.2f} | "
            f"{r['R']:.2f} | {r['tan_alpha']:.3f} | {r['median']:.3f} ({r['median_p05']:.3f}"
            f"–{r['median_p95']:.3f}) | {r['beta']:.3f} | {r['lambda']:.3g} "
            f"({r['lambda_p05']:.3g}–{r['lambda_p95']:.3g}) | {r['return_period']:.0f} | "
            f"{r['p_50yr']:.2f} |")
    return "\n\n" + "\n".join(lines) + "\n\n"


def run_time(gallery: Path) -> str:
    """"36 min 38 s": the measured wall time of the run the gallery holds (MANIFEST.json)."""
    manifest = json.loads((Path(gallery) / "MANIFEST.json").read_text(encoding="utf-8"))
    minutes, seconds = divmod(round(float(manifest["elapsed_seconds"])), 60)
    return f"{minutes} min {seconds} s"


BLOCKS: dict[str, Callable[[Path], str]] = {
    "run-time": run_time,
    "verdict-counts": verdict_counts,
    "headlines": headline_table,
    "r10-means": r10_means,
    "r10-band": r10_band,
    "fragility-r6": fragility_r6,
    "record-r6": record_r6,
    "stripe-ratio-r6": stripe_ratio_r6,
    "ensemble-parameters": ensemble_parameters,
    "risk-stripe-critical": risk_stripe_critical,
    "records-rows": records_rows,
    "records-as-recorded": records_as_recorded,
    "portfolio-example": portfolio_example,
}
"""Every quotation a document can mark, by name: its text from a gallery folder."""


def render(text: str, gallery: str | Path, where: str = "text") -> str:
    """``text`` with every marked quotation rewritten from ``gallery``.

    Raises
    ------
    ValueError
        A block names no quotation of :data:`BLOCKS` (``where`` names the document), or the
        gallery lacks what a block quotes.
    """
    cache: dict[str, str] = {}

    def fill(m: re.Match) -> str:
        name = m["name"]
        if name not in BLOCKS:
            raise ValueError(f"{where}: gallery block {name!r} is none of {sorted(BLOCKS)}")
        if name not in cache:
            cache[name] = BLOCKS[name](Path(gallery))
        return m["begin"] + cache[name] + m["end"]

    return BLOCK.sub(fill, text)


def stale_blocks(path: str | Path, gallery: str | Path) -> list[str]:
    """The names of the marked quotations of document ``path`` that differ from ``gallery``."""
    text = Path(path).read_text(encoding="utf-8")
    new = render(text, gallery, str(path))
    return [a["name"] for a, b in zip(BLOCK.finditer(text), BLOCK.finditer(new), strict=True)
            if a["body"] != b["body"]]


def marked_documents(root: str | Path) -> list[Path]:
    """README.md and docs/*.md under ``root`` that mark a gallery quotation."""
    root = Path(root)
    paths = [root / "README.md", *sorted((root / "docs").glob("*.md"))]
    return [p for p in paths if p.exists() and BLOCK.search(p.read_text(encoding="utf-8"))]


def write_documents(paths: Iterable[str | Path], gallery: str | Path) -> list[Path]:
    """Rewrite the marked quotations of each document from ``gallery``; return those changed.

    Every document is rendered before any is written, so a gallery that lacks a quoted
    number changes nothing.
    """
    texts = {Path(p): Path(p).read_text(encoding="utf-8") for p in paths}
    new = {p: render(t, gallery, str(p)) for p, t in texts.items()}
    changed = [p for p in texts if new[p] != texts[p]]
    for p in changed:
        p.write_text(new[p], encoding="utf-8")
    return changed


def main(argv: Sequence[str] | None = None) -> int:
    """Rewrite (or with ``--check`` only compare) the documents' gallery quotations."""
    parser = argparse.ArgumentParser(prog="python workflow/gallery_quotes.py",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="*", type=Path,
                        help="documents (default: README.md and docs/*.md that mark one)")
    parser.add_argument("--gallery", type=Path, default=Path("results/paper"),
                        help="the gallery folder (default results/paper)")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 naming every stale quotation")
    args = parser.parse_args(argv)
    if not args.gallery.is_dir():
        print(f"error: --gallery {args.gallery}: no such folder", file=sys.stderr)
        return 2
    files = args.files or marked_documents(Path.cwd())
    if not files:
        print(f"error: no README.md or docs/*.md under {Path.cwd()} marks a gallery quotation",
              file=sys.stderr)
        return 2
    try:
        if args.check:
            stale = [f"{p}: {name}" for p in files for name in stale_blocks(p, args.gallery)]
            for line in stale:
                print(f"stale gallery quotation {line}", file=sys.stderr)
            return 1 if stale else 0
        for p in write_documents(files, args.gallery):
            print(f"rewrote {p}")
    except (OSError, ValueError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
