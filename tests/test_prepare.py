"""A compute rule's store: made when missing, resumed for the same configuration, replaced
for another one (finished chunks survive a killed run, never a configuration change)."""

from __future__ import annotations

import _store_standins as standin
import numpy as np

from rocking.motions.ensemble_io import save_ensemble
from rocking.study import prepare, store, tasks
from rocking.study.spec import StudySpec, config_hash


def _spec(upper: float) -> dict:
    config = {"accuracy": "fast", "search": {"upper": upper},
              "ensembles": {"test": {"record": "el-centro-1940"}},
              "studies": {"s": {"ensemble": "test", "R": [0.5, 1.0, 2.0], "chunk_R": 1,
                                "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                          "limit_states": ["overturning", "tilt:1/3"]}]}}}
    return StudySpec.from_config(config, "s").spectra.to_attrs()


def test_store_is_created_resumed_and_replaced(tmp_path):
    motions = tmp_path / "motions.nc"
    save_ensemble(motions, standin.motions())
    path = tmp_path / "spectra.zarr"
    spec = _spec(20.0)
    digest = config_hash(spec)
    assert prepare.spectra_store(path, spec, digest, motions) == "created"
    layout = store.open_layout(path)
    tasks.fill_spectra_region(path, 0, motions, batch=standin.batch)
    before = store.done_mask(path).copy()
    assert before.sum() == 1
    # the same configuration (a killed run started again): the finished chunk is kept
    assert prepare.spectra_store(path, spec, digest, motions) == "resumed"
    np.testing.assert_array_equal(store.done_mask(path), before)
    assert store.pending_regions(path, layout) == list(range(1, layout.n_regions))
    # another configuration: a fresh store, nothing done, the new hash recorded
    other = _spec(10.0)
    assert prepare.spectra_store(path, other, config_hash(other), motions) == "replaced"
    assert not store.done_mask(path).any()
    assert store.read_attrs(path)["config_hash"] == config_hash(other)


def test_a_directory_that_is_not_a_store_is_replaced(tmp_path):
    motions = tmp_path / "motions.nc"
    save_ensemble(motions, standin.motions())
    path = tmp_path / "spectra.zarr"
    path.mkdir()
    (path / "junk").write_text("not zarr")
    spec = _spec(20.0)
    assert prepare.spectra_store(path, spec, config_hash(spec), motions) == "replaced"
    assert not (path / "junk").exists()
