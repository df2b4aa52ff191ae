"""The committed gallery of the paper's full run (results/paper/) cannot silently go stale.

A slice of ``config/paper.yaml`` (the El Centro study's first run: mode 3d, tan α 0.2, its
seven limit states; the record and its first synthetic pair; two sizes of the R grid) is run
again through the committed workflow (real Snakemake, Dask and zarr), once with numpy's SIMD
dispatch at its best on this machine and once lowered to its baseline
(``NPY_DISABLE_CPU_FEATURES`` naming every feature above it: another CPU's arithmetic), and
its answers must agree with the committed ``results/paper/elcentro/critical.csv`` within the
answers' stated error (:func:`rocking.study.verify.answer_tolerance`: within 2e in all but a
share 2(1 − q) of them), as ``rocking verify`` judges a run. Bit-identity with the gallery is
not asked: the gallery was made on another machine, and rocking near a goal magnifies the
last bit. The committed mean spectra must be the mean over motions of the committed table.
"""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml

from rocking.motions.ensemble_io import load_ensemble
from rocking.study.aggregate import critical_frame
from rocking.study.verify import answer_tolerance
from rocking.units import strip_units

REPO = Path(__file__).resolve().parents[1]
GALLERY = REPO / "results" / "paper"
STUDY = "elcentro"
SLICE_R = [2.0, 6.0]
KEYS = ["mode", "limit_state", "motion", "tan_alpha", "R"]


def test_gallery_is_documented_and_complete():
    manifest = json.loads((GALLERY / "MANIFEST.json").read_text())
    assert manifest["elapsed_seconds"] > 0 and manifest["commit"]
    for f in manifest["files"]:
        assert (GALLERY / f).is_file(), f
    assert (GALLERY / "README.md").is_file()
    for study in manifest["studies"]:
        for table in ("mean_spectra.csv", "fragility.csv", "linear_fit.csv", "critical.csv"):
            assert (GALLERY / study / table).stat().st_size > 0
    assert not list(GALLERY.rglob("*.zarr")) and not list(GALLERY.rglob("*.nc"))


def test_the_gallery_readme_says_every_flag_its_tables_write():
    """results/paper/README.md describes exactly the flag columns of the committed
    critical.csv (written from the code's list, workflow/gallery.py ``flag_lines``)."""
    import csv

    with open(GALLERY / STUDY / "critical.csv", newline="", encoding="utf-8") as fh:
        header = next(csv.reader(fh))
    flags = [c for c in header if "[" not in c and c not in (
        "mode", "limit_state", "motion", "quantity", "n_analyses")]
    listed = re.findall(r"^  - `(\w+)`: ", (GALLERY / "README.md").read_text(), re.M)
    assert listed == flags and "failed" in flags


def _slice_config(tmp: Path) -> Path:
    cfg = yaml.safe_load((REPO / "config" / "paper.yaml").read_text())
    ensemble = cfg["studies"][STUDY]["ensemble"]
    cfg["ensembles"] = {ensemble: {**cfg["ensembles"][ensemble], "n_synthetic": 1}}
    study = cfg["studies"][STUDY]
    cfg["studies"] = {STUDY: {"ensemble": ensemble, "R": SLICE_R, "chunk_R": 1,
                              "runs": study["runs"][:1]}}
    path = tmp / "slice.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


