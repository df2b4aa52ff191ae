"""Probe list (issue 31): a damaged input or store never yields a changed result.

Each case damages one thing a tiny study depends on (its motions file, a record file, a chunk,
a coordinate, its configuration, its cluster, a concurrent run) and asserts the outcome: the
tables identical to an undamaged run's, or an error that names what is wrong and the way out;
never a changed number. The study runs the real preparation, verification, fill and table code
(:mod:`rocking.execution.prepare`, :mod:`rocking.execution.cluster`, :mod:`rocking.store.integrity`,
:mod:`rocking.study.aggregate`, :mod:`rocking.study.records`) with the closed-form stand-in
engine of tests/_store_standins.py, so that a case runs in about a second.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
import time
import warnings
from collections.abc import Callable, Sequence
from functools import partial
from pathlib import Path

import _store_standins as standin
import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml
import zarr

from rocking import store
from rocking.config.checks import check_config
from rocking.config.study import StudySpec
from rocking.execution import cluster, prepare, products, tasks
from rocking.motions.ensemble_io import (
    MotionsDigestError,
    digest_path,
    load_ensemble,
    save_ensemble,
)
from rocking.motions.readers import RecordFormatError, read_at2, read_text
from rocking.store import integrity
from rocking.study.aggregate import ensemble_statistics, requested_answers, write_statistics
from rocking.study.records import write_record_tables

REPO = Path(__file__).resolve().parents[1]
CONFIG = {"accuracy": "fast", "search": {"upper": 20.0},
          "ensembles": {"test": {"record": "el-centro-1940"}},
          "studies": {"s": {"ensemble": "test", "R": [0.5, 1.0, 2.0, 9.0], "chunk_R": 1,
                            "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                      "limit_states": ["overturning", "tilt:1/3"]}]}}}
SPEC = StudySpec.from_config(CONFIG, "s").spectra
FILL = partial(tasks.fill_spectra_region, batch=standin.batch)


class Study:
    """A tiny study in ``folder``: its motions file, its keyed spectra store, its tables."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.motions = folder / "motions" / "test.nc"
        self.store = prepare.keyed(folder / "spectra.zarr", SPEC.digest)

    def make_motions(self) -> None:
        save_ensemble(self.motions, standin.motions(n=3))

    def spectra(self) -> dict:
        """The spectra rule: prepare the store (lock, resume or create), verify, fill."""
        with store.locked(self.store):
            products.prepare_store("spectra", self.store, SPEC, SPEC.digest, self.motions)
            return cluster.fill_store(integrity.open_checked(self.store, "r+"), FILL, self.motions,
                                      config_digest=SPEC.digest, in_process_analyses=10**9)

    def tables(self) -> dict[str, bytes]:
        """The table rules: the store checked whole, then mean_spectra and records.csv."""
        out = self.folder / "tables"
        shutil.rmtree(out, ignore_errors=True)
        out.mkdir()
        integrity.require_intact(self.store, say=lambda s: None)
        with xr.open_zarr(self.store, consolidated=True) as ds:
            stats = ensemble_statistics(ds)
        write_statistics(stats, out / "mean_spectra.nc", out / "mean_spectra.csv")
        write_record_tables(self.store, self.motions, ["pga"], out / "records.csv",
                            out / "suite_fragility.csv")
        return {p.name: p.read_bytes() for p in sorted(out.glob("*.csv"))}

    def chunk(self, name: str, region: int) -> Path:
        layout = store.open_layout(self.store)
        group = zarr.open_group(self.store, mode="r")
        dims = tuple(group[name].metadata.dimension_names)
        return integrity.chunk_file(self.store, group[name],
                                    layout.selection(dims, layout.region(region)))

    def coord_chunk(self, name: str) -> Path:
        files = [p for p in (self.store / name).rglob("*") if p.is_file()
                 and p.name != "zarr.json"]
        assert len(files) == 1, files
        return files[0]


@pytest.fixture(scope="module")
def baseline(tmp_path_factory) -> dict[str, bytes]:
    """The tables of the undamaged study."""
    s = Study(tmp_path_factory.mktemp("baseline"))
    s.make_motions()
    s.spectra()
    tables = s.tables()
    assert b"nan" not in tables["records.csv"].lower()
    return tables


@pytest.fixture()
def study(tmp_path) -> Study:
    s = Study(tmp_path)
    s.make_motions()
    s.spectra()
    return s


def _flip(path: Path, where: float = 0.5, mask: int = 0x10) -> None:
    data = bytearray(path.read_bytes())
    data[int(len(data) * where)] ^= mask
    path.write_bytes(bytes(data))


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: len(path.read_bytes()) // 2])


# --------------------------------------------------------------------------------------------
# Family 1: the motions file (silent before: a damaged file, the store rebuilt as told, gave
# changed tables)
# --------------------------------------------------------------------------------------------

def _damage_motions(s: Study) -> None:
    """One ``ay`` sample of the stored record becomes another number (a flipped byte)."""
    with xr.open_dataset(s.motions, engine="scipy", mmap=False) as ds:
        ay = ds["ay"].values
    data = bytearray(s.motions.read_bytes())
    target = np.float64(ay[0, 10]).tobytes()[::-1]  # NetCDF3 is big-endian
    at = bytes(data).find(target)
    assert at > 0
    data[at] ^= 0x7F  # the exponent byte: the sample becomes ~1e300 or its like
    s.motions.write_bytes(bytes(data))


def test_damaged_motions_file_is_refused_where_it_is_read(study):
    _damage_motions(study)
    with pytest.raises(MotionsDigestError) as err:
        load_ensemble(study.motions)
    text = str(err.value)
    assert str(study.motions) in text and "snakemake --forcerun motions" in text
    assert "\n" not in text


def test_damaged_motions_file_stops_the_spectra_rule_naming_the_motions(study):
    _damage_motions(study)
    with pytest.raises(MotionsDigestError, match=r"test\.nc.*rebuild the motions"):
        study.spectra()


def test_damaged_motions_file_and_deleted_store_never_give_tables(study):
    """The silent case: the store deleted as the old message said, then a plain rerun."""
    _damage_motions(study)
    shutil.rmtree(study.store)
    with pytest.raises(MotionsDigestError, match="rebuild the motions"):
        study.spectra()
    assert not study.store.exists() or not store.done_mask(study.store).any()


def test_damaged_motions_file_rebuilt_as_told_gives_identical_tables(study, baseline):
    _damage_motions(study)
    shutil.rmtree(study.store)
    study.make_motions()  # what `snakemake --forcerun motions` does
    study.spectra()
    assert study.tables() == baseline


def test_damaged_motions_file_is_refused_by_the_table_rule(study):
    _damage_motions(study)
    with pytest.raises(MotionsDigestError, match="rebuild the motions"):
        study.tables()


def test_motions_file_without_digest_is_recorded_then_checked(study, baseline):
    digest_path(study.motions).unlink()  # a file made before digests were written
    assert study.tables() == baseline
    assert digest_path(study.motions).is_file()
    _damage_motions(study)
    with pytest.raises(MotionsDigestError):
        load_ensemble(study.motions)


def test_damaged_digest_file_is_refused(study):
    side = digest_path(study.motions)
    side.write_text("0" * 64 + "  test.nc\n")
    with pytest.raises(MotionsDigestError, match="was written with sha256 0000"):
        load_ensemble(study.motions)


def test_digest_file_is_sha256sum_format(study):
    out = subprocess.run(["sha256sum", "-c", digest_path(study.motions).name],
                         cwd=study.motions.parent, capture_output=True, text=True)
    assert out.returncode == 0 and "OK" in out.stdout


# --------------------------------------------------------------------------------------------
# Family 2: record files parsed strictly (silent before: a number cut before its exponent was
# read 10^4 times too large)
# --------------------------------------------------------------------------------------------

AT2_HEAD = ("PEER NGA STRONG MOTION DATABASE RECORD\nSomewhere, 1/1/2000, Station, 90\n"
            "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    7, DT=   .0100 SEC,\n")
AT2_BODY = ("   .1000000E-02  -.2000000E-02   .3000000E-02\n"
            "   .4000000E-02   .5000000E-02  -.6000000E-02\n"
            "   .1773449E-03\n")


def _at2(tmp_path, body: str, name="x.AT2") -> Path:
    p = tmp_path / name
    p.write_text(AT2_HEAD + body)
    return p


def test_intact_at2_is_read_to_its_values(tmp_path):
    acc, dt, meta = read_at2(_at2(tmp_path, AT2_BODY))
    assert acc.tolist() == [1e-3, -2e-3, 3e-3, 4e-3, 5e-3, -6e-3, 0.1773449e-3] and dt == 0.01


