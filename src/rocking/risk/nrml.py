"""OpenQuake NRML 0.5 fragility model: continuous lognormal functions of PGA [g].

Layout (element order matters to OpenQuake's reader)::

    <nrml xmlns="http://openquake.org/xmlns/nrml/0.5">
      <fragilityModel id=... assetCategory=... lossCategory=...>
        <description>...</description>
        <limitStates>tilt_1over3 overturning</limitStates>
        <fragilityFunction id="3d/tan0.2/R6m" format="continuous" shape="logncdf">
          <imls imt="PGA" minIML=... maxIML=... noDamageLimit=.../>
          <params ls="tilt_1over3" mean=... stddev=.../>     (one per limit state, in order)
          ...

- One function per (mode, tan α, R): the taxonomy id ``<mode>/tan<tan α>/R<R>m``.
- ``mean`` and ``stddev`` are the arithmetic mean and standard deviation of the lognormal
  capacity in g, not its median θ and β: mean = θ·exp(β²/2), stddev = mean·√(exp(β²) − 1)
  (:func:`rocking.fragility.table.lognormal_moments`).
- Limit-state names must be identifiers in OpenQuake (letters, digits, ``_``, ``.``, ``-``):
  ``tilt:1/3`` is written ``tilt_1over3``, ``tilt:0.1`` ``tilt_0p1``, overturning as is
  (:func:`nrml_limit_state`; the description lists the mapping).
- Only the tilt axis is a damage chain (:meth:`Fragilities.damage_chain`): sliding goals
  (``sliding:<μ>``, sliding in contact) are left out, named in
  :attr:`NrmlExport.off_chain` and in a sentence of the description; their fragility stays
  in the study's fragility table.
- The model has one list of limit states for all functions: the limit states every exported
  (mode, tan α) of the table has (in increasing severity), unless given. A function lacking a
  fit for one of them is left out and named in :attr:`NrmlExport.left_out`.
- Which fragility the file carries (:attr:`Fragilities.kind`) is said by the model id,
  ``<study>-critical-intensity`` or ``<study>-stripes`` (:func:`nrml_model_id`; OpenQuake
  takes only letters, digits, ``_`` and ``-`` there, at most 60 characters), and by the first
  sentence of the description. The taxonomy ids are the same in both files: an exposure
  model serves either fragility model (one per calculation, ``fragility_file``).
- ``imls``: OpenQuake raises IMLs below ``minIML`` to it and clips those above ``maxIML`` to it
  before evaluating the CDF, and returns 0 at or below ``noDamageLimit``. ``minIML`` and
  ``noDamageLimit`` are the uplift PGA g·tan α (below it a rigid body on rigid ground does not
  rock, so no limit state can be exceeded); ``maxIML`` is the study's search bound in g
  (upper·tan α), raised to θ·exp(4β) of the most resistant limit state when that is
  higher, so that the probabilities are never capped below 0.99997.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from rocking._validate import positive_finite
from rocking.fragility.table import KINDS, Fragilities, lognormal_moments
from rocking.spectra.limit_states import TILT_AXIS, parse_limit_state, severity, sort_limit_states

NAMESPACE = "http://openquake.org/xmlns/nrml/0.5"
MAX_IML_SIGMAS = 4.0
"""maxIML is at least θ·exp(4β) of every limit state: Φ(4) = 0.99997."""


MODEL_ID = re.compile(r"^[A-Za-z0-9_-]{1,60}$")
"""What OpenQuake's reader accepts as a ``fragilityModel`` id (its ``simple_id``)."""


def nrml_model_id(study: str, kind: str) -> str:
    """``fragilityModel`` id naming the study and the fragility, e.g. ``elcentro-stripes``.

    Raises
    ------
    ValueError
        If the id is not one OpenQuake reads (letters, digits, ``_``, ``-``; ≤ 60 characters).
    """
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    return _checked_id(f"{study}-{kind.replace('_', '-')}")


def _checked_id(model_id: str) -> str:
    if not MODEL_ID.match(model_id):
        raise ValueError(f"model_id must be 1-60 letters, digits, '_' or '-' (OpenQuake's "
                         f"fragilityModel id), got {model_id!r}")
    return model_id


def taxonomy(mode: str, tan_alpha: float, R: float) -> str:
    """Taxonomy id of one body and mode, e.g. ``3d/tan0.2/R6m``."""
    return f"{mode}/tan{tan_alpha:g}/R{R:g}m"


def nrml_limit_state(name: str) -> str:
    """OpenQuake-safe spelling: ``tilt:1/3`` → ``tilt_1over3``, ``tilt:0.1`` → ``tilt_0p1``."""
    ls = parse_limit_state(name).name
    return ls.replace(":", "_").replace("/", "over").replace(".", "p")


@dataclass(frozen=True)
class NrmlExport:
    """What :func:`write_nrml` wrote.

    Attributes
    ----------
    path : Path
    limit_states : list of str
        The model's limit states (canonical names, increasing severity).
    functions : list of str
        Taxonomy ids written.
    left_out : list of str
        Taxonomy ids without a fit for some limit state of the model, and which.
    off_chain : list of str
        Limit states of the table left out of the model: not on the tilt axis (sliding).
    """

    path: Path
    limit_states: list[str]
    functions: list[str] = field(default_factory=list)
    left_out: list[str] = field(default_factory=list)
    off_chain: list[str] = field(default_factory=list)


