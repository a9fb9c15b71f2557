"""Every standard SEA structure goes through the model path, checked against the ``--Z`` path.

The 72 structures D1 ∈ {k1, k1 + b1 s}, D2 ∈ {0, k2, b2 s},
C_A ∈ {0, kd, kd + bd s, kd + ki/s}, C_L ∈ {0, kd, kd + bd s}, and a cascaded
torque/velocity-loop impedance controller, are each

* derived symbolically (the model path, ``seapass check --D1 ...``),
* rebuilt independently from numbers: the values are substituted into the
  elements first and the closed form of the module docstring of
  `seapass.model.stiffness` is cancelled as a rational function of ``s`` alone,
  then given to ``seapass check --Z`` (the raw-impedance path),
* and evaluated at a few frequencies by solving the free-body equations
  numerically (numpy, complex arithmetic).

All three must agree: the same exact verdict and reason, the same reduced ``N/D``,
and the same ``Z(jω)``.
"""

from __future__ import annotations

import contextlib
import io
import itertools
import json
import re

import numpy as np
import pytest
import sympy as sp

from seapass.cli import main
from seapass.model.catalog import REFERENCE_VALUES
from seapass.model.expr import S
from seapass.model.sea import SEA
from seapass.model.stiffness import (
    MAX_MODEL_DEGREE,
    MAX_MODEL_TERMS,
    derive_stiffness,
    load_impedance,
    model_size,
)

D1 = ("k1", "k1 + b1*s")
D2 = ("0", "k2", "b2*s")
CA = ("0", "kd", "kd + bd*s", "kd + ki/s")
CL = ("0", "kd", "kd + bd*s")
STRUCTURES = list(itertools.product(D1, D2, CA, CL))

# a virtual spring Kv around a torque loop (gain Pt) around a PI velocity loop (Pv, Iv)
CASCADED = {
    "D1": "k1 + b1*s",
    "CA": "(Pv*s + Iv)*(Pt*k1 + s)/s",
    "CL": "-(Pv*s + Iv)*Pt*(k1 - Kv)/s",
}
CASCADED_VALUES = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0,
                   "Pv": 40.0, "Iv": 400.0, "Pt": 0.5, "Kv": 300.0}  # fmt: skip


def _run(argv: list[str]) -> tuple[int, dict]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(argv)
    return code, json.loads(out.getvalue())


def _set(values: dict[str, float]) -> list[str]:
    return [f"--set={k}={v!r}" for k, v in values.items()]


def _impedance_from_numbers(elements: dict[str, str], values: dict[str, float]) -> sp.Expr:
    """``Z = F_L/(s X_L)`` from the closed form with every value substituted first."""
    sea = SEA(**elements, values=values)
    subs = sea.substitutions()
    e = {k: sp.sympify(v).xreplace(subs) for k, v in sea.elements().items()}
    alpha = e["m"] * S**2 + e["b"] * S
    pivot = alpha + e["CA"] + e["D1"]
    stiffness = (e["D1"] * (alpha + e["CA"]) + e["D2"] * pivot + e["D1"] * e["CL"]) / pivot
    return sp.cancel(sp.together(stiffness / S))


def _free_body_z(sea: SEA, omegas: np.ndarray) -> np.ndarray:
    """``Z(jω)`` from a numeric solve of the three free-body equations at each ``s = jω``."""
    subs = sea.substitutions()
    f = {
        k: sp.lambdify(S, sp.sympify(v).xreplace(subs), "numpy") for k, v in sea.elements().items()
    }
    out = []
    for w in omegas:
        s = 1j * w
        d1, d2, ca, cl = (complex(f[k](s)) for k in ("D1", "D2", "CA", "CL"))
        alpha = complex(f["m"](s)) * s**2 + complex(f["b"](s)) * s
        # unknowns (X_A, F_A, F_L) for X_L = 1
        a = np.array([[alpha + d1, -1, 0], [d1, 0, 1], [ca, 1, 0]], dtype=complex)
        rhs = np.array([d1, d1 + d2, -cl], dtype=complex)
        out.append(np.linalg.solve(a, rhs)[2] / s)
    return np.array(out)


