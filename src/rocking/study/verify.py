"""A run's tables held against a committed gallery (``rocking verify``), table by table.

Each table of the gallery's studies (``<study>/*.csv``: critical.csv, mean_spectra.csv,
fragility.csv, ...) is compared with the run's on the rows both have (matched on the table's
key columns) and the columns both have, and gets one verdict:

- **identical**: every common value equal (floats to the bit of their CSV text): what one
  machine and one process order give, reported, never required across machines;
- **within the stated error**: some values differ, by no more than the answers' stated
  error allows;
- **beyond the stated error**: more rows differ by more than that than the stated error
  allows (rows named), or a row is in one side only.

The *stated error* of an answer is the accuracy of its preset against the converged I10
(docs/performance.md, "The trade"; :func:`stated_error`): a share q of the answers lie
within e of it (relative). Two runs of one configuration on two machines are two such
estimates (their motions or their arithmetic may differ in the last bits, and rocking
magnifies that), so an answer of the run and the gallery's differ by at most 2e, relative to
the gallery's, in at least a share 2q − 1 of the answers: :func:`answer_tolerance` gives
r = 2e, and a table of answers (one row per answer: critical.csv, records.csv) is within the
stated error while at most a share 2(1 − q) of its rows differ by more (those rows are
named all the same). Every aggregate row must be within its tolerance, propagated from r:
values on the intensity scale (means, medians, percentiles) relative r (a mean or median of
values that each move by at most r relative moves by at most r); dispersions (β, lognormal
σ) absolute √2·r (the standard deviation of logarithms that each move by at most r); a
standard deviation of the answers r·a_max·√(n/(n−1)) with a_max ≤ mean + std·(n−1)/√n; the
slope and intercept of a linear fit over R by the least-squares weights of its R values;
rates of the risk table relative K·r, K the steepest log-log slope of the study's hazard
curve (λ_LS scales like the fragility median to the power −K). Counts and flags that differ
make a row "within" when its values are within (they follow the answers); a changed status
text makes it "beyond"; diagnostics (log-likelihood, R², analyses spent) never decide.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml

__all__ = ["TableVerdict", "VerifyInputError", "answer_tolerance", "config_differences",
           "format_verdicts", "motions_lines", "stated_error", "verify_run"]

_R = "__resolution__"  # a side's tolerance of each answer, carried beside its row

CRITICAL = "critical.csv"
ANSWER_TABLES = (CRITICAL, "records.csv")
"""Tables of answers, one per row with its own flags: each row takes its own resolution."""

KEYS: dict[str, tuple[str, ...]] = {
    "critical.csv": ("mode", "limit_state", "motion", "tan_alpha [-]", "R [m]"),
    "mean_spectra.csv": ("mode", "limit_state", "tan_alpha [-]", "R [m]"),
    "fragility.csv": ("mode", "limit_state", "tan_alpha [-]", "R [m]"),
    "linear_fit.csv": ("mode", "limit_state", "tan_alpha [-]"),
    "records.csv": ("motion", "mode", "tan_alpha [-]", "limit_state", "R [m]"),
    "stripe_fragility.csv": ("mode", "limit_state", "tan_alpha [-]", "R [m]", "measure"),
    "risk.csv": ("fragility", "measure", "mode", "tan_alpha [-]", "R [m]", "limit_state"),
    "suite_fragility.csv": ("motions", "mode", "tan_alpha", "limit_state", "R", "measure"),
    "fragility.pelicun.csv": ("ID",),
    "headline.csv": ("motion", "scan_step"),
    "stripe_fragility.pelicun.csv": ("ID",),
}
"""Columns naming a row of each table (a table not listed is matched row by row)."""

ANSWER_KEYS = ("mode", "limit_state", "tan_alpha", "R")
"""What ties an aggregate row to the answers it is made of (header units stripped)."""

DIAGNOSTIC = ("log_likelihood", "r_squared", "n_analyses", "n_refined", "bootstrap_fitted",
              "boot_defined", "share_extrapolated", "share_dropped", "processing",
              "as_recorded_note", "reason", "analyses", "cpu_s", "first_exceedance")
"""Columns that say how a value was obtained, not what it is: never decide a verdict. The
first exceedance on a scan grid is among them: it has no stated error (it does not converge
as the grid is refined, docs/models.md), so two runs' may differ by a window."""

