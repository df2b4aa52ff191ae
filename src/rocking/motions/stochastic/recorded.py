"""Fitted RDK parameters rounded and recorded, so a study's synthetic motions are the same
on every machine.

The spectrum-matched fit is an optimisation: two machines (another BLAS, another SIMD path
of ``exp``) end it at parameters that differ around 1e-8, and rocking answers near a goal are
chaotic in their input, so such a difference moved 700 of 3740 answers of the paper's
gallery by up to 4 %. A *recorded* fit removes the optimiser from the path: the parameters
are rounded to :data:`SIGNIFICANT_DIGITS` significant digits (decimal, so the file holds
them exactly), written with their digest to a committed file
(``config/ensembles/<ensemble>.params.json``), and the motions are simulated from them. The
file also holds the digest of each synthetic pair made from them (with the ensemble's
``seed`` and processing), so a build says when this
machine's simulation differs from the one that wrote the file (docs/motions.md,
"Recorded parameters").

File format (JSON, :data:`FORMAT`)::

    {"format": "rocking-rdk-params/1", "ensemble": <name>, "significant_digits": 6,
     "records": {<record name>: {"settings": {...}, "fit": {...}, "fit_sha256": <hex>,
                                 "pairs_sha256": [<hex> per pair], "n_synthetic": n,
                                 "seed": s}}}

Pair r of a seed is the same whatever the number of pairs
(:mod:`rocking.motions.stochastic.pairs`), so a study with fewer pairs (config/config.yaml
has 3 of the paper's 10) is checked on the first ones.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rocking.motions.motion import GroundMotion
from rocking.motions.stochastic.params import RDKParams

if TYPE_CHECKING:  # the fit (scipy, numba) is imported where one is made, not to read a file
    from rocking.motions.stochastic.fit import RDKFit

__all__ = ["FIT_SETTINGS", "FORMAT", "SIGNIFICANT_DIGITS", "check_settings", "entries_for",
           "fit_sha256",
           "pairs_match", "pairs_sha256", "read_params_file", "record_entry", "recorded_fit",
           "round_significant", "rounded_fit", "write_params_file"]

FORMAT = "rocking-rdk-params/1"
"""Format tag of a parameters file."""

SIGNIFICANT_DIGITS = 6
"""Significant digits kept of every fitted parameter. Rounding moves a parameter by at most
5e-6 of itself; measured on both paper ensembles (10 pairs, their seeds), the geometric-mean
5 % PSA of the ensemble moves by at most 4.8e-6 (0.1-4 s, both components; 4 digits: 1.8 %,
because the simulated length, hence the split of the noise between the two filtered
processes, changes with D5-95 and t_mid), far below the fit's own mismatch (per cent per
band). docs/motions.md, "Recorded parameters"."""

_PARAM_KEYS = ("Ia", "D5_95", "t_mid", "f_mid", "f_slope", "zeta_f", "f_mid2", "zeta_f2",
               "share2", "f_low", "zeta_low")

FIT_SETTINGS = ("record", "paths", "units", "dt", "mw", "rotation_deg", "highpass", "fc_hz",
                "fit_method")
"""Settings of a record that decide its fitted parameters: a recorded fit is used only where
they agree with the study's (else the file is of another processing)."""


def round_significant(x: float, digits: int = SIGNIFICANT_DIGITS) -> float:
    """``x`` rounded to ``digits`` significant decimal digits (the float nearest the
    decimal, so its JSON text is that decimal exactly)."""
    return float(f"{float(x):.{int(digits) - 1}e}")


def rounded_fit(fit: RDKFit, digits: int = SIGNIFICANT_DIGITS) -> RDKFit:
    """The fit with every parameter and the rotation rounded; the diagnostics (provenance of
    the unrounded fit, not used by the simulation) kept."""
    from rocking.motions.stochastic.fit import RDKFit

    def params(p: RDKParams) -> RDKParams:
        d = p.to_dict()
        return RDKParams.from_dict({**{k: None if d[k] is None else round_significant(d[k], digits)
                                       for k in _PARAM_KEYS}, "diagnostics": d["diagnostics"]})
    return RDKFit(round_significant(fit.angle, digits), params(fit.major), params(fit.minor),
                  fit.dt, fit.name, dict(fit.diagnostics))


def _fit_dict(fit: RDKFit | Mapping[str, Any]) -> dict[str, Any]:
    """What a recorded fit holds: name, dt, rotation and the parameters of both components
    (of an :class:`RDKFit` or of its :meth:`~RDKFit.to_dict`)."""
    d = fit if isinstance(fit, Mapping) else fit.to_dict()
    # rounded again: RDKParams stores f_low through 2π·f/2π, which may move the decimal by
    # an ulp; the file holds the decimals rounded_fit gave RDKParams, so a recorded fit
    # builds the same parameters to the bit
    return {"name": d["name"], "dt": d["dt"],
            "angle_deg": round_significant(d["angle_deg"]),
            **{c: {k: None if d[c].get(k) is None else round_significant(d[c][k])
                   for k in _PARAM_KEYS} for c in ("major", "minor")}}


