"""A self-contained HTML report: what was run, every figure with its caption, and for every
figure the paper's statements set against this run's numbers with a verdict.

Inputs are the figure PNGs with their JSON sidecars (written by :func:`.render`), the
linear fits of the mean spectra, the fragility table and, for the "what was run" section, the
configuration and the stores and summaries the run wrote. Images are embedded (base64), so
the page can be moved or mailed alone. Captions come from the figures' entries
(:mod:`.registry`), verdicts
from :mod:`.comparisons`; the figures are read back by :mod:`.entries`, the findings written by
:mod:`.findings`, the tables by :mod:`.tables` and the "what was run" rows by
:mod:`.run_summary`. This module lays them out as one HTML page.
"""

from __future__ import annotations

import base64
import html
import os
import re
from collections.abc import Callable, Sequence
from pathlib import Path

import pandas as pd

from rocking.plot.comparisons import Comparison
from rocking.plot.registry import SECTIONS, caption, figure
from rocking.report.entries import (
    FigureEntry,
    comparison_table,
    figure_comparisons,
    figure_run_rows,
    figure_tables,
    load_figures,
    measured_lines,
    write_verdicts,
)
from rocking.report.findings import findings_html, paper_findings, study_findings
from rocking.report.risk import risk_section_html
from rocking.report.tables import (
    fragility_pivot,
    linear_fit_rows,
    records_section,
    stripes_section,
    table_html,
)

_CSS = """
body{font-family:sans-serif;max-width:1150px;margin:2em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;font-size:0.85em;margin:1em 0}
td,th{border:1px solid #bbb;padding:4px 8px;vertical-align:top;text-align:left}
th{background:#eee} figure{margin:2em 0} img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:0.92em;margin-top:0.5em} .measured{color:#05509b}
td.reproduced{background:#e4f4e4} td.differs{background:#fbeede}
td.not-computed{background:#eeeeee} td.not-reproducible{background:#f8dddd}
"""


_DOC = re.compile(r"docs/equations\.md(#[a-z0-9-]+)?")
DOCS = Path(__file__).resolve().parents[3] / "docs"
"""The repository's docs folder (the derivations the verdicts cite)."""


def docs_href(folder: str | Path) -> str:
    """Link from a page in ``folder`` to ``docs/equations.md`` of this repository (relative
    when the page lies inside the repository, else the absolute file path)."""
    target = DOCS / "equations.md"
    try:
        return Path(os.path.relpath(target, Path(folder).resolve())).as_posix()
    except ValueError:  # another drive
        return target.as_uri()


def link_docs(text: str, href: str) -> str:
    """Escape ``text`` for HTML and turn every ``docs/equations.md#anchor`` into a link."""
    out, last = [], 0
    for m in _DOC.finditer(text):
        out.append(html.escape(text[last:m.start()]))
        out.append(f"<a class='doc' href='{html.escape(href + (m[1] or ''), quote=True)}'>"
                   f"{html.escape(m[0])}</a>")
        last = m.end()
    out.append(html.escape(text[last:]))
    return "".join(out)


_DOC_LINK = re.compile(r"<a class='doc' href='[^'#]*(?P<anchor>#[^']*)?'>")


def relink_docs(page: str, folder: str | Path) -> str:
    """The report with its links to docs/equations.md made relative to ``folder`` (for a copy
    of the page placed elsewhere, as the committed gallery does)."""
    href = docs_href(folder)
    return _DOC_LINK.sub(lambda m: f"<a class='doc' href='{href}{m['anchor'] or ''}'>", page)


def _verdict_html(rows: Sequence[Comparison], with_figure: bool, docs: str = "") -> str:
    """A comparison table whose verdict cells are shaded by verdict; the figure cell links
    to the figure, citations of docs/equations.md link to the derivation (``docs``)."""
    df = comparison_table(rows, with_figure=with_figure)
    head = "".join(f"<th>{html.escape(c)}</th>" for c in df.columns)
    body = []
    for c, values in zip(rows, df.itertuples(index=False), strict=True):
        cls = c.verdict.replace("not computed in this run", "not-computed").replace(" ", "-")
        cells = [f"<td>{link_docs(str(v), docs)}</td>" for v in values[:-1]]
        if with_figure:
            cells[0] = f"<td><a href='#{html.escape(c.figure)}'>{html.escape(c.figure)}</a></td>"
        cells.append(f"<td class='{cls}'>{link_docs(str(values[-1]), docs)}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def _figure_html(entry: FigureEntry, rows: Sequence[Comparison], docs: str = "",
                 paper: bool = True) -> str:
    """A figure with its caption (with the paper's statements when ``paper``) and evidence;
    its verdicts stay in the verdict table (one line here counts them and links there)."""
    img = base64.b64encode(entry.png.read_bytes()).decode("ascii")
    lines = "".join(f"<br><span class='measured'>{html.escape(s)}</span>"
                    for s in measured_lines(entry))
    table = ""
    if rows:
        counts = {}
        for c in rows:
            counts[c.verdict] = counts.get(c.verdict, 0) + 1
        table = ("<p><a href='#verdicts'>Verdicts</a>: "
                 + ", ".join(f"{n} {v}" for v, n in counts.items()) + ".</p>")
    table += "".join(f"<p>{html.escape(title)}</p>{table_html(df)}"
                     for title, df in figure_tables(entry))
    # the verdict table links #<figure name>: the first image of a figure carries it
    anchor = f" id='{entry.name}'" if entry.name != entry.stem and rows else ""
    return (f"<figure id='{entry.stem}'><img alt='{entry.stem}' "
            f"src='data:image/png;base64,{img}'><figcaption{anchor}>"
            f"{link_docs(caption(entry.name, paper, entry.notes), docs)}{lines}</figcaption>"
            f"{table}</figure>")


