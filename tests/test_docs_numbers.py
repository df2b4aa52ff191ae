"""Documents quote the run: every number or verdict README.md and docs/*.md quote from the
committed gallery (results/paper) is marked and equal to what the gallery gives (the
maintainer's tool ``workflow/gallery_quotes.py``, which reads the gallery's tables and JSON
files, never its HTML), and a gallery whose number or verdict moved leaves the document stale,
so the check fails."""

from __future__ import annotations

import csv
import importlib.util
import math
import re
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "results/paper"


def _tool(name: str):
    """A maintainer's script of ``workflow/`` as a module (loaded once)."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, ROOT / "workflow" / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


quotes = _tool("gallery_quotes")
BLOCKS, HEADLINES, main = quotes.BLOCKS, quotes.HEADLINES, quotes.main
marked_documents, render, stale_blocks = quotes.marked_documents, quotes.render, \
    quotes.stale_blocks
verdict_counts, verdict_rows, write_documents = quotes.verdict_counts, quotes.verdict_rows, \
    quotes.write_documents
QUOTED = ("MANIFEST.json", "elcentro/verdicts.csv", "lomaprieta/verdicts.csv",
          "elcentro/mean_spectra.csv", "elcentro/fragility.csv", "elcentro/critical.csv",
          "elcentro/stripe_fragility.csv", "elcentro/risk.csv", "lomaprieta/records.csv",
          "motions/elcentro.json", "motions/lomaprieta.json")
"""What the quotations read from the gallery."""


def _copy(tmp_path: Path) -> Path:
    """A copy of the files of the gallery that the documents quote."""
    out = tmp_path / "gallery"
    for rel in QUOTED:
        (out / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(GALLERY / rel, out / rel)
    return out


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8")
    assert old in text, (path, old)
    path.write_text(text.replace(old, new, 1), encoding="utf-8")


def test_every_quotation_is_that_of_the_committed_gallery():
    docs = marked_documents(ROOT)
    names = {str(p.relative_to(ROOT)) for p in docs}
    assert {"README.md", "docs/models.md", "docs/motions.md", "docs/records.md",
            "docs/risk.md"} <= names
    stale = {name: stale_blocks(ROOT / name, GALLERY) for name in names}
    assert not any(stale.values()), (
        f"stale gallery quotations {stale}: run `python workflow/gallery_quotes.py`")
    used = {m for p in docs for m in re.findall(r"<!-- BEGIN gallery:([\w-]+) -->",
                                                  p.read_text(encoding="utf-8"))}
    assert used == set(BLOCKS)          # no quotation is defined that no document uses


def test_the_models_page_says_what_the_reports_say():
    """The issue's contradictions are gone: every headline row of docs/models.md carries its
    report's number and verdict (Fig 9 "reproduced", Fig 12 Loma Prieta's ratios, Fig 10's
    flat range), and the counts are the reports' counts."""
    # as a reader sees it: without the markers
    text = re.sub(r"<!--.*?-->", "", (ROOT / "docs/models.md").read_text(encoding="utf-8"))
    assert "77 reproduced" not in text and "up to R ≈ 3 m" not in text
    assert f"({verdict_counts(GALLERY)};" in text
    lines = text.splitlines()
    for h in HEADLINES:
        row = h.pick(verdict_rows(GALLERY / h.study / "verdicts.csv"))
        line = next(x for x in lines if x.startswith(f"| {h.quantity} |"))
        assert f"| {row.ours.replace('|', chr(92) + '|')} | {row.verdict}" in line, h


def test_the_verdict_table_as_data_is_the_page_s():
    """Each report's verdicts.csv, row by row, is the verdict table its page shows: the
    figures and the verdict cells' classes read from the raw page (an independent reading of
    the same table) equal the file's."""
    for study in ("elcentro", "lomaprieta"):
        page = (GALLERY / study / "report.html").read_text(encoding="utf-8")
        table = page[page.index("<h2 id='verdicts'>"):]
        table = table[:table.index("</table>")]
        classes = re.findall(r"<td class='([\w-]+)'>", table)
        figures = re.findall(r"<tr><td><a href='#([\w]+)'>", table)
        rows = verdict_rows(GALLERY / study / "verdicts.csv")
        assert len(rows) == len(classes) > 10
        assert [r.verdict.replace(" ", "-").replace("not-computed-in-this-run", "not-computed")
                for r in rows] == classes
        assert [r.figure for r in rows] == figures
        assert all(r.figure and r.statement and r.ours for r in rows)


