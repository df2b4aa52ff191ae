"""The Snakemake workflow end to end: real snakemake (subprocess), real Dask, real zarr.

A tiny study (El Centro cut to 3 s + one synthetic pair, 2 sizes, 2 modes; 2 limit states
for 3D and one for 2D, so that one cell of the store is not requested) runs once
uninterrupted on an embedded LocalCluster of worker processes; its store is checked against
direct library calls and serves as the reference of the other runs: against an external
``dask scheduler`` with two ``dask worker`` processes (one killed mid-run), and a run killed
mid-way then resumed. Every one must give the same bytes.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml
from conftest import ELC180, ELC270, package_record

from rocking.config.ensemble import EnsembleSpec
from rocking.config.study import StudySpec
from rocking.dynamics.bodies import Cylinder
from rocking.motions.ensemble_io import load_ensemble
from rocking.spectra.critical import critical_intensity
from rocking.spectra.tilt_map import tilt_map
from rocking.units import read_table

pytestmark = pytest.mark.slow

REPO = Path(__file__).resolve().parents[1]
SNAKEFILE = REPO / "Snakefile"
STUDY = "tiny"
TINY = {
    "accuracy": "fast",
    "motions": {"max_duration": 3.0},
    "ensembles": {"tiny": {"record": "el-centro-1940", "n_synthetic": 1, "seed": 7}},
    "studies": {
        STUDY: {
            "ensemble": "tiny",
            "R": [1.0, 3.0],
            "runs": [
                {"modes": ["3d"], "tan_alpha": [0.2],
                 "limit_states": ["overturning", "tilt:1/3"]},
                {"purpose": "a run asking for fewer limit states", "modes": ["2d-x"],
                 "tan_alpha": [0.2], "limit_states": ["overturning"]},
            ],
            "chunk_R": 1,
            "tilt_map": {"modes": ["3d", "3d-damped"], "R": [2.0], "intensity": [2.0, 4.0]},
        }
    },
    "dask": {"progress_interval": 0},
}
SPECTRA = f"results/{STUDY}/spectra.zarr"  # the link to the latest keyed store
MOTIONS = f"results/motions/tiny-{EnsembleSpec.from_config(TINY, 'tiny').digest}"
"""The ensemble files' stem: named after the digest of the ensemble's settings."""
TARGETS = [f"results/{STUDY}/mean_spectra.nc", f"results/{STUDY}/tilt_map.done.json",
           f"results/{STUDY}/config.yaml"]


def write_config(workdir: Path, **dask) -> Path:
    cfg = json.loads(json.dumps(TINY))
    cfg["dask"].update(dask)
    path = workdir / "tiny.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


def snakemake(workdir: Path, *args: str, configfile: Path | None = None, cores: int = 2,
              check: bool = True, popen: bool = False, timeout: float = 300):
    """Run ``python -m snakemake`` on the project's Snakefile in ``workdir``."""
    cmd = [sys.executable, "-m", "snakemake", "-s", str(SNAKEFILE), "--directory", str(workdir),
           "--cores", str(cores), "--nocolor", *args]
    if configfile is not None:
        cmd += ["--configfile", str(configfile)]
    env = {k: v for k, v in os.environ.items() if k != "DASK_SCHEDULER_ADDRESS"}
    if popen:
        return subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL, start_new_session=True)
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    if check and out.returncode != 0:
        raise AssertionError(f"snakemake failed ({out.returncode}):\n{out.stderr[-4000:]}")
    return out


def store_bytes(path: Path) -> dict[str, bytes]:
    ds = xr.open_zarr(path, consolidated=True)  # a finished store is consolidated
    return {k: ds[k].values.view(np.uint8).tobytes() for k in ds.data_vars}


