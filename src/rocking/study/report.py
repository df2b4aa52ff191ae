"""A self-contained HTML report: what was run, every figure with its caption, and for every
figure the paper's statements set against this run's numbers with a verdict.

Inputs are the figure PNGs with their JSON sidecars (written by :func:`.figures.render`), the
linear fits of the mean spectra, the fragility table and, for the "what was run" section, the
configuration and the stores and summaries the run wrote. Images are embedded (base64), so
the page can be moved or mailed alone. Captions come from :mod:`.figures.captions`, verdicts
from :mod:`.figures.comparisons`.
"""

from __future__ import annotations

import base64
import html
import json
import math
import os
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..risk.report import risk_section_html
from ..spectra.limit_states import limit_state_title, severity
from ..spectra.modes import MODE_3D, PLANAR_MODES
from ..units import read_table
from .figures import FIGURES, _load, figure_name, module
from .figures._style import MODE_STYLE
from .figures.captions import EXTRA_CAPTIONS, caption
from .figures.comparisons import Comparison, compare, finite, fmt
from .product_specs import SpectraSpec, TiltMapSpec
from .store_attrs import decode_attrs

SHOWN = 10
"""Grids with at most this many values are listed in full, longer ones as a range."""
MODE_LABEL = {m: s["label"] for m, s in MODE_STYLE.items()}
"""Reader's name of each analysis mode ("3D", "2D, x component")."""


@dataclass(frozen=True)
class FigureEntry:
    """One figure of the report: its name, image and sidecar notes."""

    name: str
    png: Path
    notes: dict

    @property
    def stem(self) -> str:
        """File stem (``fig08_motions_elcentro``): the key of its notes."""
        return self.png.stem


def load_figures(pngs: Sequence[str | Path]) -> list[FigureEntry]:
    """Figures in paper order, each with its JSON notes (empty when there is no sidecar)."""
    out = []
    for png in pngs:
        png = Path(png)
        name = figure_name(png)
        if not png.exists():
            raise ValueError(f"figure file does not exist: {str(png)!r}")
        sidecar = png.with_suffix(".json")
        notes = json.loads(sidecar.read_text()) if sidecar.exists() else {}
        # the notes are strict JSON: a NaN measurement was written as null
        measured = notes.get("measured")
        if isinstance(measured, dict):
            notes["measured"] = {k: math.nan if v is None else v for k, v in measured.items()}
        out.append(FigureEntry(name, png, notes))
    return sorted(out, key=lambda f: (FIGURES.index(f.name), str(f.png)))


def figure_comparisons(entries: Sequence[FigureEntry]) -> dict[str, list[Comparison]]:
    """The comparisons of every figure in ``entries``, keyed by figure name."""
    notes = {e.stem: e.notes for e in entries}  # fig08 has one stem per ensemble
    names = list(dict.fromkeys(e.name for e in entries))
    out: dict[str, list[Comparison]] = {n: [] for n in names}
    for c in compare(notes, names):
        out[c.figure].append(c)
    return out


def figure_tables(entry: FigureEntry) -> list[tuple[str, pd.DataFrame]]:
    """The extra tables a figure shows under itself in the report: its module's
    ``report_tables(notes)`` (the common hook; a figure without one has none)."""
    hook = getattr(module(entry.name), "report_tables", None)
    return [] if hook is None else [(title, df) for title, df in hook(entry.notes)
                                    if not df.empty]


def figure_run_rows(entries: Sequence[FigureEntry]) -> list[tuple[str, str]]:
    """Rows a figure adds to the "what was run" section: its module's ``run_rows(notes)``
    (the common hook; e.g. the unprocessed record's PGA measured for the Fig 6 companion)."""
    rows = []
    for entry in entries:
        hook = getattr(module(entry.name), "run_rows", None)
        rows += [] if hook is None else list(hook(entry.notes))
    return rows


def comparison_table(rows: Sequence[Comparison], *, with_figure: bool = True) -> pd.DataFrame:
    """Rows as a table: (figure,) statement, paper, this run, verdict."""
    data = [((c.figure,) if with_figure else ()) + (c.statement, c.paper, c.ours,
                                                   c.verdict_text) for c in rows]
    columns = (["figure"] if with_figure else []) + ["statement", "paper", "this run", "verdict"]
    return pd.DataFrame(data, columns=columns)


def measured_lines(entry: FigureEntry) -> list[str]:
    """What a figure's notes say beyond the comparisons: directions of x/y, missing parts."""
    lines = []
    axes = entry.notes.get("axes")
    if isinstance(axes, dict) and "text" in axes:
        lines.append(f"Axes: {axes['text']}.")
    missing = entry.notes.get("missing", [])
    if missing:
        lines.append("Not computed in this run: " + "; ".join(missing) + ".")
    return lines


# --------------------------------------------------------------------------- what was run


def grid_text(values: Sequence[float], unit: str = "") -> str:
    """``"0.5, 1, 2 m"`` for short grids, ``"20 values, 0.5–10 m (step 0.5)"`` for long."""
    v = [float(x) for x in values]
    if not v:
        return "none"
    u = f" {unit}" if unit else ""
    if len(v) <= SHOWN:
        return ", ".join(f"{x:g}" for x in v) + u
    steps = np.diff(v)
    step = f" (step {steps[0]:g})" if np.allclose(steps, steps[0], rtol=1e-6) else ""
    return f"{len(v)} values, {min(v):g}–{max(v):g}{u}{step}"


def _motions_text(motions: Sequence[Mapping], spec: SpectraSpec) -> str:
    """"<record> and n synthetic pairs (seed s)", or for a suite "k records and n pairs"."""
    records = [m for m in motions if _is_recorded(m)]
    n_pairs = len(motions) - max(len(records), 1)
    pairs = (f" and {n_pairs} synthetic pairs (seed {spec.ensemble.seed})" if n_pairs
             else ", no synthetic pairs")
    if len(records) > 1:
        return f"a suite of {len(records)} records{pairs}"
    return f"{motions[0]['label']}{pairs}"