RISK_RATES = ("maf", "lambda_p05", "lambda_p95", "lambda_lo", "lambda_hi", "return_period",
              "p_50yr")
"""Columns of the risk table that scale like the fragility median to the power −K."""

IGNORED_CONFIG = ("dask", "output")
"""Configuration sections that cannot change a number (not compared): the cluster and the
output folder."""

REPORT_ONLY = ("reproduces",)
"""Study keys that change a report's verdicts, never a table (not compared)."""


class VerifyInputError(ValueError):
    """The folder is no run, a partial run, or a run of another configuration (exit 2)."""


@dataclass
class TableVerdict:
    """The comparison of one table.

    Attributes
    ----------
    table : str
        ``<study>/<file>``.
    verdict : str
        ``"identical"``, ``"within"`` or ``"beyond"``.
    rows : int
        Rows compared.
    n_within : int
        Rows that differ within their tolerance.
    beyond : list of str
        Rows that differ beyond it, or are in one side only, each described in one line.
    notes : list of str
        Columns in one side only, and the largest relative difference seen.
    allowed : int
        Rows of a table of answers that may differ beyond their tolerance while the table
        is within the stated error (the share 2(1 − q) of its rows; 0 for an aggregate).
    """

    table: str
    verdict: str
    rows: int
    n_within: int = 0
    beyond: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    allowed: int = 0


def _base(column: str) -> str:
    """A header without its unit: ``"R [m]"`` → ``"R"``."""
    return column.split(" [", 1)[0]


def _flatten(d: Any, prefix: str = "") -> dict[str, Any]:
    if isinstance(d, Mapping):
        out: dict[str, Any] = {}
        for k, v in d.items():
            out.update(_flatten(v, f"{prefix}{k}."))
        return out
    return {prefix.rstrip("."): d}


def _default(key: str) -> Any:
    """The schema default of a dotted key (:data:`rocking.config.fields.DEFAULTS`), or
    a marker that equals nothing when it has none."""
    from rocking.config.fields import DEFAULTS

    parts = key.split(".")
    where: tuple[str, ...] = ()
    if parts[0] == "ensembles" and len(parts) == 3:
        where = ("ensemble", parts[2])
    elif parts[0] == "studies" and len(parts) == 3:
        where = ("study", parts[2])
    elif parts[0] == "studies" and len(parts) == 4 and parts[2] in ("stripes", "tilt_map"):
        where = (parts[2], parts[3])
    elif len(parts) == 2:
        where = (parts[0], parts[1])
    section = DEFAULTS.get(where[0]) if where else None
    if isinstance(section, Mapping) and where[1] in section:
        return section[where[1]]
    return _ABSENT


_ABSENT = object()


def config_differences(run: Mapping[str, Any], gallery: Mapping[str, Any]) -> list[str]:
    """Dotted keys whose values differ between two resolved configurations, sorted; ``dask``,
    ``output`` and ``reproduces`` left out, and a key one side lacks compared with its schema
    default (a gallery written before the key existed)."""
    a = _flatten(_canonical({k: v for k, v in run.items() if k not in IGNORED_CONFIG}))
    b = _flatten(_canonical({k: v for k, v in gallery.items() if k not in IGNORED_CONFIG}))
    keys = {k for k in set(a) | set(b) if k.rsplit(".", 1)[-1] not in REPORT_ONLY}
    return sorted(k for k in keys if a.get(k, _default(k)) != b.get(k, _default(k)))


def _canonical(config: dict[str, Any]) -> dict[str, Any]:
    """``quantity`` in one spelling (name, p and w; a name alone or an absent key is the
    default's), so that two ways of writing one choice are one configuration."""
    from rocking.spectra.quantity import Quantity

    try:
        q = Quantity.from_value(config.get("quantity")).to_dict()
    except ValueError:
        return config  # compared as written: it differs, or is the same bad value
    return {**config, "quantity": q}


def _read_config(path: Path) -> dict[str, Any]:
    try:
        config = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise VerifyInputError(f"{path}: not a readable configuration ({exc})") from None
    if not isinstance(config, dict) or not isinstance(config.get("studies"), dict):
        raise VerifyInputError(f"{path}: not a run configuration (no studies)")
    return config


