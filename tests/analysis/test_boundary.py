"""The exact 2-D passive region against an independent method: exact 1-D sets column by column."""

import numpy as np
import pytest

from seapass.analysis.boundary import passive_region
from seapass.analysis.region import passive_intervals
from seapass.errors import ParameterError
from seapass.model.catalog import PAPER_VALUES
from seapass.model.sea import SEA

CASES = [
    # load-side P with a damped spring (the paper's Table I row 3), both orientations
    (dict(D1="k1 + b1*s", CL="kd"), {}, ("b1", (0.0, 60.0)), ("kd", (0.0, 1500.0))),
    (dict(D1="k1 + b1*s", CL="kd"), {}, ("kd", (0.0, 1200.0)), ("b1", (0.0, 100.0))),
    # a damper to ground on the load
    (dict(D1="k1", D2="b2*s", CL="kd"), {}, ("b2", (0.0, 50.0)), ("kd", (0.0, 1500.0))),
    # load-side PD: passive only where bd = 0, so no cell is passive
    (dict(D1="k1", CL="kd + bd*s"), {}, ("kd", (0.0, 2000.0)), ("bd", (0.0, 50.0))),
]


def _exact_width(ivs: list[tuple[float, float]]) -> list[tuple[float, float]]:
    # the region draws areas; an isolated passive point has none
    return [(a, b) for a, b in ivs if b > a]


@pytest.mark.parametrize(("elements", "extra", "x", "y"), CASES)
def test_region_matches_exact_columns(elements, extra, x, y):
    sea = SEA(**elements, values={**PAPER_VALUES, **extra})
    (xn, x_rng), (yn, y_rng) = x, y
    region = passive_region(sea, xn, x_rng, yn, y_rng, points=30)
    assert region.cells and region.cells[0].x_range[0] == x_rng[0]
    assert region.cells[-1].x_range[1] == x_rng[1]
    for cell in region.cells:
        sets = cell.passive_sets(y_rng)
        assert cell.branches.shape[1] == cell.x.size > 0
        assert np.all(np.diff(cell.branches, axis=0) > 0)  # branches never meet inside a cell
        for k in (cell.x.size // 2,):  # a column well inside the cell
            exact = passive_intervals(sea, yn, *y_rng, values={xn: float(cell.x[k])})
            got, want = sets[k], _exact_width(exact.intervals)
            assert len(got) == len(want), (xn, cell.x[k], got, want)
            for (a, b), (c, d) in zip(got, want, strict=True):
                assert a == pytest.approx(c, rel=1e-9, abs=1e-9 * y_rng[1])
                assert b == pytest.approx(d, rel=1e-9, abs=1e-9 * y_rng[1])


def test_boundary_of_the_damped_lp_region():
    sea = SEA(D1="k1 + b1*s", CL="kd", values=PAPER_VALUES)
    region = passive_region(sea, "b1", (0.0, 60.0), "kd", (0.0, 1500.0), points=40)
    # the largest passive kd at b1 = 20 (closed form in test_region: 849.19 N/m)
    cell = next(c for c in region.cells if c.x_range[0] < 20.0 < c.x_range[1])
    top = [max(b for _a, b in ivs) for ivs in cell.passive_sets(region.y_range)]
    assert float(np.interp(20.0, cell.x, top)) == pytest.approx(849.19, abs=0.5)
    assert all(len(c.boundary) == 1 for c in region.cells)
    doc = region.to_dict()
    assert doc["param_x"] == "b1" and doc["curves"] and len(doc["cells"]) == len(region.cells)


def test_errors_name_the_problem():
    sea = SEA(D1="k1 + b1*s", CL="kd", values=PAPER_VALUES)
    with pytest.raises(ParameterError, match="different"):
        passive_region(sea, "kd", (0, 1), "kd", (0, 1))
    with pytest.raises(ParameterError, match="lo < hi"):
        passive_region(sea, "kd", (1, 0), "b1", (0, 1))
    with pytest.raises(ParameterError, match="does not appear"):
        passive_region(sea, "kd", (0, 1), "bd", (0, 1))
    with pytest.raises(ParameterError, match="no value"):
        passive_region(SEA(D1="k1 + b1*s", CL="kd"), "kd", (0, 1), "b1", (0, 1))


def test_region_figures_draw_on_given_axes_with_units():
    from matplotlib.figure import Figure

    from seapass.analysis.region import passive_map
    from seapass.plot.region import plot_passive_map, plot_passive_region

    sea = SEA(D1="k1 + b1*s", CL="kd", values=PAPER_VALUES)
    region = passive_region(sea, "kd", (0.0, 1200.0), "b1", (0.0, 100.0), points=30)
    pmap = passive_map(sea, "kd", [0.0, 600.0, 1200.0], "b1", (0.0, 100.0), y_points=5)
    ax1, ax2 = Figure().subplots(1, 2)
    assert plot_passive_region(region, ax=ax1) is ax1
    assert plot_passive_map(pmap, ax=ax2) is ax2
    for ax in (ax1, ax2):
        assert ax.get_xlabel() == "kd [N/m]" and ax.get_ylabel() == "b1 [N·s/m]"
    # the exact boundary is drawn as curves: a vertical part at kd = 1000 for b1 >= 90
    xs = np.concatenate([line.get_xdata() for line in ax1.get_lines()])
    assert np.isclose(xs, 1000.0).sum() >= 2
