"""The contact spring-dashpot of the damped model, as a study configures it: the model's own
:class:`rocking.dynamics.contact.Contact`, read from the configuration's ``damped`` section."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from rocking._validate import positive_finite
from rocking.config.fields import config_section
from rocking.dynamics.contact import Contact
from rocking.spectra.modes import is_damped

__all__ = ["Damping"]


@dataclass(frozen=True)
class Damping(Contact):
    """Contact spring-dashpot of the ``3d-damped`` model as a study configures it: a
    :class:`~rocking.dynamics.contact.Contact` (``omega_n`` [rad/s], ``zeta`` [-]) with the
    configuration's reading and the stores' record of it.
    """

    @classmethod
    def from_config(cls, config: Mapping[str, Any]) -> Damping:
        """The configuration's ``damped`` section (defaults the damped model's,
        :data:`rocking.dynamics.names.DAMPED_OMEGA_N` and ``DAMPED_ZETA``)."""
        d = config_section(config, "damped")
        return cls(positive_finite("damped.omega_n", d["omega_n"]),
                   positive_finite("damped.zeta", d["zeta"]))

    def to_attrs(self) -> dict[str, float]:
        """``{"omega_n", "zeta"}``: the keyword arguments of the damped analyses."""
        return {"omega_n": self.omega_n, "zeta": self.zeta}

    @staticmethod
    def options(damping: Damping | None) -> dict[str, float]:
        """Keyword arguments of the analyses: empty when no damped model runs."""
        return {} if damping is None else damping.to_attrs()

    @staticmethod
    def of_modes(config: Mapping[str, Any], modes: Sequence[str]) -> Damping | None:
        """The contact model, only when a damped model runs (else it cannot matter)."""
        return Damping.from_config(config) if any(is_damped(m) for m in modes) else None

    @staticmethod
    def from_options(options: Mapping[str, Any]) -> Damping | None:
        """Inverse of :meth:`options`."""
        return Damping(options["omega_n"], options["zeta"]) if "omega_n" in options else None
