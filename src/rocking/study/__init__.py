"""A study: the zarr store of a spectrum grid (:mod:`.store`), the Dask cluster that fills it
(:mod:`.cluster`), ensemble statistics (:mod:`.aggregate`), the paper's figures
(:mod:`.figures`) and the HTML report (:mod:`.report`); :func:`select` is ``.sel`` for
their outputs accepting every spelling of a limit state."""

from .._lazy import lazy_exports

_EXPORTS = {"select": "select"}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
