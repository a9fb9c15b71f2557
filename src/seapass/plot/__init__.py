"""All figure code: every function takes ``ax=None`` (or ``axes=None``) and returns Axes.

What lives here: :mod:`~seapass.plot.style` (the one style context, bare
figures, byte-stable saving) and one module per topic:
:mod:`~seapass.plot.response`, :mod:`~seapass.plot.region`,
:mod:`~seapass.plot.sim`, :mod:`~seapass.plot.sampled`, :mod:`~seapass.plot.rig`,
:mod:`~seapass.plot.sweep`, :mod:`~seapass.plot.witness`.  Plot functions only
consume result objects; nothing here computes an analysis, sets ``rcParams``
or chooses a backend.

May import: everything in :mod:`seapass.paper` and below.
"""

from .style import bare_figures, figure_bytes, figure_style, save_figure

__all__ = ["bare_figures", "figure_bytes", "figure_style", "save_figure"]