def _common_limit_states(frag: Fragilities) -> list[str]:
    # limit states present (fitted or not) in every (mode, tan α) of the table
    cols = ["mode", "tan_alpha", "limit_state"]
    both = pd.concat([frag.rows[cols], frag.skipped[cols]])
    sets = [set(g["limit_state"]) for _, g in both.groupby(["mode", "tan_alpha"])]
    return sort_limit_states(set.intersection(*sets)) if sets else []


def write_nrml(frag: Fragilities, path: str | Path, *, search_upper: float | None = None,
               limit_states: list[str] | None = None, model_id: str | None = None,
               description: str = "") -> NrmlExport:
    """Write the fragilities as an OpenQuake NRML 0.5 continuous fragility model.

    Parameters
    ----------
    frag : Fragilities
        From :func:`rocking.fragility.table.read_fragilities`.
    path : path
        Output ``.xml`` file.
    search_upper : float, optional
        The study's search bound, PGA/(g tan α) [-]; sets maxIML (module docstring).
    limit_states : list of str, optional
        Limit states of the model (default: those of every (mode, tan α) of the table).
    model_id : str, optional
        ``fragilityModel`` id; default :func:`nrml_model_id` of ``"rocking"`` and the kind.
    description : str
        Text of the description, after the sentence naming the fragility (the limit-state
        names are appended).

    Returns
    -------
    NrmlExport
    """
    if search_upper is not None:
        positive_finite("search_upper", search_upper)
    model_id = (nrml_model_id("rocking", frag.kind) if model_id is None
                else _checked_id(model_id))
    frag, off_chain = frag.damage_chain()
    if limit_states:
        off_chain = sorted(set(off_chain) | {s for s in sort_limit_states(limit_states)
                                             if severity(s)[0] != TILT_AXIS})
        limit_states = [s for s in sort_limit_states(limit_states)
                        if severity(s)[0] == TILT_AXIS]
    states = sort_limit_states(limit_states) if limit_states else _common_limit_states(frag)
    if not states:
        raise ValueError("no limit state common to every mode and tan_alpha of the table; "
                         "pass limit_states=[...]")
    ET.register_namespace("", NAMESPACE)
    root = ET.Element(f"{{{NAMESPACE}}}nrml")
    model = ET.SubElement(root, _q("fragilityModel"), id=model_id, assetCategory="buildings",
                          lossCategory="structural")
    mapping = ", ".join(f"{nrml_limit_state(s)} = {s}" for s in states)
    kind = KINDS[frag.kind]
    text = f"{kind[0].upper()}{kind[1:]}. " + (f"{description} " if description else "") + (
        "Free-standing rocking bodies (rocking package); IMT PGA in g = vector peak of the "
        f"horizontal pair; lognormal capacity, mean/stddev arithmetic. Limit states: {mapping}."
        + (f" Left out: {', '.join(off_chain)} (sliding in contact is not a damage state of "
           "the tilt-overturning chain; its fragility is in the study's fragility table)."
           if off_chain else ""))
    ET.SubElement(model, _q("description")).text = text
    ET.SubElement(model, _q("limitStates")).text = " ".join(nrml_limit_state(s) for s in states)
    written, left_out = [], []
    for (mode, tan_alpha, R), rows in frag.groups():
        tax = taxonomy(mode, tan_alpha, R)
        by_ls = rows.set_index("limit_state")
        lacking = [s for s in states if s not in by_ls.index]
        if lacking:
            left_out.append(f"{tax} (no fit for {', '.join(lacking)})")
            continue
        uplift = float(tan_alpha)  # PGA [g] at which a rigid body starts to rock
        top = max(by_ls.loc[s, "median_g"] * math.exp(MAX_IML_SIGMAS * by_ls.loc[s, "beta"])
                  for s in states)
        if search_upper is not None:
            top = max(top, search_upper * float(tan_alpha))
        func = ET.SubElement(model, _q("fragilityFunction"), id=tax, format="continuous",
                             shape="logncdf")
        ET.SubElement(func, _q("imls"), imt="PGA", minIML=_num(uplift), maxIML=_num(top),
                      noDamageLimit=_num(uplift))
        for s in states:
            mean, std = lognormal_moments(float(by_ls.loc[s, "median_g"]),
                                          float(by_ls.loc[s, "beta"]))
            ET.SubElement(func, _q("params"), ls=nrml_limit_state(s), mean=_num(mean),
                          stddev=_num(std))
        written.append(tax)
    ET.indent(root, space="  ")
    path = Path(path)
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)
    return NrmlExport(path, states, written, left_out, off_chain)


def _q(tag: str) -> str:
    return f"{{{NAMESPACE}}}{tag}"


def _num(x: float) -> str:
    # repr: the shortest text that reads back to the same double (round trip to 1e-16)
    return repr(float(x))


__all__ = ["MODEL_ID", "NAMESPACE", "NrmlExport", "nrml_limit_state", "nrml_model_id",
           "taxonomy", "write_nrml"]
