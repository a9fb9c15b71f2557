"""Design-space sweeps: grids or random samples of one configuration, streamed to disk.

What lives here: the sweep specification ([`spec`][seapass.sweep.spec]), the
resumable on-disk store of parts ([`store`][seapass.sweep.store]), the runner that
computes chunks locally or on Dask ([`runner`][seapass.sweep.runner]) and heat-map
aggregates of a finished sweep ([`heatmap`][seapass.sweep.heatmap]).

May import: [`seapass.errors`][seapass.errors], [`seapass.progress`][seapass.progress], ``seapass.version``, [`seapass.files`][seapass.files],
[`seapass.model`][seapass.model], [`seapass.sim`][seapass.sim], [`seapass.batch`][seapass.batch].  Figures of sweeps live in
[`seapass.plot.sweep`][seapass.plot.sweep].
"""

from .heatmap import HeatmapData, heatmap_data
from .location import Location, open_location
from .runner import DesignSweepResult, compute_part, evaluate_chunk, run_design_sweep
from .spec import GridAxis, RangeAxis, SweepSpec, parse_grid, parse_range
from .store import MANIFEST, PartSummary

__all__ = [
    "MANIFEST",
    "DesignSweepResult",
    "GridAxis",
    "HeatmapData",
    "Location",
    "PartSummary",
    "RangeAxis",
    "SweepSpec",
    "compute_part",
    "evaluate_chunk",
    "heatmap_data",
    "open_location",
    "parse_grid",
    "parse_range",
    "run_design_sweep",
]