def simd_baseline_env() -> dict[str, str]:
    """``NPY_DISABLE_CPU_FEATURES`` naming every SIMD feature numpy found above its baseline
    on this machine: numpy computes as on a CPU with none of them."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    return {"NPY_DISABLE_CPU_FEATURES": " ".join(f for f in __cpu_dispatch__
                                                  if __cpu_features__.get(f))}


@pytest.fixture(scope="module", params=["best", "baseline"])
def slice_answers(request, tmp_path_factory) -> pd.DataFrame:
    work = tmp_path_factory.mktemp(f"gallery_slice_{request.param}")
    cmd = [sys.executable, "-m", "snakemake", f"results/{STUDY}/spectra.done.json", "-s",
           str(REPO / "Snakefile"), "--directory", str(work), "--cores", "2", "--nocolor",
           "--configfile", str(_slice_config(work))]
    env = {k: v for k, v in os.environ.items() if k != "DASK_SCHEDULER_ADDRESS"}
    if request.param == "baseline":
        env.update(simd_baseline_env())
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=1800)
    assert out.returncode == 0, out.stderr[-4000:]
    with xr.open_zarr(work / "results" / STUDY / "spectra.zarr", consolidated=True) as ds:
        answers = _bare(critical_frame(ds))
    motions = work / "results" / "motions"
    (motions_file,) = [f for f in motions.glob("*.nc") if not f.name.endswith(".compare.nc")]
    (params,) = [p for p in motions.glob("*.json") if not p.name.endswith(".params.json")]
    answers.attrs["motions"] = load_ensemble(motions_file)
    answers.attrs["ensemble_params"] = json.loads(params.read_text())
    answers.attrs["simd"] = request.param
    return answers


def _bare(frame: pd.DataFrame) -> pd.DataFrame:
    """Columns by their names without units (``"R [m]"`` → ``"R"``)."""
    return frame.rename(columns=strip_units)


def _fitted_parameters(params: dict) -> dict[str, float]:
    """The RDK model's fitted parameters of an ensemble's JSON (not its diagnostics)."""
    return {f"{axis}.{k}": float(v) for axis in ("major", "minor")
            for k, v in params["fit"][axis].items() if isinstance(v, int | float)}


def test_the_slice_makes_the_gallery_motions(slice_answers):
    """The record is the gallery's: rotated by the same principal angle and of the same PGA
    to 1e-12 relative (its digest is reported, not required: scipy's and numpy's arithmetic
    may differ in the last bit on another CPU); its synthetic pair is refitted to the
    gallery's parameters (relative 1e-6): an optimiser on another machine may stop a few
    ulps away, which changes the motion's last bits but not the model it was drawn from."""
    manifest = json.loads((GALLERY / "MANIFEST.json").read_text())
    ensemble = yaml.safe_load((REPO / "config" / "paper.yaml").read_text())[
        "studies"][STUDY]["ensemble"]
    made = {m.name: m for m in slice_answers.attrs["motions"]}
    record = next(m for m in made.values() if "rdk" not in m.name)
    committed = json.loads((GALLERY / "motions" / f"{ensemble}.json").read_text())
    assert record.metadata["rotation_deg"] == pytest.approx(committed["rotation_deg"],
                                                            rel=1e-12)
    records = _bare(pd.read_csv(GALLERY / STUDY / "records.csv"))
    assert record.pga_g == pytest.approx(float(records.loc[records["motion"] == record.name,
                                                           "pga_g"].iloc[0]), rel=1e-9)
    same = manifest["motion_sha256"][ensemble][record.name] == record.samples_sha256
    print(f"{slice_answers.attrs['simd']}: the record is the gallery's to the bit: {same}")
    ours = _fitted_parameters(slice_answers.attrs["ensemble_params"])
    theirs = _fitted_parameters(committed)
    assert ours.keys() == theirs.keys() and len(ours) > 10
    for k in ours:
        assert ours[k] == pytest.approx(theirs[k], rel=1e-6, abs=1e-12), k


def test_committed_answers_agree_with_a_slice_run_again_within_the_stated_error(
        slice_answers):
    """Every answer of the slice is in the gallery; they agree within 2e in all but a share
    2(1 − q) of them (the answers' stated error, as rocking verify holds a run), whatever
    numpy's SIMD dispatch, and the flags of the answers within agree."""
    committed = _bare(pd.read_csv(GALLERY / STUDY / "critical.csv"))
    assert len(slice_answers) == 2 * len(SLICE_R) * 7  # two motions, seven limit states
    merged = slice_answers.merge(committed, on=KEYS, how="left", suffixes=("", "_gallery"),
                                 indicator=True)
    assert (merged["_merge"] == "both").all(), merged[merged["_merge"] != "both"][KEYS]
    r, share = answer_tolerance("default")
    a, b = merged["pga_crit"].to_numpy(float), merged["pga_crit_gallery"].to_numpy(float)
    both_nan = np.isnan(a) & np.isnan(b)
    rel = np.where(both_nan, 0.0, np.abs(a - b) / np.abs(b))
    beyond = ~(rel <= r * (1 + 1e-9))
    # the table prints 10 significant digits: equal to them is identical
    print(f"{slice_answers.attrs['simd']}: {int(np.sum(rel <= 5e-10))} of {len(rel)} answers "
          f"identical to the gallery's (to its 10 digits), {int(beyond.sum())} beyond "
          f"{100 * r:g} %")
    assert beyond.sum() <= share * len(rel), merged.loc[beyond, KEYS + ["pga_crit",
                                                                      "pga_crit_gallery"]]
    ok = ~beyond
    assert (merged.loc[ok, "not_reached"] == merged.loc[ok, "not_reached_gallery"]).all()


def test_committed_means_are_the_committed_answers():
    """mean_spectra.csv is the mean over motions of critical.csv (the two tables agree)."""
    crit = _bare(pd.read_csv(GALLERY / STUDY / "critical.csv"))
    means = _bare(pd.read_csv(GALLERY / STUDY / "mean_spectra.csv"))
    reached = crit[~crit["not_reached"].astype(bool)]
    cell = ["mode", "limit_state", "tan_alpha", "R"]
    ours = reached.groupby(cell)["pga_crit"].mean().rename("ours").reset_index()
    merged = means.merge(ours, on=cell)
    assert len(merged) > 100
    np.testing.assert_allclose(merged["mean"], merged["ours"], rtol=1e-8)