@pytest.mark.parametrize(("body", "line", "what"), [
    # cut inside the last number: its exponent lost (the file)
    (AT2_BODY.replace(".1773449E-03", ".1773449"), 7, "not written like"),
    # cut inside the exponent
    (AT2_BODY.replace(".1773449E-03\n", ".1773449E-0"), 7, "not written like"),
    # cut inside the mantissa
    (AT2_BODY.replace(".1773449E-03", ".17734"), 7, "not written like"),
    # a middle line short of one value (the count still NPTS: one value added at the end)
    (AT2_BODY.replace("   .5000000E-02", "").replace(
        "   .1773449E-03", "   .1773449E-03   .1000000E-02"), 6, "2 values on this line"),
    # the count differs from NPTS
    (AT2_BODY.replace("   .1773449E-03\n", ""), 6, "NPTS=7"),
])
def test_damaged_at2_is_refused_naming_file_and_line(tmp_path, body, line, what):
    p = _at2(tmp_path, body)
    with pytest.raises(RecordFormatError, match=what) as err:
        read_at2(p)
    assert err.value.path == str(p) and err.value.line == line
    assert f"{p}, line {line}: " in str(err.value) and "\n" not in str(err.value)


def test_text_record_in_exponent_format_cut_short_is_refused(tmp_path):
    rows = [f"{0.01 * i:.2f} {v:.6e}" for i, v in enumerate(np.sin(np.arange(30.0)) * 1e-3)]
    p = tmp_path / "x.txt"
    p.write_text("\n".join(rows) + "\n")
    assert read_text(p)[0].size == 30
    p.write_text("\n".join(rows)[:-4] + "\n")  # the last exponent lost
    with pytest.raises(RecordFormatError, match=r"line 30: value .* not written like"):
        read_text(p)


def test_text_record_in_free_format_is_still_read(tmp_path):
    p = tmp_path / "x.txt"
    p.write_text("0.0 0.1\n0.01 -2.5e-3\n0.02 3\n0.03 0.25\n")
    assert read_text(p)[0].tolist() == [0.1, -2.5e-3, 3.0, 0.25]


def test_dry_run_refuses_a_cut_record_naming_key_file_and_line(tmp_path):
    good = _at2(tmp_path, AT2_BODY, "y.AT2")
    cut = _at2(tmp_path, AT2_BODY.replace(".1773449E-03", ".1773449"))
    cfg = _config(lambda c: c["ensembles"]["elcentro"].update(
        record="site", paths=[str(cut), str(good)], mw=6.5))
    with pytest.raises(ValueError, match=rf"ensembles.elcentro.paths=.*{cut}, line 7: value"):
        check_config(cfg)


# --------------------------------------------------------------------------------------------
# Family 3: a table only from a complete, verified store (silent before: a region whose done
# flag and data were gone became NaN rows)
# --------------------------------------------------------------------------------------------

def _delete_region(s: Study, region: int) -> None:
    for name in ("done", "pga_crit", "pga_crit_g", "not_reached", "failed"):
        s.chunk(name, region).unlink()


def test_region_with_done_flag_and_data_gone_is_never_tabulated(study):
    _delete_region(study, 3)
    with pytest.raises(ValueError, match=r"1 chunks not computed \[3\] \(the first at "
                                         r"\{'mode': \['3d'\].*--forcerun spectra"):
        study.tables()


def test_mean_spectra_of_an_incomplete_store_says_so_in_one_line(study):
    _delete_region(study, 3)
    with xr.open_zarr(study.store, consolidated=True) as ds:
        with pytest.raises(ValueError, match=r"spectra store is incomplete: 1 points not "
                                             r"done, first at \{'mode': '3d'"):
            ensemble_statistics(ds)


def test_region_gone_is_recomputed_by_a_plain_rerun_to_identical_tables(study, baseline):
    _delete_region(study, 3)
    summary = study.spectra()
    assert summary["computed"] == 1
    assert study.tables() == baseline


def test_unflagged_nan_answer_is_refused_not_written_as_an_empty_row(study):
    with xr.open_zarr(study.store, consolidated=True) as ds:
        ds = ds.load()
    ds["pga_crit"][0, 0, 0, 0, 0] = np.nan  # reached, requested, and no number
    with pytest.raises(ValueError, match=r"1 requested answers are NaN without a flag"):
        requested_answers(ds, ["pga_crit", "not_reached"])


@pytest.mark.parametrize("damage", ["flip", "truncate", "delete"])
def test_damaged_data_chunk_is_refused_then_repaired_to_identical_tables(study, baseline,
                                                                         damage):
    chunk = study.chunk("pga_crit", 5)
    {"flip": _flip, "truncate": _truncate, "delete": Path.unlink}[damage](chunk)
    with pytest.raises(ValueError, match=r"damaged chunks \[5\]"):
        study.tables()
    assert study.spectra()["damaged"] == 1
    assert study.tables() == baseline


def test_damaged_done_chunk_is_repaired_to_identical_tables(study, baseline):
    _truncate(study.chunk("done", 2))
    with pytest.raises(ValueError, match=r"damaged chunks \[2\]"):
        study.tables()
    study.spectra()
    assert study.tables() == baseline


def test_interrupted_fill_resumes_to_identical_tables(tmp_path, baseline):
    s = Study(tmp_path)
    s.make_motions()
    products.prepare_store("spectra", s.store, SPEC, SPEC.digest, s.motions)
    for i in (0, 5, 7):  # a run killed after three regions
        FILL(s.store, i, motions=s.motions)
    with pytest.raises(ValueError, match="chunks not computed"):
        s.tables()
    assert s.spectra()["done_before"] == 3
    assert s.tables() == baseline


# --------------------------------------------------------------------------------------------
# Family 4: coordinates verified like data, repaired by the same rerun
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize(("name", "damage"), [
    ("R", _flip), ("R", Path.unlink), ("R", _truncate), ("tan_alpha", _flip),
    ("requested", _flip), ("source_record", _flip), ("motion", _flip),
])
def test_damaged_coordinate_is_named_then_repaired_to_identical_tables(study, baseline, name,
                                                                       damage):
    damage(study.coord_chunk(name))
    if damage is not Path.unlink or name != "R":
        # unreadable: every reader names the store and the repair
        with pytest.raises(ValueError, match=rf"{study.store.name}.*--forcerun spectra"):
            study.tables()
    study.spectra()  # the documented repair: the rule run again
    assert study.tables() == baseline


def test_deleted_coordinate_chunk_is_restored_not_read_as_fill_values(study):
    study.coord_chunk("R").unlink()  # reads back as the fill value, with no error
    assert not np.array_equal(store.open_layout(study.store).coords["R"], SPEC.R)
    state = products.prepare_store("spectra", study.store, SPEC, SPEC.digest, study.motions)
    assert state == "resumed"
    np.testing.assert_array_equal(store.open_layout(study.store).coords["R"], SPEC.R)


# --------------------------------------------------------------------------------------------
# Family 5: the dry run sees what would fail later
# --------------------------------------------------------------------------------------------

BASE = yaml.safe_load((REPO / "config/config.yaml").read_text())


def _config(change):
    cfg = json.loads(json.dumps(BASE))
    change(cfg)
    return cfg


@pytest.mark.parametrize(("change", "message"), [
    (lambda c: c["ensembles"]["elcentro"].update(mw=12),
     r"ensembles.elcentro.mw=12 is outside 3-9.5"),
    (lambda c: c["ensembles"]["elcentro"].update(mw=2.5),
     r"ensembles.elcentro.mw=2.5 is outside 3-9.5"),
    (lambda c: c["ensembles"]["elcentro"].update(fc_hz=80.0),
     r"ensembles.elcentro.fc_hz=80.0: the high-pass corner must be below the Nyquist "
     r"frequency 50 Hz"),
])
def test_dry_run_refuses_physical_bounds_naming_the_key(change, message):
    with pytest.raises(ValueError, match=message):
        check_config(_config(change))


def test_command_line_refuses_a_magnitude_out_of_bounds(tmp_path, capsys):
    from rocking.cli import main

    assert main(["motions", "--mw", "12", "-n", "1", "-o", str(tmp_path / "m.nc")]) != 0
    err = capsys.readouterr().err
    assert "--mw=12.0 is outside 3-9.5" in err and not (tmp_path / "m.nc").exists()


def test_dry_run_warns_of_a_padding_many_times_the_record():
    # another high-pass is another fit: the recorded parameters of the shipped one do not apply
    cfg = _config(lambda c: c["ensembles"]["elcentro"].update(fc_hz=0.002, params=None))
    with pytest.warns(UserWarning, match=r"ensembles.elcentro: the oscillator high-pass at "
                                         r"0.002 Hz .* pads 1989 s of zeros onto a record of "
                                         r"54 s"):
        check_config(cfg)


def test_dry_run_of_the_shipped_configuration_is_silent():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_config(_config(lambda c: None))


