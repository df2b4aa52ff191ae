"""Whether a model's kernels are in numba's on-disk cache: the first analysis of a model on a
fresh install compiles it (tens of seconds, nothing else to show), later ones load it.

Each model has its compiled entry points among the fields of its
:class:`~rocking.dynamics.models.Model` (numba dispatchers with ``cache=True``); a model is
compiled when one of them has no entry for this machine in its cache index. The command line
asks :func:`will_compile` before the first analysis and says so in one line
(:func:`compile_notice`).
"""

from __future__ import annotations

COMPILE_SECONDS = {"3d": 40, "3d-damped": 40, "2d": 30}
"""About how long compiling each model takes [s], rounded up: a first ``rocking spectra`` on a
fresh install took 42 s (issue 38, 3d); with an empty ``NUMBA_CACHE_DIR`` the first
``rocking spectra --mode 3d`` took 27 s of CPU time, ``rocking simulate`` 29 s (2d-x) and
36 s (3d-damped), each compiling only its own model (2-core machine shared with other jobs,
load ≈ 14: the wall time was 3–4 min there)."""


def _dispatchers(model: str, monitors: bool = False, vertical: bool = False) -> list:
    """The numba dispatchers an analysis of ``model`` calls: its compiled fields and the
    kernel variant with or without the validity monitors and the vertical forcing
    (:meth:`~rocking.dynamics.models.Model.kernel`; each variant compiles on its own)."""
    from rocking.dynamics.models import MODELS

    if model not in MODELS:
        raise ValueError(f"model must be one of {sorted(MODELS)}, got {model!r}")
    entry = MODELS[model]
    found = [v for v in entry if hasattr(v, "_cache") and hasattr(v, "targetctx")]
    kernel = entry.kernel(monitors, vertical)
    return [*found, kernel] if hasattr(kernel, "_cache") else found


def _cached(dispatcher) -> bool:
    """The dispatcher's on-disk cache holds an entry compiled for this machine."""
    index = dispatcher._cache._cache_file._load_index()  # {} when absent or stale
    magic = dispatcher.targetctx.codegen().magic_tuple()
    return any(key[1] == magic for key in index)


def will_compile(model: str, monitors: bool = False, vertical: bool = False) -> bool | None:
    """Whether the next analysis of ``model`` (its variant with or without the monitors and
    the vertical forcing) in a fresh process compiles its kernels (True), loads them from
    numba's cache (False), or None where the cache cannot be read (numba's cache layout is
    not a public interface: then nothing is said).

    A dispatcher already compiled in this process counts as cached."""
    try:
        return any(not d.signatures and not _cached(d)
                   for d in _dispatchers(model, monitors, vertical))
    except ValueError:
        raise
    except Exception:  # noqa: BLE001 - a changed numba internal must never stop an analysis
        return None


def compile_notice(model: str, monitors: bool = False, vertical: bool = False) -> str | None:
    """``"compiling the 3d model once, ~40 s; cached afterwards"`` when
    :func:`will_compile`, else None."""
    if not will_compile(model, monitors, vertical):
        return None
    return (f"compiling the {model} model once, ~{COMPILE_SECONDS.get(model, 40)} s; "
            "cached afterwards")