def copy_motions(src: Path, dst: Path) -> None:
    """Reuse the reference run's ensemble file (its rule has no result-affecting change)."""
    (dst / "results/motions").mkdir(parents=True)
    # with their digests (.sha256), which every read checks
    for suffix in (".nc", ".json", ".compare.nc", ".nc.sha256", ".compare.nc.sha256",
                   ".params.json"):
        shutil.copy2(src / f"{MOTIONS}{suffix}", dst / f"{MOTIONS}{suffix}")


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    """One uninterrupted run on an embedded LocalCluster of 2 worker processes."""
    workdir = tmp_path_factory.mktemp("reference")
    out = snakemake(workdir, *TARGETS, configfile=write_config(workdir))
    (workdir / "snakemake.stderr").write_text(out.stderr)
    return workdir


def test_end_to_end_store_equals_direct_library_calls(reference):
    ds = xr.open_zarr(reference / SPECTRA, consolidated=True)
    attrs = {k: json.loads(v) if isinstance(v, str) and v[:1] in "{[" else v
             for k, v in ds.attrs.items()}
    motions = {m.name: m for m in load_ensemble(reference / f"{MOTIONS}.nc")}
    assert list(ds["motion"].values) == list(motions)  # the record first, then its pair
    assert bool(ds["done"].all())
    assert [str(s) for s in ds["limit_state"].values] == ["tilt:1/3", "overturning"]
    asked = {"3d": ["tilt:1/3", "overturning"], "2d-x": ["overturning"]}
    np.testing.assert_array_equal(ds["requested"].sel(tan_alpha=0.2).values,
                                  [[True, True], [False, True]])
    # the cell no run asked for: not computed (NaN, no flag), told apart from not reached
    skipped = ds.sel(mode="2d-x", limit_state="tilt:1/3")
    assert bool(skipped["pga_crit"].isnull().all())
    for flag in ("not_reached", "non_monotonic", "failed"):
        assert not bool(skipped[flag].any()), flag
    assert int(skipped["n_analyses"].max()) == 0
    for mode in ds["mode"].values:
        for name, motion in motions.items():
            for R in ds["R"].values:
                want = critical_intensity(Cylinder(float(R), 0.2), motion, asked[str(mode)],
                                          str(mode), accuracy=attrs["tolerances"],
                                          **attrs["search_options"])
                point = ds.sel(mode=mode, motion=name, tan_alpha=0.2, R=R)
                got = point["pga_crit"].sel(limit_state=list(want.limit_states)).values
                np.testing.assert_array_equal(got, want.intensity)
                assert np.all(np.isfinite(got))  # 3 s of El Centro tips these bodies
                np.testing.assert_array_equal(
                    point["not_reached"].sel(limit_state=list(want.limit_states)).values,
                    want.not_reached)
                assert int(point["n_analyses"].sel(limit_state="overturning")) == \
                    want.n_analyses
    # aggregation: the CSV against numpy over the stored values
    table = read_table(reference / f"results/{STUDY}/mean_spectra.csv")
    assert len(table) == 2 * 2 * 1 * 2
    for row in table.itertuples():
        v = ds["pga_crit"].sel(mode=row.mode, limit_state=row.limit_state,
                               tan_alpha=row.tan_alpha, R=row.R).values
        assert row.requested == (row.limit_state in asked[row.mode])
        if not row.requested:
            assert np.isnan(row.mean) and row.count == 0 and row.n_not_reached == 0
            continue
        assert row.mean == pytest.approx(np.mean(v), rel=1e-9)
        assert row.std == pytest.approx(np.std(v, ddof=1), rel=1e-9)
        assert row.count == 2
    # Fig 7 data through the same machinery, against the library for the record
    tm = xr.open_zarr(reference / f"results/{STUDY}/tilt_map.zarr", consolidated=True)
    record = next(iter(motions.values()))
    options = json.loads(tm.attrs["model_options"])
    assert options == {"omega_n": 2000.0, "zeta": 5.0}  # the schema's defaults
    for model in ("3d", "3d-damped"):
        want = tilt_map([2.0], 0.2, record, [2.0, 4.0], model, accuracy="fast", **options)
        np.testing.assert_array_equal(tm["theta_max_over_alpha"].sel(mode=model).values,
                                      want["theta_max_over_alpha"].values)
    # the log shows the dashboard and the progress; the summary says where it ran
    log = (reference / f"results/logs/{STUDY}/spectra.log").read_text()
    assert "dashboard: http://127.0.0.1:" in log and "8/8 chunks done" in log
    summary = json.loads((reference / f"results/{STUDY}/spectra.done.json").read_text())
    assert summary["cluster"] == "local" and summary["computed"] == 8