def study_rows(path: str | Path) -> list[tuple[str, str]]:
    """What a spectra store says was run: ensemble, grids, limit states, modes per tan α,
    accuracy, contact parameters, version (its ``config`` read as a
    :class:`~rocking.study.product_specs.SpectraSpec`)."""
    ds = _load.open_store(path)
    attrs = decode_attrs(ds.attrs)
    spec = SpectraSpec.from_attrs(attrs["config"])
    motions = attrs["ensemble"]["motions"]
    p = f"study {spec.study}"
    rows = [
        (f"{p}: motions", f"ensemble {spec.ensemble.name}: {_motions_text(motions, spec)}; "
                          + ", ".join(m["name"] for m in motions)),
        (f"{p}: sizes R", grid_text(spec.R, "m")),
        (f"{p}: slenderness tan α", grid_text(spec.plan.tan_alpha)),
        (f"{p}: limit states", ", ".join(limit_state_title(ls)
                                         for ls in spec.plan.limit_states)),
        (f"{p}: modes per tan α", modes_text(ds)),
        (f"{p}: accuracy", f"preset {spec.accuracy if isinstance(spec.accuracy, str) else 'custom'}"
                           f": {tolerances_text(attrs['tolerances'])}; search up to "
                           f"PGA/(g tan α) = {fmt(spec.upper)}"),
    ]
    if spec.damping is not None:
        rows.append((f"{p}: damped contact (3d-damped)",
                     f"ωn = {fmt(spec.damping.omega_n)} rad/s, ζ = {fmt(spec.damping.zeta)} "
                     "(Fig 4 also overlays the paper's eight pairs ωn ∈ {200, 2000} rad/s × "
                     "ζ ∈ {0.05, 0.5, 5, 50})"))
    if "unresolved" in ds:
        rows.append((f"{p}: resolution of the answers", resolution_text(ds)))
    rows.append((f"{p}: package version", f"rocking {attrs['rocking_version']}"))
    return rows


def tolerances_text(t: Mapping) -> str:
    """The accuracy settings of a store (:class:`rocking.spectra.accuracy.Accuracy` as
    attributes) in words: integration tolerance, scan step, bisection."""
    parts = []
    if "rtol" in t:
        parts.append(f"time integration to a relative tolerance of {t['rtol']:g}"
                     + (f" ({t['rtol_damped']:g} for the damped model)"
                        if t.get("rtol_damped") is not None else ""))
    step = t.get("scan_step")
    if step is not None:
        unit = f"{100 * step:g} %" if t.get("scan_relative", True) else f"{step:g}"
        scan = t.get("scan", "fixed")
        if scan == "fixed":
            parts.append(f"intensity scanned upwards in steps of {unit}")
        else:
            top = t.get("scan_step_max")
            hi = (f"{100 * top:g} %" if t.get("scan_relative", True) else f"{top:g}") if top \
                else unit
            parts.append(f"intensity scanned upwards in {scan} steps of {unit} to {hi}")
    if t.get("bisection_tol") is not None:
        parts.append(f"each first exceedance refined by bisection to "
                     f"{100 * t['bisection_tol']:g} %")
    if t.get("rest_tilt") is not None:
        parts.append(f"an analysis ends early once the body is at rest (tilt below "
                     f"{t['rest_tilt']:g} rad)")
    known = {"name", "rtol", "rtol_damped", "scan_step", "scan_relative", "scan",
             "scan_step_max", "bisection_tol", "rest_tilt", "tilt_growth", "seek_near"}
    parts += [f"{k} = {v}" for k, v in t.items() if k not in known and v is not None]
    return "; ".join(parts) or "not recorded"


def resolution_text(ds) -> str:
    """How many computed answers per mode carry the ``unresolved`` flag, and what it means."""
    reached = ~ds["not_reached"].values.astype(bool)
    if "requested" in ds:
        reached &= ds["requested"].broadcast_like(ds["not_reached"]).transpose(
            *ds["not_reached"].dims).values.astype(bool)
    flag = ds["unresolved"].values.astype(bool) & reached
    axis = ds["not_reached"].dims.index("mode")
    per = [f"{m}: {int(np.take(flag, i, axis).sum())} of {int(np.take(reached, i, axis).sum())}"
           for i, m in enumerate(_load.labels(ds, "mode"))]
    return ("answers flagged unresolved (the response came within half the goal, or θmax "
            "jumped, below the answer: narrower windows of exceedance may lie lower) — "
            + "; ".join(per) + ". On the resolution benchmark the 1 % scan's answer is "
            "0.9–1.6 % too high at the median and 14–15 % at the 90th percentile, never too "
            "low (docs/performance.md).")


def modes_text(ds) -> str:
    """``"tan α = 0.2: 3d, 3d-damped; tan α = 0.1: 3d"`` plus the share of cells not computed."""
    per = _load.modes_per_tan_alpha(ds)
    text = "; ".join(f"tan α = {t:g}: {', '.join(m) or 'none'}" for t, m in per.items())
    done = _load.computed(ds).values
    if not done.all():
        text += (f" ({int((~done).sum())} of {done.size} cells not computed: not requested "
                 "or not run, left empty)")
    return text


def tilt_map_rows(path: str | Path) -> list[tuple[str, str]]:
    """Grid and models of a Fig 7 tilt-map store (its ``config`` read as a
    :class:`~rocking.study.product_specs.TiltMapSpec`)."""
    ds = _load.open_store(path)
    attrs = decode_attrs(ds.attrs)
    spec = TiltMapSpec.from_attrs(attrs["config"])
    return [(f"study {spec.study}: Fig 7 tilt map",
             f"record {attrs['motion']}, tan α = {spec.tan_alpha:g}, models "
             f"{', '.join(spec.modes)}; R: {grid_text(spec.R, 'm')}; PGA/(g tan α): "
             f"{grid_text(spec.intensity)}")]


