"""Lazy re-exports for package ``__init__`` modules (PEP 562).

A package lists which public name lives in which submodule; the submodule is imported the
first time the name is used. ``import rocking`` therefore costs almost nothing, and a user
of the 2D model never pays for importing xarray, dask or matplotlib.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable


def lazy_exports(package: str, exports: dict[str, str]) -> tuple[Callable, Callable]:
    """``(__getattr__, __dir__)`` for a package whose names live in submodules.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    exports : dict
        Public name → submodule path relative to the package (e.g. ``"dynamics.bodies"``).
    """

    def __getattr__(name: str):
        try:
            module = exports[name]
        except KeyError:
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        value = getattr(importlib.import_module(f"{package}.{module}"), name)
        globals_of_package = importlib.import_module(package).__dict__
        globals_of_package[name] = value  # later look-ups skip __getattr__
        return value

    def __dir__() -> list[str]:
        return sorted(set(importlib.import_module(package).__dict__) | set(exports))

    return __getattr__, __dir__
