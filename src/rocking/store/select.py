"""``.sel`` for the study's stores and tables that accepts every spelling of a label.

xarray's ``.sel`` matches labels exactly: a store made with ``limit_states: ["tilt:0.3333"]``
has the label ``"tilt:0.3333"``, and ``.sel(limit_state="tilt:1/3")`` raises KeyError.
:func:`select` first turns every limit state asked for into the store's own label
(:func:`rocking.spectra.limit_states.match_limit_state`: ``"tilt:1/3"``, ``"tilt:2/6"``,
``"excessive-tilt"``, ``"tilt:0.3333"`` all select the same entry) and matches numbers
(R, tan_alpha, intensity) to a relative 1e-9, so ``R=6`` finds ``6.0``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rocking.spectra.limit_states import match_limit_state

__all__ = ["select"]

NUMBER_RTOL = 1e-9
"""Relative tolerance of numeric coordinate matches."""


def _label(ds, dim: str, value: Any) -> Any:
    coord = ds[dim].values
    if dim == "limit_state":
        if isinstance(value, (list, tuple)):
            return [match_limit_state(v, coord) for v in value]
        return match_limit_state(value, coord)
    if coord.dtype.kind == "f":
        values = np.atleast_1d(np.asarray(value, dtype=float))
        hits = []
        for v in values:
            near = np.flatnonzero(np.isclose(coord, v, rtol=NUMBER_RTOL, atol=0.0))
            if near.size != 1:
                raise KeyError(f"{dim}={float(v)!r} is not in {coord.tolist()}")
            hits.append(coord[near[0]])
        return hits if isinstance(value, (list, tuple, np.ndarray)) else hits[0]
    return value


def select(ds, **indexers: Any):
    """``ds.sel(**indexers)`` with any limit-state spelling and tolerant numbers.

    Parameters
    ----------
    ds : xarray.Dataset or DataArray
        A spectra store (``xarray.open_zarr("results/<study>/spectra.zarr")``), a tilt map,
        ``mean_spectra.nc`` or ``fragility.nc``.
    **indexers
        Dimension → label or list of labels, as for ``.sel``.

    Returns
    -------
    xarray.Dataset or DataArray

    Examples
    --------
    >>> ds = xarray.open_zarr("results/elcentro/spectra.zarr")          # doctest: +SKIP
    >>> select(ds.pga_crit, mode="3d", limit_state="excessive-tilt",     # doctest: +SKIP
    ...        motion="el-centro-1940", tan_alpha=0.2, R=6)
    """
    return ds.sel({dim: _label(ds, dim, v) for dim, v in indexers.items()})