# --------------------------------------------------------------------------------------------
# Family 6: a cluster says what is wrong with its workers
# --------------------------------------------------------------------------------------------

def test_environment_problems_name_worker_package_and_versions():
    here = {"rocking": "1.0", "numpy": "2.1.0", "numba": "0.60.0"}
    workers = {"tcp://a:1": dict(here),
               "tcp://b:2": {**here, "rocking": "cannot import: ModuleNotFoundError: x"},
               "tcp://c:3": {**here, "numpy": "2.0.0"},
               "tcp://d:4": OSError("gone")}
    problems = cluster.environment_problems(here, workers)
    assert problems == [
        "worker tcp://b:2 cannot import rocking (ModuleNotFoundError: x)",
        "worker tcp://c:3 has numpy '2.0.0' where this run has '2.1.0'",
        "worker tcp://d:4 could not run a version check (OSError: gone)",
    ]


def _fake_package(folder: Path, body: str) -> Path:
    (folder / "rocking").mkdir(parents=True)
    (folder / "rocking" / "__init__.py").write_text(body)
    return folder


@pytest.mark.parametrize(("body", "said"), [
    ("raise ModuleNotFoundError(\"No module named 'rocking'\")",
     r"cannot import rocking \(ModuleNotFoundError: No module named 'rocking'\)"),
    ("__version__ = '0.0-other'", "rocking '0.0-other' where this run has"),
])
def test_worker_of_another_environment_is_named_when_it_joins(tmp_path, body, said):
    from distributed import LocalCluster

    env = {**os.environ, "PYTHONPATH": str(_fake_package(tmp_path, body))}
    with LocalCluster(n_workers=0, processes=False, scheduler_port=0, protocol="tcp",
                      dashboard_address=":0") as lc:
        worker = subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_worker", lc.scheduler_address,
             "--nthreads", "1", "--no-nanny"], env=env, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL)
        try:
            with pytest.raises(RuntimeError, match=rf"Dask workers differ from this run's "
                                                   rf"environment: worker tcp://.* {said}"):
                with cluster.dask_client(cluster.Target("address", lc.scheduler_address),
                                         worker_timeout=60.0, say=lambda s: None):
                    pass
        finally:
            worker.terminate()
            worker.wait(timeout=30)


def test_worker_of_this_environment_passes_the_check():
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, processes=False, scheduler_port=0,
                      dashboard_address=":0") as lc, Client(lc) as client:
        cluster.check_workers(client)


# --------------------------------------------------------------------------------------------
# Family 7: two runs of one study (two working directories sharing the results)
# --------------------------------------------------------------------------------------------

HOLD = textwrap.dedent("""
    import sys, time
    from rocking import store
    with store.locked(sys.argv[1]):
        print("held", flush=True)
        time.sleep(float(sys.argv[2]))
""")