_EMBEDDED = re.compile(r"<figure id='(?P<stem>[^']+)'><img alt='(?P=stem)' "
                       r"src='data:image/png;base64,[A-Za-z0-9+/=]*'>")


def link_images(page: str, href: Callable[[str], str]) -> str:
    """The report with each embedded figure image replaced by a link ``href(stem)``.

    The standalone report embeds its PNGs; a folder that keeps the PNGs beside the report
    (the committed gallery) links them instead, so the page stays small.
    """
    return _EMBEDDED.sub(lambda m: f"<figure id='{m['stem']}'><img alt='{m['stem']}' "
                                   f"src='{html.escape(href(m['stem']), quote=True)}'>", page)


def read_headlines(paths: Sequence[str | Path]) -> dict[str, dict]:
    """:func:`rocking.study.headline.summary` of each ``<study>/headline.csv`` by study (the
    folder's name); studies whose table is empty are left out."""
    import pandas as pd

    from rocking.study.headline import summary

    out = {}
    for p in paths:
        s = summary(pd.read_csv(p)) if Path(p).is_file() else None
        if s is not None:
            out[Path(p).parent.name] = s
    return out


def report_title(study: str, ensemble: str, reproduces: str | None = None) -> str:
    """The report's title: a reproduction names the paper in full (authors, title,
    journal, year: :data:`rocking.config.study.CITATIONS`), any study its name and ensemble."""
    from rocking.config.study import CITATIONS

    own = f"study {study} (ensemble {ensemble})"
    if reproduces is None:
        return f"rocking: {own}"
    return f"Reproduction of {CITATIONS.get(reproduces, reproduces)}: {own}"