def _gallery(against: Path) -> tuple[dict[str, Any], dict[str, list[str]]]:
    """The gallery's configuration and, per study, its tables."""
    cfg = against / "config.yaml"
    if not cfg.is_file():
        raise VerifyInputError(f"{against}: no config.yaml: not a gallery (a folder written by "
                               "workflow/gallery.py, e.g. results/paper)")
    config = _read_config(cfg)
    tables = {s: sorted(p.name for p in (against / s).glob("*.csv")) for s in config["studies"]}
    empty = [s for s, t in tables.items() if not t]
    if empty:
        raise VerifyInputError(f"{against}: gallery without tables for studies {empty}")
    return config, tables


def _run_config(run: Path, studies: list[str]) -> tuple[dict[str, Any], bool]:
    """The run's resolved configuration and whether ``run`` is a gallery-like copy
    (``config.yaml`` at its root, ``critical.csv`` per study) rather than an output root
    (``<study>/config.yaml``, the answers in the spectra store)."""
    if not run.is_dir():
        raise VerifyInputError(f"{run}: no such folder")
    if (run / "config.yaml").is_file():
        return _read_config(run / "config.yaml"), True
    for s in studies:
        if (run / s / "config.yaml").is_file():
            return _read_config(run / s / "config.yaml"), False
    raise VerifyInputError(f"{run}: not a run: no config.yaml, nor {studies[0]}/config.yaml "
                           "(give the output folder of a run, e.g. results)")


def _read_table(path: Path) -> pd.DataFrame:
    """A table of a run or the gallery, in today's names (a gallery written by an earlier
    version: :func:`rocking.fragility.table.renamed`); one that cannot be read (empty,
    binary, not UTF-8, cut in a quoted field) is refused naming the file."""
    from rocking.fragility.table import renamed

    try:
        return renamed(pd.read_csv(path))
    except (OSError, ValueError, pd.errors.ParserError) as exc:  # EmptyDataError, decoding
        reason = str(exc).splitlines()[0][:120] if str(exc) else type(exc).__name__
        raise VerifyInputError(f"{path}: not a readable table ({reason})") from None


def _critical_from_store(run: Path, study: str, config: dict[str, Any]) -> pd.DataFrame | None:
    """The answers of a run's study from its spectra store (None if there is none)."""
    import xarray as xr

    from rocking.config.study import StudySpec
    from rocking.execution.prepare import keyed
    from rocking.study.aggregate import critical_frame

    store = keyed(run / study / "spectra.zarr", StudySpec.from_config(config, study)
                  .spectra.digest)
    if not Path(store).exists():
        return None
    with xr.open_zarr(store, consolidated=True) as ds:
        frame = critical_frame(ds)
    # the CSV text of the gallery's critical.csv: floats as written there, read back
    return pd.read_csv(pd.io.common.StringIO(frame.to_csv(index=False, float_format="%.10g")))


def _load(run: Path, against: Path) -> tuple[dict, dict, dict]:
    """(run config, per study {table: run frame}, per study {table: gallery frame})."""
    gconfig, gtables = _gallery(against)
    studies = list(gconfig["studies"])
    rconfig, copy = _run_config(run, studies)
    differ = config_differences(rconfig, gconfig)
    if differ:
        shown = ", ".join(differ[:6]) + (f" and {len(differ) - 6} more" if len(differ) > 6
                                         else "")
        raise VerifyInputError(f"{run}: a run of another configuration than {against} "
                               f"(keys differ: {shown})")
    missing, rframes, gframes = [], {}, {}
    for s in studies:
        rframes[s], gframes[s] = {}, {}
        for t in gtables[s]:
            gframes[s][t] = _read_table(against / s / t)
            path = run / s / t
            if path.is_file():
                rframes[s][t] = _read_table(path)
            elif t == CRITICAL and not copy:
                frame = _critical_from_store(run, s, rconfig)
                if frame is None:
                    missing.append(f"{s}/spectra.zarr")
                else:
                    rframes[s][t] = frame
            else:
                missing.append(f"{s}/{t}")
    if missing:
        raise VerifyInputError(f"{run}: partial run, missing {', '.join(missing[:8])}"
                               + (f" and {len(missing) - 8} more" if len(missing) > 8 else ""))
    return rconfig, rframes, gframes