def _holder(path: Path, seconds: float, cwd: Path) -> subprocess.Popen:
    proc = subprocess.Popen([sys.executable, "-c", HOLD, str(path), str(seconds)], cwd=cwd,
                            stdout=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert proc.stdout.readline().strip() == "held"
    return proc


def test_second_run_of_a_study_stops_and_deletes_nothing(study, tmp_path, baseline):
    other = tmp_path / "other_workdir"
    other.mkdir()
    proc = _holder(study.store, 30.0, other)
    try:
        # a store the second run would replace (another configuration's hash under the name)
        root = zarr.open_group(study.store, mode="r+")
        root.attrs["config_hash"] = "0000"
        with pytest.raises(RuntimeError, match=rf"{study.store.name}' is in use by pid "
                                               rf"{proc.pid} on .* in {other}"):
            study.spectra()
        assert store.done_mask(study.store).all()  # not replaced
        root.attrs["config_hash"] = SPEC.digest
    finally:
        proc.kill()
        proc.wait()
    study.spectra()  # the lock is free once its holder ended (even killed)
    assert study.tables() == baseline


def test_lock_is_released_when_the_block_ends(tmp_path):
    path = tmp_path / "x.zarr"
    with store.locked(path):
        pass
    t0 = time.perf_counter()
    with store.locked(path):
        assert (tmp_path / "x.zarr.lock").read_text().startswith(f"pid {os.getpid()} ")
    assert time.perf_counter() - t0 < 1.0


# --------------------------------------------------------------------------------------------
# Family 8 (issue 39): every sidecar and cache checked against what made it; errors of known
# cause in one line (silent, traceback or misleading before)
# --------------------------------------------------------------------------------------------

STRIPES = StudySpec.from_config({
    "ensembles": {"test": {"record": "el-centro-1940"}},
    "studies": {"t": {"ensemble": "test", "R": [1.0],
                      "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                "limit_states": ["overturning"]}],
                      "stripes": {"modes": ["3d", "2d-x"], "R": [0.5, 1.0, 2.0],
                                  "intensity": [1.2, 2.0, 3.5, 6.0], "chunk_R": 2}}}},
    "t").stripes


def _stripes_study(folder: Path, gain: float = 1.0) -> tuple[Path, Path]:
    """A filled stripes store of three stand-in motions (``gain`` scales them: another
    study's motions under the same names) and its motions file."""
    from rocking.execution import stripes as st
    from rocking.motions.motion import GroundMotion

    folder.mkdir(parents=True, exist_ok=True)
    ens = folder / "motions.nc"
    save_ensemble(ens, [GroundMotion(gain * m.ax, m.ay, m.dt, m.name, m.metadata)
                        for m in standin.motions(3, npts=300)])
    path = folder / "stripes-0123456789abcdef.zarr"
    products.prepare_store("stripes", path, STRIPES, STRIPES.digest, ens)
    for i in store.pending_regions(path):
        st.fill_stripes_region(path, i, ens)
    store.StoreHandle.open(path).finalize()
    return path, ens


@pytest.fixture(scope="module")
def stripe_studies(tmp_path_factory):
    """Two studies' stripes (other motions), each with its stripe table written once."""
    from rocking.execution import stripes as st

    root = tmp_path_factory.mktemp("stripes")
    out = {}
    for name, gain in (("a", 1.0), ("b", 1.3)):
        path, ens = _stripes_study(root / name, gain)
        csv = root / name / "stripe_fragility.csv"
        st.write_stripe_fragility(path, csv, root / name / "stripe_fragility_bootstrap.nc",
                                  motions=ens, refine=4, resamples=40)
        # the figure's copy of the refined analyses (the workflow's stripe_fragility_refined)
        attrs = xr.open_zarr(path, consolidated=True).attrs
        st.RefineCache(st.refine_cache_path(path), path, attrs).copy_to(
            root / name / "stripe_fragility_refined.jsonl")
        out[name] = (path, ens, csv)
    assert len(st.refine_cache_path(out["b"][0]).read_text().splitlines()) > 1
    return out


def _rewrite(study, folder: Path, cache_from: Path | None = None, record: bool = True,
             record_from: Path | None = None):
    """The stripe table of ``study`` written again in ``folder`` (its store and motions
    copied there), its refinement cache replaced by ``cache_from``'s, with the record of
    ``record_from`` (default: ``cache_from``'s; none with ``record=False``)."""
    from rocking.execution import stripes as st
    from rocking.provenance import record_path

    path, ens, _ = study
    folder.mkdir()
    shutil.copytree(path, folder / path.name)
    shutil.copy(ens, folder / ens.name)
    shutil.copy(digest_path(ens), folder / digest_path(ens).name)
    store_path = folder / path.name
    if cache_from is not None:
        cache = st.refine_cache_path(store_path)
        shutil.copy(cache_from, cache)
        if record:
            record_path(cache).parent.mkdir(exist_ok=True)
            shutil.copy(record_path(record_from or cache_from), record_path(cache))
    csv = folder / "stripe_fragility.csv"
    st.write_stripe_fragility(store_path, csv, folder / "stripe_fragility_bootstrap.nc",
                              motions=folder / ens.name, refine=4, resamples=40)
    return csv, store_path


def test_refinement_cache_of_another_study_is_detected_and_redone(stripe_studies, tmp_path,
                                                                   caplog):
    """Silent before issue 39: a copied .refined.jsonl (other motions, same keys) moved the
    medians. Its record names the store it belongs to: the analyses are redone."""
    from rocking.execution import stripes as st

    foreign = st.refine_cache_path(stripe_studies["b"][0])
    with caplog.at_level("WARNING"):
        csv, _ = _rewrite(stripe_studies["a"], tmp_path / "a2", cache_from=foreign)
    assert csv.read_bytes() == stripe_studies["a"][2].read_bytes()
    assert ".zarr than the one there: started anew" in caplog.text
    # a cache copied without its record (that lies in the study's .provenance/): redone too
    with caplog.at_level("WARNING"):
        csv, _ = _rewrite(stripe_studies["a"], tmp_path / "a3", cache_from=foreign,
                          record=False)
    assert csv.read_bytes() == stripe_studies["a"][2].read_bytes()
    assert "no record of what made it: started anew" in caplog.text


def test_refinement_cache_of_another_study_is_refused_where_it_cannot_be_redone(
        stripe_studies, tmp_path):
    """The figure replays the refinement without motions: a foreign file is named."""
    from rocking.plot import stripe_fragility as fig
    from rocking.provenance import ProvenanceError

    a, b = stripe_studies["a"], stripe_studies["b"]
    refined_b = b[2].parent / "stripe_fragility_refined.jsonl"
    with pytest.raises(ProvenanceError, match=rf"^{refined_b}: not made from zarr:.*: remake it "
                                              rf"with `snakemake --cores 2 {refined_b}`"):
        fig.data(a[0], None, mode="3d", table=a[2], refined=refined_b)
    # its own copy replays to the table's rows
    d = fig.data(a[0], None, mode="3d", table=a[2],
                 refined=a[2].parent / "stripe_fragility_refined.jsonl")
    assert d["panels"]


@pytest.mark.parametrize("damage", ["digit", "cut", "line gone"])
def test_damaged_refinement_cache_is_redone_to_the_same_table(stripe_studies, tmp_path,
                                                             damage, caplog):
    """One digit of an analysis changed (a failed flag, a stripe), the file cut in half, a
    line gone: the cache no longer matches its record, its analyses are redone and the
    table is the one of an undamaged run (before: a changed digit stopped the rule, a line
    gone was silently redone, a cut line silently dropped)."""
    from rocking.execution import stripes as st

    damaged = tmp_path / "damaged.jsonl"
    shutil.copy(st.refine_cache_path(stripe_studies["a"][0]), damaged)
    text = damaged.read_text()
    if damage == "digit":
        text = text.replace('"runs": 1', '"runs": 2', 1).replace('"failed": false',
                                                                   '"failed": true', 1)
    elif damage == "cut":
        text = text[: len(text) // 2]
    else:
        text = "".join(text.splitlines(True)[1:])
    damaged.write_text(text)
    with caplog.at_level("WARNING"):
        csv, _ = _rewrite(stripe_studies["a"], tmp_path / "a2", cache_from=damaged,
                          record_from=st.refine_cache_path(stripe_studies["a"][0]))
    assert csv.read_bytes() == stripe_studies["a"][2].read_bytes()
    assert "started anew" in caplog.text


def test_refinement_cache_killed_between_a_line_and_its_record_keeps_the_rest(
        stripe_studies, tmp_path):
    """A kill after a line is written but before its record: that line is dropped (redone),
    every line before it is kept."""
    from rocking.execution import stripes as st
    from rocking.provenance import read_record

    cache = st.refine_cache_path(stripe_studies["a"][0])
    grown = tmp_path / "grown.jsonl"
    lines = cache.read_text().splitlines(True)
    grown.write_text("".join(lines) + lines[0].replace('"runs": ', '"runs": 9'))
    csv, store_path = _rewrite(stripe_studies["a"], tmp_path / "a2", cache_from=grown,
                               record_from=cache)
    assert csv.read_bytes() == stripe_studies["a"][2].read_bytes()
    kept = st.refine_cache_path(store_path)
    assert kept.read_text() == cache.read_text()
    assert read_record(kept)["size"] == kept.stat().st_size


@pytest.mark.parametrize("table", ["stripe_fragility.csv", "fragility.csv"])
def test_bootstrap_of_another_study_is_refused_by_the_risk_table(stripe_studies, tmp_path,
                                                                 table):
    """Silent before issue 39: only the row count was checked, the interval moved."""
    from rocking.fragility.table import read_fragilities
    from rocking.provenance import ProvenanceError, record_path

    a, b = stripe_studies["a"][2], stripe_studies["b"][2]
    here = tmp_path / table
    shutil.copy(a, here)
    boot = here.with_name(here.stem + "_bootstrap.nc")
    record_path(boot).parent.mkdir()
    src = a.with_name("stripe_fragility_bootstrap.nc")
    for f in (src, record_path(src)):  # the study's samples and their record: read
        shutil.copy(f, record_path(boot) if f.suffix == ".json" else boot)
    if table == "stripe_fragility.csv":
        assert read_fragilities(here, kind="stripes").samples is not None
    src = b.with_name("stripe_fragility_bootstrap.nc")
    for f in (src, record_path(src)):  # another study's
        shutil.copy(f, record_path(boot) if f.suffix == ".json" else boot)
    with pytest.raises(ProvenanceError, match=rf"^{boot}: (made from another {here} than the "
                                              rf"one there|not made from {here}): remake it "
                                              rf"with `snakemake --cores 2 {boot}`"):
        read_fragilities(here, kind="stripes")


def test_truncated_bootstrap_names_file_and_way_out(stripe_studies, tmp_path):
    """Traceback before issue 39: ValueError: When changing to a larger dtype..."""
    from rocking.fragility.table import read_fragilities
    from rocking.provenance import ProvenanceError

    a = stripe_studies["a"][2]
    here = tmp_path / "stripe_fragility.csv"
    shutil.copy(a, here)
    boot = tmp_path / "stripe_fragility_bootstrap.nc"
    shutil.copytree(a.parent / ".provenance", tmp_path / ".provenance")
    shutil.copy(a.with_name(boot.name), boot)
    _truncate(boot)
    with pytest.raises(ProvenanceError, match=rf"^{boot}: cut short \(\d+ of its \d+ bytes\): "
                                              rf"remake it with `snakemake --cores 2 {boot}`"):
        read_fragilities(here, kind="stripes")


def test_missing_bootstrap_is_said_never_a_silent_blank(stripe_studies, tmp_path, caplog):
    from rocking.fragility.table import read_fragilities

    here = tmp_path / "stripe_fragility.csv"
    shutil.copy(stripe_studies["a"][2], here)
    with caplog.at_level("WARNING"):
        assert read_fragilities(here, kind="stripes").samples is None
    assert "has no bootstrap samples beside it (stripe_fragility_bootstrap.nc): the risk " \
           "table's lambda_p05/lambda_p95 of its rows stay empty" in caplog.text


def test_suite_bootstrap_records_its_table(study, tmp_path):
    """suite_fragility_bootstrap.nc's record names its table; another run's table (one byte
    more) is refused."""
    from rocking.fragility.bootstrap import read_bootstrap
    from rocking.provenance import ProvenanceError, file_sha256, read_record

    out = tmp_path / "t"
    out.mkdir()
    csv = out / "suite_fragility.csv"
    write_record_tables(study.store, study.motions, ["pga"], out / "records.csv", csv)
    boot = out / "suite_fragility_bootstrap.nc"
    assert read_record(boot)["inputs"] == {"suite_fragility.csv": file_sha256(csv)}
    read_bootstrap(boot, table=csv)
    csv.write_text(csv.read_text() + "\n")
    with pytest.raises(ProvenanceError, match=rf"^{boot}: made from another {csv} than"):
        read_bootstrap(boot, table=csv)


# A full disk: one line naming where, from the job's log block (every rule's script runs in
# it), nothing half-written kept.

def _log_block(tmp_path, body, log=None, outputs=()):
    """``body()`` inside the rules' log block in a child process: (exit status, stderr)."""
    code = textwrap.dedent(f"""
        import sys
        sys.path[:0] = {[str(REPO / "src"), str(REPO / "tests")]!r}
        from rocking.execution.logs import log_to
        with log_to({str(log or tmp_path / "job.log")!r}, outputs={list(map(str, outputs))!r}):
            {body}
        """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=tmp_path, timeout=300)
    return out.returncode, out.stderr


def _small_filesystem(folder: Path) -> Path | None:
    """A 1 MiB tmpfs at ``folder`` (root only), or None."""
    folder.mkdir()
    ok = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(folder)],
                        capture_output=True).returncode == 0
    return folder if ok else None


@pytest.fixture()
def full_disk(tmp_path):
    """A filesystem with no space left (a 1 MiB tmpfs filled), or /dev/full's stand-in."""
    small = _small_filesystem(tmp_path / "small")
    if small is None:
        pytest.skip("mounting a tmpfs needs root; test_figure_on_dev_full covers the line")
    (small / "filler").write_bytes(b"\0" * (1 << 20) + b"")  # fills what is left
    try:
        yield small
    finally:
        subprocess.run(["umount", str(small)], check=False)


