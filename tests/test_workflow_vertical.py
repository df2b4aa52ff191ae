"""The workflow with vertical shaking, end to end: real snakemake, Dask and zarr.

One run of three tiny studies (3 s of El Centro, fast accuracy) that differ only in their
ensemble: ``v`` with ``vertical: true`` (the shipped UP file; one synthetic pair, which stays
horizontal), ``h`` horizontal only, ``z`` with ``vertical: true`` and a vertical file of
zeros. Checked against things computed outside the workflow:

- ``v``'s record is the motion ``load_motion(name, vertical=True)`` processed as the study
  says (the same samples, vertical included), and its spectra, tilt map and stripes equal
  ``rocking.spectra`` called directly on that motion, bit for bit;
- ``v`` differs from ``h`` where the vertical matters (the record's answers) and agrees
  where it cannot (the intensity, a horizontal vector PGA);
- ``z`` gives ``h``'s answers to the bit: a zero vertical changes nothing.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from conftest import package_record
from test_workflow import snakemake

from rocking.config.ensemble import EnsembleSpec
from rocking.dynamics.bodies import Cylinder
from rocking.fragility.stripes import stripe_outcomes
from rocking.motions.catalogue import RECORDS
from rocking.motions.ensemble_io import load_ensemble
from rocking.motions.source import load_motion, process_motion
from rocking.spectra.accuracy import Accuracy
from rocking.spectra.critical import critical_intensity
from rocking.spectra.limit_states import parse_limit_states
from rocking.spectra.tilt_map import tilt_map
from rocking.units import read_table

pytestmark = pytest.mark.slow

RECORD = "el-centro-1940"
ASKED = {"3d": ["overturning", "tilt:1/3"], "2d-x": ["overturning", "tilt:1/3"]}


def _study(ensemble: str) -> dict:
    return {"ensemble": ensemble, "R": [1.0, 3.0], "chunk_R": 2,
            "runs": [{"modes": ["3d", "2d-x"], "tan_alpha": [0.2],
                      "limit_states": ["overturning", "tilt:1/3"]}],
            "tilt_map": {"modes": ["3d"], "R": [2.0], "intensity": [2.0, 4.0]},
            "stripes": {"R": [2.0], "intensity": [1.5, 3.0], "refine": 0, "bootstrap": 0}}


def _config(workdir: Path) -> dict:
    files = [str(package_record(f)) for f in RECORDS[RECORD].files]
    zeros = workdir / "zeros.txt"  # as many samples as the pair, on its time step
    np.savetxt(zeros, np.zeros(5372))
    return {
        "accuracy": "fast",
        "motions": {"max_duration": 3.0},
        "ensembles": {
            "vert": {"record": RECORD, "vertical": True, "n_synthetic": 1, "seed": 7,
                     "fit_method": "counts"},  # the cheap fit: only its pair's az matters
            "horiz": {"record": RECORD, "n_synthetic": 0},
            "zero": {"record": RECORD, "paths": [*files, str(zeros)], "dt": 0.01,
                     "vertical": True, "n_synthetic": 0},
        },
        "studies": {"v": _study("vert"), "h": _study("horiz"), "z": _study("zero")},
        "dask": {"progress_interval": 0},
    }


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> tuple[Path, dict]:
    workdir = tmp_path_factory.mktemp("vertical")
    cfg = _config(workdir)
    path = workdir / "vertical.yaml"
    path.write_text(yaml.safe_dump(cfg))
    targets = [f"results/{s}/{f}" for s in ("v", "h", "z")
               for f in ("mean_spectra.nc", "tilt_map.done.json", "stripes.done.json",
                         "records.csv")]
    snakemake(workdir, *targets, configfile=path, timeout=900)
    return workdir, cfg


def _open(workdir: Path, study: str, kind: str) -> xr.Dataset:
    return xr.open_zarr(workdir / f"results/{study}/{kind}.zarr", consolidated=True)


def _motions(workdir: Path, cfg: dict, name: str) -> list:
    digest = EnsembleSpec.from_config(cfg, name).digest
    return load_ensemble(workdir / f"results/motions/{name}-{digest}.nc")


def _attrs(ds: xr.Dataset) -> dict:
    return {k: json.loads(v) if isinstance(v, str) and v[:1] in "{[" else v
            for k, v in ds.attrs.items()}


def test_the_vertical_record_is_the_shipped_one_and_its_pairs_are_horizontal(run):
    workdir, cfg = run
    record, pair = _motions(workdir, cfg, "vert")
    direct = process_motion(load_motion(RECORD, vertical=True), rotation="auto",
                            highpass="oscillator", max_duration=3.0)
    assert direct.has_vertical
    assert record.samples_sha256 == direct.samples_sha256  # az included
    assert any(s.get("step") == "vertical" for s in record.metadata["processing"])
    assert pair.az is None  # synthetic pairs stay horizontal
    (horizontal,) = _motions(workdir, cfg, "horiz")
    np.testing.assert_array_equal(record.ax, horizontal.ax)  # the same horizontals
    # the run's log says the pairs stay horizontal
    logs = list((workdir / "results/logs/motions").glob("vert-*.log"))
    assert "its synthetic pairs are horizontal" in logs[0].read_text()


def test_spectra_equal_direct_calls_on_the_record_with_its_vertical(run):
    workdir, cfg = run
    ds = _open(workdir, "v", "spectra")
    attrs = _attrs(ds)
    direct = process_motion(load_motion(RECORD, vertical=True), rotation="auto",
                            highpass="oscillator", max_duration=3.0)
    for mode, states in ASKED.items():
        for R in (1.0, 3.0):
            want = critical_intensity(Cylinder(R, 0.2), direct, states, mode,
                                      accuracy=attrs["tolerances"], **attrs["search_options"])
            got = ds["pga_crit"].sel(mode=mode, motion=RECORD, tan_alpha=0.2, R=R,
                                     limit_state=list(want.limit_states)).values
            np.testing.assert_array_equal(got, want.intensity)
            assert np.all(np.isfinite(got))


def test_the_vertical_moves_the_answers_and_not_the_intensity(run):
    workdir, _ = run
    v = _open(workdir, "v", "spectra")["pga_crit"].sel(motion=RECORD)
    h = _open(workdir, "h", "spectra")["pga_crit"].sel(motion=RECORD)
    assert not np.array_equal(v.values, h.values)
    tv = _open(workdir, "v", "tilt_map")["theta_max_over_alpha"].values
    th = _open(workdir, "h", "tilt_map")["theta_max_over_alpha"].values
    assert not np.array_equal(tv, th)
    # the intensity stays the horizontal vector PGA
    rv = read_table(workdir / "results/v/records.csv")
    rh = read_table(workdir / "results/h/records.csv")
    for col in ("pga_recorded_g", "pga_g"):
        a = rv.loc[rv["motion"] == RECORD, col].to_numpy()
        b = rh.loc[rh["motion"] == RECORD, col].to_numpy()
        np.testing.assert_array_equal(a, b)


def test_tilt_map_and_stripes_use_the_vertical(run):
    workdir, _ = run
    direct = process_motion(load_motion(RECORD, vertical=True), rotation="auto",
                            highpass="oscillator", max_duration=3.0)
    tm = _open(workdir, "v", "tilt_map")
    want = tilt_map([2.0], 0.2, direct, [2.0, 4.0], "3d", accuracy="fast")
    np.testing.assert_array_equal(tm["theta_max_over_alpha"].sel(mode="3d").values,
                                  want["theta_max_over_alpha"].values)
    st = _open(workdir, "v", "stripes")
    attrs = _attrs(st)
    states = parse_limit_states([str(s) for s in st["limit_state"].values], sort=False)
    exceeded, _, _ = stripe_outcomes(Cylinder(2.0, 0.2), direct, states,
                                     st["intensity"].values, "3d",
                                     Accuracy.of(attrs["tolerances"]),
                                     **attrs.get("model_options", {}), measure="pga")
    np.testing.assert_array_equal(
        st["exceeded"].sel(mode="3d", motion=RECORD, R=2.0).values, exceeded.T)


def test_a_zero_vertical_gives_the_horizontal_answers_to_the_bit(run):
    workdir, _ = run
    for kind, names in (("spectra", ("pga_crit", "not_reached", "n_analyses")),
                        ("tilt_map", ("theta_max_over_alpha", "overturned")),
                        ("stripes", ("exceeded", "n_analyses"))):
        z, h = _open(workdir, "z", kind), _open(workdir, "h", kind)
        for name in names:
            np.testing.assert_array_equal(z[name].values, h[name].values, err_msg=name)