def stated_error(accuracy: Any) -> tuple[float, float]:
    """(e, q) of an accuracy preset: a share q of its answers lie within e (relative) of the
    converged I10 (:data:`rocking.spectra.accuracy.STATED`, measured on the resolution
    benchmark; a mapping overriding a preset takes its preset's, a preset without a
    measured figure the ``default``'s). ``accuracy``: an
    :class:`~rocking.spectra.accuracy.Accuracy`, or a run's configured value (resolved
    here, where it enters)."""
    from rocking.spectra.accuracy import STATED, Accuracy

    acc = Accuracy.of(accuracy)
    given = acc.configured
    name = given.get("preset", "default") if isinstance(given, Mapping) else acc.name
    return STATED.get(str(name), STATED["default"])


def answer_tolerance(accuracy: Any) -> tuple[float, float]:
    """(r, share): two runs' answers differ by at most r = 2e relative in all but a share
    2(1 − q) of the answers, (e, q) the preset's :func:`stated_error`."""
    e, q = stated_error(accuracy)
    return 2.0 * e, 2.0 * (1.0 - q)


def _resolution(frame: pd.DataFrame, tol: float) -> pd.Series:
    """Relative tolerance of each answer of a critical table: ``tol`` for every one (a
    ``plateau`` answer is ill-conditioned, and counted among the share allowed beyond)."""
    return pd.Series(np.full(len(frame), tol), index=frame.index)


def _answer_resolution(run_crit: pd.DataFrame, gal_crit: pd.DataFrame,
                       tol: float) -> tuple[pd.Series, float]:
    """Largest resolution per (mode, limit_state, tan_alpha, R) over both sides, and over all."""
    both = []
    for f in (run_crit, gal_crit):
        g = f.rename(columns=_base)[list(ANSWER_KEYS)].copy()
        g["r"] = _resolution(f, tol).to_numpy()
        both.append(g)
    frame = pd.concat(both)
    return frame.groupby(list(ANSWER_KEYS))["r"].max(), float(frame["r"].max())


def _hazard_slope(config: dict[str, Any], study: str) -> float:
    """Steepest log-log slope K of the study's hazard curve (4 where it cannot be read)."""
    spec = config["studies"][study].get("hazard")
    if spec is None:
        return 4.0
    try:
        from rocking.risk.hazard import parse_hazard

        curve = parse_hazard(spec)
        im, rate = np.log(np.asarray(curve.im_g)), np.log(np.asarray(curve.annual_rate))
        return float(np.max(np.abs(np.diff(rate) / np.diff(im))))
    except Exception:  # noqa: BLE001 - a bound for a tolerance, not a result
        return 4.0


def _fit_weights(rs: np.ndarray) -> tuple[float, float]:
    """Σ|c_i| and Σ|d_i| of least-squares slope Σc_i y_i and intercept Σd_i y_i over R."""
    if rs.size < 2:
        return math.inf, math.inf
    dev = rs - rs.mean()
    c = dev / np.sum(dev * dev)
    d = 1.0 / rs.size - rs.mean() * c
    return float(np.abs(c).sum()), float(np.abs(d).sum())


def _row_name(keys: tuple[str, ...], values: tuple) -> str:
    return " ".join(f"{_base(k)}={v}" for k, v in zip(keys, values, strict=True))


def _is_float(s: pd.Series) -> bool:
    return pd.api.types.is_float_dtype(s)


