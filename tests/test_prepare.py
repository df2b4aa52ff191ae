"""A compute rule's store: made when missing, resumed for the same configuration, replaced
for another one (finished chunks survive a killed run, never a configuration change)."""

from __future__ import annotations

import _store_standins as standin
import numpy as np
import pytest

from rocking import store
from rocking.config.study import StudySpec
from rocking.execution import prepare, products, tasks
from rocking.motions.ensemble_io import save_ensemble
from rocking.store.attrs import config_hash


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
    assert products.prepare_store("spectra", path, spec, digest, motions) == "created"
    layout = store.open_layout(path)
    tasks.fill_spectra_region(path, 0, motions, batch=standin.batch)
    before = store.done_mask(path).copy()
    assert before.sum() == 1
    # the same configuration (a killed run started again): the finished chunk is kept
    assert products.prepare_store("spectra", path, spec, digest, motions) == "resumed"
    np.testing.assert_array_equal(store.done_mask(path), before)
    assert store.pending_regions(path, layout) == list(range(1, layout.n_regions))
    # another configuration: a fresh store, nothing done, the new hash recorded
    other = _spec(10.0)
    assert products.prepare_store("spectra", path, other, config_hash(other), motions) == "replaced"
    assert not store.done_mask(path).any()
    assert store.read_attrs(path)["config_hash"] == config_hash(other)


def test_a_directory_that_is_not_a_store_is_replaced(tmp_path):
    motions = tmp_path / "motions.nc"
    save_ensemble(motions, standin.motions())
    path = tmp_path / "spectra.zarr"
    path.mkdir()
    (path / "junk").write_text("not zarr")
    spec = _spec(20.0)
    assert products.prepare_store("spectra", path, spec, config_hash(spec), motions) == "replaced"
    assert not (path / "junk").exists()


def test_keyed_stores_are_added_not_replaced_and_found_again(tmp_path):
    """A changed setting (here the search bound) adds a store beside the earlier one; the
    unkeyed name links to the latest; changing back resumes the earlier store as it was."""
    motions = tmp_path / "motions.nc"
    save_ensemble(motions, standin.motions())
    alias = tmp_path / "spectra.zarr"
    first, second = _spec(20.0), _spec(10.0)
    a = prepare.keyed(alias, config_hash(first))
    b = prepare.keyed(alias, config_hash(second))
    assert a.name == f"spectra-{config_hash(first)}.zarr" and a != b
    assert prepare.unkeyed(a, config_hash(first)) == alias
    assert products.prepare_store("spectra", a, first, config_hash(first), motions) == "created"
    tasks.fill_spectra_region(a, 0, motions, batch=standin.batch)
    done = store.done_mask(a).copy()
    assert alias.is_symlink() and alias.resolve() == a.resolve()
    assert products.prepare_store("spectra", b, second, config_hash(second), motions) == "created"
    assert alias.resolve() == b.resolve()
    assert store.read_attrs(a)["config_hash"] == config_hash(first)  # kept, untouched
    assert products.prepare_store("spectra", a, first, config_hash(first), motions) == "resumed"
    np.testing.assert_array_equal(store.done_mask(a), done)
    assert alias.resolve() == a.resolve()
    assert not alias.readlink().is_absolute()  # the folder can be moved or copied


def test_a_store_made_before_keyed_names_is_moved_and_resumed(tmp_path):
    motions = tmp_path / "motions.nc"
    save_ensemble(motions, standin.motions())
    alias = tmp_path / "spectra.zarr"
    spec = _spec(20.0)
    digest = config_hash(spec)
    products.prepare_store("spectra", alias, spec, digest, motions)  # the old, unkeyed name
    tasks.fill_spectra_region(alias, 0, motions, batch=standin.batch)
    keyed = prepare.keyed(alias, digest)
    assert products.prepare_store("spectra", keyed, spec, digest, motions) == "resumed"
    assert store.done_mask(keyed).sum() == 1 and alias.is_symlink()
    # a real directory at the alias that is not a store is never deleted nor linked over
    other = tmp_path / "other"
    other.mkdir()
    (other / "tilt_map.zarr").mkdir()
    assert prepare.adopt_unkeyed(other / "tilt_map.zarr") is None
    assert not prepare.link_alias(other / "tilt_map-00ff.zarr", other / "tilt_map.zarr")
    assert (other / "tilt_map.zarr").is_dir() and not (other / "tilt_map.zarr").is_symlink()


def test_keyed_rejects_a_digest_that_is_not_hexadecimal(tmp_path):
    with pytest.raises(ValueError, match="digest must be lowercase hexadecimal, got '../x'"):
        prepare.keyed(tmp_path / "spectra.zarr", "../x")


def test_planned_spec_is_rebuilt_from_the_config_and_checked():
    config = {"accuracy": "fast", "ensembles": {"test": {"record": "el-centro-1940"}},
              "studies": {"s": {"ensemble": "test", "R": [1.0],
                                "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                          "limit_states": ["overturning"]}]}}}
    spec = StudySpec.from_config(config, "s").spectra
    assert products.planned_spec(config, "s", "spectra", spec.digest) == spec
    with pytest.raises(ValueError, match="studies.s: the spectra settings of this "
                                         "configuration hash to"):
        products.planned_spec(config, "s", "spectra", "0" * 16)
    with pytest.raises(ValueError, match="tilt_map settings of this configuration hash to None"):
        products.planned_spec(config, "s", "tilt_map", "0" * 16)
