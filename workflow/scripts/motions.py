"""Build a ground-motion ensemble: the processed record first, then its synthetic pairs.

Record: read (package data or the configured files), rotated to its principal axes, high-
passed with the critically damped oscillator at the Brune corner of its magnitude (paper §4,
"baseline corrected via a high-pass filter based on Brune's source model"). Synthetic pairs:
the RDK model fitted to that record, simulated with independent seeded noise and the same
high-pass (rocking.stochastic). Optionally all motions are cut to motions.max_duration.
"""

import logging

from rocking.cluster import log_to
from rocking.ensemble_io import save_ensemble
from rocking.highpass import brune_corner, highpass_motion
from rocking.motion import GroundMotion
from rocking.principal import to_principal_axes
from rocking.records import load_record, loma_prieta_pair
from rocking.stochastic import fit_rdk, synthesize

# Moment magnitudes of the named records (NGA-West2 flatfile), for the Brune corner.
MAGNITUDES = {
    "el-centro-1940": 6.95,
    "loma-prieta-sjte": 6.93,
    "loma-prieta-corralitos": 6.93,
}


def read_record(spec):
    """The recorded pair; RSN 801 without files falls back to the labelled stand-in."""
    if spec["record"] == "loma-prieta-sjte":
        return loma_prieta_pair(spec["paths"])
    return load_record(spec["record"], spec["paths"])


def cut(motion, max_duration):
    """The first ``max_duration`` seconds of a motion (tests and quick looks)."""
    n = int(round(max_duration / motion.dt)) + 1
    if n >= motion.npts:
        return motion
    meta = dict(motion.metadata)
    meta["processing"] = [*meta.get("processing", []),
                          {"step": "truncate", "max_duration": max_duration, "npts": n}]
    return GroundMotion(motion.ax[:n], motion.ay[:n], motion.dt, motion.name, meta)


def main(snakemake):
    spec = snakemake.params.spec
    log = logging.getLogger("motions")
    with log_to(snakemake.log[0]):
        raw = read_record(spec)
        mw = spec.get("mw") or MAGNITUDES.get(spec["record"])
        if mw is None:
            raise ValueError(f"ensembles.{snakemake.wildcards.ensemble}.mw is needed for "
                             f"record {spec['record']!r} (Brune corner of the high-pass)")
        fc_hz = brune_corner(mw)
        rotated, angle = to_principal_axes(raw, spec["rotation_deg"])
        record = highpass_motion(rotated, "oscillator", fc_hz)
        log.info("record %s: rotated by %.3f deg, high-pass %.4f Hz (Mw %.2f), stand-in %s",
                 raw.name, angle, fc_hz, mw, record.metadata.get("stand_in"))
        motions = [record]
        if spec["n_synthetic"] > 0:
            fit = fit_rdk(record, 0.0, seed=spec["seed"])  # already on its principal axes
            log.info("RDK fit: %s", fit.to_dict())
            motions += synthesize(fit, spec["n_synthetic"], spec["seed"], highpass="oscillator",
                                  fc_hz=fc_hz)
        if spec["max_duration"] is not None:
            motions = [cut(m, spec["max_duration"]) for m in motions]
        save_ensemble(snakemake.output[0], motions,
                      {"ensemble": snakemake.wildcards.ensemble, "fc_hz": fc_hz,
                       "rotation_deg": angle})
        log.info("wrote %d motions to %s", len(motions), snakemake.output[0])


if __name__ == "__main__":
    main(snakemake)