def test_figure_on_a_full_disk_says_so_in_one_line(tmp_path, full_disk):
    """Traceback before (PIL OSError: [Errno 28] from a figure)."""
    (full_disk / "filler").unlink()
    (full_disk / "logs").mkdir()
    (full_disk / "filler").write_bytes(b"\0" * (1 << 20))  # the log's folder exists; full
    rc, err = _log_block(tmp_path, "import matplotlib; matplotlib.use('Agg'); "
                         "import matplotlib.pyplot as plt; fig = plt.figure(); "
                         "fig.gca().plot(range(100000)); "
                         f"fig.savefig({str(full_disk / 'fig.png')!r}, dpi=300)",
                         log=full_disk / "logs" / "job.log", outputs=[full_disk / "fig.png"])
    assert (rc, err.strip()) == (1, f"error: no space left on {full_disk / 'fig.png'}: free "
                                    "space there and run again (nothing half-written was "
                                    "kept)")


def test_table_on_a_full_disk_keeps_nothing_half_written(stripe_studies, tmp_path, full_disk):
    """The stripe table rule on a full disk (exit 120, no reason, before): one line; neither
    the table nor its samples left half-written."""
    path, ens, _ = stripe_studies["a"]
    csv, nc = full_disk / "stripe_fragility.csv", full_disk / "stripe_fragility_bootstrap.nc"
    rc, err = _log_block(tmp_path, "from rocking.execution.stripes import write_stripe_fragility; "
                         f"write_stripe_fragility({str(path)!r}, {str(csv)!r}, {str(nc)!r}, "
                         f"motions={str(ens)!r}, refine=4, resamples=2000)",
                         outputs=[csv, nc])
    assert rc == 1, err
    (line,) = err.strip().splitlines()
    assert line.startswith(f"error: no space left on {full_disk}"), err
    assert sorted(p.name for p in full_disk.iterdir()) == ["filler"]


def test_figure_on_dev_full_says_so_in_one_line(tmp_path):
    """The same without root: /dev/full answers every write with ENOSPC."""
    rc, err = _log_block(tmp_path, "import matplotlib; matplotlib.use('Agg'); "
                         "import matplotlib.pyplot as plt; "
                         "plt.figure().savefig('/dev/full', format='png')",
                         outputs=["/dev/full"])
    assert (rc, err.strip()) == (1, "error: no space left on /dev/full: free space there and "
                                    "run again (nothing half-written was kept)")


def test_log_on_a_full_disk_still_says_why_on_the_terminal(tmp_path):
    """The report rule on a full disk said `message: None` with an empty log before."""
    rc, err = _log_block(tmp_path, "open('/dev/full', 'w').write('x' * 10**6)",
                         log="/dev/full", outputs=["/dev/full"])
    assert (rc, err.strip()) == (1, "error: no space left on /dev/full: free space there and "
                                    "run again (nothing half-written was kept)")


# TLS and the dashboard

def test_dry_run_refuses_tls_without_its_settings_naming_them(monkeypatch):
    """A TypeError after 23 s, once other rules had run, before."""
    import dask

    cfg = _config(lambda c: c["dask"].update(scheduler_address="tls://10.0.0.1:8786"))
    with dask.config.set({"distributed.comm.tls.ca-file": None,
                          "distributed.comm.tls.client.cert": None,
                          "distributed.comm.tls.client.key": None}), \
            pytest.raises(ValueError, match=r"^dask.scheduler_address 'tls://10.0.0.1:8786' is a "
                                            r"TLS scheduler but Dask's configuration lacks "
                                            r"distributed.comm.tls.ca-file, distributed.comm.tls"
                                            r".client.cert, distributed.comm.tls.client.key"):
        check_config(cfg)
    with dask.config.set({"distributed.comm.tls.ca-file": "/ca.pem",
                          "distributed.comm.tls.client.cert": "/c.pem",
                          "distributed.comm.tls.client.key": "/k.pem"}):
        check_config(cfg)  # with them: accepted (as before)
    monkeypatch.setenv("DASK_SCHEDULER_ADDRESS", "tls://10.0.0.1:8786")
    with pytest.raises(ValueError, match="is a TLS scheduler"):
        check_config(_config(lambda c: None))


def _listening(port: int) -> set[str]:
    """Local addresses of the sockets listening on TCP ``port`` (every process)."""
    import psutil

    return {c.laddr.ip for c in psutil.net_connections(kind="tcp")
            if c.status == psutil.CONN_LISTEN and c.laddr.port == port}


def _fill_and_look(path, index, motions, seen_file):
    """A region filled on a worker, which writes down (once) its scratch space and the
    sockets its parent (the run: scheduler, dashboard, nannies) listens on, while it runs."""
    import psutil
    from distributed import get_worker

    seen = Path(seen_file)
    if not seen.exists():
        run = psutil.Process(os.getppid())
        listening = sorted({(c.laddr.ip, c.laddr.port) for c in run.net_connections("tcp")
                            if c.status == psutil.CONN_LISTEN})
        seen.write_text(json.dumps({"scratch": get_worker().local_directory,
                                    "listening": listening}))
    return FILL(path, index, motions=motions)


def test_embedded_cluster_dashboard_listens_on_loopback_only(tmp_path, caplog):
    """0.0.0.0 before (the log said 127.0.0.1); scratch space was /tmp/dask-scratch-space.

    The tiny study's spectra filled again on an embedded cluster (no in-process shortcut);
    while it runs, every socket the run listens on (the dashboard's among them) is on
    127.0.0.1, the log names the dashboard's, and the workers' scratch space is beside the
    store (removed afterwards).
    """
    study = Study(tmp_path / "run")
    study.make_motions()
    seen_file = tmp_path / "seen.json"
    with caplog.at_level("INFO"), store.locked(study.store):
        products.prepare_store("spectra", study.store, SPEC, SPEC.digest, study.motions)
        cluster.fill_store(integrity.open_checked(study.store, "r+"),
                           partial(_fill_and_look, seen_file=str(seen_file)), study.motions,
                           config_digest=SPEC.digest, in_process_analyses=0, n_workers=1)
    seen = json.loads(seen_file.read_text())
    line = next(r.message for r in caplog.records if "dashboard:" in r.message)
    port = int(line.split("dashboard: http://127.0.0.1:")[1].split("/")[0])
    assert ["127.0.0.1", port] in seen["listening"], (line, seen)
    assert {ip for ip, _ in seen["listening"]} == {"127.0.0.1"}, seen
    assert Path(seen["scratch"]).is_relative_to(study.store.parent.resolve()), seen
    assert not list(study.store.parent.glob(".dask.scratch-*"))


def test_dashboard_can_be_turned_off_or_moved():
    import urllib.error
    import urllib.request

    lines = []
    with cluster.dask_client(cluster.Target("local"), 1, dashboard_address="off",
                             say=lines.append) as c:
        assert "dashboard: off" in lines[0]
        port = c.cluster.scheduler.services["dashboard"].port  # /health etc. only
        assert _listening(port) == {"127.0.0.1"}
        with pytest.raises(urllib.error.HTTPError, match="404"):
            urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=10)
    lines = []
    with cluster.dask_client(cluster.Target("local"), 1, dashboard_address="127.0.0.1:0",
                             say=lines.append) as c:
        port = c.cluster.scheduler.services["dashboard"].port
        assert f"dashboard: http://127.0.0.1:{port}/status" in lines[0]
        assert _listening(port) == {"127.0.0.1"}


# --------------------------------------------------------------------------------------------
# Family 9 (issue 48): every derived file checked by its reader against the record of what
# made it (rocking.provenance); the workflow remakes what does not match, a command refuses it
# --------------------------------------------------------------------------------------------

COLUMNS = """id,R,tan_alpha,lon,lat
node,1.0,0.15,0.001,0.001
between,2.0,0.175,0.002,-0.001
far-node,3.0,0.2,-0.001,0.002
"""
OTHER_COLUMNS = """id,R,tan_alpha,lon,lat
squat,1.5,0.19,0.0,0.0
"""
HAZARD = {"file": str(REPO / "config/hazard/example_hazard_curve.csv"),
          "site": {"lon": 0.0, "lat": 0.0}, "component": "vector_peak"}
GRID = {"R": [1.0, 3.0], "chunk_R": 1,
        "runs": [{"modes": ["3d"], "tan_alpha": [0.15, 0.2],
                  "limit_states": ["overturning", "tilt:1/3"]}]}
TWO = {
    "accuracy": "fast", "motions": {"max_duration": 3.0},
    # the cheap fit of the synthetic pair (counts, 1 s instead of the spectrum's 9 s): these
    # probes are of the run's files, and the spectrum fit runs in test_workflow's reference
    "ensembles": {"tiny": {"record": "el-centro-1940", "n_synthetic": 1, "seed": 7,
                           "fit_method": "counts"},
                  "other": {"record": "el-centro-1940", "n_synthetic": 1, "seed": 8,
                            "fit_method": "counts"}},
    "studies": {
        "a": {"ensemble": "tiny", "hazard": HAZARD, **GRID,
              "inventory": {"file": "columns.csv", "export": "column", "resamples": 20},
              "stripes": {"modes": ["3d"], "tan_alpha": 0.2, "limit_states": ["overturning"],
                          "R": [3.0], "intensity": {"start": 1.1, "stop": 15.0, "num": 4,
                                                    "spacing": "log"},
                          "refine": 2, "bootstrap": 20}},
        "b": {"ensemble": "other", "hazard": HAZARD, **GRID,
              "inventory": {"file": "other_columns.csv", "resamples": 20}}},
    "dask": {"progress_interval": 0}}
