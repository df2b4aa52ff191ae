"""Where a ground motion comes from, and what was done to it: one loader for every front end.

The library, the command line and the workflow take a motion from the same three places:

- a named record (``record="el-centro-1940"``), as recorded;
- one or two acceleration files (``files=[x, y]``; with ``record`` the named record is read
  from those files and its sha256 checked);
- an ensemble file written by ``rocking motions`` or the workflow, and a motion in it
  (``ensemble="results/motions/elcentro.nc", motion="el-centro-1940"``): the motion exactly
  as the study used it (rotated, high-passed, padded, cut).

:func:`process_motion` applies the study's processing to a record (the steps of
:func:`rocking.motions.build.build_ensemble`), so asking for the same processing gives the
same samples. :func:`identity` (defined in :mod:`.identity`) says in a few fields where a
motion comes from and what was applied; the ensemble files, the stores and the CSV outputs
carry these fields.
"""

from __future__ import annotations

from pathlib import Path

from rocking.motions.identity import describe_processing, identity
from rocking.motions.motion import GroundMotion

__all__ = ["describe_processing", "identity", "load_motion", "process_motion"]


def load_motion(record: str | None = None, files=None, ensemble: str | Path | None = None,
                motion: str | None = None, *, name: str | None = None,
                order_by_azimuth: bool = False, dt: float | None = None,
                units: str = "g", vertical: bool = False) -> GroundMotion:
    """A ground motion from a named record, acceleration files or an ensemble file.

    Parameters
    ----------
    record : str, optional
        Named record (:data:`rocking.motions.catalogue.RECORDS`); with ``files``, the files
        of that record.
    files : sequence of one, two or three paths, optional
        Acceleration files, x then y (AT2 or text, in g), then z (vertical, positive up; a
        ``DWN`` AT2 file is turned). One file gives a motion with only an x component (for
        the 2D modes).
    ensemble : str or Path, optional
        Ensemble file (NetCDF of :mod:`rocking.motions.ensemble_io`).
    motion : str, optional
        Name of the motion in ``ensemble``; default its first motion (the record).
    name : str, optional
        Name of a motion read from ``files`` without ``record`` (default: the file stems).
    order_by_azimuth : bool
        Reorder two files by their header azimuths (x = the other's + 90°), with a warning;
        default: the order given (:func:`rocking.motions.catalogue.load_record`).
    dt : float, optional
        Time step [s] of one-column text ``files`` (AT2 and two-column files carry their
        own; given, it must agree with it).
    units : str
        Unit of the values in ``files``: ``"g"`` (default), ``"m/s2"``, ``"cm/s2"`` or
        ``"gal"`` (:func:`rocking.motions.readers.read_record`).
    vertical : bool
        With the vertical component: the named record's shipped ``UP``/``DWN`` file
        (:func:`rocking.motions.catalogue.load_record`); implied by three ``files``. A
        motion of an ``ensemble`` comes as stored (with the vertical component of a record
        built with ``vertical: true``); True there requires one (a synthetic pair has none).

    Returns
    -------
    GroundMotion
        Accelerations [m/s²].

    Raises
    ------
    ValueError
        A missing or contradictory source, an unknown record or motion name.
    FileNotFoundError
        A file that does not exist.
    """
    files = list(files or [])
    if vertical and files and len(files) != 3:
        raise ValueError(f"vertical=True needs three files (x, y, z), got {len(files)}")
    if ensemble is not None:
        if record is not None or files:
            raise ValueError("give an ensemble file or a record/files, not both")
        if units != "g":
            raise ValueError(f"units={units!r} is the unit of acceleration files; a motion of "
                             "an ensemble file is stored in m/s²")
        return _from_ensemble(Path(ensemble), motion, vertical)
    if motion is not None:
        raise ValueError(f"motion={motion!r} names a motion of an ensemble file; give ensemble")
    from rocking.motions.catalogue import load_record, loma_prieta_pair

    if not files:
        if record is None:
            raise ValueError("give a record name, acceleration files or an ensemble file")
        # the paper's SJTE record is not redistributable: its labelled stand-in
        if record == "loma-prieta-sjte":
            if vertical:
                raise ValueError("vertical=True: record 'loma-prieta-sjte' ships no files; "
                                 "give its three files")
            return loma_prieta_pair()
        return load_record(record, vertical=vertical)
    if len(files) == 3:
        stems = "+".join(Path(f).stem for f in files[:2])
        return load_record(record or name or stems, files, order_by_azimuth=order_by_azimuth,
                           dt=dt, units=units)
    if len(files) == 2:
        if record == "loma-prieta-sjte":
            return loma_prieta_pair(files, order_by_azimuth=order_by_azimuth)
        stems = "+".join(Path(f).stem for f in files)
        return load_record(record or name or stems, files, order_by_azimuth=order_by_azimuth,
                           dt=dt, units=units)
    if len(files) == 1 and record is None:
        from rocking.motions.readers import read_record

        rec = read_record(files[0], units, dt=dt)
        return GroundMotion(rec.acc, None, rec.dt, name or Path(files[0]).stem,
                            {**rec.meta, "source": "file", "components": {"x": rec.meta}})
    raise ValueError(f"files must be one, two or three paths (x, y, z), got {len(files)}: "
                     f"{files!r}")


