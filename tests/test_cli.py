"""The command line: help with defaults and examples, one-line user errors, outputs with
units, strict JSON, results in the order asked."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from rocking.cli import SUBCOMMANDS, build_parser, main
from rocking.motions.catalogue import load_record
from rocking.motions.ensemble_io import save_ensemble

# the body: spectra and stripes have no default slenderness
SPECTRA = ["spectra", "--tan-alpha", "0.2"]
STRIPES = ["stripes", "--tan-alpha", "0.2"]


def _no_nan(text):
    raise ValueError(f"non-standard JSON constant {text}")


def strict_json(path: Path):
    """json.loads that refuses NaN and Infinity (what other tools do)."""
    return json.loads(Path(path).read_text(), parse_constant=_no_nan)


def test_version_and_help_show_defaults_and_examples(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0 and capsys.readouterr().out.startswith("rocking 0.")
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name in SUBCOMMANDS:
        text = sub.choices[name].format_help()
        assert "examples:" in text and f"rocking {name} " in text, name
        assert "(default:" in text, name
    spectra = sub.choices["spectra"].format_help()
    flat = " ".join(spectra.split())
    assert "slenderness b/h [-] (no default: give it, or --height and --diameter)" in flat
    assert "(default: 3d)" in spectra and "(default: 20.0)" in spectra


def test_every_default_search_bound_is_the_one_constant():
    """The search bound is one number (:data:`rocking.spectra.accuracy.DEFAULT_UPPER`): the
    library's default, the configuration's and every command line's ``--upper``."""
    import argparse
    import inspect

    from rocking.config.fields import DEFAULTS
    from rocking.fragility.stripes import STRIPE_RANGE
    from rocking.spectra.accuracy import DEFAULT_UPPER
    from rocking.spectra.critical import critical_intensity
    from rocking.spectra.search import search_critical

    for fn in (search_critical, critical_intensity):
        assert inspect.signature(fn).parameters["upper"].default is DEFAULT_UPPER
    assert DEFAULTS["search"]["upper"] is DEFAULT_UPPER and STRIPE_RANGE[1] is DEFAULT_UPPER
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for command in ("spectra", "stripes", "risk"):
        assert sub.choices[command].get_default("upper") is DEFAULT_UPPER


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("inputs")
    (d / "adir").mkdir()
    (d / "empty.AT2").write_text("")
    (d / "repeated.txt").write_text("0 0.1\n0 0.2\n0 0.3\n")
    (d / "bad.AT2").write_text("PEER\nx\nunits g\nNPTS= 3, DT= .01 SEC\n0.1 abc 0.3\n")
    (d / "plain.txt").write_text("not an ensemble\n")
    return d


