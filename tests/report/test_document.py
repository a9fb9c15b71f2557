"""Report building blocks: every figure carries PNG and SVG."""

from __future__ import annotations

import pytest

from seapass.plot.style import bare_figures, figure_bytes
from seapass.report.document import FigureData


def _figure():  # type: ignore[no-untyped-def]
    from seapass.plot.style import axes_grid

    with bare_figures():
        return axes_grid(None, 1, 1, figsize=(1, 1))[0, 0]


def test_a_figure_needs_its_svg() -> None:
    # reproduce once wrote 13 PNG but 12 SVG: a figure built from PNG bytes alone
    with pytest.raises(TypeError, match="svg"):
        FigureData("f", "caption", figure_bytes(_figure()))  # type: ignore[call-arg]
    fig = FigureData.of("f", "caption", _figure())
    assert set(fig.files) == {"figures/f.png", "figures/f.svg"}
    assert fig.png.startswith(b"\x89PNG") and b"<svg" in fig.svg[:2000]


def test_svg_bytes_are_checked() -> None:
    png = figure_bytes(_figure())
    with pytest.raises(ValueError, match="not SVG"):
        FigureData("f", "caption", png, b"not an svg")
