"""Passivity indices ν (input feedforward) and ρ (output feedback): pinned cases, independent checks."""

from __future__ import annotations

import contextlib
import io
import json
import math
from fractions import Fraction

import control
import numpy as np
import pytest
from flint import fmpq, fmpq_poly

from seapass.analysis.indices import passivity_indices
from seapass.analysis.passivity import is_passive
from seapass.cli import main
from seapass.exact import poly as ep
from seapass.exact.halfline import half_line_cells, minimum_on_half_line
from seapass.model.catalog import PAPER_VALUES, REFERENCE_VALUES, design
from seapass.model.expr import S
from seapass.model.sea import SEA
from seapass.model.stiffness import load_impedance

F = Fraction
# the RLC circuit of MathWorks' "Passivity Indices" example, R = 2, L = 1, C = 0.1
CIRCUIT = "(s + 2)*(2*s + 10)/(s**2 + 4*s + 10)"


@pytest.mark.parametrize(
    ("z", "nu", "rho", "reasons"),
    [
        # MATLAB returns rho = -Inf here (zeros at 0 and infinity); the exact value is 0.2
        ("s/(s**2 + 0.2*s + 1)", F(0), F(0.2), ("", "")),  # 0.2: the double, exactly
        (CIRCUIT, F(2), F(2, 7), ("", "")),
        ("(s + 1)/(s + 2)", F(1, 2), F(1), ("", "")),  # rho approached as w -> inf
        ("1/(s + 1)**2", F(-1, 8), None, ("", "relative_degree")),  # min at w = sqrt(3)
        ("(s + 1)/(s - 1)", None, F(-1), ("rhp_pole", "")),
        ("1/s", F(0), F(0), ("", "")),  # a spring: lossless, both indices 0
        ("s + 3", F(3), F(0), ("", "")),  # a mass with a damper: rho = min Re 1/(jw + 3) = 0
    ],
)
def test_pinned_indices(z, nu, rho, reasons):
    ix = passivity_indices(z)
    for index, value, reason in ((ix.input, nu, reasons[0]), (ix.output, rho, reasons[1])):
        assert index.reason == reason
        exact = None if value is None else ep.rational(value)
        if exact is None:
            assert index.value == -math.inf and index.lower is None and index.sign == -1
        else:
            assert index.lower <= exact <= index.upper
            assert index.upper - index.lower <= fmpq(1, 10**15) * max(1, abs(exact))
            assert index.sign == (exact > 0) - (exact < 0)


def test_where_the_index_is_attained():
    ix = passivity_indices("1/(s + 1)**2")
    assert ix.input.omega == pytest.approx(math.sqrt(3), rel=1e-12)
    assert passivity_indices("(s + 1)/(s + 2)").output.omega is None  # at infinity


STABLE = [
    ([2.0, 3.0], [1.0, 3.0, 5.0]),
    ([1.0, 7.0, 2.0], [1.0, 2.0, 9.0]),
    ([0.5, 4.0, 4.0], [1.0, 6.0, 11.0, 6.0]),
    ([3.0, 1.0, 10.0], [1.0, 0.5, 4.0]),  # lightly damped: a dip in Re Z
    ([1.0, -1.0, 2.0], [1.0, 3.0, 2.0]),  # a right half-plane zero: rho = -inf
]


@pytest.mark.parametrize(("num", "den"), STABLE)
def test_against_python_control_lmi(num, den):
    """An independent method (python-control's LMIs, solved by cvxopt) on stable systems."""
    ix = passivity_indices((num, den))
    g = control.tf(num, den)
    assert ix.nu == pytest.approx(control.get_input_ff_index(g), rel=1e-5, abs=1e-6)
    if math.isfinite(ix.rho):
        assert ix.rho == pytest.approx(control.get_output_fb_index(g), rel=1e-5, abs=1e-6)
    else:
        assert ix.output.reason == "rhp_pole"  # a non-minimum-phase Z: 1/Z unstable


def _grid_min(z: complex | np.ndarray) -> float:
    return float(np.min(np.real(z)))


@pytest.mark.parametrize(
    ("key", "gains"),
    [
        ("LP", {"kd": 500.0}),
        ("LP", {"kd": 2000.0}),
        ("APD", {"kd": 1500.0, "bd": 40.0}),
        ("ours", {"kd": 5000.0, "bd": 25.0, "b1": 20.0}),
        ("ctrl/load-PD", {"kd": 500.0, "bd": 25.0}),
    ],
)
def test_sea_indices_against_a_dense_frequency_grid(key, gains):
    """Re Z(jw) and Re 1/Z(jw) on 200k log-spaced frequencies, from the symbolic Z."""
    sea = design(key).sea(PAPER_VALUES, **gains)
    z = load_impedance(sea).xreplace(sea.substitutions())
    num, den = (
        np.array([float(c) for c in p.all_coeffs()])
        for p in map(lambda e: e.as_poly(S), z.as_numer_denom())
    )
    w = np.logspace(-4, 6, 200_001)
    zw = np.polyval(num, 1j * w) / np.polyval(den, 1j * w)
    ix = passivity_indices(sea)
    for index, values in ((ix.input, zw), (ix.output, 1 / zw)):
        grid = _grid_min(values)
        if index.value == -math.inf:
            continue
        # the index is the infimum: never above a sampled value, and close to the smallest
        assert index.value <= grid + 1e-9 * max(1.0, abs(grid))
        assert grid - index.value <= 1e-3 * max(1.0, abs(index.value))


PLANT = {k: REFERENCE_VALUES[k] for k in ("m", "b", "k1")}


@pytest.mark.parametrize("load_side", [True, False])
@pytest.mark.parametrize(
    ("kd", "bd", "b1"), [(100, 0, 20), (1000, 25, 0), (5000, 25, 20), (3000, 300, 300)]
)
def test_sign_of_nu_is_the_passivity_verdict(kd, bd, b1, load_side):
    """nu >= 0 exactly when the impedance is positive real (its poles being admissible)."""
    sea = SEA(D1="k1 + b1*s", **({"CL": "kd + bd*s"} if load_side else {"CA": "kd + bd*s"}),
              values={**PLANT, "kd": kd, "bd": bd, "b1": b1})  # fmt: skip
    ix, verdict = passivity_indices(sea), is_passive(sea)
    assert verdict.reason in ("", "negative_real_part")
    assert (ix.input.sign >= 0) is verdict.passive
    # a passive design: nu is the damping to spare; not passive: |nu| of damping is missing
    assert (ix.nu >= 0) is verdict.passive


def test_half_line_cells_separate_close_roots():
    # (x - 1)(x - 1 - 2**-40): two roots closer than any float grid would resolve
    eps = fmpq(1, 2**40)
    p = fmpq_poly([1 + eps, -(2 + eps), 1])
    signs = [pt.sign(p) for pt in half_line_cells([p])]
    assert signs == [1, 1, 0, -1, 0, 1]
    m = minimum_on_half_line(p, [1])
    assert m.sign == -1 and m.lower <= -(eps**2) / 4 <= m.upper


def test_check_json_has_the_indices():
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(["check", "--Z", CIRCUIT, "--json"])
    doc = json.loads(out.getvalue())
    assert code == 0 and doc["indices"]["nu"] == 2.0
    assert doc["indices"]["output"]["lower"] <= 2 / 7 <= doc["indices"]["output"]["upper"]
    assert doc["indices"]["input"]["strict"] is True
