"""Bootstrap samples of a fragility table: one reader for every fragility.

A fragility table ``<name>.csv`` (``fragility.csv``, ``suite_fragility.csv``,
``stripe_fragility.csv``) may have beside it ``<name>_bootstrap.nc``: an xarray Dataset with
``median`` [the row's measure unit, g for PGA and Sa] and ``beta`` [-] over (``row``,
``resample``), ``row`` aligned with the CSV's row order (row i of the CSV ↔ ``row`` = i), NaN
where a resample has no fit. The motions were resampled with replacement and the fragility
refitted (:func:`rocking.spectra.fragility.bootstrap_lognormal`); the risk table integrates
each resample (:func:`rocking.risk.annual_frequency.annual_frequency_interval`) for the 90 %
interval of λ.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

SUFFIX = "_bootstrap.nc"


def bootstrap_path(table: str | Path) -> Path:
    """``<dir>/<name>_bootstrap.nc`` of a table ``<dir>/<name>.csv`` (or ``.nc``)."""
    table = Path(table)
    return table.with_name(table.stem + SUFFIX)


@dataclass(frozen=True)
class BootstrapSamples:
    """θ and β of every resample of every row of a fragility table.

    Attributes
    ----------
    median : numpy.ndarray
        (rows, resamples), in the row's measure unit [g].
    beta : numpy.ndarray
        (rows, resamples) [-].
    source : str
        The file read.
    """

    median: np.ndarray
    beta: np.ndarray
    source: str = ""

    @property
    def n_resamples(self) -> int:
        return int(self.median.shape[1])


def read_bootstrap(path: str | Path, n_rows: int | None = None) -> BootstrapSamples:
    """Read a ``*_bootstrap.nc`` file.

    Parameters
    ----------
    path : path
        The file.
    n_rows : int, optional
        Rows of the CSV it belongs to; a different count is refused (the samples would be
        given to the wrong rows).
    """
    import xarray as xr

    path = Path(path)
    with xr.open_dataset(path) as ds:
        missing = [v for v in ("median", "beta") if v not in ds]
        if missing or ds["median"].dims != ("row", "resample"):
            raise ValueError(f"{path}: a bootstrap file has median and beta over (row, "
                             f"resample); missing {missing or 'those dims'}")
        rows = ds["row"].values if "row" in ds.coords else np.arange(ds.sizes["row"])
        if not np.array_equal(rows, np.arange(rows.size)):
            raise ValueError(f"{path}: row must be 0..{rows.size - 1} in order")
        median = ds["median"].values.astype(float)
        beta = ds["beta"].values.astype(float)
    if n_rows is not None and median.shape[0] != n_rows:
        raise ValueError(f"{path}: {median.shape[0]} rows, its table has {n_rows}: the file "
                         "belongs to another table (recompute it)")
    return BootstrapSamples(median, beta, str(path))


def write_bootstrap(samples, path: str | Path) -> Path:
    """Write a samples Dataset (``median``, ``beta`` over (row, resample)) to ``path``."""
    path = Path(path)
    samples.to_netcdf(path)
    return path


__all__ = ["SUFFIX", "BootstrapSamples", "bootstrap_path", "read_bootstrap",
           "write_bootstrap"]
