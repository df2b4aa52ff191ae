"""The damped model's own parameters: its contact spring–dashpot, one checked object.

The damped 3D model (:data:`rocking.dynamics.names.MODEL_3D_DAMPED`) is the only model with
parameters of its own, as one method of scipy's ``solve_ivp(..., **options)`` declares its
options: :class:`Contact` is them, declared on the model's entry
(:attr:`rocking.dynamics.models.Model.contact`, the defaults) and checked once, where a caller
gives them (the keywords ``omega_n`` and ``zeta`` of the public functions, a configuration's
``damped`` section, a store's attributes); everything below takes the object as it is.

Kept free of heavy imports, like :mod:`.names`: the spectra build one without loading the
engine.
"""

from __future__ import annotations

from dataclasses import dataclass

from rocking._validate import nonnegative_finite, positive_finite
from rocking.dynamics.names import DAMPED_OMEGA_N, DAMPED_ZETA

__all__ = ["Contact"]


@dataclass(frozen=True)
class Contact:
    """Contact spring–dashpot of the damped model.

    Attributes
    ----------
    omega_n : float
        Contact natural frequency √(k/m) [rad/s], > 0 and finite.
    zeta : float
        Damping ratio c/(2 m ωn) [-], ≥ 0 and finite.

    Raises
    ------
    ValueError
        One line naming the field and the value (:func:`rocking._validate.positive_finite`).
    """

    omega_n: float = DAMPED_OMEGA_N
    zeta: float = DAMPED_ZETA

    def __post_init__(self) -> None:
        object.__setattr__(self, "omega_n", positive_finite("omega_n", self.omega_n))
        object.__setattr__(self, "zeta", nonnegative_finite("zeta", self.zeta))

    @classmethod
    def of(cls, omega_n: float | None = None, zeta: float | None = None) -> Contact:
        """The contact of the keywords a public function takes (None: the model's default)."""
        return cls(DAMPED_OMEGA_N if omega_n is None else omega_n,
                   DAMPED_ZETA if zeta is None else zeta)
