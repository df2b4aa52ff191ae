"""Probe list (issue 31): a damaged input or store never yields a changed result.

Each case damages one thing a tiny study depends on (its motions file, a record file, a chunk,
a coordinate, its configuration, its cluster, a concurrent run) and asserts the outcome: the
tables identical to an undamaged run's, or an error that names what is wrong and the way out;
never a changed number. The study runs the real preparation, verification, fill and table code
(:mod:`rocking.study.prepare`, :mod:`rocking.study.cluster`, :mod:`rocking.study.integrity`,
:mod:`rocking.study.aggregate`, :mod:`rocking.study.records`) with the closed-form stand-in
engine of tests/_store_standins.py, so that a case runs in about a second.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
import time
import warnings
from functools import partial
from pathlib import Path

import _store_standins as standin
import numpy as np
import pytest
import xarray as xr
import yaml
import zarr

from rocking.motions.ensemble_io import (
    MotionsDigestError,
    digest_path,
    load_ensemble,
    save_ensemble,
)
from rocking.motions.readers import RecordFormatError, read_at2, read_text
from rocking.study import cluster, integrity, prepare, products, store, tasks
from rocking.study.aggregate import ensemble_statistics, requested_answers, write_statistics
from rocking.study.config_checks import check_config
from rocking.study.records import write_record_tables
from rocking.study.study_spec import StudySpec

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
    cfg = _config(lambda c: c["ensembles"]["elcentro"].update(fc_hz=0.002))
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
    from rocking.study import store
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
