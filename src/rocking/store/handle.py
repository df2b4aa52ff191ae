"""A grid store opened once (:class:`StoreHandle`): path, group, layout and attributes read
once for the driver of a fill and the verification of a store (:mod:`rocking.store`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import zarr

from rocking.store.attrs import decode_attrs
from rocking.store.layout import Layout
from rocking.store.read import (
    describing_of,
    done_of,
    layout_of,
    open_group,
    pending_of,
    requested_of,
)
from rocking.store.write import consolidate


@dataclass(frozen=True, eq=False)
class StoreHandle:
    """A store opened once: its path, zarr group, layout and decoded attributes.

    The driver of a fill (:func:`rocking.execution.cluster.fill_store`) and the verification of
    a store (:func:`rocking.store.integrity.verify_store`) take one instead of a path, so the
    store's metadata is read once, not by every step. Task bodies in worker processes still
    take the path (a handle is not sent between processes).

    Attributes
    ----------
    path : Path
        Store directory.
    group : zarr.Group
        The open root group (mode ``mode``).
    layout : Layout
        Coordinates, variables and task regions.
    attrs : dict
        Attributes with JSON-text values decoded (:func:`read_attrs`).
    mode : str
        ``"r"`` (read only) or ``"r+"`` (results and done flags may be written).
    """

    path: Path
    group: zarr.Group
    layout: Layout
    attrs: dict[str, Any]
    mode: str

    @classmethod
    def open(cls, path: str | Path, mode: str = "r") -> StoreHandle:
        """Open the store at ``path`` and read its layout and attributes.

        Raises
        ------
        ValueError
            When ``path`` is not a zarr v3 store, or a coordinate is unreadable (naming the
            store and the remedy).
        """
        if mode not in ("r", "r+"):
            raise ValueError(f"mode must be 'r' or 'r+', got {mode!r}")
        path = Path(path)
        group = open_group(path, mode)
        return cls(path, group, layout_of(group, path), decode_attrs(group.attrs), mode)

    def check_config_hash(self, expected: str) -> None:
        """Refuse to continue a store built for another configuration.

        Raises
        ------
        ValueError
            Naming both hashes, when the store's ``config_hash`` differs from ``expected``.
        """
        found = self.group.attrs.get("config_hash")
        if found != expected:
            raise ValueError(
                f"store {str(self.path)!r} has config_hash={found!r} but this run's "
                f"configuration has config_hash={expected!r}; rebuild the store (its rule "
                f"reruns when the configuration changes) instead of mixing results"
            )

    def requested(self) -> np.ndarray:
        """The ``requested`` mask (:func:`read_requested`)."""
        return requested_of(self.group, self.layout)

    def describing_arrays(self) -> list[str]:
        """The arrays describing the grid (:func:`describing_arrays`)."""
        return describing_of(self.group)

    def done_mask(self) -> np.ndarray:
        """The completion mask over the task dimensions (:func:`done_mask`)."""
        return done_of(self.group, self.path)

    def pending_regions(self) -> list[int]:
        """Indices of the task regions not yet marked done, in order."""
        return pending_of(self.layout, self.done_mask())

    def finalize(self) -> None:
        """Check that every region is done, then consolidate the metadata.

        Raises
        ------
        ValueError
            If some region is not done (naming how many).
        """
        done = self.done_mask()
        if not done.all():
            raise ValueError(f"store {str(self.path)!r} has {int((~done).sum())} of "
                             f"{done.size} points not done")
        consolidate(self.path)