def _compare_table(name: str, table: str, run: pd.DataFrame, gal: pd.DataFrame,
                   tol: float, res: pd.Series, r_all: float, k_hazard: float,
                   rs_by_key: dict[tuple, np.ndarray], share: float = 0.0) -> TableVerdict:
    """Verdict on one table (see the module notes for the tolerances)."""
    notes = []
    only_run = [c for c in run.columns if c not in gal.columns]
    only_gal = [c for c in gal.columns if c not in run.columns]
    if only_run:
        notes.append(f"columns only in the run: {', '.join(only_run)}")
    if only_gal:
        notes.append(f"columns only in the gallery: {', '.join(only_gal)}")
    cols = [c for c in gal.columns if c in run.columns]
    keys = tuple(k for k in KEYS.get(table, ()) if k in cols)
    own = table in ANSWER_TABLES
    if own:
        run = run.assign(**{_R: _resolution(run, tol).to_numpy()})
        gal = gal.assign(**{_R: _resolution(gal, tol).to_numpy()})
    if keys:
        if run.duplicated(list(keys)).any() or gal.duplicated(list(keys)).any():
            # keys that do not name a row alone (a table of an older version): the n-th row
            # of each key against the n-th
            run = run.assign(occurrence=run.groupby(list(keys)).cumcount())
            gal = gal.assign(occurrence=gal.groupby(list(keys)).cumcount())
            keys = (*keys, "occurrence")
        run = run[cols + [_R] * own + ["occurrence"] * ("occurrence" in keys)] \
            .set_index(list(keys))
        gal = gal[cols + [_R] * own + ["occurrence"] * ("occurrence" in keys)] \
            .set_index(list(keys))
    else:
        run, gal = run[cols + [_R] * own], gal[cols + [_R] * own]
        keys = ("row",)
    beyond: list[str] = []
    only = [(i, "run") for i in run.index.difference(gal.index)] + \
        [(i, "gallery") for i in gal.index.difference(run.index)]
    for i, side in only:
        beyond.append(f"{_row_name(keys, i if isinstance(i, tuple) else (i,))}: only in the "
                      f"{side}")
    common = gal.index.intersection(run.index)
    a, b = run.loc[common], gal.loc[common]
    if own:
        r_a, r_b = a[_R].to_numpy(), b[_R].to_numpy()
        a, b = a.drop(columns=_R), b.drop(columns=_R)
    n_within, worst = 0, 0.0
    answer_keys = [k for k in keys if _base(k) in ANSWER_KEYS]
    # only the rows with some difference are compared one by one
    equal = ((a == b) | (a.isna() & b.isna())).all(axis=1).to_numpy()
    for pos in np.flatnonzero(~equal):
        idx = common[pos]
        ra, rb = a.iloc[pos], b.iloc[pos]
        tup = idx if isinstance(idx, tuple) else (idx,)
        key = dict(zip(keys, tup, strict=True))
        if own:
            r = float(max(r_a[pos], r_b[pos]))
        elif len(answer_keys) == len(ANSWER_KEYS):
            r = float(res.get(tuple(_match(key[k]) for k in answer_keys), r_all))
        else:
            r = r_all
        verdict, why, rel = _compare_row(table, ra, rb, r, k_hazard, key, rs_by_key)
        worst = max(worst, rel)
        if verdict == "beyond":
            beyond.append(f"{_row_name(keys, tup)}: {why}")
        elif verdict == "within":
            n_within += 1
    rows = len(common) + len(only)
    verdict, allowed = _judge(table, rows, len(only), beyond, n_within, share)
    if verdict != "identical" and (n_within or beyond):
        notes.append(f"largest relative difference {worst:.3g}")
    return TableVerdict(f"{name}/{table}", verdict, rows, n_within, beyond, notes, allowed)


def _judge(table: str, rows: int, n_only: int, beyond: list[str], n_within: int,
           share: float) -> tuple[str, int]:
    """(verdict, rows allowed beyond): a table of answers is within the stated error while
    at most ``share`` of its rows differ beyond their tolerance (none in one side only);
    an aggregate while none does."""
    allowed = int(math.floor(share * rows + 1e-9)) if table in ANSWER_TABLES else 0
    if n_only or len(beyond) > allowed:
        return "beyond", allowed
    return ("within" if beyond or n_within else "identical"), allowed


def _match(v: Any) -> Any:
    return float(v) if isinstance(v, (int, float, np.number)) else v