@pytest.mark.parametrize(
    ("argv", "what"),
    [
        (["simulate", "--R", "1", "--tan-alpha", "0.2", "--files", "nosuch.AT2", "y.AT2",
          "-o", "o"], "nosuch.AT2"),
        ([*SPECTRA, "--R", "1", "--files", "nosuch.AT2", "y.AT2"], "nosuch.AT2"),
        (["motions", "--files", "nosuch.AT2", "y.AT2", "-o", "m.nc"], "nosuch.AT2"),
        ([*SPECTRA, "--R", "1", "--files", "{d}/adir", "{d}/adir"], "is a directory"),
        ([*SPECTRA, "--R", "1", "--files", "{d}/empty.AT2", "{d}/empty.AT2"], "is empty"),
        ([*SPECTRA, "--R", "1", "--files", "{d}/repeated.txt", "{d}/repeated.txt"],
         "time does not increase"),
        ([*SPECTRA, "--R", "1", "--files", "{d}/bad.AT2", "{d}/bad.AT2"], "line 5"),
        ([*SPECTRA, "--R", "1", "--record", "kobe-1995"], "kobe-1995"),
        ([*SPECTRA, "--R", "1", "--ensemble", "{d}/nosuch.nc"], "nosuch.nc"),
        ([*SPECTRA, "--R", "1", "--ensemble", "{d}/plain.txt"], "plain.txt"),
        ([*SPECTRA, "--R", "1", "-o", "{d}/x.txt"], "x.txt"),
        ([*SPECTRA, "--R", "1", "-q", "--accuracy", "fast", "--limit-states", "tilt:1",
          "-o", "{d}/adir/sub/x.csv/"], None),
        (["simulate", "--R", "1", "--tan-alpha", "0.2", "--theta0", "0.01", "--duration",
          "1", "-o", "{d}/bad.AT2"], "bad.AT2"),
        (["simulate", "--R", "1", "--tan-alpha", "0.2", "--body", "block", "-o", "o"],
         "--body block"),
        (["motions", "-o", "{d}/m.csv"], "m.csv"),
    ],
)
def test_user_errors_are_one_line_with_nonzero_exit(argv, what, files, capsys, tmp_path,
                                                     monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = [a.format(d=files) for a in argv]
    code = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    if what is None:  # writing into a file as if it were a folder
        assert code == 0 or (code == 2 and len(err) == 1)
        return
    assert code == 2
    assert len(err) == 1 and err[0].startswith(f"rocking {argv[0]}: error: "), err
    assert what in err[0] and "Traceback" not in err[0]


def test_unwritable_output_is_one_line_without_traceback(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    out = subprocess.run([sys.executable, "-m", "rocking.cli", "simulate", "--R", "1",
                          "--tan-alpha", "0.2", "--theta0", "0.01", "--duration", "0.5",
                          "-o", str(blocker / "run")], capture_output=True, text=True)
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
    assert str(blocker / "run") in out.stderr or str(blocker) in out.stderr


def test_simulate_outputs_have_units_and_strict_json(tmp_path, capsys):
    # a body too wide to uplift: t_uplift is "never" (NaN inside), null in the JSON
    assert main(["simulate", "--R", "1", "--tan-alpha", "1e6", "--record", "el-centro-1940",
                 "-o", str(tmp_path / "wide"), "--json"]) == 0
    summary = strict_json(tmp_path / "wide/summary.json")
    assert summary["t_uplift"] is None and summary["uplifted"] is False
    assert json.loads(capsys.readouterr().out, parse_constant=_no_nan)["t_uplift"] is None
    assert summary["units"]["theta_max"] == "rad"
    # 2D: no 3D-only columns, impacts named as impacts
    assert main(["simulate", "--R", "1", "--tan-alpha", "0.2", "--mode", "2d-x", "--record",
                 "el-centro-1940", "--pga-ratio", "2", "-o", str(tmp_path / "two")]) == 0
    hist = pd.read_csv(tmp_path / "two/history.csv")
    assert list(hist.columns) == ["t [s]", "theta [rad]", "theta_dot [rad/s]",
                                  "normal_force [mg]", "mu_required [-]"]
    summary = strict_json(tmp_path / "two/summary.json")
    assert "n_impacts" in summary and "n_quasi_impacts" not in summary
    assert summary["n_impacts"] > 0
    assert summary["pga_ratio"] == pytest.approx(2.0, rel=1e-12)
    assert summary["pga_g"] == pytest.approx(2.0 * 0.2, rel=1e-12)
    # damped: contact quantities with their units
    assert main(["simulate", "--R", "6", "--tan-alpha", "0.2", "--mode", "3d-damped",
                 "--theta0", "0.1", "--phi-dot0", "1e-3", "--duration", "0.2",
                 "-o", str(tmp_path / "damped")]) == 0
    cols = pd.read_csv(tmp_path / "damped/history.csv").columns
    assert list(cols)[-5:] == ["w [m]", "w_dot [m/s]", "contact_force [N/kg]",
                               "normal_force [mg]", "mu_required [-]"]
    assert "J/kg" in strict_json(tmp_path / "damped/summary.json")["units"]["dissipated"]


def _short_ensemble(path: Path) -> Path:
    rec = load_record("el-centro-1940")
    keep = 800  # 8 s: quick searches that still tip a small cylinder
    from rocking.motions.motion import GroundMotion

    m = GroundMotion(rec.ax[:keep], rec.ay[:keep], rec.dt, "elc-8s", rec.metadata)
    return save_ensemble(path, [m])


def test_spectra_csv_json_order_units_and_both_intensities(tmp_path):
    ens = _short_ensemble(tmp_path / "e.nc")
    common = [*SPECTRA, "--R", "1,2", "--ensemble", str(ens), "--accuracy", "fast",
              "--limit-states", "overturning,tilt:1/3", "-q"]
    assert main([*common, "-o", str(tmp_path / "s.csv")]) == 0
    table = pd.read_csv(tmp_path / "s.csv")
    assert list(table["limit_state"][:2]) == ["overturning", "tilt:1/3"]  # order asked
    np.testing.assert_allclose(table["pga_crit_g [g]"],  # both to 10 digits in the CSV
                               table["pga_crit [g tan(alpha)]"] * 0.2, rtol=1e-9)
    assert {"R [m]", "tan_alpha [-]", "source_record", "processing"} <= set(table.columns)
    assert main([*common, "--upper", "1.05", "-o", str(tmp_path / "s.json")]) == 0
    doc = strict_json(tmp_path / "s.json")  # not reached up to 1.05: null, never NaN
    values = [r["pga_crit"] for r in doc["results"]]
    assert None in values and all(v is None or math.isfinite(v) for v in values)
    assert doc["units"]["pga_crit_g"] == "g" and doc["limit_states"][0] == "overturning"


def test_motions_json_is_strict(tmp_path):
    assert main(["motions", "-n", "1", "--max-duration", "5", "-q",
                 "-o", str(tmp_path / "m.nc")]) == 0
    params = strict_json(tmp_path / "m.json")
    assert params["n_synthetic"] == 1


def _pair_files(d):
    """Two AT2 files with azimuths 180 (given first) and 270: 270 is 180 + 90."""
    out = []
    for az, values in ((180, [0.1, -0.2, 0.05, 0.0]), (270, [0.3, 0.1, 0.0, 0.0])):
        p = d / f"site_{az}.AT2"
        body = "\n".join(f"  {v:.7E}" for v in values)
        p.write_text("PEER NGA STRONG MOTION DATABASE RECORD\n"
                     f"Somewhere, 1/1/2000, Station, {az}\n"
                     "ACCELERATION TIME SERIES IN UNITS OF G\n"
                     f"NPTS=   {len(values)}, DT=   .0100 SEC,\n{body}\n")
        out.append(p)
    return out


def test_files_are_taken_in_the_order_given(tmp_path, capsys):
    import warnings

    from rocking.cli import _common, build_parser
    from rocking.constants import G

    first, second = _pair_files(tmp_path)
    argv = ["simulate", "--R", "1", "--tan-alpha", "0.2", "--mode", "2d-x", "--files",
            str(first), str(second), "-o", str(tmp_path / "run")]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no swap, so no warning
        motion = _common.motion_from_args(build_parser(["simulate"]).parse_args(argv))
    np.testing.assert_allclose(motion.ax, np.array([0.1, -0.2, 0.05, 0.0]) * G)
    assert motion.metadata["x_azimuth"] == 180.0
    # reordering only on request, and then said
    args = build_parser(["simulate"]).parse_args([*argv, "--order-by-azimuth"])
    with pytest.warns(UserWarning, match=r"x = \S*site_270.AT2 \(azimuth 270°\).*swapped"):
        motion = _common.motion_from_args(args)
    np.testing.assert_allclose(motion.ax, np.array([0.3, 0.1, 0.0, 0.0]) * G)
    sub = build_parser(["spectra"])._subparsers._group_actions[0].choices["spectra"]
    assert "in the order given" in sub.format_help() and "--order-by-azimuth" in \
        sub.format_help()


@pytest.mark.parametrize("where", ["directory", "read-only", "under a file"])
def test_unwritable_spectra_output_fails_before_any_analysis(where, tmp_path, capsys,
                                                             monkeypatch):
    import rocking.spectra.critical as critical

    def no_analysis(*a, **k):
        raise AssertionError("an analysis ran before the output was checked")

    monkeypatch.setattr(critical, "critical_intensity_batch", no_analysis)
    (tmp_path / "out.csv").mkdir()
    (tmp_path / "blocker").write_text("x")
    out = {"directory": tmp_path / "out.csv",
           "read-only": "/proc/rocking-test/s.csv",  # not writable, even by root
           "under a file": tmp_path / "blocker" / "s.csv"}[where]
    code = main([*SPECTRA, "--R", "1", "-q", "--accuracy", "fast", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert str(out) in err[0] or str(Path(out).parent) in err[0]


def test_full_disk_names_the_file_and_leaves_no_partial_output(tmp_path, capsys, monkeypatch):
    import errno

    import pandas as pd

    def full_disk(self, path, *a, **k):
        Path(path).write_text("R [m],pga")  # a few bytes went out, then the disk was full
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(pd.DataFrame, "to_csv", full_disk)
    out = tmp_path / "s.csv"
    code = main([*SPECTRA, "--R", "1", "-q", "--accuracy", "fast", "--limit-states",
                 "tilt:1", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert str(out) in err[0] and "No space left on device" in err[0]
    assert list(tmp_path.iterdir()) == []  # neither the output nor a temporary file


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--R", "2,2"], "--R repeats [2.0]"),
        (["--R", "2", "--R", "1,2"], "--R repeats [2.0]"),
        (["--R", ""], "--R: give at least one size R [m], got none"),
        (["--R", "nan"], "--R must hold finite sizes > 0"),
        (["--R", "1", "--upper", "1"], "--upper must be a finite number > 1"),
        (["--R", "1", "--upper", "0.5"], "--upper must be a finite number > 1"),
        (["--R", "1", "--mu", "0"], "--mu must be a finite number > 0, got 0.0"),
        (["--R", "1", "--mu", "-1"], "--mu must be a finite number > 0, got -1.0"),
        (["--R", "1", "--limit-states", "sliding:abc"], "'sliding:abc'"),
        (["--R", "1", "--limit-states", "sliding:0"], "'sliding:0'"),
    ],
)
def test_spectra_rejects_bad_lists_and_bounds_before_work(argv, message, capsys, monkeypatch):
    import rocking.spectra.critical as critical

    def no_analysis(*a, **k):
        raise AssertionError("an analysis ran")

    monkeypatch.setattr(critical, "critical_intensity_batch", no_analysis)
    assert main([*SPECTRA, "-q", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err


def test_motions_refuses_an_ensemble_too_large_for_memory_before_work(tmp_path, capsys):
    code = main(["motions", "-n", "1000000000", "-q", "-o", str(tmp_path / "m.nc")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert "--n-synthetic=1000000000: building the ensemble needs about" in err[0]
    assert not (tmp_path / "m.nc").exists()


@pytest.mark.parametrize(
    ("extra", "said", "not_said"),
    [
        (["--files", "{x}"], "use --mode 2d-x", "model="),
        (["--files", "{x}", "{x}", "--highpass", "oscillator"],
         "--mw (or --fc-hz) is needed for the high-pass", "fc_hz"),
        (["--files", "{x}", "{x}", "--highpass", "butterworth", "--fc-hz", "1000"],
         "--fc-hz=1000.0 must be below the Nyquist frequency", "fc_hz"),
        (["--files", "{x}", "{x}", "--highpass", "oscillator", "--fc-hz", "1000"],
         "--fc-hz=1000.0 must be below the Nyquist frequency", "fc_hz"),
    ],
    ids=["one-component", "highpass-without-mw", "corner-above-nyquist",
         "oscillator-corner-above-nyquist"],
)
def test_library_errors_are_told_in_the_command_line_s_words(extra, said, not_said, capsys,
                                                              tmp_path):
    from conftest import ELC180, package_record

    argv = ["simulate", "--R", "2", "--tan-alpha", "0.2", "-o", str(tmp_path / "run"),
            *[a.format(x=package_record(ELC180)) for a in extra]]
    assert main(argv) == 2
    # on an empty numba cache the one-line compile notice may come first: it is no error
    err = "\n".join(line for line in capsys.readouterr().err.strip().splitlines()
                    if not line.startswith("rocking simulate: compiling"))
    assert said in err and not_said not in err and len(err.splitlines()) == 1, err


def test_one_column_files_take_their_time_step_from_dt(tmp_path, capsys):
    """``--dt`` gives one-column text files the time step a two-column file carries itself:
    the same samples either way give the same answer."""
    dt = 0.01
    t = np.arange(400) * dt
    ax, ay = 0.3 * np.sin(2 * np.pi * 1.5 * t), 0.2 * np.cos(2 * np.pi * 1.1 * t)  # [g]
    for name, acc in (("x", ax), ("y", ay)):
        np.savetxt(tmp_path / f"{name}1.txt", acc)
        np.savetxt(tmp_path / f"{name}2.txt", np.column_stack([t, acc]))
    common = ["simulate", "--R", "1", "--tan-alpha", "0.2", "-q"]
    assert main([*common, "--files", str(tmp_path / "x1.txt"), str(tmp_path / "y1.txt"),
                 "--dt", str(dt), "-o", str(tmp_path / "one")]) == 0
    assert main([*common, "--files", str(tmp_path / "x2.txt"), str(tmp_path / "y2.txt"),
                 "-o", str(tmp_path / "two")]) == 0
    one, two = (strict_json(tmp_path / f"{k}/summary.json") for k in ("one", "two"))
    assert one["theta_max"] > 0 and one["theta_max"] == two["theta_max"]
    capsys.readouterr()
    # without it: one line naming the option; a --dt the file contradicts is refused
    assert main([*common, "--files", str(tmp_path / "x1.txt"), "--mode", "2d-x",
                 "-o", str(tmp_path / "none")]) == 2
    err = capsys.readouterr().err
    assert "--dt (the time step [s]) is required for the one-column file" in err, err
    assert main([*common, "--files", str(tmp_path / "x2.txt"), "--mode", "2d-x", "--dt",
                 "0.02", "-o", str(tmp_path / "bad")]) == 2
    assert "--dt=0.02 disagrees with the time column" in capsys.readouterr().err


def test_ctrl_c_mid_search_is_one_line_exit_130_and_no_output(tmp_path):
    """SIGINT while the spectra search runs (inside a numba kernel or not): one line, no
    traceback, exit code 130, no output file."""
    import signal

    out = tmp_path / "s.csv"
    many_R = ",".join(f"{0.3 + 0.25 * i:g}" for i in range(80))
    # Ctrl-C as a terminal sends it (a process started in the background may ignore SIGINT)
    code = ("import signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
            "from rocking.cli import main; sys.exit(main(sys.argv[1:]))")
    proc = subprocess.Popen([sys.executable, "-c", code, *SPECTRA, "--R", many_R,
                             "--record", "el-centro-1940", "-o", str(out)],
                            stderr=subprocess.PIPE, text=True)
    lines = []
    for line in proc.stderr:  # wait for the search itself, not the imports
        lines.append(line)
        if "points done" in line:
            break
    proc.send_signal(signal.SIGINT)
    lines += proc.stderr.readlines()
    assert proc.wait(timeout=60) == 130, "".join(lines)
    text = "".join(lines)
    assert "Traceback" not in text, text
    assert lines[-1].startswith("rocking spectra: interrupted; partial results are discarded")
    assert not out.exists() and not list(tmp_path.iterdir())


def test_an_error_caused_by_ctrl_c_is_reported_as_the_interrupt(monkeypatch, capsys):
    """numba re-raises a KeyboardInterrupt from a compiled kernel as SystemError."""
    from rocking.cli import spectra

    def run(args):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise SystemError("CPUDispatcher returned a result with an exception set") from exc

    monkeypatch.setattr(spectra, "run", run)
    assert main([*SPECTRA, "--R", "1"]) == 130
    assert capsys.readouterr().err.startswith("rocking spectra: interrupted;")


def test_csv_floats_have_ten_digits_and_the_json_every_bit(tmp_path):
    """No ``0.20812080200000002`` in a CSV: 10 significant digits; the JSON keeps the double."""
    import re

    ens = _short_ensemble(tmp_path / "e.nc")
    common = ["spectra", "--R", "1", "--tan-alpha", "0.15", "--ensemble", str(ens),
              "--accuracy", "fast", "--limit-states", "overturning,tilt:1/3", "-q"]
    assert main([*common, "-o", str(tmp_path / "s.csv")]) == 0
    assert main([*common, "-o", str(tmp_path / "s.json")]) == 0
    text = (tmp_path / "s.csv").read_text()
    numbers = re.findall(r"(?<![\w.])\d+\.\d+(?:e[-+]\d+)?", text)
    assert numbers
    digits = [len(re.sub(r"e.*", "", n).replace(".", "").lstrip("0")) for n in numbers]
    assert max(digits) <= 10, [n for n, d in zip(numbers, digits, strict=True) if d > 10]
    table = pd.read_csv(tmp_path / "s.csv")
    exact = pd.DataFrame(strict_json(tmp_path / "s.json")["results"])
    for col in ("pga_crit", "pga_crit_g"):
        csv_col = table[next(c for c in table.columns if c.split(" [")[0] == col)]
        np.testing.assert_allclose(csv_col, exact[col], rtol=5e-10)
    # the doubles behind the table do carry more digits: the rounding is what is tested
    assert any(len(repr(float(v)).replace(".", "").lstrip("0")) > 10
               for v in exact["pga_crit_g"].dropna())


# ------------------------------------------------------------- what the commands print


def _numbers(text: str, label: str) -> list[float]:
    """The numbers on the line starting with ``label`` of a labelled block."""
    import re

    line = next(x for x in text.splitlines() if x.startswith(label))
    return [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?", line[len(label):])]


def test_simulate_prints_labelled_lines_and_json_on_request(tmp_path, capsys):
    """By default labelled lines: θmax in rad and as θmax/α, the intensity as PGA in g and as
    PGA/(g tan α), the processing; ``--json`` prints summary.json's content on one line."""
    ens = _short_ensemble(tmp_path / "e.nc")
    argv = ["simulate", "--R", "1", "--tan-alpha", "0.2", "--ensemble", str(ens),
            "--pga-ratio", "2", "-q"]
    assert main([*argv, "-o", str(tmp_path / "a")]) == 0
    text = capsys.readouterr().out
    summary = strict_json(tmp_path / "a/summary.json")
    alpha = math.atan(0.2)
    theta, share, t_peak = _numbers(text, "peak tilt")[:3]
    assert theta == pytest.approx(summary["theta_max"], rel=1e-3)
    assert share == pytest.approx(summary["theta_max"] / alpha, rel=1e-3)
    assert t_peak == pytest.approx(summary["t_theta_max"], rel=1e-3)
    assert "θmax =" in text and " α at t = " in text
    pga_g, ratio = _numbers(text, "intensity")[:2]
    assert pga_g == pytest.approx(0.4) and ratio == pytest.approx(2.0)
    assert "PGA = 0.4 g = 2 g tan α" in text
    for label in ("body", "mode", "motion", "processing", "outcome", "uplift", "written"):
        assert any(x.startswith(label) for x in text.splitlines()), label
    assert "rotation: none (recorded axes); high-pass: none" in text
    with pytest.raises(json.JSONDecodeError):
        json.loads(text)
    # --json: the one JSON line it always printed, equal to the file
    assert main([*argv, "-o", str(tmp_path / "b"), "--json"]) == 0
    out = capsys.readouterr().out
    assert out.count("\n") == 1
    assert json.loads(out, parse_constant=_no_nan) == strict_json(tmp_path / "b/summary.json")


def test_simulate_prints_the_processing_it_applied(tmp_path, capsys):
    """Asked the workflow's processing, the answer says so: principal axes and the
    oscillator high-pass with its corner (and the same in the JSON's processing line)."""
    argv = ["simulate", "--R", "1", "--tan-alpha", "0.2", "--record", "el-centro-1940",
            "--rotation", "auto", "--highpass", "oscillator", "--max-duration", "4",
            "--pga-ratio", "0.5", "-q"]  # below uplift: no rocking, quick
    assert main([*argv, "-o", str(tmp_path / "a")]) == 0
    text = capsys.readouterr().out
    line = next(x for x in text.splitlines() if x.startswith("processing"))
    assert "rotation: principal axes (turned -70.46°)" in line
    fc = _numbers(line.split("corner fc =")[1], "")[0]
    from rocking.motions.highpass import brune_corner

    assert fc == pytest.approx(brune_corner(6.95), rel=1e-3)  # the record's Mw
    assert "high-pass: oscillator" in line and "workflow" not in line
    assert "ok: did not uplift" in text and "uplift         never" in text
    assert main([*argv, "-o", str(tmp_path / "b"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert "rotated -70.46 deg to principal axes" in summary["processing"]
    assert "high-passed (oscillator" in summary["processing"]


def test_spectra_prints_a_labelled_table_and_json_on_request(tmp_path, capsys):
    ens = _short_ensemble(tmp_path / "e.nc")
    common = [*SPECTRA, "--R", "1,2", "--ensemble", str(ens), "--accuracy", "fast",
              "--limit-states", "overturning,tilt:1/3", "-q", "--tan-alpha", "0.15"]
    assert main([*common, "-o", str(tmp_path / "s.json")]) == 0
    text = capsys.readouterr().out
    doc = strict_json(tmp_path / "s.json")
    header = next(x for x in text.splitlines() if x.startswith("R [m]"))
    assert "PGA/(g tan α) [-]" in header and "PGA [g]" in header and "flags" in header
    for r in doc["results"]:
        row = next(x for x in text.splitlines()
                   if x.split()[:2] == [f"{r['R']:g}", r["limit_state"]])
        crit, crit_g = (float(v) for v in row.split()[2:4])
        assert crit == pytest.approx(r["pga_crit"], rel=1e-5)
        assert crit_g == pytest.approx(r["pga_crit"] * 0.15, rel=1e-5)
    # a motion of an ensemble file is used as stored: no options to suggest
    assert "processing  rotation: none (recorded axes); high-pass: none (as stored in the " \
        "ensemble file)" in text and "--rotation auto" not in text
    assert "tan α = 0.15 (α = 0.1489 rad" in text and f"written: {tmp_path / 's.json'}" in text
    # --json prints the document the file holds (the time it took aside)
    assert main([*common, "--json"]) == 0
    printed = json.loads(capsys.readouterr().out, parse_constant=_no_nan)
    assert printed.keys() == doc.keys()
    assert {k: v for k, v in printed.items() if k != "seconds"} == \
        {k: v for k, v in doc.items() if k != "seconds"}
    # a not-reached limit state reads as beyond the bound, not as a number
    assert main([*common, "--upper", "1.05"]) == 0
    text = capsys.readouterr().out
    assert "> 1.05" in text and "not reached: no exceedance up to the search bound" in text


def test_stripes_json_is_the_file_s_document_with_the_processing(tmp_path, capsys):
    ens = _short_ensemble(tmp_path / "e.nc")
    common = [*STRIPES, "--R", "1", "--ensemble", str(ens), "--intensities", "1.5,3",
              "--limit-states", "overturning", "-q"]
    assert main([*common, "-o", str(tmp_path / "s.json")]) == 0
    text = capsys.readouterr().out
    assert "median PGA/(g tan α) [-]" in text and "exceeding" in text and "1 of 1" in text
    assert "processing" in text and "stripes     2 intensities" in text
    assert main([*common, "--json"]) == 0
    printed = json.loads(capsys.readouterr().out, parse_constant=_no_nan)
    doc = strict_json(tmp_path / "s.json")
    assert {k: v for k, v in printed.items() if k != "seconds"} == \
        {k: v for k, v in doc.items() if k != "seconds"}
    assert printed["processing"] == {"elc-8s": doc["processing"]["elc-8s"]}


def test_risk_json_carries_the_table_and_the_fragility_it_integrates(tmp_path, capsys):
    rows = [("3d", "overturning", 0.2, 2.0, 0.4, 0.3, "ok"),
            ("3d", "tilt:1/3", 0.2, 2.0, 0.25, 0.2, "ok")]
    path = tmp_path / "fragility.csv"
    pd.DataFrame(rows, columns=["mode", "limit_state", "tan_alpha [-]", "R [m]",
                                "median_pga_g [g]", "beta [-]", "status"]).to_csv(path,
                                                                                 index=False)
    argv = ["risk", "--fragility", str(path), "--hazard", "1e-4,2.5"]
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out, parse_constant=_no_nan)
    assert doc["fragility"] == "critical_intensity" and doc["units"]["maf"] == "1/yr"
    lam = {r["limit_state"]: r["maf"] for r in doc["rows"]}
    # λ of a power law: k0 θ^-k exp(k² β² / 2) (Cornell et al. 2002)
    assert lam["overturning"] == pytest.approx(1e-4 * 0.4 ** -2.5 * math.exp(3.125 * 0.09),
                                               rel=1e-3)
    assert [r["limit_state"] for r in doc["rows"]] == ["tilt:1/3", "overturning"]
    assert main([*argv, "-o", str(tmp_path / "r.csv")]) == 0
    text = capsys.readouterr().out
    assert "fragility  " in text and "critical-intensity fragility" in text
    assert f"2 rows (every column) written: {tmp_path / 'r.csv'}" in text


def test_docs_cli_page_shows_what_its_commands_print(tmp_path, capsys, monkeypatch):
    """docs/cli.md's example commands print the text shown under them: the same words, the
    numbers within the answers' stated error (another CPU need not give the same bits)."""
    import re
    import shlex

    from conftest import assert_prints_within

    from rocking.study.verify import answer_tolerance

    page = (Path(__file__).resolve().parents[1] / "docs/cli.md").read_text(encoding="utf-8")
    commands = re.findall(r"^```bash\n(.*?)^```", page, flags=re.S | re.M)
    shown = re.findall(r"^```text\n(.*?)^```", page, flags=re.S | re.M)
    assert len(commands) == len(shown) == 2
    monkeypatch.chdir(tmp_path)  # simulate writes run/ here
    for command, text in zip(commands, shown, strict=True):
        argv = shlex.split(command.replace("\\\n", " "))
        assert argv[0] == "rocking"
        assert main(argv[1:]) == 0
        assert_prints_within(capsys.readouterr().out, text, answer_tolerance("default")[0])


def test_a_reader_closing_stdout_ends_the_command_quietly():
    """``rocking risk --json | head -1``: no error line, no traceback, exit code 141."""
    root = Path(__file__).resolve().parents[1]
    proc = subprocess.Popen([sys.executable, "-m", "rocking.cli", "risk", "--fragility",
                             str(root / "results/paper/elcentro/fragility.csv"), "--hazard",
                             "1e-4,2.5", "--json"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    assert proc.stdout.readline() == "{\n"
    proc.stdout.close()  # the rest (~100 kB) no longer fits the pipe: the writer hits EPIPE
    err = proc.stderr.read()
    assert proc.wait(timeout=60) == 141, err
    # the gallery keeps no bootstrap samples (no .nc): one warning line says the interval
    # stays empty (and one that the table has no record, in a gallery copied without them);
    # nothing else, and no traceback
    lines = [line for line in err.splitlines() if "no record of what made" not in line]
    assert all("no bootstrap samples beside it" in line for line in lines), err
    assert len(lines) <= 1 and "Traceback" not in err


def test_help_names_every_catalogue_record_and_unit():
    """`--help` spells the record names and units out (it imports no numpy): they are those
    the library knows."""
    from rocking.cli._common import RECORD_NAMES, UNITS
    from rocking.motions.catalogue import RECORDS
    from rocking.motions.readers import UNIT_FACTORS

    assert sorted(RECORD_NAMES.split(", ")) == sorted(RECORDS)
    assert set(UNITS) <= set(UNIT_FACTORS)
    assert {UNIT_FACTORS[u] for u in UNITS} == set(UNIT_FACTORS.values())


def test_files_in_cm_per_s2_read_with_units(tmp_path, capsys):
    """One-column text in cm/s² (--units, --dt) gives the motion the same file in g gives."""
    from rocking.constants import G

    acc_g = np.sin(np.linspace(0.0, 40.0, 1500)) * 0.3 * np.exp(-np.linspace(0, 3, 1500))
    in_g = tmp_path / "x_g.txt"
    in_cm = tmp_path / "x_cm.txt"
    np.savetxt(in_g, acc_g)
    np.savetxt(in_cm, acc_g * G * 100.0)
    args = ["simulate", "--R", "1", "--tan-alpha", "0.2", "--dt", "0.01", "--mode", "2d-x",
            "--scale", "1", "--json"]  # as recorded: the unit decides the answer
    assert main([*args, "--files", str(in_g), "-o", str(tmp_path / "g")]) == 0
    by_g = json.loads(capsys.readouterr().out)
    assert main([*args, "--files", str(in_cm), "--units", "cm/s2", "-o",
                 str(tmp_path / "cm")]) == 0
    by_cm = json.loads(capsys.readouterr().out)
    assert by_cm["pga_g"] == pytest.approx(by_g["pga_g"], rel=1e-9)
    assert by_cm["pga_g"] == pytest.approx(0.3, rel=0.15)
    assert by_cm["t_theta_max"] == pytest.approx(by_g["t_theta_max"], rel=1e-6)


def test_a_file_pair_is_named_once_in_the_motion_line(tmp_path, capsys):
    """A pair read from the user's files has no title but its name: the label says it once."""
    from rocking.motions.identity import describe_processing
    from rocking.motions.source import load_motion

    acc = np.sin(np.linspace(0.0, 30.0, 800)) * 0.2
    x, y = tmp_path / "site_x.txt", tmp_path / "site_y.txt"
    np.savetxt(x, acc)
    np.savetxt(y, 0.5 * acc)
    motion = load_motion(None, [x, y], dt=0.01)
    line = describe_processing(motion)
    assert line.startswith("site_x+site_y (recorded)"), line
    assert line.count("site_x+site_y") == 1, line


# --- the body as engineers give it: height and diameter -----------------------------------

COLUMN = ["--height", "6", "--diameter", "0.66"]  # a marble column: tan α 0.11, R 3.018 m


def test_simulate_takes_the_column_s_dimensions_and_a_pga_in_g(tmp_path, capsys):
    from rocking.constants import G

    code = main(["simulate", *COLUMN, "--record", "el-centro-1940", "--pga-g", "0.3",
                 "--stop-at", "0.01", "-q", "--json", "-o", str(tmp_path / "run")])
    assert code == 0
    captured = capsys.readouterr()
    doc = json.loads(captured.out, parse_constant=_no_nan)
    # R = sqrt(b² + h²) of b = 0.33, h = 3; tan α = b/h, written out here
    assert doc["R"] == pytest.approx(math.sqrt(0.33**2 + 3.0**2), rel=1e-12)
    assert doc["tan_alpha"] == pytest.approx(0.11, rel=1e-12)
    rec = load_record("el-centro-1940")
    assert doc["pga_g"] == pytest.approx(0.3, rel=1e-12)
    assert doc["scale"] == pytest.approx(0.3 * G / rec.pga, rel=1e-12)
    assert captured.err.strip() == ("rocking simulate: height 6 m, diameter 0.66 m: "
                                    "R = 3.018 m, tan α = 0.11 (α = 6.28°)")


def test_risk_selects_the_row_of_the_body_given_by_its_dimensions(tmp_path, capsys):
    rows = [("3d", "overturning", 0.2, 1.0, 0.4, 0.3, "ok"),
            ("3d", "overturning", 0.2, 2.0, 0.5, 0.3, "ok"),
            ("3d", "overturning", 0.11, 1.0, 0.3, 0.3, "ok")]
    path = tmp_path / "fragility.csv"
    pd.DataFrame(rows, columns=["mode", "limit_state", "tan_alpha [-]", "R [m]",
                                "median_pga_g [g]", "beta [-]", "status"]).to_csv(path,
                                                                                 index=False)
    # the body of R = 2 m, tan α = 0.2: h = R/sqrt(1 + 0.04), 2b = 0.2 * 2h
    h = 2.0 / math.sqrt(1.04)
    argv = ["risk", "--fragility", str(path), "--hazard", "1e-4,2.5", "--json",
            "--height", repr(2 * h), "--diameter", repr(0.4 * h)]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out, parse_constant=_no_nan)
    assert [(r["tan_alpha"], r["R"]) for r in doc["rows"]] == [(0.2, 2.0)]
    assert main(["risk", "--fragility", str(path), "--hazard", "1e-4,2.5", *COLUMN]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert "has no record of what made it: read as a table of your own" in err.pop(0)
    assert len(err) == 2 and "is not a body of the table" in err[1]  # the body, then why


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["spectra", "--R", "1"], "give the body's slenderness: --tan-alpha, or --height "
                                  "and --diameter (there is no default)"),
        (["stripes", "--R", "1"], "give the body's slenderness"),
        (["spectra", "--tan-alpha", "0.2"], "give the body's size: --R, or --height"),
        (["simulate", "--height", "-6", "--diameter", "0.66", "-o", "o"],
         "--height must be a finite length > 0 [m], got -6.0"),
        (["spectra", "--height", "6"], "--height and --diameter go together"),
        (["simulate", *COLUMN, "--tan-alpha", "0.2", "-o", "o"],
         "--tan-alpha 0.2 contradicts --height 6 and --diameter 0.66 (--tan-alpha = 0.11)"),
        (["spectra", *COLUMN, "--R", "2"], "--R 2.0 contradicts --height 6"),
        (["simulate", "--R", "1", "--tan-alpha", "0.2", "--record", "el-centro-1940",
          "--pga-g", "-0.3", "-o", "o"], "--pga-g must be a finite number > 0, got -0.3"),
    ],
)
def test_bad_bodies_are_one_line_before_any_work(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"rocking {argv[0]}: error: "), err
    assert message in err[0]
    assert not (tmp_path / "o").exists()
