"""Copy a finished study run into the committed gallery (``results/paper/``).

    snakemake --cores 2 --configfile config/paper.yaml
    python workflow/gallery.py --elapsed 842 --command "snakemake --cores 2 --configfile ..."

The gallery keeps what a reader needs to hold the run against the paper without running
anything: every figure (PNG and its JSON sidecar of measured numbers), each study's report
(images linked, not embedded, so the page stays small), the small tables (mean spectra,
fragility, linear fits as CSV) and the fitted ensemble parameters. Stores (zarr, NetCDF) and
PDFs stay out. ``MANIFEST.json`` records the commit, the configuration and the run time.
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
from rocking.study.report import link_images

TABLES = ("mean_spectra.csv", "fragility.csv", "linear_fit.csv")
CRITICAL = "critical.csv"
"""Every motion's answers (the spectra store as a table): what tests/test_gallery.py holds
against a slice of the study run again."""


def write_critical(store: Path, csv: Path) -> None:
    """The spectra store of a study as one row per computed answer."""
    import xarray as xr

    from rocking.study.aggregate import critical_frame

    with xr.open_zarr(store, consolidated=True) as ds:
        critical_frame(ds).to_csv(csv, index=False, float_format="%.10g")


def _copy(src: Path, dst: Path) -> None:
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy2(src, dst)


def collect(results: Path, out: Path, studies: list[str]) -> list[Path]:
    """Copy the gallery files of ``studies`` from ``results`` to ``out``; return them."""
    copied = []
    for f in sorted((results / "figures").glob("*")):
        if f.suffix in (".png", ".json"):
            _copy(f, out / "figures" / f.name)
            copied.append(out / "figures" / f.name)
    for f in sorted((results / "motions").glob("*.json")):
        _copy(f, out / "motions" / f.name)
        copied.append(out / "motions" / f.name)
    for study in studies:
        src, dst = results / study, out / study
        for f in sorted((src / "figures").glob("*")):
            if f.suffix in (".png", ".json"):
                _copy(f, dst / "figures" / f.name)
                copied.append(dst / "figures" / f.name)
        for name in TABLES:
            _copy(src / name, dst / name)
            copied.append(dst / name)
        write_critical(src / "spectra.zarr", dst / CRITICAL)
        copied.append(dst / CRITICAL)
        page = (src / "report.html").read_text()
        # study figures live in <study>/figures/, the others in ../figures/
        page = link_images(page, lambda stem, d=dst: (
            f"figures/{stem}.png" if (d / "figures" / f"{stem}.png").exists()
            else f"../figures/{stem}.png"))
        (dst / "report.html").write_text(page)
        copied.append(dst / "report.html")
    (out / "config.yaml").write_text((results / "config.yaml").read_text())
    copied.append(out / "config.yaml")
    return copied


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python workflow/gallery.py", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", type=Path, default=Path("results"),
                        help="folder the run wrote (default: results)")
    parser.add_argument("--out", type=Path, default=Path("results/paper"),
                        help="gallery folder (default: results/paper)")
    parser.add_argument("--elapsed", type=float, required=True,
                        help="measured wall time of the whole run [s]")
    parser.add_argument("--command", default="snakemake --cores 2 --configfile "
                        "config/paper.yaml", help="the command that was timed")
    parser.add_argument("--machine", default=f"{os.cpu_count()} cores",
                        help="where it ran (cores, load)")
    args = parser.parse_args(argv)
    run_config = yaml.safe_load((args.results / "config.yaml").read_text())
    studies = list(run_config["studies"])
    if args.out.exists():
        shutil.rmtree(args.out)
    files = collect(args.results, args.out, studies)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                            check=False).stdout.strip() or None
    manifest = {"command": args.command, "elapsed_seconds": args.elapsed,
                "machine": args.machine, "commit": commit, "rocking_version": __version__,
                "studies": studies,
                "files": sorted(str(f.relative_to(args.out)) for f in files)}
    (args.out / "MANIFEST.json").write_text(json.dumps(manifest, indent=2) + "\n")
    print(f"gallery: {len(files)} files in {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
