"""pelicun / FEMA P-58 damage model CSV: one component per (mode, tan α, R).

Columns (pelicun 3's damage model parameters)::

    ID, Incomplete, Demand-Type, Demand-Unit, Demand-Offset, Demand-Directional,
    LS1-Family, LS1-Theta_0, LS1-Theta_1, LS1-DamageStateWeights, LS2-..., ...

- ``ID``: ``rocking.<mode>.tan<tan α>.R<R>m.<kind>`` (``-`` of a mode written ``_``: pelicun
  joins component, location and direction with ``-`` in its sample columns), ``<kind>``
  ``critical_intensity`` or ``stripes``: which fragility the file carries
  (:attr:`Fragilities.kind`). The CSV has no description column, so the id says it; and
  pelicun reads a list of files into one damage model, so the two fragilities of one body
  must not share an id.
- ``Demand-Type`` ``Peak Ground Acceleration``, ``Demand-Unit`` ``g``, ``Demand-Offset`` 0,
  ``Demand-Directional`` 1. The study's PGA is the vector peak of the pair, already the
  largest peak over all orientations (RotD100). pelicun multiplies a *non*-directional demand
  (``Demand-Directional`` 0) by its ``NonDirectionalMultipliers`` (1.2 by default, FEMA
  P-58's step from the larger component to the peak over orientations), which would count
  that step twice: seen running pelicun 3.10, a demand equal to a median gave P = 0.97 with
  0 and 0.5 with 1. So the demand is marked directional, and the user gives the vector-peak
  PGA as the demand of the component's direction (e.g. ``PGA-1-1`` with the component at
  location 1, direction 1).
- ``LS<i>-Family`` ``lognormal``, ``LS<i>-Theta_0`` the median capacity [g], ``LS<i>-Theta_1``
  β; limit states in increasing severity (damage state i = the i-th limit state exceeded):
  increasing tilt goal, overturning last. Components with fewer limit states leave the
  further columns empty; a limit state without a fit is left out of its component (the
  component's damage states then skip it; :attr:`Fragilities.skipped` names it).
- Only the tilt axis (:meth:`Fragilities.damage_chain`): pelicun reads LS1, LS2, ... as
  damage states of increasing severity, so a sliding goal after overturning would read as a
  worse damage than overturning; sliding goals are left out (the caller's log says so, the
  study's fragility table keeps them).
- ``Incomplete`` 0. The limit-state names are not a pelicun column; they are in the
  ``limit_states`` this writer returns and in the risk table.
"""

from __future__ import annotations

import csv
from pathlib import Path

from rocking.fragility.table import CRITICAL_INTENSITY, KINDS, Fragilities

BASE_COLUMNS = ("ID", "Incomplete", "Demand-Type", "Demand-Unit", "Demand-Offset",
                "Demand-Directional")
LS_FIELDS = ("Family", "Theta_0", "Theta_1", "DamageStateWeights")
DEMAND_TYPE = "Peak Ground Acceleration"


def component_id(mode: str, tan_alpha: float, R: float,
                 kind: str = CRITICAL_INTENSITY) -> str:
    """pelicun component id of one body, mode and fragility, e.g.
    ``rocking.3d.tan0.2.R6m.stripes``."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    return f"rocking.{mode.replace('-', '_')}.tan{tan_alpha:g}.R{R:g}m.{kind}"


def columns(n_limit_states: int) -> list[str]:
    """Header of a file whose components have at most ``n_limit_states`` limit states."""
    return [*BASE_COLUMNS,
            *(f"LS{i}-{f}" for i in range(1, n_limit_states + 1) for f in LS_FIELDS)]


def write_pelicun_csv(frag: Fragilities, path: str | Path) -> dict[str, list[str]]:
    """Write the fragilities as a pelicun damage model CSV.

    Parameters
    ----------
    frag : Fragilities
        From :func:`rocking.fragility.table.read_fragilities`.
    path : path
        Output ``.csv`` file.

    Returns
    -------
    dict
        Component id → its limit states (canonical names), in the order of LS1, LS2, ...
    """
    comps: dict[str, list[str]] = {}
    lines = []
    frag = frag.damage_chain()[0]
    for (mode, tan_alpha, R), rows in frag.groups():
        cid = component_id(mode, tan_alpha, R, frag.kind)
        row = {"ID": cid, "Incomplete": 0, "Demand-Type": DEMAND_TYPE, "Demand-Unit": "g",
               "Demand-Offset": 0, "Demand-Directional": 1}
        for i, r in enumerate(rows.itertuples(), start=1):
            row[f"LS{i}-Family"] = "lognormal"
            row[f"LS{i}-Theta_0"] = repr(float(r.median_g))
            row[f"LS{i}-Theta_1"] = repr(float(r.beta))
            row[f"LS{i}-DamageStateWeights"] = ""
        comps[cid] = list(rows["limit_state"])
        lines.append(row)
    n = max((len(v) for v in comps.values()), default=0)
    with Path(path).open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=columns(n), restval="")
        w.writeheader()
        w.writerows(lines)
    return comps


__all__ = ["BASE_COLUMNS", "DEMAND_TYPE", "LS_FIELDS", "columns", "component_id",
           "write_pelicun_csv"]