def _processing_text(e: Mapping) -> str:
    """How one record was processed and how many pairs were simulated from it."""
    hp = e.get("highpass") or {}
    stand_in = f" — stand-in for {e['stand_in_for']}" if e.get("stand_in") else ""
    if e.get("rotation_deg") is None:
        rotation = "recorded axes kept"
    else:
        rotation = (f"rotated by {fmt(e.get('rotation_deg'))}° to principal axes (x = major; "
                    f"offset {fmt(e.get('principal_offset_deg'))}° from the nearest recording "
                    "axis)")
    highpass = ("no high-pass" if not hp or hp.get("kind") in (None, "none") else
                f"high-pass {hp['kind']} at {fmt(hp.get('fc_hz'))} Hz (Mw {fmt(hp.get('mw'))})")
    pairs = (f"; {e['n_synthetic']} synthetic pairs, seed {e.get('seed', '?')}"
             if e.get("n_synthetic") else "")
    return f"{e.get('label', e.get('record'))}{stand_in}; {rotation}; {highpass}{pairs}"


def ensemble_rows(path: str | Path) -> list[tuple[str, str]]:
    """Processing of an ensemble's record and its synthetic pairs (``results/motions/*.json``);
    a suite: one row per record."""
    e = json.loads(Path(path).read_text())
    name = e.get("ensemble", Path(path).stem)
    if e.get("suite"):
        return [(f"ensemble {name}", str(e.get("label")))] + [
            (f"ensemble {name}: record {r.get('record')}", _processing_text(r))
            for r in e.get("records", [])]
    return [(f"ensemble {name}", _processing_text(e))]


def _is_recorded(m: Mapping) -> bool:
    """A motion of a store's ensemble that is a record (its own source), not a pair."""
    return m.get("name") is not None and m.get("name") == m.get("source_record")


def pga_row(store: str | Path) -> tuple[str, str]:
    """The record's PGA (a suite: every record's): one number each and what it is (a figure
    may add the unprocessed record's through its ``run_rows`` hook,
    :func:`figure_run_rows`)."""
    motions = decode_attrs(_load.open_store(store).attrs)["ensemble"]["motions"]
    if not motions:
        return ("record PGA", "not recorded in the store")
    from ..constants import G

    def pga_g(m: Mapping) -> float:
        # stores record the motion's identity "PGA" [g]; older ones its "pga" [m/s²]
        return m["PGA"] if "PGA" in m else m["pga"] / G

    records = [m for m in motions if _is_recorded(m)]
    if len(records) > 1:  # a suite
        values = ", ".join(f"{m['label']} {pga_g(m):.3f} g" for m in records)
        return ("records' PGA", f"{values}: vector peaks max √(ax² + ay²) after each record's "
                "processing, as every spectrum is scaled")
    first = motions[0]
    return ("record PGA", f"{pga_g(first):.3f} g: vector peak max √(ax² + ay²) of "
            f"{first['label']} after rotation to principal axes and high-pass, as every "
            "spectrum is scaled (a vector peak does not depend on the rotation)")


def timing_rows(done: Sequence[str | Path] = (), ensembles: Sequence[str | Path] = (),
                elapsed_seconds: float | None = None) -> list[tuple[str, str]]:
    """Wall times of the main jobs (from their completion summaries) and of the workflow."""
    rows = []
    for path in ensembles:
        t = json.loads(Path(path).read_text()).get("timings", {})
        if t:
            rows.append((f"run time: ensemble {Path(path).stem}",
                         ", ".join(f"{k.removesuffix('_s')} {v:.1f} s" for k, v in t.items())))
    for path in done:
        s = json.loads(Path(path).read_text())
        if "wall_seconds" in s:
            before = s.get("done_before", 0)
            if s.get("store_state") in ("created", "replaced"):
                # a new store marks the chunks that hold no requested cell done at once
                origin = f"new store; {before} chunks hold no requested cell" if before else \
                    "new store"
            else:
                origin = f"resumed: {before} chunks were already done"
            points = s.get("points_computed")
            what = f" ({points} spectrum points)" if points else ""
            rows.append((f"run time: {Path(path).parent.name}/{Path(path).name.split('.')[0]}",
                         f"{s['wall_seconds']:.0f} s wall for {s.get('computed', '?')} of "
                         f"{s.get('chunks', '?')} chunks{what} on {s.get('cluster', '?')} "
                         f"({origin})"))
    if elapsed_seconds is not None and math.isfinite(elapsed_seconds):
        rows.append(("run time: workflow", f"{elapsed_seconds / 60:.1f} min from the start of "
                                           "the Snakemake invocation that wrote this report "
                                           "(jobs done by earlier invocations not counted)"))
    return rows


def what_was_run(*, stores: Sequence[str | Path] = (), tilt_maps: Sequence[str | Path] = (),
                 ensembles: Sequence[str | Path] = (), done: Sequence[str | Path] = (),
                 elapsed_seconds: float | None = None) -> list[tuple[str, str]]:
    """Rows (item, value) of the report's "what was run" section.

    Parameters
    ----------
    stores : sequence of path
        Spectra stores of the studies (configuration, grids, modes per tan α, accuracy, contact
        parameters, version).
    tilt_maps : sequence of path
        Fig 7 tilt-map stores.
    ensembles : sequence of path
        ``results/motions/<ensemble>.json`` (rotation, high-pass, seeds, timings).
    done : sequence of path
        Completion summaries ``*.done.json`` (wall times).
    elapsed_seconds : float, optional
        Time from the start of the workflow to the report [s].
    """
    rows = []
    for path in ensembles:
        rows += ensemble_rows(path)
    if stores:
        rows.append(pga_row(stores[0]))
    for path in stores:
        rows += study_rows(path)
    for path in tilt_maps:
        rows += tilt_map_rows(path)
    return rows + timing_rows(done, ensembles, elapsed_seconds)


# --------------------------------------------------------------------------- HTML


_CSS = """
body{font-family:sans-serif;max-width:1150px;margin:2em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;font-size:0.85em;margin:1em 0}
td,th{border:1px solid #bbb;padding:4px 8px;vertical-align:top;text-align:left}
th{background:#eee} figure{margin:2em 0} img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:0.92em;margin-top:0.5em} .measured{color:#05509b}
td.reproduced{background:#e4f4e4} td.differs{background:#fbeede}
td.not-computed{background:#eeeeee} td.not-reproducible{background:#f8dddd}
"""