def build(out: str | Path, *, title: str, figures: Sequence[str | Path],
          linear_fit: str | Path | None = None, fragility: str | Path | None = None,
          notes: Sequence[str] = (), run: Sequence[tuple[str, str]] = (),
          risk: str | Path | None = None, hazard: str = "",
          stripes: str | Path | None = None, paper: bool = True,
          records: str | Path | None = None, suite_fragility: str | Path | None = None,
          paper_record: bool = True,
          study: str = "", headline: Sequence[str | Path] = (),
          portfolio: str | Path | None = None, verdicts_csv: str | Path | None = None) -> Path:
    """Write the HTML report.

    A study that reproduces the paper (``paper``) gets the paper's statements set against
    its numbers (the verdict table, a verdict line per figure) and the paper's captions; a
    study of one's own gets what was computed only: figures with what they show and
    measure, and the tables.

    Parameters
    ----------
    out : path
        The HTML file to write.
    title : str
        Page title (study name and configuration).
    figures : sequence of path
        Figure PNGs (each with an optional ``.json`` sidecar beside it); a figure whose entry
        names a report section (the stripe, risk and portfolio figures) is shown in that
        section, under its tables.
    linear_fit, fragility : path, optional
        CSV tables of :mod:`rocking.fragility.lognormal`.
    notes : sequence of str
        Extra paragraphs (e.g. stand-in records of this run).
    run : sequence of (str, str)
        Rows of the "what was run" section (:func:`.run_summary.what_was_run`).
    risk : path, optional
        ``results/<study>/risk.csv`` (:mod:`rocking.risk`): adds the risk section.
    hazard : str
        Where the study's hazard curve came from (quoted in the risk section).
    stripes : path, optional
        ``results/<study>/stripe_fragility.csv``: adds the section that sets the
        multiple-stripe fragility beside the critical-intensity one
        (:func:`.tables.stripes_section`).
    paper : bool
        The study reproduces the paper (``studies.<name>.reproduces``): verdicts shown.
    records, suite_fragility : path, optional
        ``records.csv`` (the per-record answers) and ``suite_fragility.csv`` (the fragility
        over the suite in each intensity measure) of :mod:`rocking.study.records`.
    paper_record : bool
        The study's ensemble is built on the record of the paper's Figs 6–11 (El Centro):
        verdicts the paper states for that record only are judged here; another
        reproduction study (Loma Prieta) gets the verdicts that concern it (Figs 8, 10's
        linearity and 12), and the El Centro-only rows stay in the El Centro report.
    study : str
        The study's name (its curves of Fig 12 come first in the findings).
    headline : sequence of path
        ``<study>/headline.csv`` of the studies whose headline the findings quote
        (:mod:`rocking.study.headline`): the mean first exceedance of the headline cells on
        each scan grid, said beside the mean of the study's answers.
    portfolio : path, optional
        ``portfolio.csv`` (:mod:`rocking.risk.portfolio`): adds the section on every
        column of the inventory.
    verdicts_csv : path, optional
        Also write the verdict table as data there (``verdicts.csv``,
        :func:`.entries.write_verdicts`; no rows unless ``paper``).

    Returns
    -------
    Path
        ``out``.
    """
    entries = load_figures(figures)
    sections = {s: [e for e in entries if figure(e.name).section == s] for s in SECTIONS}
    verdicts = figure_comparisons(entries) if paper else {}
    if paper and not paper_record:
        verdicts = {k: [c for c in rows if not el_centro_only(c)] for k, rows in
                    verdicts.items()}
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}"
             f"</title><style>{_CSS}</style></head><body><h1>{html.escape(title)}</h1>"]
    found = (paper_findings(entries, verdicts, study, read_headlines(headline))
             if paper else []) + \
        study_findings(entries=entries, fragility=fragility, records=records, risk=risk,
                       stripes=stripes)
    parts.append("<h2 id='findings'>Findings</h2>")
    parts.append(findings_html(found))
    parts += [f"<p>{html.escape(n)}</p>" for n in notes]
    if paper and not paper_record:
        parts.append("<p>The paper's figures of the model (Figs 3, 4 and 6) and the statements "
                     "it makes of its El Centro study only are in the report of the study on "
                     "El Centro.</p>")
    parts.append("<h2 id='what-was-run'>What was run</h2>")
    run = [*run, *figure_run_rows(entries)]
    parts.append(table_html(pd.DataFrame(run, columns=["item", "value"])) if run
                 else "<p>Not recorded.</p>")
    docs = docs_href(Path(out).parent)
    table = [c for rows in verdicts.values() for c in rows]
    if paper:
        parts.append("<h2 id='verdicts'>The paper against this run, figure by figure</h2>")
        parts.append(_verdict_html(table, True, docs))
    parts.append("<h2>Figures</h2>")
    shown = sections[""]
    parts += [_figure_html(e, verdicts.get(e.name, []) if i == _first(shown, e) else [], docs,
                           paper)
              for i, e in enumerate(shown)]
    fits = linear_fit_rows(linear_fit) if linear_fit is not None else pd.DataFrame()
    if not fits.empty:
        parts.append("<h2>Linear fits of the mean spectra (PGA/(g tan α) = slope·R + intercept)"
                     "</h2>")
        parts.append(table_html(fits))
    if fragility is not None:
        parts.append("<h2 id='fragility'>Lognormal fragility parameters: median PGA/(g tan α) "
                     "(× tan α for g) and, in brackets, dispersion β; \"k&gt;\" = k motions "
                     "right-censored at the search bound; points without a fit left out</h2>")
        parts.append(table_html(fragility_pivot(fragility)))
    if records is not None:
        parts += records_section(records, suite_fragility)
    if stripes is not None:
        parts += stripes_section(stripes)
        parts += [_section_figure_html(e, paper) for e in sections["stripes"]]
    if risk is not None:
        parts.append(risk_section_html(risk, hazard=hazard))
        parts += [_section_figure_html(e, paper) for e in sections["risk"]]
    if portfolio is not None:
        from rocking.report.tables import section_html as portfolio_section

        parts += portfolio_section(portfolio)
        parts += [_section_figure_html(e, paper) for e in sections["portfolio"]]
    parts.append("</body></html>")
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(parts), encoding="utf-8")
    if verdicts_csv is not None:
        write_verdicts(table, verdicts_csv)
    return out




def el_centro_only(row: Comparison) -> bool:
    """Whether a verdict row states what the paper reports for El Centro only: every row of
    a figure whose entry says so (``el_centro_only``: the paper's model figures and Figs 7,
    9–11) but those its entry calls ``general`` (Fig 10's linearity in R, which the paper
    states of rocking spectra in general, §6, judged by one criterion in every study)."""
    entry = figure(row.figure)
    if not entry.el_centro_only:
        return False
    return entry.general is None or not entry.general(row.statement)


def _section_figure_html(entry: FigureEntry, paper: bool) -> str:
    """A figure shown in a section of its own (the stripe, risk and portfolio figures):
    embedded with its entry's caption (the same markup as the other figures, so a gallery
    links it instead)."""
    img = base64.b64encode(entry.png.read_bytes()).decode("ascii")
    text = caption(entry.name, paper, entry.notes)
    return (f"<figure id='{entry.stem}'><img alt='{entry.stem}' "
            f"src='data:image/png;base64,{img}'><figcaption>{html.escape(text)}</figcaption>"
            "</figure>")


def _first(entries: Sequence[FigureEntry], entry: FigureEntry) -> int:
    """Index of the first entry of ``entry``'s figure (its verdict table is shown once)."""
    return next(i for i, e in enumerate(entries) if e.name == entry.name)