def _start(cmd: list[str], cwd: Path) -> subprocess.Popen:
    return subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def test_external_cluster_survives_a_killed_worker(reference, tmp_path):
    from distributed import Client

    sched_file = tmp_path / "scheduler.json"
    procs = [_start([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host",
                     "127.0.0.1", "--port", "0", "--dashboard-address", ":0",
                     "--scheduler-file", str(sched_file)], tmp_path)]
    client = None
    try:
        for _ in range(600):
            if sched_file.exists():
                break
            time.sleep(0.1)
        for _ in range(2):
            procs.append(_start([sys.executable, "-m", "distributed.cli.dask_worker",
                                 "--scheduler-file", str(sched_file), "--host", "127.0.0.1",
                                 "--nthreads", "1", "--no-nanny"], tmp_path))
        client = Client(scheduler_file=str(sched_file), timeout="60s")
        client.wait_for_workers(2, timeout=120)
        pids = client.run(os.getpid)
        copy_motions(reference, tmp_path)
        run = snakemake(tmp_path, *TARGETS, popen=True,
                        configfile=write_config(tmp_path, scheduler_file=str(sched_file)))
        # kill a worker while it is computing a spectra chunk (not before, not after)
        victim = None
        deadline = time.monotonic() + 240
        while victim is None and time.monotonic() < deadline and run.poll() is None:
            for addr, keys in client.processing().items():
                if any("spectra" in str(k) for k in keys):
                    victim = addr
                    break
            time.sleep(0.01)
        assert victim is not None, "no spectra chunk was seen running"
        os.kill(pids[victim], signal.SIGKILL)
        assert run.wait(timeout=300) == 0
        client.wait_for_workers(1)
        assert len(client.scheduler_info()["workers"]) == 1
    finally:
        if client is not None:
            client.close()
        for p in procs:
            p.kill()
            p.wait(timeout=30)
    summary = json.loads((tmp_path / f"results/{STUDY}/spectra.done.json").read_text())
    assert summary["cluster"] == "scheduler_file" and summary["computed"] == 8
    assert store_bytes(tmp_path / SPECTRA) == store_bytes(reference / SPECTRA)
    tm = f"results/{STUDY}/tilt_map.zarr"
    assert store_bytes(tmp_path / tm) == store_bytes(reference / tm)


def test_killed_run_resumes_without_redoing_chunks(reference, tmp_path):
    config = write_config(tmp_path)
    copy_motions(reference, tmp_path)
    target = f"results/{STUDY}/spectra.done.json"
    # one worker: chunks run one after the other, so there is time to kill between them
    run = snakemake(tmp_path, target, configfile=config, cores=1, popen=True)
    done_dir = tmp_path / SPECTRA / "done" / "c"
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and run.poll() is None:
        if done_dir.exists() and any(p.is_file() for p in done_dir.rglob("*")):
            break
        time.sleep(0.01)
    os.killpg(run.pid, signal.SIGKILL)  # snakemake, its job and the Dask workers at once
    run.wait(timeout=30)
    n_done = sum(p.is_file() for p in done_dir.rglob("*"))
    assert 1 <= n_done < 8, f"kill landed after {n_done} of 8 chunks"
    assert not (tmp_path / target).exists()
    snakemake(tmp_path, "--unlock", configfile=config)
    snakemake(tmp_path, target, "--rerun-incomplete", configfile=config)
    summary = json.loads((tmp_path / target).read_text())
    assert summary["done_before"] >= n_done and summary["computed"] == 8 - summary["done_before"]
    assert store_bytes(tmp_path / SPECTRA) == store_bytes(reference / SPECTRA)


def _chunk_files(store: Path) -> dict[str, bytes]:
    return {str(p.relative_to(store)): p.read_bytes() for p in sorted(store.rglob("*"))
            if p.is_file() and "c" in p.relative_to(store).parts}


