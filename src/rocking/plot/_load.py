"""Reading the study store and its aggregates for the figures (layouts of docs/design.md)."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.spectra.limit_states import (
    EXCESSIVE_TILT,
    OVERTURNING,
    match_limit_state,
    parse_limit_state,
    severity,
)
from rocking.spectra.modes import MODE_3D
from rocking.store.attrs import decode_attrs

if TYPE_CHECKING:
    import xarray as xr


def open_store(path: str | Path) -> xr.Dataset:
    """Load a zarr store (``spectra.zarr``, ``tilt_map.zarr``) into memory; they are small.

    Limit states are renamed to their canonical spelling (``"tilt:0.5"``, ``"tilt:1/3"``) and a
    tilt map's ``model`` dimension to ``mode``, so figures read stores of either layout.
    """
    import xarray as xr

    path = Path(path)
    if not path.exists():
        raise ValueError(f"store path does not exist: {str(path)!r}")
    with warnings.catch_warnings():
        # Snakemake marks directory outputs with a .snakemake_timestamp file inside them.
        warnings.filterwarnings("ignore", message=".*snakemake_timestamp.*")
        with xr.open_zarr(path, consolidated=False) as ds:
            return canonical(ds.load())


def open_means(path: str | Path) -> xr.Dataset:
    """Load ``mean_spectra.nc`` (``mean``, ``std``, ``median``, ``count`` over motions)."""
    import xarray as xr

    path = Path(path)
    if not path.exists():
        raise ValueError(f"mean spectra path does not exist: {str(path)!r}")
    with xr.open_dataset(path) as ds:
        return canonical(ds.load())


def canonical(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with canonical limit-state labels and ``mode`` as the name of the mode dimension."""
    if "model" in ds.dims and "mode" not in ds.dims:
        ds = ds.rename({"model": "mode"})
    if "limit_state" in ds.coords:
        names = [parse_limit_state(ls).name for ls in labels(ds, "limit_state")]
        ds = ds.assign_coords(limit_state=np.array(names, dtype=object))
    for dim in ("mode", "motion"):
        if dim in ds.coords:
            ds = ds.assign_coords({dim: np.array(labels(ds, dim), dtype=object)})
    return ds


def labels(da: xr.DataArray | xr.Dataset, dim: str) -> list[str]:
    """String values of coordinate ``dim`` (zarr/NetCDF may hand back bytes or objects)."""
    if dim not in da.coords:
        return []
    return [v.decode() if isinstance(v, bytes) else str(v) for v in da[dim].values]


def excessive_tilt(available: list[str]) -> str | None:
    """The store's name of the paper's excessive-tilt limit state (θ > α/3), if computed.

    The exact ``"tilt:1/3"`` wins over a rounded spelling such as ``"tilt:0.3333"``.
    """
    return match_limit_state(EXCESSIVE_TILT, available, missing_ok=True)


def paper_limit_states(available: list[str], missing: list[str],
                       prefix: str = "") -> Iterator[tuple[str, str]]:
    """(title, store name) of the paper's overturning and excessive tilt, those computed."""
    for title, ls in (("overturning", match_limit_state(OVERTURNING, available,
                                                        missing_ok=True)),
                      ("excessive tilt", excessive_tilt(available))):
        if ls is None:
            # a generator, so this note lands between the notes of the panels, as it did inline
            missing.append(f"{prefix}limit state {title} not computed")
            continue
        yield title, ls


def panel_limit_states(available: list[str]) -> list[str]:
    """The limit states a spectrum figure draws as panels, most severe first (at most two).

    Overturning and the paper's excessive tilt θ > α/3 where computed, the study's most
    severe other goals in their place: a study's own goals get panels, and no panel is left
    empty for a goal the study did not ask for.
    """
    order = sorted(available, key=severity, reverse=True)
    chosen = [ls for ls in (match_limit_state(OVERTURNING, available, missing_ok=True),
                            excessive_tilt(available)) if ls is not None]
    chosen += [ls for ls in order if ls not in chosen][:2 - len(chosen)]
    return sorted(chosen, key=severity, reverse=True)


