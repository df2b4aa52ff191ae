"""`rocking verify`: the committed gallery against itself, copies with answers moved, and the
bad inputs (no run, another configuration, a partial run)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pandas as pd
import pytest
import yaml

from rocking.cli import main
from rocking.study.verify import answer_tolerance, config_differences, verify_run

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "results" / "paper"
VALUE = "pga_crit [g tan(alpha)]"


def _copy(tmp_path: Path) -> Path:
    """The gallery's configuration and tables (no figures) in a folder of the test."""
    out = tmp_path / "run"
    shutil.copytree(GALLERY, out, ignore=shutil.ignore_patterns("*.png", "*.html", "*.xml",
                                                                 "figures", "motions"))
    return out


R_TOL, SHARE = answer_tolerance("default")
"""Two runs' answers: within 2e of each other in all but a share 2(1 − q) of them."""


def _rows(run: Path) -> tuple[Path, pd.DataFrame, pd.Index]:
    """El Centro's critical.csv of ``run``, and its answers of synthetic motions."""
    path = run / "elcentro" / "critical.csv"
    frame = pd.read_csv(path)
    return path, frame, frame.index[frame[VALUE].notna()
                                    & (frame["motion"] != "el-centro-1940")]


def _move(run: Path, factor: float, n: int = 1, start: int = 7) -> pd.Series:
    """Multiply ``n`` El Centro answers by ``factor``; the first of them."""
    path, frame, rows = _rows(run)
    pick = rows[start:start + n]
    frame.loc[pick, VALUE] *= factor
    frame.loc[pick, "pga_crit_g [g]"] *= factor
    frame.to_csv(path, index=False, float_format="%.10g")
    return frame.loc[pick[0]]


def test_the_tolerance_is_twice_the_stated_error():
    """The default preset's stated error (e, q) in one place (rocking.spectra.accuracy)."""
    from rocking.spectra.accuracy import STATED

    e, q = STATED["default"]
    assert (R_TOL, SHARE) == pytest.approx((2 * e, 2 * (1 - q)))
    assert answer_tolerance({"preset": "default", "rtol": 1e-9}) == (R_TOL, SHARE)


def test_the_gallery_against_itself_is_identical_table_by_table(capsys):
    assert main(["verify", str(GALLERY), "--against", str(GALLERY)]) == 0
    out = capsys.readouterr().out.splitlines()
    tables = sorted(p.relative_to(GALLERY).as_posix() for p in GALLERY.glob("*/*.csv"))
    assert tables and "elcentro/critical.csv" in tables
    for t in tables:
        assert any(line.startswith(f"{t}: identical (") for line in out), t
    assert f"bit-identical: {len(tables)} of {len(tables)} tables" in "\n".join(out)


