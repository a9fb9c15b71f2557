"""n coupled SEA axes: the derivation against an independent matrix formula, the TOML form, the text matrix."""

from __future__ import annotations

import pytest
import sympy as sp

from seapass.errors import ExpressionError, FileFormatError
from seapass.model.expr import S, symbol
from seapass.model.sea import SEA
from seapass.model.stiffness import load_impedance
from seapass.ports.axes import CoupledAxes, load_axes
from seapass.ports.matrixtext import parse_matrix_text

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0, kc=30.0)


@pytest.mark.parametrize("side", ["actuator", "load"])
def test_derivation_matches_the_matrix_formula(side: str) -> None:
    ca = CoupledAxes(
        axes=({"D1": "k1 + b1*s"}, {"D1": "k1", "m": 2.0}), K=[["kd", "kc"], ["-kc", "kd"]],
        B=[["bd", 0], [0, "bd"]], side=side, values=RIG,
    )  # fmt: skip
    z = ca.n_port().entries
    k1, b1, kd, bd, kc, m, b = (symbol(n) for n in ("k1", "b1", "kd", "bd", "kc", "m", "b"))
    d1 = sp.diag(k1 + b1 * S, k1)
    alpha = sp.diag(m * S**2 + b * S, 2 * S**2 + b * S)
    c = sp.Matrix([[kd + bd * S, kc], [-kc, kd + bd * S]])
    ca_m, cl_m = (c, sp.zeros(2)) if side == "actuator" else (sp.zeros(2), c)
    # Z = [D1 + D2 − D1 (α + D1 + C_A)⁻¹ (D1 − C_L)] / s, written out independently
    expected = (d1 - d1 * (alpha + d1 + ca_m).inv() * (d1 - cl_m)) / S
    for k in range(4):
        assert sp.cancel(z[k] - expected[k // 2, k % 2]) == 0


def test_one_axis_is_the_one_port_impedance() -> None:
    ca = CoupledAxes(
        axes=({"D1": "k1 + b1*s"},),
        K=[["kd"]],
        B=[["bd"]],
        values={k: v for k, v in RIG.items() if k != "kc"},
    )
    assert (
        sp.cancel(ca.n_port().entries[0] - load_impedance(SEA(D1="k1 + b1*s", CA="kd + bd*s"))) == 0
    )


def test_the_example_file_loads(tmp_path) -> None:
    from pathlib import Path

    ca = load_axes(Path(__file__).resolve().parents[2] / "examples" / "axes" / "two-axis.toml")
    assert ca.n == 2 and ca.side == "actuator" and ca.values["kc"] == 100.0
    bad = tmp_path / "bad.toml"
    bad.write_text(
        '[controller]\nside = "middle"\n[[axis]]\nD1 = "k1"\n[parameters]\nm = 1.0\nb = 1.0\nk1 = 1.0\n'
    )
    with pytest.raises(FileFormatError, match="side"):
        load_axes(bad)


def test_matrix_text_is_parsed_safely() -> None:
    assert parse_matrix_text("[[1, s], [0, k/s]]") == [["1", "s"], ["0", "k/s"]]
    with pytest.raises(ExpressionError, match="square"):
        parse_matrix_text("[[1, 2], [3]]")
    with pytest.raises(ExpressionError, match="matrix of rows"):
        parse_matrix_text("(1, 2)")
    with pytest.raises(ExpressionError, match="limit"):
        parse_matrix_text("[" + ",".join(["[1]"] * 7) + "]")
    with pytest.raises(ExpressionError, match="characters"):
        parse_matrix_text("[[" + "1+" * 200_000 + "1]]")