"""Two tiny studies on other motions (b's surface is another one over the same grid), with
a hazard, an inventory each (a's exported), stripes in a: every rule of the workflow."""


def _recorded_table(folder: Path) -> tuple[Path, Path, Path]:
    """A table made from a source, written with a sibling, and recorded."""
    from rocking.provenance import record

    folder.mkdir()
    source, table, sibling = folder / "source.csv", folder / "t.csv", folder / "t.nc"
    source.write_text("x\n1\n")
    table.write_text("mode,median [g]\n3d,0.4567\n3d,0.8123\n")
    sibling.write_bytes(b"CDF\x01" + bytes(range(64)))
    for f in (table, sibling):
        record(f, inputs=[source], together=[table, sibling], settings="0123456789abcdef",
               rule="fragility")
    return source, table, sibling


@pytest.mark.parametrize(("damage", "said"), [
    ("one digit", r"changed since it was written \(sha256 \w+, recorded \w+\)"),
    ("cut in half", r"cut short \(18 of its 36 bytes\)"),
    ("another source", r"made from another {source} than the one there"),
    ("source gone", r"made from {source}, which is missing"),
    ("sibling changed", r"made with another {sibling} than the one there"),
    ("record damaged", r"its record {record} is damaged"),
])
def test_a_derived_file_is_refused_by_its_reader_in_one_line(tmp_path, damage, said):
    """Every damage a reader meets (issue 48): the file named, what is wrong, the command
    that remakes it; one line."""
    from rocking.provenance import ProvenanceError, check, record_path

    source, table, sibling = _recorded_table(tmp_path / "s")
    check(table)  # intact: read
    if damage == "one digit":
        table.write_text(table.read_text().replace("0.4567", "0.4568"))
    elif damage == "cut in half":
        _truncate(table)
    elif damage == "another source":
        source.write_text("x\n2\n")
    elif damage == "source gone":
        source.unlink()
    elif damage == "sibling changed":
        _flip(sibling)
    else:
        record_path(table).write_text('{"sha256": ')
    pattern = said.format(source=re.escape(str(source)), sibling=re.escape(str(sibling)),
                          record=re.escape(str(record_path(table))))
    with pytest.raises(ProvenanceError) as err:
        check(table)
    text = str(err.value)
    assert "\n" not in text
    assert re.fullmatch(rf"{re.escape(str(table))}: {pattern}: remake it with `snakemake "
                        rf"--cores 2 {re.escape(str(table))}` .*", text), text


def test_what_a_reader_does_without_a_record_and_without_the_inputs(tmp_path):
    """No record: a source, or a table of the user's own (said); the workflow's planning
    takes it as a derived file that lost it. Inputs not handed along: not asked for by a
    command (``partial``), missing for the workflow. Other settings: stale for the planning.
    """
    from rocking.provenance import check, problem, record_path

    source, table, sibling = _recorded_table(tmp_path / "s")
    said = []
    record_path(table).unlink()
    assert check(table, say=said.append) is None
    assert said == [f"{table} has no record of what made it: read as a table of your own (a "
                    f"table the workflow wrote carries one in .provenance/)"]
    assert problem(table) == "no record of what made it"
    source.unlink()
    assert problem(sibling, partial=True) is None
    assert problem(sibling).startswith(f"made from {source}, which is missing")
    assert problem(sibling, settings="fedcba9876543210", rule="fragility", partial=True) == \
        "made with other settings of rule fragility"
    assert problem(sibling, rule="records_table", partial=True) == \
        "its record says rule fragility wrote it, not rule records_table"


def _workdir(folder: Path, cfg: dict | None = None) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "columns.csv").write_text(COLUMNS)
    (folder / "other_columns.csv").write_text(OTHER_COLUMNS)
    (folder / "c.yaml").write_text(yaml.safe_dump(cfg or TWO))
    return folder


def _command(*args: str) -> list[str]:
    return [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile"), "--configfile",
            "c.yaml", "--cores", "2", "--nocolor", *args]


def _run(workdir: Path, *args: str, ok: bool = True) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k != "DASK_SCHEDULER_ADDRESS"}
    out = subprocess.run(_command(*args), capture_output=True, text=True, cwd=workdir,
                         timeout=2400, env=env)
    if ok:
        assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    return out


@pytest.fixture(scope="module")
def two_studies(tmp_path_factory) -> Path:
    """The two studies run once, uninterrupted, to the end: the reference."""
    work = _workdir(tmp_path_factory.mktemp("two") / "run")
    _run(work)
    return work


def _restored(reference: Path, folder: Path) -> Path:
    """A copy of the finished run (dates kept, its .snakemake/ record too)."""
    shutil.copytree(reference, folder, symlinks=True)
    return folder


RUN_FACTS = ("logs", ".provenance", ".snakemake_timestamp")
"""What differs between two runs of the same configuration by nature: the logs, the records
(they hold the files' dates), Snakemake's timestamp in a directory output."""
RUN_FACT_FILES = (".done.json", "numba_cache.json", "report.html", ".lock", ".refined.jsonl")
"""Files that say how a run went: the completion summaries (times, chunks done before), the
kernels' compile times, the report (its "what was run": elapsed time), the stores' locks, a
stripes store's append-only cache of refined analyses (in the order they were done); and
the ensembles' summaries, ``motions/<name>-<digest>.json`` (the fit's and synthesis' times)."""
ENSEMBLE_SUMMARY = re.compile(r"^motions/[\w.-]+-[0-9a-f]{16}\.json$")


def _outputs(root: Path) -> dict[str, bytes]:
    """Every file of an output root that two runs of one configuration must write alike."""
    out = {}
    for p in sorted(root.rglob("*")):
        rel = p.relative_to(root)
        if p.is_file() and not any(part in RUN_FACTS for part in rel.parts) \
                and not p.name.endswith(RUN_FACT_FILES) \
                and not ENSEMBLE_SUMMARY.match(rel.as_posix()):
            out[rel.as_posix()] = p.read_bytes()
    return out


def _differing(a: dict[str, bytes], b: dict[str, bytes]) -> list[str]:
    return sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))


def _copy_with_record(src: Path, dst: Path) -> None:
    """A file copied over another, with its record when it has one."""
    shutil.copy(src, dst)
    rec = src.parent / ".provenance" / f"{src.name}.json"
    if rec.is_file():
        shutil.copy(rec, dst.parent / ".provenance" / f"{dst.name}.json")


@pytest.mark.slow
@pytest.mark.parametrize("with_records", [False, True])
def test_another_studys_surface_copied_in_is_remade_before_the_portfolio(two_studies,
                                                                          tmp_path,
                                                                          with_records):
    """Silent before: fragility.csv and critical.csv of another study copied into a study,
    then `snakemake <study>/portfolio.csv`: the portfolio was rebuilt on the other study's
    surface, exit 0. Now both tables are remade from the study's own store first (copied
    alone, they are not what their records say; copied with their records, those name
    another store's answers), and the portfolio is the study's."""
    work = _restored(two_studies, tmp_path / "w")
    a, b = work / "results/a", work / "results/b"
    for name in ("fragility.csv", "critical.csv"):
        (_copy_with_record if with_records else shutil.copy)(b / name, a / name)
    out = _run(work, "results/a/portfolio.csv")
    ref = two_studies / "results/a"
    for name in ("fragility.csv", "critical.csv", "portfolio.csv"):
        assert (a / name).read_bytes() == (ref / name).read_bytes(), (name, out.stderr[-3000:])
    assert "provenance: results/a/" in out.stderr


def _damage_portfolio(a: Path, b: Path, damage: str) -> None:
    table = a / "portfolio.csv"
    if damage == "another inventory's":
        _copy_with_record(b / "portfolio.csv", table)
    elif damage == "cut in half":
        _truncate(table)
    else:
        frame = pd.read_csv(table)
        frame.loc[0, "median"] *= 1.5
        frame.to_csv(table, index=False, float_format="%.6g")


