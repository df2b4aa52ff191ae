"""The motions the resolution benchmark runs on, built as the study builds them: El Centro
and five of its synthetic pairs, and the Loma Prieta record, from the recorded RDK fits of
config/ensembles/*.params.json. Only :mod:`rocking.motions` is imported, so the same motions
are built under the library of an earlier commit (the benchmark's baseline)."""

from __future__ import annotations

from pathlib import Path

from rocking.motions.motion import GroundMotion

MOTION_LABELS = {
    "ec": "El Centro 1940, principal axes, high-passed (the study's processing)",
    "syn0": "synthetic pair 0 of El Centro's ensemble (recorded RDK fit, seed 2017)",
    "syn1": "its pair 1", "syn2": "its pair 2", "syn3": "its pair 3", "syn4": "its pair 4",
    "lp": "Loma Prieta 1989 (the study's record), as the study processes it",
    "lpsyn0": "synthetic pair 0 of Loma Prieta's ensemble (recorded RDK fit, seed 1989)",
    "lpsyn1": "its pair 1",
}
"""Short names of the motions and what they are."""


def study_motions() -> dict[str, GroundMotion]:
    """The motions of :data:`MOTION_LABELS` by short name."""
    from rocking.motions.build import build_ensemble
    from rocking.motions.catalogue import load_record
    from rocking.motions.stochastic.recorded import read_params_file

    root = Path(__file__).resolve().parents[1] / "config" / "ensembles"
    ec_rec = read_params_file(root / "elcentro.params.json")["records"]["el-centro-1940"]
    lp_rec = read_params_file(root / "lomaprieta.params.json")["records"]
    lp_name = next(iter(lp_rec))
    ec = build_ensemble(load_record("el-centro-1940"), 5, 2017, recorded=ec_rec).motions
    lp = build_ensemble(load_record(lp_name), 2, 1989, recorded=lp_rec[lp_name]).motions
    out = {"ec": ec[0], "lp": lp[0], "lpsyn0": lp[1], "lpsyn1": lp[2]}
    out.update({f"syn{i}": m for i, m in enumerate(ec[1:])})
    return out