def _compare_row(table: str, a: pd.Series, b: pd.Series, r: float, k_hazard: float,
                 key: dict[str, Any], rs_by_key: dict[tuple, np.ndarray]
                 ) -> tuple[str, str, float]:
    """("identical" | "within" | "beyond", why, largest relative difference) of two rows."""
    state, why, worst = "identical", "", 0.0
    for col in a.index:
        x, y = a[col], b[col]
        if _same(x, y):
            continue
        base = _base(col)
        if any(base.startswith(d) for d in DIAGNOSTIC):
            state = "within" if state == "identical" else state
            continue
        fx, fy = _as_float(x), _as_float(y)
        if fx is None or fy is None:
            text = not (_boolish(x) and _boolish(y)) and not (_intish(x) and _intish(y))
            if text:
                return "beyond", f"{base} {x!r} vs {y!r}", worst
            state = "within" if state == "identical" else state
            continue
        if math.isnan(fx) or math.isnan(fy):
            return "beyond", f"{base} {x} vs {y} (one not computed)", worst
        if _intish(x) and _intish(y) and float(fx).is_integer() and float(fy).is_integer() \
                and base in ("n", "count", "n_censored", "n_not_reached", "n_plateau",
                             "n_motions", "stripes"):
            state = "within" if state == "identical" else state
            continue
        tol = _tolerance(table, base, r, k_hazard, fx, fy, a, b, key, rs_by_key)
        diff = abs(fx - fy)
        rel = diff / abs(fy) if fy != 0 else (math.inf if diff else 0.0)
        worst = max(worst, rel)
        if diff > tol * (1 + 1e-9):
            return ("beyond", f"{base} {fx:.6g} (run) vs {fy:.6g} (gallery): {rel:.2%} off "
                    f"the gallery's, tolerance {_relative(tol, fx, fy):.2%}", worst)
        state = "within" if state == "identical" else state
    return state, why, worst


def _relative(tol: float, x: float, y: float) -> float:
    """A tolerance relative to the larger of two values (as it was applied)."""
    scale = max(abs(x), abs(y))
    return tol / scale if scale > 0 else tol


def _tolerance(table: str, base: str, r: float, k_hazard: float, x: float, y: float,
               a: pd.Series, b: pd.Series, key: dict[str, Any],
               rs_by_key: dict[tuple, np.ndarray]) -> float:
    """Absolute tolerance of one value (module notes)."""
    scale = max(abs(x), abs(y))
    if base.startswith("beta") or base.endswith("Theta_1") or base == "critical_beta":
        return math.sqrt(2.0) * r
    if base == "std" and "count" in a.index:
        # the standard deviation of n values that each move by at most r times the largest,
        # a_max <= mean + std (n - 1)/sqrt(n): |d std| <= r a_max sqrt(n/(n - 1))
        n = max(float(_as_float(a["count"]) or 0.0), float(_as_float(b["count"]) or 0.0))
        if n >= 2:
            top = max(abs(_as_float(s.get("mean [g tan(alpha)]")) or 0.0)
                      + abs(_as_float(s["std [g tan(alpha)]"]) or 0.0) * (n - 1) / math.sqrt(n)
                      for s in (a, b))
            return r * top * math.sqrt(n / (n - 1))
    if table == "risk.csv" and base in RISK_RATES:
        return k_hazard * r * scale
    if table == "linear_fit.csv" and base in ("slope", "intercept"):
        k = tuple(_match(key[c]) for c in ("mode", "limit_state", "tan_alpha [-]"))
        rs = rs_by_key.get(k, np.array([]))
        sc, sd = _fit_weights(rs)
        if not math.isfinite(sc):
            return r * scale
        y_max = max(abs(_as_float(s["intercept [g tan(alpha)]"]) or 0.0)
                    + abs(_as_float(s["slope [1/m]"]) or 0.0) * float(rs.max()) for s in (a, b))
        return r * y_max * (sc if base == "slope" else sd)
    return r * scale


def _same(x: Any, y: Any) -> bool:
    if isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y):
        return True
    try:
        return bool(x == y)
    except (TypeError, ValueError):
        return False


def _as_float(v: Any) -> float | None:
    if isinstance(v, (bool, np.bool_)):
        return None
    if isinstance(v, (int, float, np.number)):
        return float(v)
    return None


def _boolish(v: Any) -> bool:
    return isinstance(v, (bool, np.bool_)) or str(v) in ("True", "False")


def _intish(v: Any) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_))


