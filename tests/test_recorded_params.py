"""Recorded RDK parameters: rounded fits with their digests (config/ensembles/*.params.json),
and the synthetic pairs made from them bit-identical build after build and to the digests
the committed files hold."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from rocking.config.ensemble import EnsembleSpec
from rocking.motions.build import build_ensemble, read_motion
from rocking.motions.stochastic.fit import RDKFit
from rocking.motions.stochastic.params import RDKParams
from rocking.motions.stochastic.recorded import (
    SIGNIFICANT_DIGITS,
    _fit_dict,
    check_settings,
    entries_for,
    fit_sha256,
    pairs_match,
    read_params_file,
    recorded_fit,
    round_significant,
    rounded_fit,
)

ROOT = Path(__file__).resolve().parents[1]
FILES = {"elcentro": ROOT / "config" / "ensembles" / "elcentro.params.json",
         "lomaprieta": ROOT / "config" / "ensembles" / "lomaprieta.params.json"}


def _fit() -> RDKFit:
    """A fit with the extension and awkward decimals (f_low goes through 2π·f/2π)."""
    major = RDKParams(1.6114612345, 24.04551234, 5.112149876, 5.902823456, -0.05493213579,
                      0.4420461234, f_mid2=2.035034567, zeta_f2=0.2583749876,
                      share2=0.4499771234, f_low=0.1860149876, zeta_low=0.3323051234)
    minor = RDKParams(1.11266123, 23.8415123, 11.2898123, 3.62847123, -0.0340039123,
                      0.601998123)
    return RDKFit(-0.1234567891, major, minor, 0.01, "test-record")


def test_rounding_keeps_six_digits_and_the_file_builds_the_same_parameters_to_the_bit():
    fit = _fit()
    r = rounded_fit(fit)
    for p, q in ((fit.major, r.major), (fit.minor, r.minor)):
        for k in ("Ia", "D5_95", "t_mid", "f_mid", "f_slope", "zeta_f"):
            a, b = getattr(p, k), getattr(q, k)
            assert abs(b - a) <= 5.0001 * 10.0 ** (-SIGNIFICANT_DIGITS) * abs(a)
            assert b != a   # the test's values have more digits: rounding did something
    assert round_significant(0.1860149876) == 0.186015
    # written and read back: the same parameters to the bit, and rounding is idempotent
    text = json.loads(json.dumps(_fit_dict(r)))
    entry = {"fit": text, "settings": {"fit_method": "spectrum"}}
    again = recorded_fit(entry)
    assert again.major == r.major and again.minor == r.minor and again.angle == r.angle
    assert _fit_dict(rounded_fit(r)) == _fit_dict(r) == text
    assert fit_sha256(text) == fit_sha256(_fit_dict(again))


@pytest.mark.parametrize("name", sorted(FILES))
def test_the_committed_files_hold_rounded_fits_with_their_digests(name):
    body = read_params_file(FILES[name])   # checks every fit against its fit_sha256
    assert body["ensemble"] == name and body["significant_digits"] == SIGNIFICANT_DIGITS
    for entry in body["records"].values():
        assert entry["fit_sha256"] == fit_sha256(entry["fit"])
        for comp in ("major", "minor"):
            for v in entry["fit"][comp].values():
                assert v is None or v == round_significant(v)
        assert len(entry["pairs_sha256"]) == entry["n_synthetic"] == 10


@pytest.mark.parametrize(("name", "record", "seed", "n"),
                         [("elcentro", "el-centro-1940", 2017, 2),
                          ("lomaprieta", "loma-prieta-sjte", 1989, 1)])
def test_pairs_from_recorded_parameters_are_bit_identical_to_the_committed_digests(
        name, record, seed, n):
    entry = next(iter(read_params_file(FILES[name])["records"].values()))
    motion = read_motion(record)
    builds = [build_ensemble(motion, n, seed, recorded=entry) for _ in range(2)]
    shas = [[m.samples_sha256 for m in b.motions[1:]] for b in builds]
    assert shas[0] == shas[1] == entry["pairs_sha256"][:n]
    assert all(b.info["motions_match"] is True and b.info["fit_source"] == "recorded"
               for b in builds)
    # the fit was not run: the parameters simulated are the file's
    assert _fit_dict(builds[0].fit) == entry["fit"]


def test_an_altered_file_is_refused_naming_the_record(tmp_path):
    body = json.loads(FILES["elcentro"].read_text())
    body["records"]["el-centro-1940"]["fit"]["major"]["zeta_f"] = 0.45
    path = tmp_path / "altered.params.json"
    path.write_text(json.dumps(body))
    with pytest.raises(ValueError, match=r"record 'el-centro-1940' has fit_sha256 .* hash to"):
        read_params_file(path)
    with pytest.raises(ValueError, match=r"^ensembles\.e\.params: parameters file .* has"):
        entries_for(path, [("el-centro-1940", {"n_synthetic": 1})], "ensembles.e.params")


def test_a_fit_of_other_settings_or_records_is_refused():
    entry = read_params_file(FILES["elcentro"])["records"]["el-centro-1940"]
    settings = dict(entry["settings"])
    check_settings(entry, settings, "here")
    with pytest.raises(ValueError, match=r"here: .*highpass: file 'oscillator', study "
                                         r"'butterworth'"):
        check_settings(entry, {**settings, "highpass": "butterworth"}, "here")
    with pytest.raises(ValueError, match="holds no fit of record 'other'"):
        entries_for(FILES["elcentro"], [("other", {"n_synthetic": 2})], "f")
    # a record without pairs needs no fit
    assert entries_for(FILES["elcentro"], [("other", {"n_synthetic": 0})], "f")
    # another seed: the fit is used, the pairs are not the recorded ones (no verdict)
    assert pairs_match(entry, 1, entry["pairs_sha256"][:1]) is None
    assert pairs_match(entry, 2017, ["0" * 64]) is False


def test_the_params_key_changes_the_ensemble_digest_only_when_given():
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    given = EnsembleSpec.from_config(config, "elcentro")
    assert given.params == "config/ensembles/elcentro.params.json"
    config["ensembles"]["elcentro"].pop("params")
    plain = EnsembleSpec.from_config(config, "elcentro")
    assert "params" not in plain.to_attrs() and given.digest != plain.digest
    assert EnsembleSpec.from_attrs(given.to_attrs()) == given
    config["ensembles"]["elcentro"]["params"] = 3
    with pytest.raises(ValueError, match=r"ensembles\.elcentro\.params must be a file name"):
        EnsembleSpec.from_config(config, "elcentro")


_PROBE = """
import json, sys
from rocking.motions.build import build_ensemble, read_motion
from rocking.motions.stochastic.recorded import read_params_file
entry = read_params_file(sys.argv[1])["records"]["el-centro-1940"]
b = build_ensemble(read_motion("el-centro-1940"), 2, 2017, recorded=entry)
print(json.dumps([m.samples_sha256 for m in b.motions[1:]]))
"""


def test_pairs_do_not_depend_on_the_cpu_paths_numpy_and_numba_pick():
    """numpy's SIMD dispatch lowered to its baseline and numba compiled for a generic x86-64:
    the same pairs to the bit (numpy's AVX-512 exp and FMA complex products changed them)."""
    import os
    import subprocess
    import sys

    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    present = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]
    env = {**os.environ, "NPY_DISABLE_CPU_FEATURES": " ".join(present),
           "NUMBA_CPU_NAME": "generic", "NUMBA_CACHE_DIR": str(Path(os.environ.get(
               "TMPDIR", "/tmp")) / "rocking-numba-generic")}
    out = subprocess.run([sys.executable, "-c", _PROBE, str(FILES["elcentro"])], env=env,
                         capture_output=True, text=True, check=True, timeout=600)
    entry = read_params_file(FILES["elcentro"])["records"]["el-centro-1940"]
    assert json.loads(out.stdout.strip().splitlines()[-1]) == entry["pairs_sha256"][:2]


def test_a_suite_uses_each_record_s_recorded_fit():
    from rocking.motions.build import build_suite, recorded_entries

    entries = read_params_file(FILES["elcentro"])["records"]
    settings = {"n_synthetic": 1, "seed": 2017, "mw": None, "rotation_deg": "auto",
                "highpass": "oscillator", "fc_hz": None}
    build = build_suite([(read_motion("el-centro-1940"), settings)], recorded=entries)
    (record,) = build.info["records"]
    assert record["fit_source"] == "recorded" and record["motions_match"] is True
    assert record["pairs_sha256"] == entries["el-centro-1940"]["pairs_sha256"][:1]
    # and the suite's file written again holds the same fit
    again = recorded_entries(build, [{**entries["el-centro-1940"]["settings"]}])
    assert again["el-centro-1940"]["fit"] == entries["el-centro-1940"]["fit"]
