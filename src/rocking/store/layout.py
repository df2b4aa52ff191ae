"""The grid of a resumable store: coordinates, variables and the regions tasks fill.

A :class:`Layout` says which data variables a store holds over which coordinates, and along
which *task dimensions* the grid is cut into rectangular regions, one per Dask task; every
array is chunked so that one region is exactly one chunk of every variable
(:mod:`rocking.store` writes and reads them).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rocking._validate import positive_finite_array


@dataclass(frozen=True)
class Variable:
    """One data variable of a store.

    Attributes
    ----------
    dims : tuple of str
        Its dimensions, a subset of the layout's, in storage order.
    dtype : str
        NumPy dtype name.
    fill : Any
        Value of never-written entries (NaN for floats: "not computed").
    """

    dims: tuple[str, ...]
    dtype: str
    fill: Any


@dataclass(frozen=True)
class Layout:
    """Coordinates, variables and task chunking of a store.

    Attributes
    ----------
    coords : dict of str to ndarray
        Coordinate values of every dimension.
    variables : dict of str to Variable
        Data variables (the ``done`` mask is added automatically over ``task_dims``).
    task_dims : tuple of str
        Dimensions cut into task regions, in the order regions are numbered (C order).
    task_chunks : dict of str to int
        Region length along each task dimension (the last region may be shorter).
    static : dict of str to Variable
        Variables of the configuration rather than of the results (e.g. ``requested``),
        written whole when the store is created, never by a task.
    """

    coords: dict[str, np.ndarray]
    variables: dict[str, Variable]
    task_dims: tuple[str, ...]
    task_chunks: dict[str, int]
    static: dict[str, Variable] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for dim in self.task_dims:
            if dim not in self.coords:
                raise ValueError(f"task dimension {dim!r} has no coordinate")
            n = self.task_chunks.get(dim, 1)
            if not isinstance(n, (int, np.integer)) or n < 1:
                raise ValueError(f"task chunk along {dim!r} must be an integer >= 1, got {n!r}")
        for name, var in self.variables.items():
            missing = [d for d in var.dims if d not in self.coords]
            if missing:
                raise ValueError(f"variable {name!r} uses dimensions without coordinates "
                                 f"{missing}")
            if not set(self.task_dims) <= set(var.dims):
                raise ValueError(f"variable {name!r} must span every task dimension "
                                 f"{self.task_dims}, has {var.dims}")
        for name, var in self.static.items():
            missing = [d for d in var.dims if d not in self.coords]
            if missing or name in self.variables:
                raise ValueError(f"static variable {name!r} uses dimensions without "
                                 f"coordinates {missing} or repeats a variable's name")

    def shape(self, dims: Sequence[str]) -> tuple[int, ...]:
        """Array shape over ``dims``."""
        return tuple(len(self.coords[d]) for d in dims)

    def chunks(self, dims: Sequence[str]) -> tuple[int, ...]:
        """Chunk shape over ``dims``: the task chunk along task dims, whole elsewhere."""
        return tuple(
            min(self.task_chunks.get(d, 1), len(self.coords[d])) if d in self.task_dims
            else len(self.coords[d])
            for d in dims
        )

    @property
    def region_counts(self) -> tuple[int, ...]:
        """Number of regions along each task dimension."""
        return tuple(math.ceil(n / c) for n, c in
                     zip(self.shape(self.task_dims), self.chunks(self.task_dims), strict=True))

    @property
    def n_regions(self) -> int:
        """Total number of task regions."""
        return int(np.prod(self.region_counts))

    def region(self, index: int) -> dict[str, slice]:
        """The slices along the task dimensions of region ``index`` (C order)."""
        if not 0 <= index < self.n_regions:
            raise ValueError(f"region index must be in [0, {self.n_regions}), got {index!r}")
        block = np.unravel_index(index, self.region_counts)
        out = {}
        for dim, b, c, n in zip(self.task_dims, block, self.chunks(self.task_dims),
                                self.shape(self.task_dims), strict=True):
            out[dim] = slice(int(b) * c, min((int(b) + 1) * c, n))
        return out

    def selection(self, dims: Sequence[str], region: dict[str, slice]) -> tuple[slice, ...]:
        """Index tuple of ``region`` in an array over ``dims`` (whole along other dims)."""
        return tuple(region.get(d, slice(None)) for d in dims)

    def to_json(self) -> str:
        """The chunking part of the layout (coordinates live in the store's arrays)."""
        return json.dumps({"task_dims": list(self.task_dims),
                           "task_chunks": {d: int(self.task_chunks.get(d, 1))
                                           for d in self.task_dims},
                           "static": sorted(self.static)})


def label_coord(name: str, values: Sequence[str]) -> np.ndarray:
    labels = [str(v) for v in values]
    if not labels:
        raise ValueError(f"{name} must not be empty, got {values!r}")
    dup = sorted({v for v in labels if labels.count(v) > 1})
    if dup:
        raise ValueError(f"{name} has duplicate labels {dup}")
    # object dtype: zarr v3 stores it as its variable-length "string" type
    return np.array(labels, dtype=object)


def value_coord(name: str, values: Sequence[float]) -> np.ndarray:
    a = np.asarray(values, dtype=np.float64)
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name} must be a non-empty list of numbers, got {values!r}")
    positive_finite_array(name, a)
    if np.unique(a).size != a.size:
        raise ValueError(f"{name} has duplicate values {values!r}")
    return a


POINT_FREE_DIMS = ("limit_state",)
"""Dimensions that do not multiply the work: one search decides every limit state."""


def region_points(layout: Layout, index: int) -> int:
    """Points of work in region ``index``: spectrum points (searches) or tilt-map analyses.

    The product of the region's lengths over the largest variable's dimensions, without
    :data:`POINT_FREE_DIMS`; tasks report the same count as ``points``.
    """
    region = layout.region(index)
    dims = max((v.dims for v in layout.variables.values()), key=len)
    n = 1
    for d in dims:
        if d in region:
            n *= len(range(*region[d].indices(len(layout.coords[d]))))
        elif d not in POINT_FREE_DIMS:
            n *= len(layout.coords[d])
    return n


def region_coords(layout: Layout, index: int) -> dict[str, np.ndarray]:
    """Coordinate values of region ``index`` along every dimension."""
    region = layout.region(index)
    return {d: v[region[d]] if d in region else v for d, v in layout.coords.items()}
