"""Progress reports: points done / total, rate, ETA; lines off a terminal, a bar on one."""

from __future__ import annotations

import io
import logging
import re

import numpy as np

from rocking._progress import Progress, format_seconds
from rocking.dynamics.bodies import Cylinder
from rocking.motions.motion import GroundMotion
from rocking.spectra.critical import critical_intensity_batch
from rocking.spectra.tilt_map import tilt_map

LINE = re.compile(r"^(?P<label>.+): (?P<done>\d+)/(?P<total>\d+) (?P<unit>\w+) done "
                  r"\((?P<pct>\d+) %\), [0-9.e+-]+ \w+/s, elapsed \d+:\d\d, ETA (\d+:\d\d|\?)$")


class FakeTTY(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_lines_count_points_and_end_with_a_final_line(caplog):
    stream = io.StringIO()
    log = logging.getLogger("test.progress")
    with caplog.at_level(logging.INFO, logger="test.progress"):
        with Progress(5, "job", stream=stream, log=log, interval=0.0) as bar:
            for _ in range(5):
                bar.update()
            bar.message("dashboard: http://x")
    lines = stream.getvalue().splitlines()
    assert lines[-1].startswith("job: 5/5 points done (100 %)") and "ETA 0:00" in lines[-1]
    parsed = [LINE.match(line) for line in lines if line.startswith("job:")]
    assert all(parsed) and [int(m["done"]) for m in parsed] == [1, 2, 3, 4, 5]
    assert "dashboard: http://x" in lines and "dashboard: http://x" in caplog.text
    assert "job: 5/5 points done" in caplog.text


def test_terminal_gets_a_live_bar_not_lines():
    tty = FakeTTY()
    with Progress(3, "bar", stream=tty, interval=0.0) as bar:
        for _ in range(3):
            bar.update()
    text = tty.getvalue()
    assert "\r" in text and "3/3" in text and "points done" not in text


def test_format_seconds():
    assert format_seconds(59.4) == "0:59" and format_seconds(3725) == "1:02:05"
    assert format_seconds(float("inf")) == "?"


def _pulse() -> GroundMotion:
    t = np.arange(0, 3.0, 0.01)
    a = np.where(t < 1.0, 3.0 * np.sin(2 * np.pi * t), 0.0)
    return GroundMotion(a, 0.5 * a, 0.01, "pulse")


def test_batch_and_tilt_map_report_on_stderr(capsys):
    m = _pulse()
    critical_intensity_batch([(1.0, 0.2, m, "2d-x"), (2.0, 0.2, m, "2d-x")], ["tilt:0.5"],
                             accuracy="fast", upper=3.0, progress=True)
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("spectra: 2/2 points done (100 %)")
    tilt_map([1.0, 2.0], 0.2, m, [0.5, 2.0], "2d-x", accuracy="fast", progress=True)
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("tilt map 2d-x: 4/4 analyses done (100 %)")
    # silent by default
    critical_intensity_batch([(1.0, 0.2, m, "2d-x")], ["tilt:0.5"], accuracy="fast", upper=3.0)
    assert capsys.readouterr().err == ""
    assert Cylinder(1.0, 0.2).R == 1.0