@pytest.mark.slow
@pytest.mark.parametrize("damage", ["another inventory's", "cut in half", "one median x 1.5"])
def test_damaged_portfolio_is_remade_before_its_export(two_studies, tmp_path, damage):
    """Silent before: a restored run, its portfolio.csv of another inventory, cut in half or
    with one median times 1.5, then `snakemake <study>/exposure`: the export was made from
    the damaged table. Now the table is remade first, and the export is the study's."""
    work = _restored(two_studies, tmp_path / "w")
    a = work / "results/a"
    _damage_portfolio(a, work / "results/b", damage)
    out = _run(work, "results/a/exposure")
    ref = two_studies / "results/a"
    assert (a / "portfolio.csv").read_bytes() == (ref / "portfolio.csv").read_bytes()
    assert _outputs(a / "exposure") == _outputs(ref / "exposure")
    assert "provenance: results/a/portfolio.csv: " in out.stderr


def _run_and_kill(workdir: Path, args: Sequence[str], when: Callable[[str], bool],
                  delay: float = 0.0, ready: Callable[[], bool] = lambda: True
                  ) -> tuple[bool, str]:
    """Run Snakemake; at the first line of its output that ``when`` accepts, wait ``delay``
    seconds (and until ``ready()``), then kill it with its job and workers (SIGKILL to the
    process group). Returns (finished without being killed, the line)."""
    import signal

    env = {k: v for k, v in os.environ.items() if k != "DASK_SCHEDULER_ADDRESS"}
    run = subprocess.Popen(_command(*args), cwd=workdir, env=env, text=True,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           start_new_session=True)
    seen = []
    for line in run.stdout:
        seen.append(line)
        if when(line):
            deadline = time.monotonic() + 30
            time.sleep(delay)
            while not ready() and time.monotonic() < deadline:
                time.sleep(0.01)
            os.killpg(run.pid, signal.SIGKILL)
            run.wait(timeout=60)
            return False, line.strip()
    assert run.wait(timeout=60) == 0, "".join(seen)[-4000:]
    return True, ""


@pytest.mark.slow
def test_killed_portfolio_then_a_downstream_target_remakes_it(two_studies, tmp_path):
    """Silent before: Snakemake killed (-9) during the portfolio rule, `--unlock`, then a
    rerun naming a downstream target (the export): "Nothing to be done", and portfolio.csv
    stayed missing. Now the export's record names the portfolio it was made from: both are
    remade, to the bytes of an uninterrupted run."""
    work = _restored(two_studies, tmp_path / "w")
    table = work / "results/a/portfolio.csv"
    killed, _ = _run_and_kill(work, ["--forcerun", "portfolio", "results/a/portfolio.csv"],
                              when=lambda line: line.strip() in ("rule portfolio:",
                                                                 "localrule portfolio:"),
                              ready=lambda: not table.exists())
    assert not killed and not table.exists()
    _run(work, "--unlock")
    out = _run(work, "results/a/exposure")
    ref = two_studies / "results/a"
    assert table.read_bytes() == (ref / "portfolio.csv").read_bytes(), out.stderr[-3000:]
    assert _outputs(work / "results/a/exposure") == _outputs(ref / "exposure")


@pytest.mark.slow
def test_kill_anywhere_then_the_same_command_ends_as_an_uninterrupted_run(two_studies,
                                                                         tmp_path):
    """Kill -9 of Snakemake (with its job and workers) while each rule runs in turn, each
    time `--unlock` and the same command again: the run ends with every output identical to
    the uninterrupted run's (before: the same command stopped on the killed job's
    incomplete files)."""
    work = _workdir(tmp_path / "w")
    killed: list[str] = []

    def new_rule(line: str) -> bool:
        m = re.match(r"^(?:local)?rule (\w+):$", line.strip())
        return m is not None and m.group(1) not in killed and m.group(1) != "all"

    for attempt in range(80):
        finished, line = _run_and_kill(work, [], when=new_rule,
                                       delay=(0.0, 0.5, 2.0)[attempt % 3])
        if finished:
            break
        killed.append(line.split()[-1].rstrip(":"))
        _run(work, "--unlock")
    assert finished, killed
    reference = _outputs(two_studies / "results")
    assert _differing(_outputs(work / "results"), reference) == [], killed
    assert set(killed) == {r for r in _planned_rules(two_studies) if r != "all"}, killed


def _planned_rules(workdir: Path) -> set[str]:
    """Every rule the configuration's default target runs."""
    dry = _run(workdir, "-n", "--forceall")
    return set(re.findall(r"^(\w+)\s+\d+$", dry.stdout, re.MULTILINE)) - {"total"}


def _jobs(workdir: Path) -> list[dict]:
    """Every job of the default target (a dry run of them all): rule, inputs, outputs."""
    dry = _run(workdir, "-n", "--forceall").stdout
    jobs = []
    for block in re.split(r"\n(?=(?:local)?rule \w+:\n)", dry):
        head = re.match(r"(?:local)?rule (\w+):\n", block)
        if head is None:
            continue
        fields = dict(re.findall(r"^    (input|output): (.*)$", block, re.MULTILINE))
        jobs.append({"rule": head.group(1),
                     "input": [f for f in fields.get("input", "").split(", ") if f],
                     "output": [f for f in fields.get("output", "").split(", ") if f]})
    return jobs


@pytest.mark.slow
def test_every_derived_input_of_every_rule_is_checked_by_its_record(two_studies):
    """The rule walk: for every job of the workflow, every output carries a record naming
    its rule (its script ran in rocking.execution.logs.job, which records what made each
    output), and every input another rule writes is among the inputs of that record (the
    job checked it against its own record before reading it). A new rule whose script does
    not record its outputs, or whose derived input is not checked, fails here."""
    from rocking.provenance import read_record

    jobs = _jobs(two_studies)
    written = {f: j["rule"] for j in jobs for f in j["output"]}
    assert {"portfolio", "exposure", "fragility", "stripe_fragility", "report",
            "motion_measures", "risk"} <= {j["rule"] for j in jobs}
    # the tables that replaced the refinement's (issues 45, 47) among the files walked
    assert {f"results/a/{name}" for name in ("motion_measures.csv", "stripe_exceedance.csv",
                                             "portfolio_site.csv", "verdicts.csv")} <= \
        set(written)
    ordering_only = {"results/numba_cache.json"}  # ancient(): the order of jobs alone
    uncovered = []
    for j in jobs:
        for out in j["output"]:
            path = two_studies / out
            rec = read_record(path)
            if rec is None or rec.get("rule") != j["rule"]:
                uncovered.append(f"{out}: no record by rule {j['rule']}")
                continue
            made_from = {os.path.normpath(path.parent / rel) for rel in rec["inputs"]}
            for f in j["input"]:
                if f in written and f not in ordering_only and \
                        os.path.normpath(two_studies / f) not in made_from:
                    uncovered.append(f"{out} (rule {j['rule']}): input {f} of rule "
                                     f"{written[f]} is not checked")
    assert uncovered == []
    # and the planning holds every job's outputs against their records: its input function
    # is added to every rule by the last include, after which no rule is defined
    snakefile = (REPO / "Snakefile").read_text()
    includes = re.findall(r'^include: "([^"]+)"', snakefile, re.MULTILINE)
    assert includes[-1] == "workflow/rules/provenance.smk"
    assert not re.search(r"^rule ", snakefile.split(includes[-1])[1].split("rule all:")[0],
                         re.MULTILINE)


def test_every_script_runs_in_the_job_block_and_every_command_checks_what_it_is_handed():
    """The readers: every workflow script reads and writes inside
    rocking.execution.logs.job (its inputs checked, its outputs recorded), and the commands
    that read a study's tables check them (rocking.cli._common.check_handed)."""
    scripts = sorted((REPO / "workflow/scripts").glob("*.py"))
    assert scripts
    for script in scripts:
        text = script.read_text()
        assert re.search(r"with (logs\.)?job\(snakemake\)", text), script.name
        assert "log_to(" not in text, script.name
    for command in ("portfolio", "risk"):
        assert "_common.check_handed(" in (REPO / f"src/rocking/cli/{command}.py").read_text()


def _study_tables(reference: Path, folder: Path) -> Path:
    """Study a's folder without its stores (a surface handed to someone)."""
    shutil.copytree(reference / "results/a", folder,
                    ignore=shutil.ignore_patterns("*.zarr", "figures", "exposure"))
    return folder


@pytest.mark.slow
def test_portfolio_command_refuses_another_studys_table_in_one_line(two_studies, tmp_path,
                                                                    capsys):
    """Silent before: `rocking portfolio --surface` read a fragility.csv of another study
    copied into the folder. Now: refused, naming the file and the command that remakes it;
    the study's own folder, handed on without its stores, is read."""
    from rocking.cli import main

    folder = _study_tables(two_studies, tmp_path / "a")
    argv = ["portfolio", "--surface", str(folder), "--inventory", str(two_studies /
            "columns.csv"), "--hazard", HAZARD["file"], "--site-lon", "0", "--site-lat", "0",
            "--resamples", "0"]
    assert main(argv) == 0
    assert "no record" not in capsys.readouterr().err
    shutil.copy(two_studies / "results/b/fragility.csv", folder / "fragility.csv")
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert f"{folder / 'fragility.csv'}: changed since it was written" in err
    assert f"snakemake --cores 2 {folder / 'fragility.csv'}" in err


