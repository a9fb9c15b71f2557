"""Design-space sweeps: grids or random samples of one configuration, streamed to disk.

What lives here: the sweep specification (:mod:`~seapass.sweep.spec`), the
resumable on-disk store of parts (:mod:`~seapass.sweep.store`), the runner that
computes chunks locally or on Dask (:mod:`~seapass.sweep.runner`) and heat-map
aggregates of a finished sweep (:mod:`~seapass.sweep.heatmap`).

May import: :mod:`seapass.errors`, :mod:`seapass.files`, :mod:`seapass.model`,
:mod:`seapass.batch` (and what they import).  Figures of sweeps live in
:mod:`seapass.plot.sweep`.
"""

from .heatmap import HeatmapData, heatmap_data
from .runner import DesignSweepResult, evaluate_chunk, run_design_sweep
from .spec import GridAxis, RangeAxis, SweepSpec, parse_grid, parse_range

__all__ = [
    "DesignSweepResult",
    "GridAxis",
    "HeatmapData",
    "RangeAxis",
    "SweepSpec",
    "evaluate_chunk",
    "heatmap_data",
    "parse_grid",
    "parse_range",
    "run_design_sweep",
]