def requested_cells(ds: xr.Dataset) -> xr.DataArray:
    """(mode, limit_state, tan_alpha): True where the study computed the cell.

    The ``requested`` mask where the store or aggregate has one, else the cells with a
    result (a store's critical intensity or "not reached", an aggregate's finite mean).
    """
    if "requested" in ds:
        return ds["requested"].astype(bool)
    done = computed(ds) if "pga_crit" in ds else np.isfinite(ds["mean"])
    other = [d for d in done.dims if d not in ("mode", "limit_state", "tan_alpha")]
    return done.any(other) if other else done


def primary_mode(ds: xr.Dataset) -> str | None:
    """The mode a study's spectrum figures draw: ``"3d"`` where computed, else the first
    computed mode (None when nothing was computed)."""
    cells = requested_cells(ds)
    done = [m for m in labels(ds, "mode") if bool(cells.sel(mode=m).any())]
    return MODE_3D if MODE_3D in done else (done[0] if done else None)


def main_tan_alpha(ds: xr.Dataset, modes: list[str]) -> float | None:
    """The slenderness a one-slenderness figure draws: the one at which every mode of
    ``modes`` has the most computed limit states (the paper's tan α = 0.2, with seven goals,
    in its study); among equals the middle one. None when no tan α has them all."""
    cells = requested_cells(ds)
    modes = [m for m in modes if m in labels(ds, "mode")]
    if not modes:
        return None
    score = cells.sel(mode=modes).sum("limit_state").min("mode")
    tans = ds["tan_alpha"].values.astype(float)
    best = [float(t) for t, s in zip(tans, score.values, strict=True)
            if s > 0 and s == score.values.max()]
    return best[len(best) // 2] if best else None


def has_value(ds: xr.Dataset | xr.DataArray, dim: str, value: float, rtol: float = 1e-6) -> bool:
    """Whether numeric coordinate ``dim`` holds ``value`` (to ``rtol``)."""
    if dim not in ds.coords:
        return False
    return bool(np.any(np.isclose(ds[dim].values.astype(float), value, rtol=rtol, atol=0.0)))


def select_value(ds, dim: str, value: float):
    """``ds`` at the coordinate of ``dim`` equal to ``value`` (float-tolerant)."""
    coord = ds[dim].values.astype(float)
    hits = np.flatnonzero(np.isclose(coord, value, rtol=1e-6, atol=0.0))
    if hits.size == 0:
        raise ValueError(f"{dim}={value!r} is not in the data (available: {coord.tolist()})")
    return ds.isel({dim: int(hits[0])})


def ensemble_label(attrs: dict, default: str) -> tuple[str, bool]:
    """Human label of a study's ensemble and whether it is a stand-in.

    The store's ``ensemble`` attribute may be a plain label, a JSON object or a mapping;
    stand-in flags may sit in it or beside it (``stand_in``). Unknown layouts fall back to
    ``default`` so a figure never fails on a label.
    """
    attrs = decode_attrs(attrs)
    raw = attrs.get("ensemble", default)
    stand_in = attrs.get("stand_in", attrs.get("stand_ins", False))
    if isinstance(raw, dict):
        motions = raw.get("motions") or [{}]
        records = [m for m in motions if m.get("name") is not None
                   and m.get("name") == m.get("source_record")]
        if len(records) > 1:  # a suite: named after itself, not after its first record
            label = f"suite {raw.get('name', default)} ({len(records)} records)"
        else:
            # The store's ensemble record: its first motion is the record, labelled by source.
            label = str(raw.get("label", motions[0].get("label", raw.get("name", default))))
        stand_in = raw.get("stand_in", stand_in)
    elif isinstance(raw, list | tuple):
        label = ", ".join(str(x) for x in raw) or default
    else:
        label = str(raw)
    if isinstance(stand_in, str):  # not JSON (decoded above): a word
        stand_in = stand_in.lower() in {"true", "yes", "1"}
    if isinstance(stand_in, dict | list):
        stand_in = any(bool(v) for v in (stand_in.values() if isinstance(stand_in, dict)
                                          else stand_in))
    return label, bool(stand_in)


def ensemble_title(attrs: dict, default: str = "ensemble") -> str:
    """What a study's figures are drawn from, for their titles: the record (or the suite)
    with its synthetic pairs, and "stand-in" where the record stands in for another
    (``"Loma Prieta 1989 (stand-in: Corralitos RSN 753) + 10 synthetic pairs"``,
    ``"suite mine (4 records)"``)."""
    label, stand_in = ensemble_label(attrs, default)
    raw = decode_attrs(attrs).get("ensemble")
    motions = raw.get("motions") or [] if isinstance(raw, dict) else []
    records = sum(1 for m in motions if m.get("name") is not None
                  and m.get("name") == m.get("source_record"))
    pairs = len(motions) - max(records, 1) if motions else 0
    if pairs > 0:
        label += f" + {pairs} synthetic pair{'s' if pairs > 1 else ''}"
    if stand_in and "stand-in" not in label:
        label += " (stand-in)"
    return label


def mean_curve(agg: xr.Dataset, mode: str, limit_state: str, stat: str = "mean"):
    """``agg[stat]`` over R for one (mode, limit state); None when either is absent or no point
    of the curve was computed (a mode not requested at this tan α is all NaN)."""
    if mode not in labels(agg, "mode") or limit_state not in labels(agg, "limit_state"):
        return None
    if "requested" in agg and not bool(agg["requested"].sel(mode=mode,
                                                            limit_state=limit_state).any()):
        return None  # no run of the study asked for it
    y = agg[stat].sel(mode=mode, limit_state=limit_state).values.astype(float)
    return y if np.isfinite(y).any() else None


def plateau_means(agg: xr.Dataset, mode: str, limit_state: str) -> np.ndarray | None:
    """Sizes R where the mean of (mode, limit state) includes answers flagged ``plateau``
    (``n_plateau`` > 0 of ``mean_spectra``: there P rises near p without crossing it, so a
    small change of the response could move the answer down); None when none is set."""
    if "n_plateau" not in agg:
        return None
    n = agg["n_plateau"].sel(mode=mode, limit_state=limit_state).values.astype(float)
    flag = np.nan_to_num(n) > 0
    return flag if flag.any() else None


def answer_label(attrs: dict) -> str:
    """What a figure's answers are, from its store's (or mean spectra's) attributes: the
    quantity's label (``"I10"``), or ``"first exceedance (1 % grid)"`` with the scan's step
    (:class:`rocking.spectra.quantity.Quantity`)."""
    from rocking.spectra.quantity import Quantity
    from rocking.study.aggregate import store_quantity

    q = Quantity.from_value(store_quantity(attrs))
    if q.is_quantile:
        return q.label
    step = decode_attrs(dict(attrs)).get("tolerances", {}).get("scan_step")
    return f"first exceedance ({100 * float(step):g} % grid)" if step else q.label


def answer_definition(attrs: dict) -> str:
    """The quantity in one phrase for a legend: ``"I10 = lowest PGA/(g tan α) at which ≥ 10 %
    of the intensities within ±2 % exceed"``, or the first exceedance with its grid
    (:func:`answer_label`)."""
    from rocking.spectra.quantity import Quantity
    from rocking.study.aggregate import store_quantity

    q = Quantity.from_value(store_quantity(attrs))
    if not q.is_quantile:
        return answer_label(attrs)
    return (f"{q.label} = lowest PGA/(g tan α) at which ≥ {100 * q.p:g} % of the intensities "
            f"within ±{100 * q.w:g} % exceed")


def computed(ds: xr.Dataset) -> xr.DataArray:
    """Cells of a spectra store that hold a result: a critical intensity or "not reached".

    A cell left NaN and not flagged ``not_reached`` was not computed (not requested for its
    mode and tan α, or not run yet).
    """
    value = np.isfinite(ds["pga_crit"])
    if "not_reached" in ds:
        value = value | ds["not_reached"].astype(bool)
    return value


def modes_per_tan_alpha(ds: xr.Dataset) -> dict[float, list[str]]:
    """Modes with at least one computed cell, per slenderness tan α of a spectra store."""
    done = computed(ds)
    other = [d for d in done.dims if d not in ("mode", "tan_alpha")]
    anywhere = done.any(other) if other else done
    out = {}
    for t in ds["tan_alpha"].values.astype(float):
        row = anywhere.sel(tan_alpha=t)
        out[float(t)] = [m for m, ok in zip(labels(ds, "mode"), row.values, strict=True) if ok]
    return out


def search_bound(attrs: dict) -> float | None:
    """Highest intensity PGA/(g tan α) the search tried, from a store's ``search_options``."""
    opts = decode_attrs({"search_options": attrs.get("search_options")})["search_options"]
    upper = opts.get("upper") if isinstance(opts, dict) else None
    return float(upper) if isinstance(upper, int | float) else None