def test_a_moved_verdict_leaves_the_models_page_stale(tmp_path):
    gallery = _copy(tmp_path)
    _edit(gallery / "elcentro/verdicts.csv",
          "reproduced,spread ≤ 15 % of the mean at every R",
          "differs,the spread exceeds 15 %")
    assert stale_blocks(ROOT / "docs/models.md", gallery) == ["verdict-counts", "headlines"]
    assert stale_blocks(ROOT / "docs/motions.md", gallery) == []
    new = render((ROOT / "docs/models.md").read_text(encoding="utf-8"), gallery)
    assert "El Centro report: 19 reproduced, 15 differ" in new
    assert "| differs: the spread exceeds 15 % |" in new


def test_a_moved_number_leaves_its_documents_stale(tmp_path):
    gallery = _copy(tmp_path)
    with open(gallery / "elcentro/mean_spectra.csv", newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    hit = [r for r in rows if (r["mode"], r["limit_state"], r["tan_alpha [-]"], r["R [m]"])
           == ("3d", "overturning", "0.2", "10")]
    assert len(hit) == 1
    hit[0]["std [g tan(alpha)]"] = str(2 * float(hit[0]["std [g tan(alpha)]"]))
    with open(gallery / "elcentro/mean_spectra.csv", "w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    assert stale_blocks(ROOT / "docs/motions.md", gallery) == ["r10-means"]
    _edit(gallery / "motions/lomaprieta.json", '"f_mid": 3.42358', '"f_mid": 3.52')
    assert stale_blocks(ROOT / "docs/motions.md", gallery) == ["r10-means",
                                                                "ensemble-parameters"]
    assert stale_blocks(ROOT / "docs/models.md", gallery) == ["r10-band"]
    assert stale_blocks(ROOT / "README.md", gallery) == []
    assert main(["--gallery", str(gallery), "--check", str(ROOT / "docs/motions.md")]) == 1
    assert main(["--gallery", str(GALLERY), "--check", str(ROOT / "docs/motions.md")]) == 0


def test_writing_makes_a_stale_document_current(tmp_path):
    gallery = _copy(tmp_path)
    _edit(gallery / "elcentro/fragility.csv", "3d,overturning,0.2,6,2.484404501",
          "3d,overturning,0.2,6,2.91")                          # the R = 6 m median moves
    doc = tmp_path / "README.md"
    shutil.copy2(ROOT / "README.md", doc)
    assert stale_blocks(doc, gallery) == ["fragility-r6"]
    assert write_documents([doc], gallery) == [doc]
    assert stale_blocks(doc, gallery) == []
    assert "median 2.91" in doc.read_text(encoding="utf-8")
    assert write_documents([doc], gallery) == []                # nothing left to change
    # only the marked text changed
    old = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    new = doc.read_text(encoding="utf-8").splitlines()
    assert sum(a != b for a, b in zip(old, new, strict=True)) == 1


def test_a_statement_no_report_makes_is_an_error_naming_it(tmp_path):
    gallery = _copy(tmp_path)
    _edit(gallery / "elcentro/verdicts.csv", "Angle of turn measured numerically",
          "Angle of turn as read off")
    with pytest.raises(ValueError, match="Angle of turn measured numerically"):
        render("<!-- BEGIN gallery:headlines --><!-- END gallery:headlines -->", gallery)
    # nothing is written when one document cannot be rendered
    doc = tmp_path / "models.md"
    shutil.copy2(ROOT / "docs/models.md", doc)
    before = doc.read_text(encoding="utf-8")
    with pytest.raises(ValueError):
        write_documents([doc], gallery)
    assert doc.read_text(encoding="utf-8") == before
    assert main(["--gallery", str(gallery), str(doc)]) == 2


def test_an_unknown_quotation_is_an_error(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)                 # no marked document here: said, not skipped
    assert main(["--check", "--gallery", str(GALLERY)]) == 2
    assert "marks a gallery quotation" in capsys.readouterr().err
    assert main(["--check"]) == 2                 # and no results/paper here
    assert "--gallery results/paper: no such folder" in capsys.readouterr().err
    with pytest.raises(ValueError, match="'nope' is none of"):
        render("a <!-- BEGIN gallery:nope -->1<!-- END gallery:nope --> b", GALLERY, "x.md")
    with pytest.raises(ValueError, match=r"no column \['figure'"):
        verdict_rows(GALLERY / "elcentro/fragility.csv")
    bad = tmp_path / "verdicts.csv"
    bad.write_text("figure,statement,paper,this_run,verdict,reason\nfig04,s,1,2,roughly,\n")
    with pytest.raises(ValueError, match="line 2: verdict 'roughly' is none of"):
        verdict_rows(bad)


def test_the_quoted_fig12_ratio_is_that_of_the_fragility_table():
    """The report's verdict number of the paper's comparator (the 3D model under one
    component against both), quoted in docs/models.md, is the geometric mean of the
    censoring-aware medians' ratios over the sizes, recomputed here from fragility.csv."""
    with open(GALLERY / "elcentro/fragility.csv", newline="", encoding="utf-8") as fh:
        rows = [r for r in csv.DictReader(fh) if r["limit_state"] == "overturning"
                and r["tan_alpha [-]"] == "0.2" and r["status"] == "ok"]
    med = {(r["mode"], r["R [m]"]): float(r["median [g tan(alpha)]"]) for r in rows}
    sizes = sorted({R for m, R in med if m == "3d"})
    text = (ROOT / "docs/models.md").read_text(encoding="utf-8")
    for axis in ("x", "y"):
        logs = [math.log(med[(f"3d-{axis}", R)] / med[("3d", R)]) for R in sizes]
        quoted = (f"3D {axis}/3D of the censoring-aware medians = "
                  f"{math.exp(sum(logs) / len(logs)):.3g} ")
        row = next(line for line in text.splitlines()
                   if line.startswith(f"| Fig 12: 3D under {axis} alone \"twice as high\""))
        assert quoted in row


def test_the_stripe_section_names_each_interval_by_its_level():
    """The report's stripe section: the brackets beside the median in PGA/(g tan α) are the
    Wald interval at ``CONFIDENCE`` (95 %), those beside the median in g the bootstrap's
    5–95 % percentiles (90 %); the section says which is which, from the same constants."""
    from rocking.fragility.stripes import BOOTSTRAP_LEVEL, CONFIDENCE
    from rocking.report.tables import stripes_section

    assert (CONFIDENCE, BOOTSTRAP_LEVEL) == (0.95, 0.90)
    page = "\n".join(stripes_section(GALLERY / "elcentro/stripe_fragility.csv"))
    assert "95 % interval in brackets" not in page
    assert "its 95 % Wald interval" in page and "its 90 % bootstrap interval" in page
    assert "(95 % Wald)</th>" in page and "90 % over motions</th>" in page
    with open(GALLERY / "elcentro/stripe_fragility.csv", newline="", encoding="utf-8") as fh:
        row = next(r for r in csv.DictReader(fh) if r["status"] == "ok")
    lo, hi = (float(row[f"median_{k} [g]"]) for k in ("p05", "p95"))
    assert f"({lo:.3g}–{hi:.3g})" in page          # the g column's brackets: the percentiles


def test_the_gallery_script_requotes_the_documents_of_its_repository(tmp_path):
    """workflow/gallery.py, after copying a run to the repository's results/paper, rewrites
    the documents' quotations from it; a gallery written elsewhere leaves them alone."""
    gallery = _tool("gallery")
    root = tmp_path / "repo"
    (root / "docs").mkdir(parents=True)
    shutil.copy2(ROOT / "README.md", root / "README.md")
    shutil.copy2(ROOT / "docs/motions.md", root / "docs/motions.md")
    shutil.copytree(_copy(tmp_path), root / "results/paper")
    _edit(root / "results/paper/elcentro/fragility.csv", "3d,overturning,0.2,6,2.484404501",
          "3d,overturning,0.2,6,2.91")
    assert gallery.requote(tmp_path / "gallery", root) == []       # not the repository's
    assert stale_blocks(root / "README.md", root / "results/paper") == ["fragility-r6"]
    assert gallery.requote(root / "results/paper", root) == [root / "README.md"]
    assert stale_blocks(root / "README.md", root / "results/paper") == []


def test_records_quotation_follows_the_records_table(tmp_path):
    """docs/records.md's account of the analyses at scale 1 is counted from records.csv: a
    row whose scale factor said "survives" but that exceeds at scale 1 is said, and with no
    row changed the sentence says none."""
    gallery = _copy(tmp_path)
    path = gallery / "lomaprieta/records.csv"
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))

    def write(rows):
        with open(path, "w", newline="", encoding="utf-8") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)

    def survives(r) -> bool:  # the scale factor says the record survives as recorded
        return float(r["scale_factor [-]"]) > 1

    before = sum(survives(r) and r["as_recorded_disagrees"] == "True" for r in rows)
    above = next(r for r in rows if survives(r) and r["as_recorded_disagrees"] == "False")
    above["as_recorded_disagrees"] = "True"
    write(rows)
    assert stale_blocks(ROOT / "docs/records.md", gallery) == ["records-as-recorded"]
    n = before + 1
    assert f"; {n} row{'s' if n > 1 else ''} that the scale factor said survives exceeds" in \
        render((ROOT / "docs/records.md").read_text(encoding="utf-8"), gallery)
    for r in rows:
        r["as_recorded_disagrees"] = "False"
    write(rows)
    text = render("<!-- BEGIN gallery:records-as-recorded --><!-- END gallery:records-"
                  "as-recorded -->", gallery)
    exceed = sum(not survives(r) for r in rows)
    assert f"changed none of the {exceed} rows" in text and "; no row that" in text
