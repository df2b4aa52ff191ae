"""Saying so when a model's kernels compile: the first analysis of a model on a fresh install
compiles it (tens of seconds, nothing else to show), later ones load it from numba's on-disk
cache.

Numba broadcasts the event ``"numba:compile"`` (its documented event API,
``numba.core.event``) when a dispatcher compiles, and only then: a kernel loaded from the
on-disk cache broadcasts nothing. :func:`announcing_compile` listens for it while an analysis
runs and says one line at the first compilation of one of this package's functions; the
command line wraps its analyses in it. Nothing here reads numba's cache files.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager

COMPILE_SECONDS = {"3d": 40, "3d-damped": 40, "2d": 30}
"""About how long compiling each model takes [s], rounded up: a first ``rocking spectra`` on a
fresh install took 42 s (issue 38, 3d); with an empty ``NUMBA_CACHE_DIR`` the first
``rocking spectra --mode 3d`` took 27 s of CPU time, ``rocking simulate`` 29 s (2d-x) and
36 s (3d-damped), each compiling only its own model (2-core machine shared with other jobs,
load ≈ 14: the wall time was 3–4 min there)."""

EVENT = "numba:compile"
"""The event numba broadcasts when a dispatcher compiles (not when it loads from its cache)."""


def compile_notice(model: str) -> str:
    """``"compiling the 3d model once, ~40 s; cached afterwards"``.

    Raises
    ------
    ValueError
        Naming the model and the known ones.
    """
    from rocking.dynamics.models import MODELS

    if model not in MODELS:
        raise ValueError(f"model must be one of {sorted(MODELS)}, got {model!r}")
    return (f"compiling the {model} model once, ~{COMPILE_SECONDS.get(model, 40)} s; "
            "cached afterwards")


@contextmanager
def announcing_compile(model: str, say: Callable[[str], None]) -> Iterator[list[str]]:
    """While the block runs, call ``say(compile_notice(model))`` once, when numba starts
    compiling a function of ``rocking`` (a kernel of the model, its stepper, ...): nothing is
    said when every kernel loads from the cache. Yields the names of the functions compiled
    (numba's event for each), for a caller or a test to read afterwards."""
    from numba.core import event

    notice = compile_notice(model)
    compiled: list[str] = []

    class _Listener(event.Listener):
        def on_start(self, ev: event.Event) -> None:
            func = getattr(ev.data.get("dispatcher"), "py_func", None)
            if func is None or not func.__module__.startswith("rocking."):
                return
            if not compiled:
                say(notice)
            compiled.append(f"{func.__module__}.{func.__qualname__}")

        def on_end(self, ev: event.Event) -> None:
            pass

    with event.install_listener(EVENT, _Listener()):
        yield compiled
