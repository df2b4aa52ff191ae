"""Strict JSON for every file the project writes (metadata, settings, summaries).

``json.dumps`` writes ``NaN`` and ``Infinity`` by default, which other tools (JavaScript,
jq, most JSON parsers) reject. Here a non-finite float becomes ``null`` — JSON's "no value",
the meaning a NaN has in a summary (e.g. ``t_uplift`` of a body that never uplifted) — and
``allow_nan=False`` guarantees nothing else slips through.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np


def json_default(obj: Any) -> Any:
    """``default=`` hook of :func:`json.dumps`: numpy scalars and arrays, paths.

    Metadata often carries numpy values from the processing steps.
    """
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"value {obj!r} of type {type(obj).__name__} is not JSON-serialisable")


def to_plain(value: Any) -> Any:
    """Numpy scalars and arrays turned into Python numbers and lists, dict keys into strings
    (recursively); non-finite floats are kept (unlike :func:`finite_or_none`)."""
    if isinstance(value, dict):
        return {str(k): to_plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_plain(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    return value


def finite_or_none(obj: Any) -> Any:
    """``obj`` with every non-finite float (also inside containers and numpy) as None."""
    if isinstance(obj, dict):
        return {k: finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_or_none(v) for v in obj]
    if isinstance(obj, (np.generic, np.ndarray)):
        return finite_or_none(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def dumps(obj: Any, **kwargs: Any) -> str:
    """Strict JSON text of ``obj``: NaN and ±inf written as ``null``, numpy converted.

    Keyword arguments go to :func:`json.dumps` (``indent``, ``sort_keys`` ...).
    """
    return json.dumps(finite_or_none(obj), allow_nan=False, default=json_default, **kwargs)


def write(path: str | Path, obj: Any, **kwargs: Any) -> Path:
    """Write ``obj`` as strict JSON (indented, newline-terminated) to ``path``."""
    path = Path(path)
    path.write_text(dumps(obj, indent=kwargs.pop("indent", 2), **kwargs) + "\n")
    return path
