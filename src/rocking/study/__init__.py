"""A study: the zarr store of a spectrum grid (:mod:`.store`), the Dask cluster that fills it
(:mod:`.cluster`), ensemble statistics (:mod:`.aggregate`); :func:`select` is ``.sel`` for
its outputs accepting every spelling of a limit state. The figures and the report, which
only read these outputs, are :mod:`rocking.plot`."""

from .._lazy import lazy_exports

_EXPORTS = {"select": "select"}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