def test_forcerun_spectra_repairs_damaged_chunks_to_identical_bytes(reference, tmp_path):
    """A flipped bit, a truncated chunk and a damaged done flag: `--forcerun spectra`
    re-reads every chunk, recomputes exactly the damaged ones, ends with the same bytes."""
    work = tmp_path / "work"
    shutil.copytree(reference, work, symlinks=True)
    store = work / SPECTRA
    chunks = sorted(p for p in (store / "pga_crit" / "c").rglob("*") if p.is_file())
    flipped = bytearray(chunks[0].read_bytes())
    flipped[len(flipped) // 2] ^= 0x04
    chunks[0].write_bytes(bytes(flipped))
    chunks[1].write_bytes(chunks[1].read_bytes()[:-7])
    done = sorted(p for p in (store / "done" / "c").rglob("*") if p.is_file())
    done[-1].write_bytes(done[-1].read_bytes()[:3])
    config = write_config(work)
    snakemake(work, *TARGETS, "--forcerun", "spectra", configfile=config)
    summary = json.loads((work / f"results/{STUDY}/spectra.done.json").read_text())
    assert summary["damaged"] == 3 and summary["computed"] == 3
    assert _chunk_files(store) == _chunk_files(reference / SPECTRA)
    assert store_bytes(store) == store_bytes(reference / SPECTRA)
    log = (work / f"results/logs/{STUDY}/spectra.log").read_text()
    assert len(re.findall(r"chunk \d+ damaged, ", log)) == 3 and "unreadable" in log
    assert (work / f"results/{STUDY}/mean_spectra.csv").read_text() == \
        (reference / f"results/{STUDY}/mean_spectra.csv").read_text()


@pytest.mark.parametrize("config", ["config/config.yaml", "config/paper.yaml"])
def test_lint_is_clean(config, tmp_path):
    lint = snakemake(tmp_path, "--lint", configfile=REPO / config, check=False)
    text = lint.stdout + lint.stderr
    found = [line for line in text.splitlines() if line.startswith("Lints for")]
    assert lint.returncode == 0 and not found, "\n".join(found) or text[-3000:]


@pytest.mark.parametrize("config", ["config/config.yaml", "config/paper.yaml"])
def test_dry_run_plans_every_rule(config, tmp_path):
    dry = snakemake(tmp_path, "-n", configfile=REPO / config)
    for rule in ("motions", "numba_cache", "spectra", "tilt_map",
                 "mean_spectra"):
        assert re.search(rf"^{rule}\s+\d+$", dry.stdout, re.MULTILINE), rule
    assert not (tmp_path / "results").exists()


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda c: c["studies"][STUDY].update(Rr=[1.0]),
         "unknown config key 'Rr' in studies.tiny; allowed: R, "),
        (lambda c: c.update(studys={}), "unknown config key 'studys' at the top level"),
        (lambda c: c.update(quantity="median"), "quantity must be one of "
         "['exceedance_quantile', 'first_exceedance'], got 'median'"),
        (lambda c: c.update(quantity={"p": 1.5}), "quantity.p must be a number in (0, 1), "
         "got 1.5"),
        (lambda c: c.update(quantity={"name": "exceedance_quantile", "w": 0.5}),
         "quantity.w must be a number in (0, 0.5), got 0.5"),
        (lambda c: c.update(quantity={"w": 0}), "quantity.w must be a number in (0, 0.5), "
         "got 0"),
        (lambda c: c["ensembles"]["tiny"].update(record="kobe-1995"),
         "ensembles.tiny.record='kobe-1995' is not a known record"),
        (lambda c: c["ensembles"]["tiny"].update(paths=["nosuch_x.AT2", "nosuch_y.AT2"]),
         "ensembles.tiny.paths[0]='nosuch_x.AT2' does not exist"),
        (lambda c: c["studies"][STUDY]["runs"][1].update(limit_states=["tilt:50"]),
         "studies.tiny.runs[1].limit_states: 'tilt:50' with tan_alpha=0.2"),
        (lambda c: c["studies"][STUDY]["runs"][1].update(modes=["3d", "4d"]),
         "config key studies.tiny.runs[1].modes[1]='4d': must be one of"),
        (lambda c: c["studies"][STUDY]["runs"][1].pop("limit_states"),
         "config studies.tiny.runs[1]: 'limit_states' is a required property"),
        (lambda c: c["studies"][STUDY]["runs"][0].update(limit_states=["tilt:0.5", "tilt:1/2"]),
         "studies.tiny.runs[0].limit_states names one tilt goal twice"),
        (lambda c: c["studies"][STUDY].update(ensemble="nope"),
         "studies.tiny.ensemble='nope' is not a key of ensembles"),
        (lambda c: c["studies"][STUDY].update(hazard="nosuch_hazard.csv"),
         "studies.tiny.hazard: hazard must be an existing hazard-curve file"),
        (lambda c: c["studies"][STUDY].update(hazard={"k0": 1e-4, "k": 2.0,
                                                     "measure": "sa:1.0"}),
         "studies.tiny.hazard: the hazard (power law k0=0.0001/yr, k=2 (SA(1.0))) is of "
         "SA(1.0), study tiny of pga, pgv only: add sa:1.0 to the study's intensity_measures"),
        (lambda c: c["studies"][STUDY].update(R=[float("nan")]),
         "studies.tiny.R[0]=nan: must be a finite number"),
        (lambda c: c["studies"][STUDY]["tilt_map"].update(intensity=[1.0, float("inf")]),
         "studies.tiny.tilt_map.intensity[1]=inf: must be a finite number"),
        (lambda c: c["studies"][STUDY]["tilt_map"].update(motion="el-centro"),
         "studies.tiny.tilt_map.motion='el-centro' is not a motion of the ensemble"),
        (lambda c: c["motions"].update(max_duration=0.01),
         "motions.max_duration=0.01 s keeps fewer than two samples of ensembles.tiny"),
        (lambda c: c["studies"][STUDY].update(R={"start": 1, "stop": 2, "num": 100_000_000}),
         "studies.tiny.R: 100000000 values exceed the bound"),
        (lambda c: c["ensembles"]["tiny"].update(
            record="my-pair", paths=[str(package_record(ELC180)), str(package_record(ELC270))]),
         "ensembles.tiny.mw is needed: record 'my-pair' is not in the catalogue"),
        (lambda c: c["ensembles"]["tiny"].update(record="loma-prieta-sjte", vertical=True),
         "ensembles.tiny.vertical: true for record 'loma-prieta-sjte', which ships no files"),
        (lambda c: c["ensembles"]["tiny"].update(
            record="my-pair", vertical=True,
            paths=[str(package_record(f)) for f in (ELC180, ELC270,
                                                    "RSN753_LOMAP_CLS-UP.AT2")]),
         "vertical file RSN753_LOMAP_CLS-UP.AT2: dt 0.005 s differs from the horizontal "
         "pair's 0.01 s"),
    ],
    ids=["unknown-key", "unknown-top-level-key", "quantity-unknown", "quantity-p-above-1",
         "quantity-w-half", "quantity-w-zero", "unknown-record", "missing-record-file",
         "tilt-beyond-overturning", "bad-mode", "run-without-limit-states", "goal-twice",
         "missing-ensemble", "missing-hazard-file", "hazard-measure-not-fitted", "nan-grid",
         "inf-grid", "tilt-map-motion", "max-duration", "huge-grid", "user-record-without-mw",
         "vertical-without-file", "vertical-other-dt"],
)
def test_invalid_config_stops_before_any_work(change, message, tmp_path, monkeypatch):
    """The check the Snakefile runs before it plans any job
    (:func:`rocking.config.checks.check_workflow_config`), called in-process on the
    configuration as a YAML file hands it over: one line naming the key and the value.
    That the Snakefile runs this very check, and says its line alone:
    test_the_snakefile_refuses_a_bad_config_with_the_one_check."""
    from snakemake.utils import validate

    from rocking.config.checks import check_workflow_config

    cfg = json.loads(json.dumps(TINY))
    change(cfg)
    cfg = yaml.safe_load(yaml.safe_dump(cfg))  # as --configfile reads it (nan, inf)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError) as refused:
        check_workflow_config(cfg, REPO, validate)
    assert message in str(refused.value)
    assert "\n" not in str(refused.value)  # the message, not the schema
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_the_snakefile_refuses_a_bad_config_with_the_one_check(tmp_path):
    """The one subprocess case of the refusals above: `snakemake -n` stops on the last step
    of check_workflow_config (a hazard file that does not exist), before any job, and says
    the one line."""
    cfg = json.loads(json.dumps(TINY))
    cfg["studies"][STUDY]["hazard"] = "nosuch_hazard.csv"
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(cfg))
    out = snakemake(tmp_path, "-n", *TARGETS, configfile=path, check=False)
    assert out.returncode != 0
    text = out.stdout + out.stderr
    assert "studies.tiny.hazard: hazard must be an existing hazard-curve file" in text
    assert "check_workflow_config" in text  # the Snakefile's one call
    assert len(text.splitlines()) < 15  # the message, not the schema
    assert not (tmp_path / "results").exists()