def _as_recorded_word(value) -> str:
    """records.csv's ``exceeds_as_recorded`` (one analysis at scale 1) in a table cell."""
    if pd.isna(value):
        return "analysis failed"
    return "yes" if str(value).lower() in ("true", "1") else "no"


def _as_recorded_finding(row) -> str:
    """What the analysis of the record at scale 1 says, and whether the scale factor agrees
    (rocking is not monotonic in the intensity: docs/records.md)."""
    word = _as_recorded_word(row.get("exceeds_as_recorded"))
    if word == "analysis failed":
        return "its analysis as recorded failed"
    said = "as recorded (scale 1) it exceeds" if word == "yes" else \
        "as recorded (scale 1) it does not"
    if str(row.get("as_recorded_disagrees", "")).lower() in ("true", "1"):
        said += " although the scale factor says otherwise: the response is not monotonic"
    return said


def _table_html(df: pd.DataFrame) -> str:
    return df.to_html(index=False, escape=True, border=0, na_rep="—",
                      float_format=lambda v: f"{v:.4g}")


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
    table += "".join(f"<p>{html.escape(title)}</p>{_table_html(df)}"
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


def build(out: str | Path, *, title: str, figures: Sequence[str | Path],
          linear_fit: str | Path | None = None, fragility: str | Path | None = None,
          notes: Sequence[str] = (), run: Sequence[tuple[str, str]] = (),
          risk: str | Path | None = None, hazard: str = "",
          stripes: str | Path | None = None, paper: bool = True,
          records: str | Path | None = None, suite_fragility: str | Path | None = None,
          stripe_figures: Sequence[str | Path] = (), paper_record: bool = True,
          study: str = "") -> Path:
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
        Figure PNGs (each with an optional ``.json`` sidecar beside it).
    linear_fit, fragility : path, optional
        CSV tables of :mod:`rocking.spectra.fragility`.
    notes : sequence of str
        Extra paragraphs (e.g. stand-in records of this run).
    run : sequence of (str, str)
        Rows of the "what was run" section (:func:`what_was_run`).
    risk : path, optional
        ``results/<study>/risk.csv`` (:mod:`rocking.risk`): adds the risk section, with the
        figure ``figures/risk.png`` beside it when it exists.
    hazard : str
        Where the study's hazard curve came from (quoted in the risk section).
    stripes : path, optional
        ``results/<study>/stripe_fragility.csv``: adds the section that sets the
        multiple-stripe fragility beside the first-exceedance one (:func:`stripes_section`).
    paper : bool
        The study reproduces the paper (``studies.<name>.reproduces``): verdicts shown.
    records, suite_fragility : path, optional
        ``records.csv`` (the per-record answers) and ``suite_fragility.csv`` (the fragility
        over the suite in each intensity measure) of :mod:`rocking.study.records`.
    stripe_figures : sequence of path
        The stripe-fragility figures (PNG, a JSON sidecar with their ``caption`` beside),
        shown in the stripes section.
    paper_record : bool
        The study's ensemble is built on the record of the paper's Figs 6–11 (El Centro):
        verdicts the paper states for that record only are judged here; another
        reproduction study (Loma Prieta) gets the verdicts that concern it (Figs 8, 10's
        linearity and 12), and the El Centro-only rows stay in the El Centro report.
    study : str
        The study's name (its curves of Fig 12 come first in the findings).

    Returns
    -------
    Path
        ``out``.
    """
    entries = load_figures(figures)
    verdicts = figure_comparisons(entries) if paper else {}
    if paper and not paper_record:
        verdicts = {k: [c for c in rows if not el_centro_only(c)] for k, rows in
                    verdicts.items()}
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}"
             f"</title><style>{_CSS}</style></head><body><h1>{html.escape(title)}</h1>"]
    found = (paper_findings(entries, verdicts, study) if paper else []) + study_findings(
        entries=entries, fragility=fragility, records=records, risk=risk, stripes=stripes)
    parts.append("<h2 id='findings'>Findings</h2>")
    parts.append(findings_html(found))
    parts += [f"<p>{html.escape(n)}</p>" for n in notes]
    if paper and not paper_record:
        parts.append("<p>The paper's figures of the model (Figs 3, 4 and 6) and the statements "
                     "it makes of its El Centro study only are in the report of the study on "
                     "El Centro.</p>")
    parts.append("<h2 id='what-was-run'>What was run</h2>")
    run = [*run, *figure_run_rows(entries)]
    parts.append(_table_html(pd.DataFrame(run, columns=["item", "value"])) if run
                 else "<p>Not recorded.</p>")
    docs = docs_href(Path(out).parent)
    if paper:
        parts.append("<h2 id='verdicts'>The paper against this run, figure by figure</h2>")
        parts.append(_verdict_html([c for rows in verdicts.values() for c in rows], True, docs))
    parts.append("<h2>Figures</h2>")
    parts += [_figure_html(e, verdicts.get(e.name, []) if i == _first(entries, e) else [], docs,
                           paper)
              for i, e in enumerate(entries)]
    fits = linear_fit_rows(linear_fit) if linear_fit is not None else pd.DataFrame()
    if not fits.empty:
        parts.append("<h2>Linear fits of the mean spectra (PGA/(g tan α) = slope·R + intercept)"
                     "</h2>")
        parts.append(_table_html(fits))
    if fragility is not None:
        parts.append("<h2 id='fragility'>Lognormal fragility parameters: median PGA/(g tan α) "
                     "(× tan α for g) and, in brackets, dispersion β; \"k&gt;\" = k motions "
                     "right-censored at the search bound; points without a fit left out</h2>")
        parts.append(_table_html(fragility_pivot(fragility)))
    if records is not None:
        parts += records_section(records, suite_fragility)
    if stripes is not None:
        parts += stripes_section(stripes)
        parts += [_extra_figure_html(p) for p in stripe_figures]
    if risk is not None:
        from .figures.risk import CAPTION as RISK_CAPTION

        parts.append(risk_section_html(risk, hazard=hazard))
        parts.append(_extra_figure_html(Path(risk).parent / "figures" / "risk.png",
                                        RISK_CAPTION))
    parts.append("</body></html>")
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(parts), encoding="utf-8")
    return out


EL_CENTRO_FIGURES = ("fig03_wobbling_period", "fig04_free_vibration", "fig06_el_centro",
                     "fig06_theta_max_sensitivity", "fig07_tilt_map", "fig09_spectra",
                     "fig10_goals", "fig11_slenderness")
"""Figures the paper draws for its El Centro study only (its model figures and Figs 7, 9–11)."""


def el_centro_only(row: Comparison) -> bool:
    """Whether a verdict row states what the paper reports for El Centro only: every row of
    :data:`EL_CENTRO_FIGURES` but Fig 10's linearity in R, which the paper states of rocking
    spectra in general (§6) and which is judged by one criterion in every study."""
    from .figures.fig10_goals import LINEAR_STATEMENT

    if row.figure == "fig10_goals":
        return not row.statement.startswith(LINEAR_STATEMENT)
    return row.figure in EL_CENTRO_FIGURES


def _extra_figure_html(png: str | Path, text: str | None = None) -> str:
    """A figure beyond :data:`.figures.FIGURES` (the stripe and the risk figures): embedded
    with ``text`` as caption, else the ``caption`` of its JSON sidecar, else its module's
    ``CAPTION`` (the same markup as the other figures, so a gallery links it instead)."""
    png = Path(png)
    if not png.exists():
        return ""
    if text is None:
        sidecar = png.with_suffix(".json")
        notes = json.loads(sidecar.read_text()) if sidecar.exists() else {}
        text = notes.get("caption") or ""
        if not text:
            kind = str(notes.get("figure") or re.sub(r"_(3d|2d).*$", "", png.stem))
            try:
                text = getattr(module(kind), "CAPTION", "")
            except ValueError:  # not a module of .figures: the report's own caption
                text = ""
            text = text or EXTRA_CAPTIONS.get(kind, "")
    img = base64.b64encode(png.read_bytes()).decode("ascii")
    return (f"<figure id='{png.stem}'><img alt='{png.stem}' src='data:image/png;base64,{img}'>"
            f"<figcaption>{html.escape(text)}</figcaption></figure>")


def records_section(records: str | Path, suite_fragility: str | Path | None = None
                    ) -> list[str]:
    """HTML of the per-record answers (``records.csv``) at the study's main mode and
    slenderness, largest and smallest R, and of the fragility over the suite in each
    intensity measure (``suite_fragility.csv``; fits only)."""
    df = pd.read_csv(records)
    parts = ["<h2 id='records'>The recorded motions one by one</h2>"]
    if df.empty:
        return parts + ["<p>No recorded motion in this study.</p>"]
    ta = next(c for c in df.columns if c.startswith("tan_alpha"))
    r = next(c for c in df.columns if c.startswith("R"))
    sf = next(c for c in df.columns if c.startswith("scale_factor"))
    crit = next(c for c in df.columns if c.startswith("pga_crit_g"))
    rec = next(c for c in df.columns if c.startswith("pga_g"))
    sizes = sorted(set(df[r]))
    keep = df[df[r].isin({sizes[0], sizes[len(sizes) // 2], sizes[-1]})]
    table = pd.DataFrame({
        "record": keep["motion"], "mode": keep["mode"].map(lambda m: MODE_LABEL.get(m, m)),
        "tan α": keep[ta], "limit state": keep["limit_state"].map(limit_state_title),
        "R [m]": keep[r], "PGA processed [g]": keep[rec], "critical PGA [g]": keep[crit],
        "scale factor to exceed": keep[sf],
        "exceeds as recorded": keep["exceeds_as_recorded"].map(_as_recorded_word),
    })
    parts.append(f"<p>Per record: the factor its processed version must be scaled by to "
                 f"exceed each limit state, at R = {sizes[0]:g}, {sizes[len(sizes) // 2]:g} "
                 f"and {sizes[-1]:g} m (every size, Sa(T) and PGV: records.csv).</p>")
    parts.append(_table_html(table))
    if suite_fragility is not None and Path(suite_fragility).exists():
        fr = pd.read_csv(suite_fragility)
        fr = fr[np.isfinite(pd.to_numeric(fr["median"], errors="coerce"))]
        if fr.empty:
            parts.append("<p>Fragility over the suite: no fit (too few records reached the "
                         "limit states).</p>")
        else:
            out = pd.DataFrame({
                "motions": fr["motions"], "mode": fr["mode"].map(lambda m: MODE_LABEL.get(m, m)),
                "tan α": fr["tan_alpha"], "limit state": fr["limit_state"].map(
                    limit_state_title), "R [m]": fr["R"],
                "measure": fr["measure"] + " [" + fr["unit"].astype(str) + "]",
                "median IM₅₀": fr["median"], "β": fr["beta"], "n": fr["n"],
                "censored": fr["n_censored"]})
            parts.append("<p id='suite-fragility'>Lognormal fragility over the suite in each "
                         "intensity measure (median IM₅₀ in the measure's unit; recorded "
                         "motions and synthetic pairs fitted separately).</p>")
            parts.append(_table_html(out))
    return parts


def stripes_section(path: str | Path) -> list[str]:
    """HTML of the report's stripe-fragility section: what each answer means, then one row
    per (mode, limit state, tan α, R) with both medians and their ratio."""
    df = read_table(path)
    ok = df[np.isfinite(df["ratio"].to_numpy(dtype=float))]
    parts = ["<h2 id='stripes'>Two answers to \"how strong must the earthquake be\": first "
             "exceedance and multiple-stripe fragility</h2>",
             "<p>The answer of the spectra and of the fragility curves above (and the "
             "paper's) is the <em>first exceedance</em>: per "
             "motion, the smallest PGA/(g tan α) found to exceed the limit state, then the "
             "lognormal fit over motions. Rocking near a limit state is chaotic in the "
             "intensity: a motion exceeds it in narrow windows and the body survives stronger "
             "scalings of the same motion, so the first exceedance is where exceedance "
             "<em>starts</em>, not where it becomes likely. The <em>multiple-stripe</em> "
             "fragility analyses every motion once at each of a fixed set of intensities and "
             "fits the share exceeding by binomial maximum likelihood: its median is the "
             "intensity at which half the motions exceed (95 % interval in brackets). It "
             "converges as stripes are added; the first exceedance depends on where a scan "
             "falls among the windows (docs/performance.md).</p>"]
    measure = str(df["measure"].iloc[0]) if "measure" in df and len(df) else "pga"
    name = "PGA" if measure == "pga" else measure
    if ok.empty:
        parts.append("<p>No (mode, limit state, R) has both fits in this run"
                     + ("" if measure == "pga" else f" (the stripes are in {name}, the first "
                        "exceedance in PGA)") + ".</p>")
        if measure == "pga" or df.empty:
            return parts
    else:
        ratio = ok["ratio"].to_numpy(dtype=float)
        parts.append(f"<p>Over the {len(ok)} cells with both fits, the stripe median is "
                     f"{np.min(ratio):.2f}–{np.max(ratio):.2f} times the first-exceedance "
                     f"median (median ratio {np.median(ratio):.2f}): a column designed with "
                     "the first exceedance is designed for the onset of exceedance, with the "
                     "stripe median as its 50 % point.</p>")
    nan = pd.Series(np.nan, index=df.index)
    rows = pd.DataFrame({
        "mode": df["mode"], "limit state": df["limit_state"].map(limit_state_title),
        "tan α": df["tan_alpha"], "R [m]": df["R"],
        f"stripe median [{name}/(g tan α)]": [
            f"{m:.3g} ({lo:.3g}–{hi:.3g})" if np.isfinite(m) else f"— ({st})"
            for m, lo, hi, st in zip(df["median"], df["median_lo"], df["median_hi"],
                                     df["status"], strict=True)],
        # in the measure's unit: the bootstrap's 90 % interval, or where no lognormal fits
        # the stripes that bracket the median (never a number for a missing fit)
        f"stripe median [{name}, g], 90 % over motions": [
            f"{m:.3g} ({a:.3g}–{b:.3g})" if np.isfinite(m) and np.isfinite(a)
            else f"{m:.3g}" if np.isfinite(m)
            else f"between {lo:.3g} and {hi:.3g}" if np.isfinite(lo) else "—"
            for m, a, b, lo, hi in zip(df.get("median_im", nan), df.get("median_p05", nan),
                                       df.get("median_p95", nan), df.get("bracket_lo", nan),
                                       df.get("bracket_hi", nan), strict=True)],
        "stripe β": df["beta"].map(lambda b: f"{b:.2f}" if np.isfinite(b) else "—"),
        "first-exceedance median": df["first_median"].map(
            lambda m: f"{m:.3g}" if np.isfinite(m) else "—"),
        "ratio": df["ratio"].map(lambda r: f"{r:.2f}" if np.isfinite(r) else "—"),
        "motions × stripes": [f"{n} × {k}" + (f" + {int(a)} added" if a > 0 else "")
                              for n, k, a in zip(df["n_motions"], df["stripes"],
                                                 df.get("n_refined", nan).fillna(0),
                                                 strict=True)],
    })
    parts.append(_table_html(rows))
    return parts


def fragility_pivot(path: str | Path) -> pd.DataFrame:
    """The fragility table as one row per (mode, limit state, tan α) and one column per R.

    Each cell is ``"median (β)"`` with the median in PGA/(g tan α) (× tan α for g) and, when
    motions were right-censored at the search bound, ``"+k>"`` for the k of them. Points not
    computed (no fit) are left out: a reader wants the fits, not the empty grid.
    """
    df = pd.read_csv(path)
    med = next(c for c in df.columns if c.startswith("median [") or c == "median")
    ta = next(c for c in df.columns if c.startswith("tan_alpha"))
    r = next(c for c in df.columns if c.startswith("R"))
    df = df[np.isfinite(pd.to_numeric(df[med], errors="coerce"))]
    if df.empty:
        return pd.DataFrame()
    beta = next(c for c in df.columns if c.startswith("beta"))
    cens = "n_censored" if "n_censored" in df.columns else None

    def cell(row) -> str:
        text = f"{row[med]:.3g} ({row[beta]:.2f})"
        if cens and row[cens] > 0:
            text += f" {int(row[cens])}>"
        return text

    df = df.assign(cell=df.apply(cell, axis=1))
    out = df.pivot_table(index=["mode", "limit_state", ta], columns=r, values="cell",
                         aggfunc="first", sort=False)
    out.columns = [f"R = {c:g}" for c in out.columns]
    out = out.reset_index().rename(columns={"limit_state": "limit state", ta: "tan α"})
    return out.assign(**{"limit state": out["limit state"].map(limit_state_title)})


def linear_fit_rows(path: str | Path) -> pd.DataFrame:
    """Linear fits of the mean spectra over enough sizes to mean something (at least
    :data:`.figures.fig10_goals.MIN_FIT_SIZES`; rows without a fit dropped), limit states
    in words."""
    from .figures.fig10_goals import MIN_FIT_SIZES

    df = pd.read_csv(path)
    n = next((c for c in df.columns if c == "n"), None)
    df = df[df[n] >= MIN_FIT_SIZES] if n is not None else df
    if "limit_state" in df:
        df = df.assign(limit_state=df["limit_state"].map(limit_state_title))
    return df


def _first(entries: Sequence[FigureEntry], entry: FigureEntry) -> int:
    """Index of the first entry of ``entry``'s figure (its verdict table is shown once)."""
    return next(i for i, e in enumerate(entries) if e.name == entry.name)


# --------------------------------------------------------------------------- findings


@dataclass(frozen=True)
class Finding:
    """One line of the report's findings summary: its text (with its number) and the
    anchor in the page of the figure or table it comes from."""

    text: str
    anchor: str


def _stem(entries: Sequence[FigureEntry], name: str) -> str | None:
    """Anchor (file stem) of the first figure of kind ``name`` in ``entries``."""
    return next((e.stem for e in entries if e.name == name), None)


def _notes(entries: Sequence[FigureEntry], name: str) -> Mapping:
    return next((e.notes for e in entries if e.name == name), {}).get("measured", {}) or {}


def _ensemble_title(m: Mapping, ens: str) -> str:
    """``"El Centro (elcentro)"``: an ensemble of Fig 12's notes by its record's label."""
    return re.sub(r": mean of \d+ motions?$", "", str(m.get(f"{ens}|label", ens)))


def paper_findings(entries: Sequence[FigureEntry],
                   verdicts: Mapping[str, Sequence[Comparison]], study: str = ""
                   ) -> list[Finding]:
    """Headline answers of a reproduction of the paper, read from the figures' notes:
    2D against 3D and the 3D mean at R = 10 m (Fig 12: every study it draws, ``study``'s
    first), damped against undamped (Fig 9), linearity in R
    (Fig 10), the El Centro peak tilts (Fig 6)."""
    out = []
    m12, a12 = _notes(entries, "fig12_2d_vs_3d"), _stem(entries, "fig12_2d_vs_3d")
    if a12 is not None:
        R = m12.get("R", 10.0)
        names = sorted({k.split("|")[0] for k in m12 if k.count("|") >= 2})
        names = sorted(names, key=lambda n: n != study)  # the study's own curves first
        for ens in names:
            v3 = m12.get(f"{ens}|overturning|3d")
            if not finite(v3):
                continue
            std, n = m12.get(f"{ens}|overturning|3d|std"), m12.get(f"{ens}|overturning|3d|count")
            se = f" ± {std / math.sqrt(n):.2f} (standard error, {n:g} motions)" if finite(
                std, n) and n > 0 else ""
            ratios = []
            for ls in ("overturning", "tilt:1/3"):
                key = "excessive tilt" if ls != "overturning" else ls
                base = m12.get(f"{ens}|{key}|3d")
                parts = [f"{c[-1]} {m12[f'{ens}|{key}|{c}'] / base:.2f}×" for c in
                         PLANAR_MODES if finite(m12.get(f"{ens}|{key}|{c}"), base)]
                if parts:
                    ratios.append(f"{key} " + ", ".join(parts))
            who = _ensemble_title(m12, ens)
            # the paper gives the 3D number for El Centro only
            paper4 = " (paper: about 4)" if "centro" in (ens + who).lower() else ""
            out.append(Finding(
                f"{who}, R = {R:g} m: the 3D model overturns at a mean PGA/(g tan α) of "
                f"{v3:.2f}{se}{paper4}; the 2D model under one "
                f"component needs {'; '.join(ratios)} the 3D mean (x = major, y = minor axis; "
                "paper: about twice)", a12))
    m9, a9 = _notes(entries, "fig09_spectra"), _stem(entries, "fig09_spectra")
    for key, eff in m9.items():
        if not key.startswith("damping|") or not isinstance(eff, Mapping):
            continue
        worst, k, R = eff.get("max_abs_rel_diff_means"), eff.get("R_index_of_max"), m9.get("R")
        row = next((c for c in verdicts.get("fig09_spectra", [])
                    if limit_state_title(key.removeprefix("damping|")) in c.statement), None)
        if finite(worst):
            at = f" (at R = {R[k]:g} m)" if R and k is not None else ""
            out.append(Finding(
                f"Damped against undamped, {limit_state_title(key.removeprefix('damping|'))}: "
                f"the ensemble means differ by at most {100 * worst:.1f} %{at}"
                + (f" — {row.verdict}" if row else "")
                + " (paper: essentially identical)", a9))
    from .figures.fig10_goals import LINEAR_STATEMENT, LINEARITY_TOLERANCE

    rows10 = [c for c in verdicts.get("fig10_goals", [])
              if c.statement.startswith(LINEAR_STATEMENT)]
    rows10 = [c for c in rows10 if c.verdict in ("reproduced", "differs")]
    if rows10:
        ok = sum(c.verdict == "reproduced" for c in rows10)
        r2 = [float(x) for c in rows10 for x in re.findall(r"R² = ([0-9.]+)", c.ours)]
        span = f"; R² {min(r2):.3f}–{max(r2):.3f}" if r2 else ""
        out.append(Finding(
            f"Linearity in R (paper: 'almost straight lines'): {ok} of {len(rows10)} mean "
            f"spectra pass the one criterion of every study ({LINEARITY_TOLERANCE}"
            f"){span}" + ("" if ok == len(rows10) else "; those that fail bend: flat near the "
                          "uplift intensity at small R, then rising"),
            _stem(entries, "fig10_goals") or ""))
    m6 = _notes(entries, "fig06_el_centro")
    u, d = m6.get("theta_max_3d"), m6.get("theta_max_3d-damped")
    if finite(u, d):
        out.append(Finding(
            f"El Centro, R = 6 m, tan α = 0.2 (Fig 6): peak tilt θmax {u:.4f} rad undamped and "
            f"{d:.4f} rad damped (paper: 0.0838 and 0.0668 rad); the companion figure shows "
            "θmax scattering by a factor of two within ±5 % of the scale", _stem(
                entries, "fig06_el_centro") or ""))
    return out




def _main(df: pd.DataFrame, col: str, prefer: Sequence) -> object | None:
    """The first of ``prefer`` present in column ``col``, else its most frequent value."""
    values = list(dict.fromkeys(df[col]))
    hit = next((p for p in prefer if p in values), None)
    return hit if hit is not None else (df[col].mode().iloc[0] if len(df) else None)


def study_findings(*, entries: Sequence[FigureEntry] = (), fragility=None, records=None,
                   risk=None, stripes=None) -> list[Finding]:
    """Headline answers of any study: the most dangerous record (``records.csv``), the
    median capacities (``fragility.csv``), λ with its interval (``risk.csv``; 5–95 % when
    the table has ``lambda_p05``/``lambda_p95``) and the stripe against first-exceedance
    medians. Each at the study's main mode (3D where run), slenderness and largest R."""
    out = []
    if records is not None and Path(records).exists():
        df = pd.read_csv(records)
        if len(df):
            mode = _main(df, "mode", [MODE_3D])
            df = df[df["mode"] == mode]
            ta = next(c for c in df.columns if c.startswith("tan_alpha"))
            ls = _main(df, "limit_state", ["overturning"])
            t = _main(df, ta, [0.2])
            r = next(c for c in df.columns if c.startswith("R"))
            sub = df[(df["limit_state"] == ls) & (df[ta] == t)]
            n_records = sub["motion"].nunique()
            sub = sub[sub[r] == sub[r].max()]
            sf = next(c for c in sub.columns if c.startswith("scale_factor"))
            sub = sub[np.isfinite(pd.to_numeric(sub[sf], errors="coerce"))]
            if len(sub):
                worst = sub.loc[sub[sf].idxmin()]
                g = next(c for c in sub.columns if c.startswith("pga_crit_g"))
                who = (f"The most dangerous of the {n_records} records is {worst['motion']}: it"
                       if n_records > 1 else f"The record {worst['motion']}")
                out.append(Finding(
                    f"{who} exceeds {limit_state_title(ls).lower()} of the R = {worst[r]:g} m, "
                    f"tan α = {t:g} cylinder ({MODE_LABEL.get(mode, mode)}) when scaled by "
                    f"{worst[sf]:.2f} (critical PGA {worst[g]:.3f} g); "
                    + _as_recorded_finding(worst), "records"))
    if fragility is not None and Path(fragility).exists():
        df = pd.read_csv(fragility)
        med = next(c for c in df.columns if c.startswith("median ["))
        df = df[np.isfinite(pd.to_numeric(df[med], errors="coerce"))]
        if len(df):
            ta = next(c for c in df.columns if c.startswith("tan_alpha"))
            r = next(c for c in df.columns if c.startswith("R"))
            mode = _main(df, "mode", [MODE_3D])
            t = _main(df[df["mode"] == mode], ta, [0.2])
            sub = df[(df["mode"] == mode) & (df[ta] == t)]
            present = list(dict.fromkeys(sub["limit_state"]))
            shown = [ls for ls in ("overturning", "tilt:1/3") if ls in present] or sorted(
                present, key=lambda s: -severity(s))[:2]
            texts = []
            for ls in shown:
                rows = sub[sub["limit_state"] == ls].sort_values(r)
                ends = rows.iloc[[0, -1]] if len(rows) > 1 else rows
                texts.append(f"{limit_state_title(ls).lower()} " + " to ".join(
                    f"{x[med]:.2f} (β {x['beta [-]']:.2f}) at R = {x[r]:g} m"
                    for _, x in ends.iterrows()))
            out.append(Finding(
                f"Median capacities IM₅₀ in PGA/(g tan α), {MODE_LABEL.get(mode, mode)}, "
                f"tan α = {t:g}: " + "; ".join(texts), "fragility"))
    if risk is not None and Path(risk).exists():
        from ..risk.report import main_tan_alpha, read_risk_table
        frame = read_risk_table(risk)
        df = frame[(frame["fragility"] == "first_exceedance") & np.isfinite(frame["maf"])]
        if len(df):
            mode = _main(df, "mode", [MODE_3D])
            t = main_tan_alpha(df[df["mode"] == mode])
            ls = _main(df, "limit_state", ["overturning"])
            stripes_df = frame[(frame["fragility"] != "first_exceedance")
                               & np.isfinite(frame["maf"])] if "fragility" in frame else \
                frame.iloc[:0]
            sub = df[(df["mode"] == mode) & (df["tan_alpha"] == t)
                     & (df["limit_state"] == ls)].sort_values("R")
            stripe = stripes_df[(stripes_df["mode"] == mode) & (stripes_df["tan_alpha"] == t)
                                & (stripes_df["limit_state"] == ls)].sort_values("R")
            if len(sub):
                def lam(x) -> str:
                    text = f"{x['maf']:.2g} /yr at R = {x['R']:g} m"
                    if finite(x.get("lambda_p05"), x.get("lambda_p95")):
                        text += f" (5–95 %: {x['lambda_p05']:.2g}–{x['lambda_p95']:.2g})"
                    return text
                ends = sub.iloc[[0, -1]] if len(sub) > 1 else sub
                text = (f"Annual frequency λ of {limit_state_title(ls).lower()}, "
                        f"{MODE_LABEL.get(mode, mode)}, tan α = {t:g}, under the study's "
                        "hazard curve: " + " to ".join(lam(x) for _, x in ends.iterrows())
                        + " (first-exceedance fragility)")
                if len(stripe):  # the λ the risk section recommends
                    text += "; with the multiple-stripe fragility " + ", ".join(
                        lam(x) for _, x in stripe.iterrows())
                out.append(Finding(text, "risk"))
    if stripes is not None and Path(stripes).exists():
        df = read_table(stripes)
        ratio = df["ratio"].to_numpy(dtype=float)
        ratio = ratio[np.isfinite(ratio)]
        if ratio.size:
            out.append(Finding(
                f"Multiple-stripe median against first-exceedance median: "
                f"{ratio.min():.2f}–{ratio.max():.2f}× over {ratio.size} cells (the first "
                "exceedance marks where exceedance starts, the stripe median where half the "
                "motions exceed)", "stripes"))
    return out


TABLE_ANCHORS = ("records", "fragility", "stripes")
"""Anchors of the report's tables (the other findings link a figure)."""


def findings_html(findings: Sequence[Finding]) -> str:
    """The findings summary: a list, each line linking to where its number comes from."""
    if not findings:
        return "<p>No headline answer could be read from this run's outputs.</p>"
    def link(anchor: str) -> str:
        what = "table" if anchor in TABLE_ANCHORS else "figure"
        return f" <a href='#{html.escape(anchor)}'>({what})</a>" if anchor else ""

    items = "".join(f"<li>{html.escape(f.text)}.{link(f.anchor)}</li>" for f in findings)
    return f"<ul class='findings'>{items}</ul>"