def _from_ensemble(path: Path, name: str | None, vertical: bool = False) -> GroundMotion:
    from rocking.motions.ensemble_io import load_ensemble

    motions = load_ensemble(path)
    by_name = {m.name: m for m in motions}
    if name is not None and name not in by_name:
        raise ValueError(f"motion {name!r} is not in ensemble {str(path)!r}; it holds "
                         f"{list(by_name)}")
    found = motions[0] if name is None else by_name[name]
    if vertical and found.az is None:
        if identity(found)["kind"] == "synthetic":
            raise ValueError(f"vertical=True: motion {found.name!r} of {str(path)!r} is a "
                             "synthetic pair, whose horizontals are simulated: it has no "
                             "vertical component (synthetic pairs stay horizontal)")
        raise ValueError(f"vertical=True: motion {found.name!r} of {str(path)!r} was stored "
                         "without a vertical component (build the ensemble with vertical: "
                         "true)")
    return found


def process_motion(motion: GroundMotion, *, rotation: float | str | None = None,
                   highpass: str = "none", fc_hz: float | None = None,
                   mw: float | None = None, max_duration: float | None = None) -> GroundMotion:
    """Apply the study's processing of a record: principal axes, high-pass, cut.

    Parameters
    ----------
    motion : GroundMotion
        A recorded pair [m/s²].
    rotation : None, "auto" or float
        None: keep the recorded axes; otherwise as in
        :func:`rocking.motions.principal.to_principal_axes` [deg].
    highpass : {"none", "oscillator", "butterworth"}
        High-pass filter (zero padding kept).
    fc_hz, mw : float, optional
        Corner frequency [Hz], default the Brune corner of ``mw`` (default: the record's).
    max_duration : float, optional
        Keep the first seconds [s].

    Returns
    -------
    GroundMotion
        With rotation given, exactly the first motion :func:`build_ensemble` writes for the
        same settings (the workflow's ensemble files); the steps are in
        ``metadata["processing"]``.
    """
    from rocking.motions.build import build_ensemble

    if rotation is not None:
        return build_ensemble(motion, 0, 0, rotation=rotation, highpass=highpass, fc_hz=fc_hz,
                              mw=mw, max_duration=max_duration).motions[0]
    out = motion
    if highpass != "none":
        from rocking.motions.build import HIGHPASS_KINDS
        from rocking.motions.highpass import brune_corner, highpass_motion

        if highpass not in HIGHPASS_KINDS:
            raise ValueError(f"highpass must be one of {HIGHPASS_KINDS}, got {highpass!r}")
        if fc_hz is None:
            mw = mw if mw is not None else motion.metadata.get("mw")
            if mw is None:
                raise ValueError(f"mw (or fc_hz) is needed for the high-pass of {motion.name!r}")
            fc_hz = brune_corner(mw)
        out = highpass_motion(out, highpass, fc_hz)
    if max_duration is not None:
        from rocking.motions.build import cut

        out = cut(out, max_duration)
    return out
