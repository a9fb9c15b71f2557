"""The SEA as a two-port: the derivation, the forms, the exact matrix, python-control."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from seapass.errors import DegenerateModelError, ExpressionError, ModelError, ParameterError
from seapass.model.catalog import CATALOG, REFERENCE_VALUES
from seapass.model.expr import S, symbol
from seapass.model.sea import SEA
from seapass.model.stiffness import load_impedance
from seapass.ports import Form, TwoPort, two_port
from seapass.ports.forms import convert_entries

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


def _sea(key: str) -> SEA:
    d = CATALOG[key]
    sea = d.sea()
    return sea.with_values(**{k: REFERENCE_VALUES[k] for k in sea.parameters})


@pytest.mark.parametrize("key", sorted(CATALOG))
def test_z11_is_the_one_port_impedance_for_every_catalog_design(key: str) -> None:
    sea = _sea(key)
    tp = two_port(sea)
    assert tp.form is Form.Z
    assert sp.cancel(tp.entries[0] - load_impedance(sea)) == 0
    # and numerically, at the values: the same exact N/D as the one-port test uses
    from seapass.analysis.impedance import exact_rational_function
    from seapass.analysis.portresponse import reduced_impedance

    n, d = reduced_impedance(*exact_rational_function(sea))
    m = tp.exact()
    assert m.num[0][0] * d == n * m.den[0][0]


def _independent_z(d1: sp.Expr, d2: sp.Expr, ca: sp.Expr, cl: sp.Expr) -> sp.Matrix:
    """The impedance matrix from sympy.solve of the free-body equations (written separately)."""
    m, b = symbol("m"), symbol("b")
    xa, fa, fl, f2, xl, th = sp.symbols("xa fa fl f2 xl th")
    eqs = [
        m * S**2 * xa + b * S * xa - fa - d1 * (xl - xa),
        fl - d1 * (xl - xa) - d2 * xl,
        fa - ca * (th - xa) - cl * (th - xl),
        f2 - fa,
    ]
    sol = sp.solve(eqs, [xa, fa, fl, f2], dict=True)[0]
    z = sp.zeros(2, 2)
    for i, f in enumerate((fl, f2)):
        for j, x in enumerate((xl, th)):
            z[i, j] = sp.cancel(sp.diff(sol[f], x) / S)
    return z


@pytest.mark.parametrize(
    ("D1", "D2", "CA", "CL"),
    [
        ("k1", "0", "kd", "0"),
        ("k1 + b1*s", "0", "kd + bd*s", "kd"),
        ("k1", "b2*s", "kd + ki/s", "kd + bd*s"),
    ],
)
def test_derivation_matches_an_independent_solve(D1: str, D2: str, CA: str, CL: str) -> None:
    sea = SEA(D1=D1, D2=D2, CA=CA, CL=CL)
    tp = two_port(sea)
    e = sea.elements()
    z = _independent_z(e["D1"], e["D2"], e["CA"], e["CL"])
    for k, entry in enumerate(tp.entries):
        assert sp.cancel(entry - z[k // 2, k % 2]) == 0


def test_spring_coupling_is_reciprocal_and_load_side_feedback_is_not() -> None:
    assert two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s")).reciprocal_symbolically
    assert not two_port(SEA(D1="k1", CA="kd", CL="kd")).reciprocal_symbolically


def _textbook(z: list[sp.Expr], form: str) -> list[sp.Expr]:
    z11, z12, z21, z22 = z
    det = z11 * z22 - z12 * z21
    return {
        "y": [z22 / det, -z12 / det, -z21 / det, z11 / det],
        "h": [det / z22, z12 / z22, -z21 / z22, 1 / z22],
        "g": [1 / z11, -z12 / z11, z21 / z11, det / z11],
    }[form]


@pytest.mark.parametrize("form", ["y", "h", "g"])
def test_conversions_match_the_textbook_formulas_and_round_trip(form: str) -> None:
    tp = two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kd", values=RIG))
    conv = tp.convert(form)
    for a, b in zip(conv.entries, _textbook(list(tp.entries), form), strict=True):
        assert sp.cancel(a - b) == 0
    back = conv.convert("z")
    for a, b in zip(back.entries, tp.entries, strict=True):
        assert sp.cancel(a - b) == 0
    for other in "yhg":  # between any two forms
        via = conv.convert(other).convert(form)
        assert all(sp.cancel(a - b) == 0 for a, b in zip(via.entries, conv.entries, strict=True))


def test_a_form_that_does_not_exist_is_refused_clearly() -> None:
    s = sp.Symbol("s")
    # a series element: z = [[Z, Z], [Z, Z]] has no admittance matrix
    with pytest.raises(DegenerateModelError, match=r"the y form does not exist.*det Z"):
        convert_entries([1 / s, 1 / s, 1 / s, 1 / s], Form.Z, Form.Y)
    # z22 = 0: no h form
    with pytest.raises(DegenerateModelError, match=r"the h form does not exist.*z22"):
        convert_entries([1 / s, 1, 1, 0], "z", "h")
    tp = TwoPort.from_matrix([["1/s", "1/s"], ["1/s", "1/s"]])
    with pytest.raises(DegenerateModelError, match="y form"):
        tp.convert("y")


def test_from_matrix_parses_safely_and_checks_names() -> None:
    tp = TwoPort.from_matrix(
        [["r + k/s", "k/s"], ["k/s", "k/s"]], form="Z", values={"r": 2, "k": 100}
    )
    assert tp.form is Form.Z and tp.parameters == ("k", "r")
    assert tp.free_parameters == ()
    with pytest.raises(ExpressionError, match="h12: unknown symbol 'kk'"):
        TwoPort.from_matrix([[1, "kk"], [1, 1]], form="h")
    with pytest.raises(ExpressionError, match="function call"):
        TwoPort.from_matrix([["__import__('os')", 1], [1, 1]])
    with pytest.raises(ParameterError, match=r"'kx' is not a parameter.*did you mean 'k'"):
        TwoPort.from_matrix([["k/s", 0], [0, 1]], values={"k": 1, "kx": 2})
    with pytest.raises(ModelError, match="2×2"):
        TwoPort.from_matrix([[1, 2, 3], [4, 5, 6]])
    with pytest.raises(ModelError, match="2×2"):
        TwoPort.from_matrix([[1, 2], [3, 4], [5, 6]])
    with pytest.raises(ParameterError, match="not a two-port form"):
        TwoPort.from_matrix([[1, 0], [0, 1]], form="q")
    with pytest.raises(ParameterError, match="no value for parameter"):
        TwoPort.from_matrix([["k", 0], [0, 1]], values={"k": None}).exact()


def test_numeric_cancellation_is_kept_as_a_hidden_mode() -> None:
    # (s - a)/((s - 1)(s + 1)) cancels only for a = 1; the mode s = 1 is hidden and unstable
    tp = TwoPort.from_matrix([["(s - a)/((s - 1)*(s + 1))", 0], [0, 1]], values={"a": 1})
    m = tp.exact()
    assert m.num[0][0].degree() == 0 and m.den[0][0].degree() == 1
    assert m.hidden.degree() == 1 and m.hidden(1) == 0
    tp2 = tp.with_values(a=2)
    assert tp2.exact().hidden.degree() == 0


def test_swapped_exchanges_the_ports_in_every_form() -> None:
    tp = two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kd", values=RIG))
    sw = tp.swapped()
    assert sw.entries == (tp.entries[3], tp.entries[2], tp.entries[1], tp.entries[0])
    assert sw.ports == tp.ports[::-1]
    h = tp.convert("h")
    assert h.swapped().form is Form.G
    g_direct = sw.convert("g")
    assert all(
        sp.cancel(a - b) == 0 for a, b in zip(h.swapped().entries, g_direct.entries, strict=True)
    )


def test_to_control_is_the_exact_matrix_rounded() -> None:
    tp = two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG))
    sys = tp.to_control()
    assert (sys.noutputs, sys.ninputs) == (2, 2)
    assert sys.input_labels == ["v1", "v2"] and sys.output_labels == ["F1", "F2"]
    w = 3.7
    resp = sys(1j * w)
    m = tp.exact()
    for i in range(2):
        for j in range(2):
            num = [float(c) for c in reversed(m.num[i][j].coeffs())]
            den = [float(c) for c in reversed(m.den[i][j].coeffs())]
            assert resp[i, j] == pytest.approx(
                np.polyval(num, 1j * w) / np.polyval(den, 1j * w), rel=1e-12
            )
    assert tp.convert("h").to_control().output_labels == ["F1", "v2"]


def test_repr_and_html_are_short_and_escaped() -> None:
    tp = two_port(
        SEA(D1="k1", CA="kd", values=dict(m=1, b=10, k1=1000, kd=500)), values={"kd": 400}
    )
    assert repr(tp).startswith("TwoPort(form='z', z11=")
    assert "<script>" not in TwoPort.from_matrix([[1, 0], [0, 1]], name="<script>")._repr_html_()
    assert tp.values["kd"] == 400
    assert tp.to_dict()["form"] == "z"
