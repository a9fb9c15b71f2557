"""Robust passive regions over two gains (issue 26, item 3: 2-D robust regions)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from seapass.analysis.passivity import is_passive
from seapass.analysis.region import passive_intervals
from seapass.cli import main
from seapass.errors import ParameterError
from seapass.model.sea import SEA
from seapass.plot.style import bare_figures
from seapass.robust.region import RobustPassiveMap, robust_passive_map

# load-side PD on a damped spring: kd's passive set moves with bd and with k1
DESIGN = SEA(D1="k1 + b1*s", CL="kd + bd*s", values=dict(m=1.0, b=10.0, b1=5.0))
BOX = {"k1": (800.0, 1200.0)}
ARGV = ["region", "bd", "kd", "--D1", "k1 + b1*s", "--CL", "kd + bd*s", "--set", "m=1",
        "--set", "b=10", "--set", "b1=5", "--range", "bd=0:4", "--range", "kd=0:2000"]  # fmt: skip


def _intersection(bd: float, k1s: np.ndarray) -> list[tuple[float, float]]:
    """kd's passive set intersected over plants, each by the exact per-plant test."""
    out = [(0.0, 2000.0)]
    for k1 in k1s:
        ivs = passive_intervals(DESIGN, "kd", 0, 2000, values={"k1": float(k1), "bd": bd}).intervals
        out = [(max(a, c), min(b, d)) for a, b in out for c, d in ivs if max(a, c) <= min(b, d)]
    return out


@pytest.fixture(scope="module")
def exact_map() -> RobustPassiveMap:
    return robust_passive_map(DESIGN, "bd", [0.0, 2.0, 4.0], "kd", (0, 2000), box=BOX)


def test_one_uncertain_parameter_gives_each_column_exactly(exact_map: RobustPassiveMap) -> None:
    assert str(exact_map.method) == "exact"
    assert exact_map.nominal_values == {"k1": 1000.0}
    for bd, robust, nominal in zip(
        exact_map.x, exact_map.intervals, exact_map.nominal, strict=True
    ):
        ((a, b),) = robust
        # independent: intersect the exact passive sets of plants spread over the box
        ((ra, rb),) = _intersection(float(bd), np.linspace(800, 1200, 9))
        assert a == ra and b <= rb and b == pytest.approx(rb, rel=1e-9)
        # inward: the printed end is passive at the box's worst plant (here the softest spring)
        assert is_passive(DESIGN, values={"k1": 800.0, "bd": float(bd), "kd": b}).passive
        beyond = b * (1 + 1e-9)
        assert not is_passive(DESIGN, values={"k1": 800.0, "bd": float(bd), "kd": beyond}).passive
        # the nominal column is the centre plant's exact set, wider than the robust one
        ref = passive_intervals(DESIGN, "kd", 0, 2000, values={"k1": 1000.0, "bd": float(bd)})
        assert nominal == ref.intervals and nominal[0][1] > b
    assert 0.5 < exact_map.robust_share() < 1.0


def test_several_uncertain_parameters_give_certified_inner_inside_outer() -> None:
    box = {"k1": (800.0, 1200.0), "m": (0.9, 1.1)}
    sea = DESIGN.with_values(m=None)
    r = robust_passive_map(sea, "bd", [0.0, 4.0], "kd", (0, 2000), box=box, rtol=1e-3)
    assert str(r.method) == "certified"
    rng = np.random.default_rng(7)
    for bd, inner, outer in zip(r.x, r.intervals, r.outer, strict=True):
        ((a, b),) = inner
        ((oa, ob),) = outer
        assert oa <= a <= b <= ob
        # 40 random plants of the box: every kd of the inner set is passive for each
        for k1, m in zip(rng.uniform(800, 1200, 40), rng.uniform(0.9, 1.1, 40), strict=True):
            for kd in (a, (a + b) / 2, b):
                vals = {"k1": float(k1), "m": float(m), "bd": float(bd), "kd": kd}
                assert is_passive(sea, values=vals).passive, vals
        # just above the outer set some corner plant of the box is not passive
        corners = [{"k1": k1, "m": m} for k1 in (800.0, 1200.0) for m in (0.9, 1.1)]
        assert any(
            not is_passive(sea, values={**c, "bd": float(bd), "kd": ob * 1.001}).passive
            for c in corners
        )