def _model_z(sea: SEA, omegas: np.ndarray) -> np.ndarray:
    z = load_impedance(sea).xreplace(sea.substitutions())
    return np.array([complex(z.subs(S, 1j * w)) for w in omegas])


def _check_both_paths(elements: dict[str, str], values: dict[str, float]) -> dict:
    model_argv = [f"--{k}={v}" for k, v in elements.items()]
    code_m, by_model = _run(["check", *model_argv, *_set(values), "--json"])
    z = _impedance_from_numbers(elements, values)
    code_z, by_z = _run(["check", f"--Z={z}", "--json"])
    assert code_m in (0, 1) and code_z in (0, 1)
    assert (by_model["passive"], by_model["reason"]) == (by_z["passive"], by_z["reason"])
    # the same reduced N/D (both normalised by the leading denominator coefficient)
    for key in ("num", "den"):
        a = np.array(by_model[key]) / by_model["den"][0]
        b = np.array(by_z[key]) / by_z["den"][0]
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=0)
    sea = SEA(**elements, values=values)
    omegas = np.array([0.3, 7.0, 45.0, 900.0])
    np.testing.assert_allclose(_model_z(sea, omegas), _free_body_z(sea, omegas), rtol=1e-9)
    return by_model


@pytest.mark.parametrize(("d1", "d2", "ca", "cl"), STRUCTURES)
def test_every_standard_structure_through_the_model_path(d1, d2, ca, cl):
    elements = {"D1": d1, "D2": d2, "CA": ca, "CL": cl}
    sea = SEA(**elements)
    deg, terms = model_size(sea)
    assert deg <= MAX_MODEL_DEGREE and terms <= MAX_MODEL_TERMS
    # the bound is an upper bound of the cancelled stiffness
    num, den = sp.fraction(derive_stiffness(sea).stiffness)
    assert sp.Poly(num, S).degree() + sp.Poly(den, S).degree() <= deg
    values = {p: REFERENCE_VALUES[p] for p in sea.parameters}
    _check_both_paths(elements, values)


def test_the_elimination_solves_the_free_body_equations():
    """The derivation's solution satisfies its three equations (for every structure)."""
    xa, xl, fa, fl = sp.symbols("X_A X_L F_A F_L")
    for d1, d2, ca, cl in [
        *STRUCTURES[::17],
        (CASCADED["D1"], "0", CASCADED["CA"], CASCADED["CL"]),
    ]:
        used = " ".join((d1, d2, ca, cl, "m b"))  # values are strict: only names the model uses
        names = [k for k in CASCADED_VALUES if re.search(rf"\b{k}\b", used)]
        sea = SEA(D1=d1, D2=d2, CA=ca, CL=cl, values=dict.fromkeys(names))
        d = derive_stiffness(sea)
        sol = {xa: d.actuator_motion * xl, fl: d.stiffness * xl}
        sol[fa] = sp.solve(d.equations[2], fa)[0].xreplace(sol)
        for eq in d.equations:
            assert sp.cancel(sp.together((eq.lhs - eq.rhs).xreplace(sol))) == 0


def test_cascaded_impedance_controller_through_the_model_path():
    sea = SEA(**CASCADED, values=dict.fromkeys(CASCADED_VALUES))
    deg, terms = model_size(sea)
    assert deg <= MAX_MODEL_DEGREE and terms <= MAX_MODEL_TERMS
    result = _check_both_paths(CASCADED, CASCADED_VALUES)
    assert len(result["den"]) - 1 >= 3  # a real controller, not a degenerate cancellation


def test_model_size_counts_degrees_after_cancellation():
    # once refused with "up to degree 17 ... limit 16"; its stiffness is 4th over 3rd order
    sea = SEA(D1="k1", D2="b2*s", CA="kd + ki/s", CL="kd")
    assert model_size(sea)[0] == 7
    num, den = sp.fraction(derive_stiffness(sea).stiffness)
    assert (sp.Poly(num, S).degree(), sp.Poly(den, S).degree()) == (4, 3)