@pytest.mark.slow
def test_a_table_of_ones_own_is_read_and_said_so(two_studies, tmp_path, capsys):
    """A table a user wrote (no record beside it) handed to `rocking risk`: read as it is,
    one line on stderr saying so."""
    from rocking.cli import main

    own = tmp_path / "mine.csv"
    shutil.copy(two_studies / "results/a/fragility.csv", own)
    assert main(["risk", "--fragility", str(own), "--hazard", "2e-4,2.2"]) == 0
    err = capsys.readouterr().err
    assert f"rocking risk: {own} has no record of what made it: read as a table of your own" \
        in err


@pytest.fixture()
def read_only_folder(tmp_path):
    """A read-only filesystem (a tmpfs mounted ro), or a folder without write permission."""
    folder = tmp_path / "ro"
    folder.mkdir()
    if os.geteuid() != 0:
        folder.chmod(0o555)
        yield folder
        folder.chmod(0o755)
        return
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m,ro", "tmpfs", str(folder)],
                      capture_output=True).returncode != 0:
        pytest.skip("a read-only folder needs a tmpfs mount as root")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=False)


def _refused_before_any_job(work: Path, folder: Path) -> str:
    cfg = {**json.loads(json.dumps(TWO)), "output": str(folder)}
    _workdir(work, cfg)
    out = _run(work, ok=False)
    assert out.returncode != 0
    assert "Traceback" not in out.stderr, out.stderr[-3000:]
    errors = [line for line in out.stderr.splitlines() if line.startswith("error: ")]
    assert len(errors) == 1, out.stderr[-3000:]
    assert not re.search(r"^(local)?rule \w+:$", out.stdout + out.stderr, re.MULTILINE)
    return errors[0]


@pytest.mark.slow
def test_read_only_output_folder_is_said_in_one_line_before_any_job(tmp_path,
                                                                    read_only_folder):
    """A traceback from the provenance stamp before (OSError: [Errno 30] Read-only file
    system: .../.provenance/...part.json)."""
    line = _refused_before_any_job(tmp_path / "w", read_only_folder)
    assert line.startswith(f"error: output folder {read_only_folder}") and "cannot write" in line


@pytest.mark.slow
def test_full_output_folder_is_said_in_one_line_before_any_job(tmp_path, full_disk):
    line = _refused_before_any_job(tmp_path / "w", full_disk)
    assert line.startswith(f"error: output folder {full_disk}") and "no space left" in line


@pytest.mark.parametrize("content", [b"", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe",
                                     "mode,ü\n3d,1\n".encode("latin-1")],
                         ids=["0-byte", "binary", "latin-1"])
def test_verify_names_a_table_it_cannot_read(tmp_path, capsys, content):
    """"No columns to parse from file" or a UTF-8 decoding error before, naming no file."""
    from rocking.cli import main

    gallery = REPO / "results" / "paper"
    run = tmp_path / "run"
    shutil.copytree(gallery, run, ignore=shutil.ignore_patterns("*.png", "*.html", "*.xml",
                                                                "figures", "motions"))
    table = run / "elcentro" / "fragility.csv"
    table.write_bytes(content)
    assert main(["verify", str(run), "--against", str(gallery)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"rocking verify: error: {table}: "), err


@pytest.mark.slow
def test_a_copied_folder_remakes_the_tables_its_new_settings_change(two_studies, tmp_path):
    """A folder copied with `cp -a` (no .snakemake/ record of the rules' parameters), a
    measure added and the hazard put in it: the records' settings differ, the tables are
    remade (before issue 48, by two stamp files rewritten at planning); then nothing is left
    to do."""
    subprocess.run(["cp", "-a", str(two_studies / "results"), str(tmp_path / "copy")],
                   check=True)
    for name in ("columns.csv", "other_columns.csv"):
        shutil.copy(two_studies / name, tmp_path / name)
    cfg = json.loads(json.dumps(TWO))
    cfg.update(output="copy")
    cfg["studies"]["b"].update(intensity_measures=["pga", "sa:1.0"],
                               hazard={"k0": 2.0e-4, "k": 2.2, "measure": "sa:1.0"})
    del cfg["studies"]["b"]["inventory"]
    (tmp_path / "c.yaml").write_text(yaml.safe_dump(cfg))
    plan = _run(tmp_path, "-n", "copy/b/risk.csv")
    # risk refits in the hazard's measure from each motion's measures (motion_measures.csv)
    assert {"motion_measures", "risk"} <= _planned(plan.stdout), plan.stdout[-3000:]
    assert "spectra" not in _planned(plan.stdout)
    # and the suite's tables in the measure added
    assert "records_table" in _planned(_run(tmp_path, "-n", "copy/b/suite_fragility.csv")
                                       .stdout)
    _run(tmp_path, "copy/b/risk.csv")
    assert set(pd.read_csv(tmp_path / "copy/b/risk.csv")["measure"]) == {"sa:1.0"}
    again = _run(tmp_path, "-n", "copy/b/risk.csv")
    assert _planned(again.stdout) == set(), again.stdout[-3000:] + again.stderr[-3000:]
    # a deleted sidecar (never a silent blank interval): remade before risk reads it
    (tmp_path / "copy/a/stripe_fragility_bootstrap.nc").unlink()
    assert {"stripe_fragility", "risk"} <= _planned(_run(tmp_path, "-n",
                                                         "copy/a/risk.csv").stdout)


def _planned(text: str) -> set[str]:
    return {line.split()[-1].rstrip(":") for line in text.splitlines()
            if line.startswith(("rule ", "localrule "))}


def test_store_fill_on_a_full_disk_says_so_in_one_line(tmp_path, full_disk):
    """The compute rules (exit 120, no reason, before): a chunk that cannot be written."""
    (full_disk / "filler").unlink()
    rc, err = _log_block(tmp_path, textwrap.dedent(f"""\
        from functools import partial
        import _store_standins as standin
        from rocking.motions.ensemble_io import save_ensemble
        from rocking.execution import cluster
        from rocking.store import integrity
        from rocking.execution import prepare
        from rocking.execution import products
        from rocking import store
        from rocking.execution import tasks
        from rocking.config.study import StudySpec
        spec = StudySpec.from_config({CONFIG!r}, "s").spectra
        motions = {str(tmp_path / "m.nc")!r}
        save_ensemble(motions, standin.motions(n=3))
        path = prepare.keyed({str(full_disk / "spectra.zarr")!r}, spec.digest)
        products.prepare_store("spectra", path, spec, spec.digest, motions)
        with open({str(full_disk / "filler")!r}, "wb") as fh:  # the disk fills up
            try:
                while True:
                    fh.write(b"0" * 4096)
                    fh.flush()
            except OSError:
                pass
        cluster.fill_store(integrity.open_checked(path, "r+"),
                           partial(tasks.fill_spectra_region, batch=standin.batch), motions,
                           config_digest=spec.digest, in_process_analyses=10**9)
        """).replace("\n", "\n            "), outputs=[full_disk / "spectra.done.json"])
    assert rc == 1, err
    (line,) = err.strip().splitlines()[-1:]
    assert line.startswith("error: no space left on ") and str(full_disk) in line, err
    assert len(err.strip().splitlines()) == 1, err


def test_a_rewrite_with_the_same_bytes_records_only_its_own_inputs(tmp_path):
    """Silent before (seen in CI, a repository under /tmp): a table rewritten with the same
    bytes from other inputs (a closed-form hazard instead of a hazard file) kept the earlier
    run's inputs in its record, so the plan found a "missing" input and remade the job again
    and again. A record written for the very same write (same bytes, same modification time:
    a library function recording while its job runs) still keeps what it recorded."""
    import time

    from rocking.provenance import read_record, record

    table, old_source, new_source = (tmp_path / n for n in ("t.csv", "a.csv", "b.csv"))
    old_source.write_text("1\n")
    new_source.write_text("2\n")
    table.write_text("x\n")
    record(table, inputs=[old_source], rule="r")
    assert set(read_record(table)["inputs"]) == {"a.csv"}
    record(table, inputs=[new_source], rule="r")  # the same write: both kept
    assert set(read_record(table)["inputs"]) == {"a.csv", "b.csv"}
    time.sleep(0.01)
    table.write_text("x\n")  # the next run: the same bytes, written again
    record(table, inputs=[new_source], rule="r")
    assert set(read_record(table)["inputs"]) == {"b.csv"}