def test_an_answer_moved_beyond_its_tolerance_is_named_and_counted(tmp_path, capsys):
    """One answer 1.5 × 2e off: named, and the table stays within the stated error (one row
    is within the share it allows); the tables not touched stay identical."""
    run = _copy(tmp_path)
    row = _move(run, 1 + 1.5 * R_TOL)
    assert main(["verify", str(run), "--against", str(GALLERY)]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    head = next(line for line in lines if line.startswith("elcentro/critical.csv:"))
    assert "within the answers' stated error" in head and "1 beyond of" in head
    named = lines[lines.index(head) + 1:]
    said = f"{150 * R_TOL:.2f}% off the gallery's, tolerance {100 * R_TOL:.2f}%"
    assert any(f"motion={row['motion']}" in line and f"R={row['R [m]']}" in line and
               f"limit_state={row['limit_state']}" in line and said in line for line in named)
    assert "elcentro/mean_spectra.csv: identical" in out
    assert "lomaprieta/critical.csv: identical" in out


def test_more_answers_beyond_than_the_stated_error_allows_differ(tmp_path, capsys):
    run = _copy(tmp_path)
    _, _, rows = _rows(run)
    _move(run, 1 + 1.5 * R_TOL, n=int(SHARE * len(pd.read_csv(
        run / "elcentro" / "critical.csv"))) + 10, start=0)
    assert main(["verify", str(run), "--against", str(GALLERY)]) == 1
    out = capsys.readouterr().out
    assert "elcentro/critical.csv: DIFFERS beyond the answers' stated error" in out
    assert "1 of" in out.splitlines()[-1] and "elcentro/critical.csv" in out.splitlines()[-1]


def test_a_move_within_the_tolerance_is_reported_as_such(tmp_path, capsys):
    run = _copy(tmp_path)
    _move(run, 1 + 0.9 * R_TOL, n=2)
    assert main(["verify", str(run), "--against", str(GALLERY)]) == 0
    out = capsys.readouterr().out
    assert "elcentro/critical.csv: within the answers' stated error (" in out
    assert ", 2 within)" in out


def test_an_aggregate_takes_the_tolerance_of_its_answers(tmp_path):
    """A mean moved within r is within; one moved beyond is beyond (no share of an
    aggregate's rows may differ beyond)."""
    run = _copy(tmp_path)
    path = run / "elcentro" / "mean_spectra.csv"
    frame = pd.read_csv(path)
    rows = frame.index[frame["mean [g tan(alpha)]"].notna()]
    frame.loc[rows[0], "mean [g tan(alpha)]"] *= 1 + 0.5 * R_TOL    # within
    frame.loc[rows[1], "mean [g tan(alpha)]"] *= 1 + 1.5 * R_TOL    # beyond
    frame.to_csv(path, index=False, float_format="%.10g")
    verdict = next(v for v in verify_run(run, GALLERY) if v.table == "elcentro/mean_spectra.csv")
    assert verdict.verdict == "beyond" and verdict.n_within == 1 and len(verdict.beyond) == 1
    assert verdict.allowed == 0
    assert verdict.beyond[0].split(": ", 1)[1].startswith("mean ")


def test_a_quantity_written_another_way_is_the_same_configuration():
    """``quantity`` absent, a name, or the mapping: one choice; another p is another."""
    base = {"studies": {"s": {}}}
    assert config_differences({**base, "quantity": "exceedance_quantile"}, base) == []
    assert config_differences(
        {**base, "quantity": {"name": "exceedance_quantile", "p": 0.1, "w": 0.02}}, base) == []
    assert config_differences({**base, "quantity": {"p": 0.2}}, base) == ["quantity.p"]
    assert config_differences({**base, "quantity": "first_exceedance"}, base) == [
        "quantity.name"]


def _one_line_exit_2(argv, capsys) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("rocking verify: error: ")
    return err


def test_a_folder_that_is_no_run(tmp_path, capsys):
    err = _one_line_exit_2(["verify", str(tmp_path), "--against", str(GALLERY)], capsys)
    assert str(tmp_path) in err and "not a run" in err and "config.yaml" in err


def test_a_run_of_another_configuration_names_the_keys(tmp_path, capsys):
    run = _copy(tmp_path)
    config = yaml.safe_load((run / "config.yaml").read_text())
    config["search"]["upper"] = 30.0
    config["studies"]["lomaprieta"]["upper"] = 50.0
    config["dask"]["progress_interval"] = 5          # cannot change a number: not compared
    (run / "config.yaml").write_text(yaml.safe_dump(config))
    err = _one_line_exit_2(["verify", str(run), "--against", str(GALLERY)], capsys)
    assert "another configuration" in err and "search.upper" in err
    assert "studies.lomaprieta.upper" in err and "dask" not in err


def test_a_partial_run_names_what_is_missing(tmp_path, capsys):
    run = _copy(tmp_path)
    (run / "lomaprieta" / "fragility.csv").unlink()
    err = _one_line_exit_2(["verify", str(run), "--against", str(GALLERY)], capsys)
    assert str(run) in err and "partial run" in err and "lomaprieta/fragility.csv" in err


def test_an_output_root_without_its_store_is_partial(tmp_path, capsys):
    # a run's output root: <study>/config.yaml, the answers in the spectra store
    run = tmp_path / "results"
    for study in ("elcentro", "lomaprieta"):
        shutil.copytree(GALLERY / study, run / study,
                        ignore=shutil.ignore_patterns("critical.csv", "figures", "*.html"))
        shutil.copy(GALLERY / "config.yaml", run / study / "config.yaml")
    err = _one_line_exit_2(["verify", str(run), "--against", str(GALLERY)], capsys)
    assert "partial run, missing elcentro/spectra.zarr, lomaprieta/spectra.zarr" in err


def test_config_differences_are_dotted_keys():
    a = {"search": {"upper": 20.0}, "ensembles": {"e": {"seed": 1}}, "dask": {"x": 1}}
    b = {"search": {"upper": 20.0}, "ensembles": {"e": {"seed": 2, "params": "p.json"}},
         "dask": {"x": 2}}
    assert config_differences(a, b) == ["ensembles.e.params", "ensembles.e.seed"]


def test_motions_that_differ_from_the_gallery_s_are_named(tmp_path, capsys):
    """An output root: <study>/config.yaml, the tables, motions/<name>-<digest>.nc."""
    import numpy as np

    from rocking.config.ensemble import EnsembleSpec
    from rocking.motions.ensemble_io import save_ensemble
    from rocking.motions.motion import GroundMotion

    run = tmp_path / "results"
    for study in ("elcentro", "lomaprieta"):
        shutil.copytree(GALLERY / study, run / study,
                        ignore=shutil.ignore_patterns("figures", "*.html"))
        shutil.copy(GALLERY / "config.yaml", run / study / "config.yaml")
    config = yaml.safe_load((GALLERY / "config.yaml").read_text())
    digest = EnsembleSpec.from_config(config, "elcentro").digest
    a = np.sin(np.linspace(0.0, 3.0, 50))
    save_ensemble(run / "motions" / f"elcentro-{digest}.nc",
                  [GroundMotion(a, a, 0.01, "el-centro-1940")])
    assert main(["verify", str(run), "--against", str(GALLERY)]) == 0
    out = capsys.readouterr().out
    assert "motions/elcentro: 11 of 11 motions differ from the gallery's in their bits: " \
           "el-centro-1940, el-centro-1940-rdk-000" in out
    assert "motions/lomaprieta" not in out   # no file of it: nothing said


def test_a_key_one_side_lacks_is_held_to_its_default():
    """A gallery written before a key existed: absent = the schema default; the output folder
    and a study's `reproduces` change no table."""
    run = {"ensembles": {"e": {"units": "g", "highpass": "oscillator"}}, "output": "mine",
           "studies": {"s": {"reproduces": "vassiliou2017", "stripes": {"refine": 8}}}}
    gallery = {"ensembles": {"e": {}}, "studies": {"s": {"stripes": {}}}}
    assert config_differences(run, gallery) == []
    run["studies"]["s"]["stripes"]["refine"] = 4
    run["ensembles"]["e"]["units"] = "m/s2"
    assert config_differences(run, gallery) == ["ensembles.e.units",
                                                "studies.s.stripes.refine"]


def test_rows_with_repeated_keys_are_matched_in_order(tmp_path, capsys):
    run = _copy(tmp_path)
    path = run / "elcentro" / "linear_fit.csv"
    frame = pd.read_csv(path)
    frame = pd.concat([frame, frame.iloc[[3]]], ignore_index=True)   # a key twice
    frame.to_csv(path, index=False, float_format="%.10g")
    assert main(["verify", str(run), "--against", str(GALLERY)]) == 1
    out = capsys.readouterr().out
    assert "elcentro/linear_fit.csv: DIFFERS" in out and "occurrence=1: only in the run" in out


def test_a_first_exceedance_never_decides(tmp_path):
    """The first exceedance on a scan grid has no stated error (it moves by a window when
    the last bits do): a moved one leaves the table within, never beyond, while the same
    move of the answer beside it is beyond."""
    column = "first_exceedance [g tan(alpha)]"
    sides = {}
    for side in ("gallery", "run"):
        folder = _copy(tmp_path / side)
        path = folder / "elcentro" / "critical.csv"
        frame = pd.read_csv(path)
        frame[column] = frame[VALUE]
        sides[side] = (folder, path, frame)
    folder, path, frame = sides["gallery"]
    frame.to_csv(path, index=False, float_format="%.10g")
    folder, path, frame = sides["run"]
    pick = frame[VALUE].notna().idxmax()
    frame.loc[pick, column] *= 10.0
    frame.to_csv(path, index=False, float_format="%.10g")
    gallery = sides["gallery"][0]
    verdict = next(v for v in verify_run(folder, gallery) if v.table == "elcentro/critical.csv")
    assert verdict.verdict == "within" and not verdict.beyond and verdict.n_within == 1
    frame.loc[pick, VALUE] *= 10.0
    frame.to_csv(path, index=False, float_format="%.10g")
    verdict = next(v for v in verify_run(folder, gallery) if v.table == "elcentro/critical.csv")
    assert len(verdict.beyond) == 1
