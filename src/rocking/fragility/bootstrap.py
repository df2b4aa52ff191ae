"""Bootstrap samples of a fragility table: one reader for every fragility.

A fragility table ``<name>.csv`` (``fragility.csv``, ``suite_fragility.csv``,
``stripe_fragility.csv``) may have beside it ``<name>_bootstrap.nc``: an xarray Dataset with
``median`` [the row's measure unit, g for PGA and Sa] and ``beta`` [-] over (``row``,
``resample``), ``row`` aligned with the CSV's row order (row i of the CSV ↔ ``row`` = i), NaN
where a resample has no fit. The motions were resampled with replacement and the fragility
refitted (:func:`rocking.fragility.lognormal.bootstrap_lognormal`); the risk table integrates
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


def read_bootstrap(path: str | Path, n_rows: int | None = None,
                   table: str | Path | None = None) -> BootstrapSamples:
    """Read a ``*_bootstrap.nc`` file.

    Parameters
    ----------
    path : path
        The file.
    n_rows : int, optional
        Rows of the CSV it belongs to; a different count is refused (the samples would be
        given to the wrong rows).
    table : path, optional
        The CSV it belongs to: the file's record (:mod:`rocking.provenance`) must say it was
        made with this very table (a bootstrap of another study, another run or another
        table is refused).

    Raises
    ------
    rocking.provenance.ProvenanceError
        One line naming the file and the command that remakes it: the file cannot be read
        (cut short, damaged), or belongs to another table.
    """
    import xarray as xr

    from rocking.provenance import ProvenanceError, check, remake

    path = Path(path)
    way_out = remake(path)
    if table is not None:
        check(path, expect=[table], own=False, partial=True)  # its job checked the inputs
    try:
        with xr.open_dataset(path) as ds:
            missing = [v for v in ("median", "beta") if v not in ds]
            if missing or ds["median"].dims != ("row", "resample"):
                raise ProvenanceError(f"{path}: a bootstrap file has median and beta over "
                                      f"(row, resample); missing {missing or 'those dims'}: "
                                      f"{way_out}")
            rows = ds["row"].values if "row" in ds.coords else np.arange(ds.sizes["row"])
            if not np.array_equal(rows, np.arange(rows.size)):
                raise ProvenanceError(f"{path}: row must be 0..{rows.size - 1} in order: "
                                      f"{way_out}")
            median = ds["median"].values.astype(float)
            beta = ds["beta"].values.astype(float)
    except ProvenanceError:
        raise
    except FileNotFoundError:
        raise
    except Exception as exc:  # netCDF/HDF5 raise many types for a cut or damaged file
        raise ProvenanceError(f"{path} cannot be read (damaged or cut short: "
                              f"{type(exc).__name__}: {str(exc).splitlines()[0][:120]}): "
                              f"{way_out}") from None
    if n_rows is not None and median.shape[0] != n_rows:
        raise ProvenanceError(f"{path}: {median.shape[0]} rows, its table has {n_rows}: the "
                              f"file belongs to another table: {way_out}")
    return BootstrapSamples(median, beta, str(path))


def write_bootstrap(samples, path: str | Path, *, table: str | Path | None = None) -> Path:
    """Write a samples Dataset (``median``, ``beta`` over (row, resample)) to ``path``.

    ``table`` (the CSV the samples belong to, written first) is recorded as what the file was
    made from (:func:`rocking.provenance.record`), checked by :func:`read_bootstrap`. The
    file is written under a temporary name and renamed: nothing half-written is left.
    """
    from rocking.provenance import record, write_atomic

    write_atomic(path, samples.to_netcdf)
    record(path, inputs=[table] if table is not None else [])
    return Path(path)


__all__ = ["SUFFIX", "BootstrapSamples", "bootstrap_path", "read_bootstrap",
           "write_bootstrap"]
