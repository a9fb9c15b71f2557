"""Heat-map aggregates of a sweep dataset over two parameters (streaming, bounded memory)."""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FileFormatError, ParameterError, did_you_mean
from .location import Location, open_location
from .store import iter_batches, schema_columns

__all__ = [
    "HeatmapData",
    "heatmap_data",
]


@dataclass(frozen=True, kw_only=True)
class HeatmapData:
    """Per-cell aggregates of a sweep over two parameters.

    Arrays have shape ``(len(y_centers), len(x_centers))`` (rows: ``y``).
    Cells without designs hold NaN.

    Attributes
    ----------
    x, y : str
        Parameter names.
    x_centers, y_centers : ndarray
        Cell centres (the grid values themselves for a grid sweep).
    passive_fraction : ndarray
        Fraction of the cell's designs that are passive (over all other parameters).
    settling_time : ndarray or None
        Mean settling time (s) of the cell's settled designs.
    settled_fraction : ndarray or None
    count : ndarray of int
    """

    x: str
    y: str
    x_centers: np.ndarray
    y_centers: np.ndarray
    passive_fraction: np.ndarray
    settling_time: np.ndarray | None
    settled_fraction: np.ndarray | None
    count: np.ndarray


def _axis_bins(
    path: Location, name: str, bins: int
) -> tuple[np.ndarray, Callable[[np.ndarray], np.ndarray]]:
    uniq: set[float] = set()
    lo, hi = math.inf, -math.inf
    rows = 0
    for b in iter_batches(path, [name]):
        v = b.column(0).to_numpy(zero_copy_only=False).astype(float)
        rows += v.size
        if v.size:
            lo, hi = min(lo, float(v.min())), max(hi, float(v.max()))
        if len(uniq) <= 400:
            uniq.update(np.unique(v).tolist())
    if not math.isfinite(lo):
        raise FileFormatError(f"{path.url}: no rows")
    if len(uniq) <= 400:
        centers = np.array(sorted(uniq))
        return centers, lambda v: np.searchsorted(centers, v)
    # scattered samples: about 8 designs per cell on average, at most `bins` per axis
    nb = int(min(bins, max(4, math.isqrt(max(rows // 8, 1)))))
    edges = np.linspace(lo, hi, nb + 1)
    centers = 0.5 * (edges[1:] + edges[:-1])
    return centers, lambda v: np.clip(np.searchsorted(edges, v, side="right") - 1, 0, nb - 1)


def heatmap_data(
    path: str | os.PathLike[str] | Location,
    x: str,
    y: str,
    *,
    bins: int = 60,
    storage_options: Mapping[str, Any] | None = None,
) -> HeatmapData:
    """Aggregate a sweep dataset over the parameters ``x`` and ``y`` (streaming, bounded memory).

    ``path`` is a ``.parquet`` or ``.csv`` output or a directory of parts, as a
    path or an fsspec URL.  Grid axes with at most 400 distinct values keep
    their values as cells; other axes are binned into ``bins`` equal cells.
    Other swept parameters are aggregated over.
    """
    where = open_location(path, storage_options)
    if x == y:
        raise ParameterError(f"heat map: x and y must be different parameters, got {x},{y}")
    schema_cols = set(schema_columns(where))
    for name in (x, y):
        if name not in schema_cols:
            params = sorted(
                schema_cols
                - {
                    "index",
                    "passive",
                    "margin",
                    "settling_time",
                    "final_error",
                    "overshoot",
                    "status",
                }
            )
            raise ParameterError(
                f"heat map: {name!r} is not a column of {where.url}{did_you_mean(name, params)}; "
                f"swept parameters: {', '.join(params)}"
            )
    has_metrics = "settling_time" in schema_cols
    xc, xb = _axis_bins(where, x, bins)
    yc, yb = _axis_bins(where, y, bins)
    shape = (yc.size, xc.size)
    count = np.zeros(shape, dtype=np.int64)
    npass = np.zeros(shape, dtype=np.int64)
    nset = np.zeros(shape, dtype=np.int64)
    tsum = np.zeros(shape)
    cols = [x, y, "passive"] + (["settling_time"] if has_metrics else [])
    for b in iter_batches(where, cols):
        xv = b.column(0).to_numpy(zero_copy_only=False).astype(float)
        yv = b.column(1).to_numpy(zero_copy_only=False).astype(float)
        flat = yb(yv) * xc.size + xb(xv)
        count += np.bincount(flat, minlength=count.size).reshape(shape)
        pv = b.column(2).to_numpy(zero_copy_only=False).astype(bool)
        npass += np.bincount(flat, weights=pv, minlength=count.size).astype(np.int64).reshape(shape)
        if has_metrics:
            ts = b.column(3).to_numpy(zero_copy_only=False).astype(float)
            ok = np.isfinite(ts)
            nset += np.bincount(flat[ok], minlength=count.size).reshape(shape)
            tsum += np.bincount(flat[ok], weights=ts[ok], minlength=count.size).reshape(shape)
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(count > 0, npass / count, np.nan)
        st = np.where(nset > 0, tsum / np.maximum(nset, 1), np.nan) if has_metrics else None
        sf = np.where(count > 0, nset / count, np.nan) if has_metrics else None
    return HeatmapData(
        x=x,
        y=y,
        x_centers=xc,
        y_centers=yc,
        passive_fraction=frac,
        settling_time=st,
        settled_fraction=sf,
        count=count,
    )
