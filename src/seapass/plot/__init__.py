"""All figure code: every function takes ``ax=None`` (or ``axes=None``) and returns Axes.

What lives here: [`style`][seapass.plot.style] (the one style context, bare
figures, byte-stable saving) and one module per topic:
[`response`][seapass.plot.response], [`region`][seapass.plot.region],
[`sim`][seapass.plot.sim], [`sampled`][seapass.plot.sampled], [`rig`][seapass.plot.rig],
[`sweep`][seapass.plot.sweep], [`witness`][seapass.plot.witness].  Plot functions only
consume result objects; nothing here computes an analysis, sets ``rcParams``
or chooses a backend.

May import: everything in [`seapass.paper`][seapass.paper] and below.
"""

from .style import bare_figures, figure_bytes, figure_style, save_figure

__all__ = ["bare_figures", "figure_bytes", "figure_style", "save_figure"]