def test_dry_run_takes_config_numbers_given_as_text(tmp_path):
    """``--config dask='{..., progress_interval: 2}'`` hands the values over as strings."""
    out = snakemake(tmp_path, "-n", *TARGETS, "--config",
                    "dask={scheduler_address: null, progress_interval: 2, worker_timeout: 5}",
                    configfile=write_config(tmp_path), check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    bad = snakemake(tmp_path, "-n", *TARGETS, "--config", "dask={progress_interval: soon}",
                    configfile=write_config(tmp_path), check=False)
    assert bad.returncode != 0
    assert "config key dask.progress_interval='soon'" in bad.stdout + bad.stderr


def test_dask_settings_never_rerun_a_rule(reference, tmp_path):
    """A new progress interval, worker timeout or cluster cannot change a number: after a
    finished run the dry run plans nothing; a result-affecting change still plans spectra."""
    cfg = json.loads(json.dumps(TINY))
    cfg["dask"].update(progress_interval=7, worker_timeout=5,
                       scheduler_file=str(tmp_path / "scheduler.json"))
    path = tmp_path / "dask.yaml"
    path.write_text(yaml.safe_dump(cfg))
    dry = snakemake(reference, "-n", *TARGETS, configfile=path)
    assert "Nothing to be done" in dry.stdout + dry.stderr, dry.stdout[-3000:]
    cfg["accuracy"] = "default"
    path.write_text(yaml.safe_dump(cfg))
    dry = snakemake(reference, "-n", *TARGETS, configfile=path)
    assert re.search(r"^spectra\s+1$", dry.stdout, re.MULTILINE), dry.stdout[-3000:]
    # short "reason" lines: the parameters that changed are a store name and a hash
    reasons = [line for line in dry.stdout.splitlines() if "Params have changed" in line]
    assert reasons and max(map(len, reasons)) < 400, reasons
    assert "spectra-" in " ".join(reasons) and "'runs'" not in " ".join(reasons)


def _planned(workdir: Path, cfg: dict, name: str) -> set[str]:
    """Every output and log file a dry run of the whole workflow plans for ``cfg``."""
    path = workdir / f"{name}.yaml"
    path.write_text(yaml.safe_dump(cfg))
    dry = snakemake(workdir, "-n", configfile=path)
    files = set()
    for line in dry.stdout.splitlines():
        m = re.match(r"^\s+(output|log): (.*)$", line)
        if m:
            files.update(f.strip() for f in m[2].split(", "))
    assert files, dry.stdout[-2000:]
    return files


def test_two_configs_write_disjoint_outputs(tmp_path):
    """Two output roots share no file; one root shared by studies and ensembles of other
    names shares only what depends on no study (Figs 3 and 4, the compilation marker); an
    ensemble name given other settings writes other motion files."""
    a = {**json.loads(json.dumps(TINY)), "output": "results/a"}
    b = {**json.loads(json.dumps(TINY)), "output": "results/b/"}
    plan_a, plan_b = _planned(tmp_path, a, "a"), _planned(tmp_path, b, "b")
    assert not plan_a & plan_b
    assert all(f.startswith("results/a/") for f in plan_a)
    assert all(f.startswith("results/b/") for f in plan_b)
    # the same root, another study on another ensemble (both reproductions of the paper, so
    # that both draw the paper's model figures, Figs 3 and 4)
    a["studies"][STUDY]["reproduces"] = "vassiliou2017"
    plan_a = _planned(tmp_path, a, "a")
    c = json.loads(json.dumps(a))
    c["ensembles"] = {"other": {**c["ensembles"]["tiny"], "n_synthetic": 2}}
    c["studies"] = {"other": {**c["studies"][STUDY], "ensemble": "other"}}
    plan_c = _planned(tmp_path, c, "c")
    shared = {Path(f).name for f in plan_a & plan_c}
    assert shared == {f"{stem}{suffix}" for stem in ("fig03_wobbling_period",
                                                     "fig04_free_vibration")
                      for suffix in (".png", ".pdf", ".json", ".log")} | \
        {"numba_cache.json", "numba_cache.log"}, sorted(shared)
    for f in plan_c - plan_a:
        assert not f.startswith("results/a/tiny/")
    # the same ensemble name with another seed: its own motion files, never the other's
    d = json.loads(json.dumps(a))
    d["ensembles"]["tiny"]["seed"] = 8
    d["studies"] = {"seed8": d["studies"][STUDY]}
    d["studies"]["seed8"]["ensemble"] = "tiny"
    motions_a = {f for f in plan_a if "/motions/" in f}
    motions_d = {f for f in _planned(tmp_path, d, "d") if "/motions/" in f}
    # .nc, .compare.nc, .json, .params.json (the recorded fits) and the log
    assert len(motions_a) == len(motions_d) == 5 and not motions_a & motions_d


def test_a_changed_setting_adds_a_store_and_changing_back_reuses_it(reference, tmp_path):
    """A changed accuracy preset adds a store beside the first (kept byte for byte);
    changing back finds the first store finished: nothing is computed again."""
    work = tmp_path / "work"
    shutil.copytree(reference, work, symlinks=True)
    folder = work / "results" / STUDY
    first = (work / SPECTRA).readlink()
    before = store_bytes(folder / first)
    target = f"results/{STUDY}/spectra.done.json"
    cfg = json.loads(json.dumps(TINY))
    cfg["accuracy"] = "default"
    path = work / "default.yaml"
    path.write_text(yaml.safe_dump(cfg))
    snakemake(work, target, configfile=path)
    second = (work / SPECTRA).readlink()
    assert second != first
    assert str(second) == f"spectra-{StudySpec.from_config(cfg, STUDY).spectra.digest}.zarr"
    assert store_bytes(folder / first) == before  # the earlier store is kept, untouched
    assert json.loads((work / target).read_text())["computed"] == 8
    # back to the first configuration: resumed in its store, nothing computed
    snakemake(work, *TARGETS, configfile=write_config(work))
    summary = json.loads((work / target).read_text())
    assert summary["store_state"] == "resumed" and summary["computed"] == 0
    assert summary["done_before"] == 8
    assert (work / SPECTRA).readlink() == first
    assert (work / f"results/{STUDY}/mean_spectra.csv").read_text() == \
        (reference / f"results/{STUDY}/mean_spectra.csv").read_text()


def _no_nan(text):
    raise ValueError(f"non-standard JSON constant {text}")


def test_progress_and_dashboard_reach_the_terminal(reference):
    err = (reference / "snakemake.stderr").read_text()
    # spectra: 8 chunks of one point each; tilt map: 2 chunks of 2 analyses
    assert re.search(r"spectra tiny: \d+/8 points done \(\d+ %\), [0-9.e+-]+ point/s, "
                     r"elapsed \d+:\d\d, ETA", err)
    assert "spectra tiny: 8/8 points done (100 %)" in err
    assert "tilt map tiny: 4/4 points done (100 %)" in err
    assert re.search(r"embedded Dask LocalCluster: 2 worker processes.*dashboard: "
                     r"http://127\.0\.0\.1:\d+", err)
    assert "motions tiny: wrote 2 motions" in err
    log = (reference / f"results/logs/{STUDY}/spectra.log").read_text()
    assert "spectra tiny: 8/8 points done (100 %)" in log and "dashboard: http://" in log
    # quiet logs: no scipy mmap warning from reading the ensemble file
    for path in (reference / "results/logs").rglob("*.log"):
        assert "Cannot close a netcdf_file" not in path.read_text(), path


def test_every_output_is_self_describing(reference):
    from rocking.motions.ensemble_io import open_netcdf

    spectra = xr.open_zarr(reference / SPECTRA, consolidated=True)
    tm = xr.open_zarr(reference / f"results/{STUDY}/tilt_map.zarr", consolidated=True)
    with open_netcdf(reference / f"results/{STUDY}/mean_spectra.nc") as means:
        for ds in (spectra, tm, means):
            for name in ds.variables:
                attrs = ds[name].attrs
                assert attrs.get("units") and attrs.get("long_name"), name
    assert spectra["pga_crit_g"].attrs["units"] == "gravity"
    np.testing.assert_array_equal(spectra["pga_crit_g"].values,
                                  spectra["pga_crit"].values * 0.2)
    # each motion says where it comes from and what was done to it
    record = spectra.sel(motion="el-centro-1940")
    text = str(record["processing"].values)
    assert "rotated -70.46 deg to principal axes" in text and "cut to 3 s" in text
    assert "high-passed (oscillator, fc 0.09465 Hz)" in text
    assert str(spectra.sel(motion="el-centro-1940-rdk-000")["source_record"].values) == \
        "el-centro-1940"
    table = pd.read_csv(reference / f"results/{STUDY}/mean_spectra.csv")
    assert "R [m]" in table.columns and "mean_pga_g [g]" in table.columns
    for path in (reference / "results").rglob("*.json"):
        json.loads(path.read_text(), parse_constant=_no_nan)


@pytest.mark.parametrize(("mode", "motion", "R", "states"),
                         [("3d", "el-centro-1940", 3.0, "overturning,tilt:1/3"),
                          ("2d-x", "el-centro-1940-rdk-000", 1.0, "overturning")])
def test_store_entry_reproduced_by_the_cli_and_the_library_bit_for_bit(reference, tmp_path,
                                                                         mode, motion, R, states):
    from rocking.cli import main
    from rocking.store.select import select

    ds = xr.open_zarr(reference / SPECTRA, consolidated=True)
    out = tmp_path / "spectrum.json"  # every bit (the CSV rounds to 10 digits)
    # the README's command: the store's ensemble file and motion, mode, the limit states the
    # study asked of the mode (one search serves them all: its steps depend on the set)
    assert main(["spectra", "--ensemble", str(reference / f"{MOTIONS}.nc"),
                 "--motion", motion, "--R", str(R), "--tan-alpha", "0.2", "--mode", mode,
                 "--limit-states", states, "--accuracy", "fast",
                 "-q", "-o", str(out)]) == 0
    table = pd.DataFrame(json.loads(out.read_text())["results"]).set_index("limit_state")
    for spelling, row in (("overturning", "overturning"), ("tilt:1/3", "tilt:1/3"),
                          ("excessive-tilt", "tilt:1/3"), ("tilt:0.3333", "tilt:1/3")):
        if row not in table.index:
            continue
        stored = select(ds, mode=mode, motion=motion, tan_alpha=0.2, R=R, limit_state=spelling)
        assert table.loc[row, "pga_crit"] == float(stored["pga_crit"])
        assert table.loc[row, "pga_crit_g"] == float(stored["pga_crit_g"])
        assert table.loc[row, "n_analyses"] == int(stored["n_analyses"])
    # the README's one xarray call: canonical labels need nothing but .sel
    label = "tilt:1/3" if "tilt:1/3" in table.index else "overturning"
    assert ds["pga_crit"].sel(mode=mode, motion=motion, tan_alpha=0.2, R=R,
                              limit_state=label).values == \
        table.loc[label, "pga_crit"]