def test_the_nominal_plant_can_be_given_and_must_lie_in_the_box() -> None:
    r = robust_passive_map(DESIGN, "bd", [2.0], "kd", (0, 2000), box=BOX, nominal={"k1": 1200.0})
    ref = passive_intervals(DESIGN, "kd", 0, 2000, values={"k1": 1200.0, "bd": 2.0})
    assert r.nominal == (ref.intervals,)
    with pytest.raises(ParameterError, match=r"nominal\['k1'\] = 1300 lies outside"):
        robust_passive_map(DESIGN, "bd", [2.0], "kd", (0, 2000), box=BOX, nominal={"k1": 1300.0})
    with pytest.raises(ParameterError, match="not an uncertain parameter"):
        robust_passive_map(DESIGN, "bd", [2.0], "kd", (0, 2000), box=BOX, nominal={"m": 1.0})


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"param_x": "k1"}, "column parameter; it cannot also be uncertain"),
        ({"x_values": []}, "x_values must be a 1-D sequence"),
        ({"x_values": [[1.0]]}, "x_values must be a 1-D sequence"),
        ({"x_values": [float("nan")]}, "x_values must be finite"),
        ({"param_x": "kd"}, "must be different parameters"),
    ],
)
def test_bad_arguments_name_the_argument(kwargs: dict, match: str) -> None:
    args = {"param_x": "bd", "x_values": [1.0], **kwargs}
    with pytest.raises(ParameterError, match=match):
        robust_passive_map(DESIGN, args["param_x"], args["x_values"], "kd", (0, 2000), box=BOX)


def test_the_plot_draws_the_columns_within_the_range(exact_map: RobustPassiveMap) -> None:
    with bare_figures():
        ax = exact_map.plot()
        assert ax.get_xlim() == (0.0, 4.0)
        assert ax.get_ylim() == (0.0, 2000.0)
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert labels[0] == "passive for every plant (k1 in [800, 1200])"
        assert labels[1] == "passive for the nominal plant (k1=1000)"
        # one nominal and one robust bar per column, the robust bar ending at the robust end
        bars = [p for p in ax.patches if p.get_height() > 0 and p.get_width() < 4.0]
        tops = sorted(round(p.get_y() + p.get_height(), 6) for p in bars)
        expected = sorted(round(ivs[0][1], 6) for ivs in (*exact_map.intervals, *exact_map.nominal))
        assert tops == expected


def test_repr_and_dict(exact_map: RobustPassiveMap) -> None:
    d = exact_map.to_dict()
    assert d["robust"] is True and d["box"] == {"k1": [800.0, 1200.0]}
    assert d["intervals"][0] == [list(exact_map.intervals[0][0])]
    assert d["nominal_values"] == {"k1": 1000.0} and d["method"] == "exact"
    json.dumps(d, allow_nan=False)
    assert "RobustPassiveMap(" in repr(exact_map) and "robust_share=" in repr(exact_map)
    assert "Robust passive region" in exact_map._repr_html_()


def test_cli_region_with_a_box_prints_robust_and_nominal_columns(
    capsys: pytest.CaptureFixture[str], tmp_path
) -> None:
    figure = tmp_path / "robust.png"
    argv = [*ARGV, "--uncertain", "k1=800:1200", "--points", "2", "--plot", str(figure)]
    assert main(argv) == 0
    out = capsys.readouterr().out.splitlines()
    assert (
        out[0] == "robust: passive for every plant with k1 in [800, 1200] (exact); nominal: k1=1000"
    )
    assert out[1].startswith("bd = 0: robust kd in [0, 744.73") and "; nominal [0, 924.93" in out[1]
    assert len(out) == 3 and figure.stat().st_size > 0
    assert main([*ARGV, "--uncertain", "k1=800:1200", "--points", "2", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["x"] == [0.0, 4.0] and d["robust"] is True and len(d["intervals"]) == 2


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--uncertain", "bd=0:1"], "--uncertain bd: bd is already the parameter of `region X bd`"),
        (["--uncertain", "k1=1200:800"], "--uncertain k1"),
        (["--uncertain", "zz=1:2"], "zz"),
        (["--uncertain", "m=0.9:1.1"], "--set m: m is a free parameter here"),
        (["--uncertain", "k1=800:1200", "--budget", "0"], "--budget must be a positive"),
    ],
)
def test_cli_bad_boxes_give_one_error_line(
    capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    assert main([*ARGV, "--points", "2", *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: ") and message in err[0]


def test_cli_region_uses_the_design_files_uncertainty_table(
    capsys: pytest.CaptureFixture[str], tmp_path
) -> None:
    design = tmp_path / "boxed.toml"
    design.write_text(
        'name = "boxed"\n[model]\nD1 = "k1 + b1*s"\nCL = "kd + bd*s"\n'
        "[parameters]\nm = 1.0\nb = 10.0\nb1 = 5.0\nk1 = 1000.0\nkd = 100.0\nbd = 1.0\n"
        "[uncertainty]\nk1 = [800.0, 1200.0]\n"
    )
    argv = ["region", "bd", "kd", str(design), "--range", "bd=0:4", "--range", "kd=0:2000"]
    assert main([*argv, "--points", "2", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["robust"] is True and d["box"] == {"k1": [800.0, 1200.0]}
    assert d["intervals"][0][0][1] == pytest.approx(744.733, rel=1e-5)
    # --set fixes the name: the plain exact region runs
    assert main([*argv, "--points", "2", "--set", "k1=1000", "--json"]) == 0
    assert "robust" not in json.loads(capsys.readouterr().out)