def motions_lines(run: str | Path, against: str | Path = "results/paper") -> list[str]:
    """Whether the run's motions are the gallery's to the bit, per ensemble (lines), from the
    gallery's ``MANIFEST.json`` (``motion_sha256``) and the run's ensemble files
    (``<run>/motions/<name>-<digest>.nc``); nothing where either is absent (a gallery-like
    copy keeps no motions). Motions that differ in their bits explain answers that do."""
    import json

    from rocking.config.ensemble import EnsembleSpec
    from rocking.motions.ensemble_io import load_ensemble

    run, against = Path(run), Path(against)
    manifest = against / "MANIFEST.json"
    if not manifest.is_file() or (run / "config.yaml").is_file():
        return []
    try:
        digests = json.loads(manifest.read_text()).get("motion_sha256") or {}
    except (OSError, ValueError, AttributeError) as exc:
        raise VerifyInputError(f"{manifest}: not a readable manifest ({exc})") from None
    config, _ = _run_config(run, list(_gallery(against)[0]["studies"]))
    lines = []
    for name, recorded in digests.items():
        if name not in (config.get("ensembles") or {}):
            continue
        path = run / "motions" / f"{name}-{EnsembleSpec.from_config(config, name).digest}.nc"
        if not path.is_file():
            continue
        got = {m.name: m.samples_sha256 for m in load_ensemble(path)}
        differ = sorted(k for k in recorded if got.get(k) != recorded[k])
        if differ:
            lines.append(f"motions/{name}: {len(differ)} of {len(recorded)} motions differ "
                         f"from the gallery's in their bits: {', '.join(differ[:5])}"
                         + (" ..." if len(differ) > 5 else ""))
        else:
            lines.append(f"motions/{name}: identical to the gallery's ({len(recorded)} motions)")
    return lines


def verify_run(run: str | Path, against: str | Path = "results/paper") -> list[TableVerdict]:
    """Compare every table of the gallery ``against`` with the run in ``run``.

    Parameters
    ----------
    run : path
        A run's output folder (``<root>`` holding ``<study>/config.yaml``, its tables and
        spectra store) or a gallery-like copy of one (``config.yaml`` at its root).
    against : path
        The gallery (``results/paper``).

    Returns
    -------
    list of TableVerdict
        One per table of the gallery, study by study.

    Raises
    ------
    VerifyInputError
        ``run`` is no run, a partial run (a table or store missing), or of another
        configuration (the differing keys named).
    """
    run, against = Path(run), Path(against)
    config, rframes, gframes = _load(run, against)
    try:
        tol, share = answer_tolerance(config.get("accuracy", "default"))
    except (TypeError, ValueError) as exc:
        where = run / "config.yaml" if (run / "config.yaml").is_file() else run
        raise VerifyInputError(f"{where}: accuracy {config.get('accuracy')!r}: {exc}") \
            from None
    out = []
    for study, tables in gframes.items():
        gcrit, rcrit = tables.get(CRITICAL), rframes[study].get(CRITICAL)
        if gcrit is not None and rcrit is not None:
            res, r_all = _answer_resolution(rcrit, gcrit, tol)
            rs_by_key = {k: np.unique(g["R [m]"].to_numpy(dtype=float))
                         for k, g in gcrit.groupby(["mode", "limit_state", "tan_alpha [-]"])}
        else:
            res, r_all, rs_by_key = pd.Series(dtype=float), tol, {}
        k_hazard = _hazard_slope(config, study)
        for table, gal in tables.items():
            out.append(_compare_table(study, table, rframes[study][table], gal, tol, res,
                                      r_all, k_hazard, rs_by_key, share))
    return out


VERDICT_TEXT = {"identical": "identical",
                "within": "within the answers' stated error",
                "beyond": "DIFFERS beyond the answers' stated error"}


def format_verdicts(verdicts: list[TableVerdict], show: int = 5) -> list[str]:
    """Lines for the terminal: one per table, then the first ``show`` rows beyond."""
    lines = []
    for v in verdicts:
        extra = f", {v.n_within} within" if v.n_within else ""
        head = f"{v.table}: {VERDICT_TEXT[v.verdict]} ({v.rows} rows{extra}"
        if v.beyond:
            head += f", {len(v.beyond)} beyond"
            if v.verdict == "within":
                head += f" of {v.allowed} the stated error allows"
        lines.append(head + ")")
        lines += [f"    {n}" for n in v.notes]
        lines += [f"    {row}" for row in v.beyond[:show]]
        if len(v.beyond) > show:
            lines.append(f"    ... and {len(v.beyond) - show} more rows")
    return lines