def fit_sha256(fit_dict: Mapping[str, Any]) -> str:
    """sha256 (hex) of a recorded fit's canonical JSON (sorted keys, shortest float text)."""
    text = json.dumps(fit_dict, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


def pairs_sha256(motions: Sequence[GroundMotion]) -> list[str]:
    """:attr:`GroundMotion.samples_sha256` of each motion: equal digests are the same
    samples to the bit."""
    return [m.samples_sha256 for m in motions]


def pairs_match(entry: Mapping[str, Any], seed: int, got: Sequence[str]) -> bool | None:
    """Whether pairs made from a recorded fit with ``seed`` are the recorded ones to the bit
    (compared on the pairs both have); None where the file recorded another seed."""
    if int(entry["seed"]) != int(seed):
        return None
    k = min(len(got), len(entry["pairs_sha256"]))
    return list(got[:k]) == list(entry["pairs_sha256"][:k])


def record_entry(fit: RDKFit | Mapping[str, Any], settings: Mapping[str, Any],
                 pairs: Sequence[str], seed: int) -> dict[str, Any]:
    """One record's entry of a parameters file: the (already rounded) ``fit`` (or its
    ``to_dict``), its digest, the settings that decided it (:data:`FIT_SETTINGS`) and the
    digests :func:`pairs_sha256` of the pairs of ``seed`` made from it."""
    fit_dict = _fit_dict(fit)
    return {"settings": {k: _norm(settings.get(k)) for k in FIT_SETTINGS}, "fit": fit_dict,
            "fit_sha256": fit_sha256(fit_dict), "n_synthetic": len(pairs),
            "seed": int(seed), "pairs_sha256": list(pairs)}


def write_params_file(path: str | Path, ensemble: str, records: Mapping[str, Any]) -> Path:
    """Write a parameters file (:data:`FORMAT`) of ``ensemble`` with its ``records``
    (:func:`record_entry` by record name)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    body = {"format": FORMAT, "ensemble": ensemble, "significant_digits": SIGNIFICANT_DIGITS,
            "records": dict(records)}
    path.write_text(json.dumps(body, indent=1, sort_keys=True, allow_nan=False) + "\n")
    return path


def read_params_file(path: str | Path) -> dict[str, Any]:
    """A parameters file, checked: its format, and every record's fit against its digest
    (one-line ValueError naming the file and the record)."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"parameters file {str(path)!r} does not exist (a run writes it as "
                         "<output>/motions/<ensemble>-<digest>.params.json, `rocking motions "
                         "--write-params FILE` too; docs/motions.md)")
    try:
        body = json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise ValueError(f"parameters file {str(path)!r} is not readable JSON: {exc}") from None
    if not isinstance(body, dict) or body.get("format") != FORMAT:
        raise ValueError(f"parameters file {str(path)!r}: format must be {FORMAT!r}, got "
                         f"{body.get('format') if isinstance(body, dict) else body!r}")
    records = body.get("records")
    if not isinstance(records, dict) or not records:
        raise ValueError(f"parameters file {str(path)!r} holds no records")
    for name, entry in records.items():
        missing = [k for k in ("settings", "fit", "fit_sha256", "pairs_sha256", "n_synthetic",
                               "seed") if k not in entry]
        if missing:
            raise ValueError(f"parameters file {str(path)!r}: record {name!r} lacks {missing}")
        got = fit_sha256(entry["fit"])
        if got != entry["fit_sha256"]:
            raise ValueError(f"parameters file {str(path)!r}: record {name!r} has fit_sha256 "
                             f"{entry['fit_sha256']!r} but its parameters hash to {got!r} "
                             "(edited by hand? write the file again)")
    return body


def check_settings(entry: Mapping[str, Any], settings: Mapping[str, Any], where: str) -> None:
    """ValueError naming the keys where a recorded fit's settings differ from the study's."""
    differ = [k for k in FIT_SETTINGS if _norm(entry["settings"].get(k)) != _norm(settings.get(k))]
    if differ:
        pairs = ", ".join(f"{k}: file {entry['settings'].get(k)!r}, study {settings.get(k)!r}"
                          for k in differ)
        raise ValueError(f"{where}: the recorded fit is of other settings ({pairs}); write the "
                         "parameters file again or remove the params key")


def entries_for(path: str | Path, records: Sequence[tuple[str, Mapping[str, Any]]],
                field: str) -> dict[str, Any]:
    """The entries of the parameters file ``path`` by record name, checked for ``records``
    ((motion name, settings) of every record of an ensemble; a record without synthetic
    pairs needs none): each must be in the file with the settings it was fitted under.
    Errors are one line naming ``field`` (``ensembles.<name>.params``) and the file."""
    try:
        body = read_params_file(path)
    except ValueError as exc:
        raise ValueError(f"{field}: {exc}") from None
    for name, settings in records:
        if not settings.get("n_synthetic"):
            continue
        entry = body["records"].get(name)
        if entry is None:
            raise ValueError(f"{field}: {str(path)!r} holds no fit of record {name!r} (it has "
                             f"{sorted(body['records'])})")
        check_settings(entry, settings, f"{field} ({path}, record {name!r})")
    return body["records"]


def _norm(v: Any) -> Any:
    return list(v) if isinstance(v, tuple) else v


def recorded_fit(entry: Mapping[str, Any]) -> RDKFit:
    """The :class:`RDKFit` of a record's entry (read with :func:`read_params_file`); its
    diagnostics say it was recorded and by which method it was fitted."""
    from rocking.motions.stochastic.fit import RDKFit

    d = entry["fit"]
    return RDKFit(float(d["angle_deg"]), RDKParams.from_dict(d["major"]),
                  RDKParams.from_dict(d["minor"]), float(d["dt"]), str(d["name"]),
                  {"method": entry["settings"].get("fit_method"), "recorded": True})
