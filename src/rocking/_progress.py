"""Progress of long computations: points done / total, rate and time left.

One reporter serves the library's batch functions (``progress=True``), the command line and
the workflow's Dask rules. On a terminal it draws a live bar (tqdm); on anything else (a log
file, a pipe) it writes a line every ``interval`` seconds and a last one at the end, because
a bar redrawn with carriage returns is unreadable in a file. It can also send the same lines
to a :class:`logging.Logger` (a rule's log) while the bar runs on the terminal.
"""

from __future__ import annotations

import logging
import sys
import time
from typing import TextIO

__all__ = ["Progress", "format_seconds"]


def format_seconds(seconds: float) -> str:
    """``h:mm:ss`` or ``m:ss`` of a duration [s] (``?`` when unknown)."""
    if not seconds >= 0.0 or seconds == float("inf"):
        return "?"
    s = int(round(seconds))
    h, rest = divmod(s, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


class Progress:
    """Count finished points and report done / total, rate and ETA.

    Parameters
    ----------
    total : int
        Points to do.
    label : str
        What is being computed (starts every line), e.g. ``"spectra elcentro"``.
    unit : str
        Name of one point (``"point"``, ``"analysis"``).
    stream : text stream, "stderr" or None
        Where to report (default: ``sys.stderr`` at the time of the call); None: nowhere.
    log : logging.Logger, optional
        Also write the lines there (e.g. a rule's log).
    interval : float
        Seconds between lines [s] (lines are written on updates; 0: every update).
    live : bool, optional
        Force the live bar on (True) or off (False); default: on when ``stream`` is a TTY.
    """

    def __init__(self, total: int, label: str = "progress", *, unit: str = "point",
                 stream: TextIO | None | str = "stderr", log: logging.Logger | None = None,
                 interval: float = 5.0, live: bool | None = None) -> None:
        self.total = int(total)
        self.label = label
        self.unit = unit
        self.stream = sys.stderr if stream == "stderr" else stream
        stream = self.stream
        self.log = log
        self.interval = float(interval)
        self.done = 0
        self.t0 = self._last = time.monotonic()
        isatty = bool(stream is not None and getattr(stream, "isatty", lambda: False)())
        self._bar = None
        if stream is not None and (isatty if live is None else live):
            from tqdm import tqdm  # only a terminal needs it

            self._bar = tqdm(total=self.total, desc=label, unit=unit, file=stream,
                             dynamic_ncols=True, leave=True)

    # -- reporting ---------------------------------------------------------------------
    def line(self) -> str:
        """The current state as one line: done/total, per cent, rate, elapsed and ETA."""
        elapsed = time.monotonic() - self.t0
        rate = self.done / elapsed if elapsed > 0.0 else 0.0
        left = (self.total - self.done) / rate if rate > 0.0 else float("inf")
        pct = 100.0 * self.done / self.total if self.total else 100.0
        plural = self.unit[:-2] + "es" if self.unit.endswith("is") else self.unit + "s"
        return (f"{self.label}: {self.done}/{self.total} {plural} done ({pct:.0f} %), "
                f"{rate:.3g} {self.unit}/s, elapsed {format_seconds(elapsed)}, "
                f"ETA {format_seconds(0.0 if self.done >= self.total else left)}")

    def message(self, text: str) -> None:
        """A one-off line (e.g. the Dask dashboard address) on the stream and in the log."""
        if self.log is not None:
            self.log.info("%s", text)
        if self.stream is not None:
            if self._bar is not None:
                self._bar.write(text, file=self.stream)
            else:
                print(text, file=self.stream, flush=True)

    def _emit(self) -> None:
        text = self.line()
        if self.log is not None:
            self.log.info("%s", text)
        if self.stream is not None and self._bar is None:
            print(text, file=self.stream, flush=True)

    def update(self, n: int = 1) -> None:
        """``n`` more points are done."""
        self.done += int(n)
        if self._bar is not None:
            self._bar.update(int(n))
        now = time.monotonic()
        if now - self._last >= self.interval and self.done < self.total:
            self._last = now
            self._emit()

    def close(self) -> None:
        """Write the last line (always) and end the bar."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
            if self.log is not None:
                self.log.info("%s", self.line())
        else:
            self._emit()

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def maybe(progress: bool | Progress | None, total: int, label: str,
          unit: str = "point") -> Progress | None:
    """The reporter a library function with a ``progress=`` switch uses.

    ``True``: a new :class:`Progress` on stderr; a :class:`Progress`: itself (the caller
    shares one across calls); ``False``/None: None (silent).
    """
    if isinstance(progress, Progress):
        return progress
    if progress:
        return Progress(total, label, unit=unit)
    return None
