"""The exact derivation (``model.freebody``, no sympy) against the sympy derivation.

For every catalog design, the 72 standard structures, the cascaded torque/velocity
controller of ``tests/model/test_structures.py`` and the PID-force-loop-in-impedance-loop cascade:

* the generic ``N/D`` (parameters symbolic) equals sympy's ``fraction(cancel(...))`` of
  [`load_impedance`][seapass.model.stiffness.load_impedance] *exactly*, scaling included;
* at values, ``evaluate_system`` equals an independent sympy evaluation, coefficient for
  coefficient, so every verdict, reason, margin and printed ``N/D`` is unchanged;
* factors that cancel only at the given values stay, and are reported as hidden modes
  exactly as before (a pure numeric gcd would hide them).
"""

from __future__ import annotations

import itertools
import re
from fractions import Fraction

import pytest
import sympy as sp
from flint import fmpq, fmpq_poly
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.analysis.impedance import compiled_impedance, evaluate_system, exact_support
from seapass.analysis.impedance import structural_support as sympy_support
from seapass.analysis.passivity import is_passive, positive_real_test
from seapass.errors import DegenerateModelError, SymbolicLimitError
from seapass.files.limits import MAX_MODEL_TERMS
from seapass.model.catalog import CATALOG, REFERENCE_VALUES
from seapass.model.expr import STANDARD_SYMBOLS, S, symbol
from seapass.model.freebody import UNKNOWNS, derive
from seapass.model.sea import SEA, Impedance
from seapass.model.stiffness import derive_stiffness, load_impedance, model_size

D1 = ("k1", "k1 + b1*s")
D2 = ("0", "k2", "b2*s")
CA = ("0", "kd", "kd + bd*s", "kd + ki/s")
CL = ("0", "kd", "kd + bd*s")
STRUCTURES = [
    dict(zip(("D1", "D2", "CA", "CL"), e, strict=True)) for e in itertools.product(D1, D2, CA, CL)
]

CASCADED = {  # a virtual spring Kv around a torque loop around a PI velocity loop
    "D1": "k1 + b1*s",
    "CA": "(Pv*s + Iv)*(Pt*k1 + s)/s",
    "CL": "-(Pv*s + Iv)*Pt*(k1 - Kv)/s",
}
CASCADED_VALUES = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0,
                   "Pv": 40.0, "Iv": 400.0, "Pt": 0.5, "Kv": 300.0}  # fmt: skip

CF = "(kp + ki/s + kdf*s/(1 + s/wf))"  # PID force loop, filtered derivative
PID_IMPEDANCE = {  # on the spring force k1 (x_A - x_L), inside an impedance loop kv + bv s
    "D1": "k1 + b1*s",
    "CA": f"{CF}*k1 + ba*s",
    "CL": f"(1 + {CF})*(kv + bv*s) - {CF}*k1",
}
PID_VALUES = {"m": 0.4, "b": 3.0, "k1": 2500.0, "b1": 2.0, "kp": 2.0, "ki": 20.0,
              "kdf": 0.01, "wf": 300.0, "ba": 5.0, "kv": 1000.0, "bv": 20.0}  # fmt: skip


def _mpoly_to_sympy(p) -> sp.Expr:
    names = p.context().names()
    gens = [S if n == "s" else symbol(n) for n in names]
    out = sp.Integer(0)
    for exps, c in zip(p.monoms(), p.coeffs(), strict=True):
        term = sp.Rational(int(c.p), int(c.q))
        for g, e in zip(gens, exps, strict=True):
            term *= g**e
        out += term
    return out


def _sympy_nd(sea: SEA) -> tuple[sp.Expr, sp.Expr]:
    return sp.fraction(sp.cancel(sp.together(load_impedance(sea))))


def _sympy_at(expr: sp.Expr, values: dict[str, float]) -> fmpq_poly:
    """Independent evaluation: substitute the exact values into a sympy polynomial in s."""
    subs = {symbol(k): sp.Rational(Fraction(v)) for k, v in values.items()}
    e = sp.expand(expr.xreplace(subs))
    if e == 0:
        return fmpq_poly([])
    coeffs = sp.Poly(e, S).all_coeffs()[::-1]
    return fmpq_poly([fmpq(int(sp.Rational(c).p), int(sp.Rational(c).q)) for c in coeffs])


def _cases() -> list[tuple[str, dict[str, str], dict[str, float]]]:
    out = []
    for key, d in CATALOG.items():
        used = SEA(**d.elements()).parameters
        out.append((f"catalog:{key}", d.elements(), {p: REFERENCE_VALUES[p] for p in used}))
    for elements in STRUCTURES:
        used = SEA(**elements).parameters
        out.append(("/".join(elements.values()), elements, {p: REFERENCE_VALUES[p] for p in used}))
    out.append(("cascaded", CASCADED, CASCADED_VALUES))
    return out


CASES = _cases()


@pytest.mark.parametrize(("name", "elements", "values"), CASES, ids=[c[0] for c in CASES])
def test_generic_n_d_are_sympys_exactly(name, elements, values):
    sea = SEA(**elements, values=values)
    num, den, support = compiled_impedance(sea)
    n_sym, d_sym = _sympy_nd(sea)
    assert sp.expand(_mpoly_to_sympy(num) - n_sym) == 0
    assert sp.expand(_mpoly_to_sympy(den) - d_sym) == 0
    assert support == sympy_support(n_sym, d_sym)
    n, d, _support = evaluate_system(sea, None)
    assert n == _sympy_at(n_sym, values) and d == _sympy_at(d_sym, values)


def test_the_pid_force_loop_in_an_impedance_loop_derives_exactly():
    """Over the sympy budget (bounded by 360 terms) yet small: 40 + 15 terms, degree 5 over 5."""
    sea = SEA(**PID_IMPEDANCE, values=dict.fromkeys(PID_VALUES))
    assert model_size(sea)[1] > MAX_MODEL_TERMS
    z = derive(sea).impedance
    assert z.degrees_in_s() == (5, 5)
    assert len(z.num) + len(z.den) == 55
    # the same function as the closed form of model.stiffness, from the sympy elements
    e = {k: v for k, v in sea.elements().items()}
    alpha = e["m"] * S**2 + e["b"] * S
    closed = (e["D1"] * (alpha + e["CA"] + e["CL"]) + e["D2"] * (alpha + e["D1"] + e["CA"])) / (
        S * (alpha + e["D1"] + e["CA"])
    )
    num, den = (_mpoly_to_sympy(p) for p in z.canonical())
    assert sp.cancel(sp.together(closed - num / den)) == 0


def test_the_solution_satisfies_the_three_free_body_equations():
    for elements in [*STRUCTURES[::7], CASCADED, PID_IMPEDANCE]:
        names = set(re.findall(r"[A-Za-z_]\w*", " ".join(elements.values()))) - {"s"}
        sea = SEA(**elements, values={k: None for k in names if k not in STANDARD_SYMBOLS})
        fb = derive(sea)
        # X_L = 1: X_A = motion, F_L = stiffness, F_A from the controller law
        xa, fl = fb.actuator_motion, fb.stiffness
        _newton, _port, control = fb.equations
        one = fl / fl
        fa = -(control["X_A"] * xa + control["X_L"] * one)
        sol = {"X_A": xa, "X_L": one, "F_A": fa, "F_L": fl}
        for eq in fb.equations:
            assert set(eq) <= set(UNKNOWNS)
            total = fl - fl
            for unknown, coeff in eq.items():
                total = total + coeff * sol[unknown]
            assert total.is_zero


def test_matches_the_sympy_stiffness_and_motion():
    for elements in STRUCTURES[::5]:
        sea = SEA(**elements)
        fb, sym = derive(sea), derive_stiffness(sea)
        for mine, theirs in (
            (fb.stiffness, sym.stiffness),
            (fb.actuator_motion, sym.actuator_motion),
        ):
            n, d = (_mpoly_to_sympy(p) for p in mine.canonical())
            assert sp.cancel(n / d - theirs) == 0


# ---------------------------------------------------------------- hidden modes


def _both(sea: SEA):
    """The verdict from the exact path and from an independent sympy evaluation."""
    n_sym, d_sym = _sympy_nd(sea)
    vals = {k: v for k, v in sea.values.items() if v is not None}
    ref = positive_real_test(
        _sympy_at(n_sym, vals), _sympy_at(d_sym, vals), support=sympy_support(n_sym, d_sym)
    )
    return is_passive(sea), ref


def test_a_controller_pole_cancelled_at_the_values_is_a_hidden_unstable_mode():
    # C_L = kd (s - a)/(s - c): an unstable controller pole at s = c, cancelled by its
    # zero only because a = c; a numeric gcd before the test would hide the mode
    sea = SEA(D1="k1", CL="kd*(s - a)/(s - c)", values=dict(m=1, b=10, k1=1000, kd=500, a=2, c=2))
    mine, ref = _both(sea)
    assert mine.reason == ref.reason == "hidden_unstable_mode"
    assert not mine.passive
    n, d, _ = evaluate_system(sea, None)
    assert n.gcd(d).degree() >= 1  # the factor (s - 2) is still in both


def test_a_lossless_mode_cancelled_at_the_values_stays_marginal():
    """b = 0, kd = k1: the actuator mode at ±j sqrt(k1/m) cancels from Z only at these values."""
    sea = SEA(D1="k1", CL="kd", values={"m": 1.0, "b": 0.0, "k1": 100.0, "kd": 100.0})
    mine, ref = _both(sea)
    assert (mine.passive, mine.reason, mine.num, mine.den) == (
        ref.passive,
        ref.reason,
        ref.num,
        ref.den,
    )
    n, d, _ = evaluate_system(sea, None)
    assert n.gcd(d).degree() == 2


def test_a_factor_common_for_every_value_cancels_silently():
    # the shared integrator of C_A and C_L cancels for every value: not a hidden mode
    sea = SEA(
        D1="k1",
        CA="(kd*s + ki)/s",
        CL="(kd*s + ki)/s",
        values=dict(m=1, b=10, k1=1000, kd=500, ki=100),
    )
    mine, ref = _both(sea)
    assert (mine.passive, mine.reason, mine.num, mine.den) == (
        ref.passive,
        ref.reason,
        ref.num,
        ref.den,
    )


@pytest.mark.parametrize(
    ("elements", "message"),
    [
        ({"D1": "k1", "CA": "kd", "CL": "-m*s**2 - b*s - kd"}, "identically zero"),
        ({"D1": "k1", "CA": "-m*s**2 - b*s - k1"}, "no unique solution"),
    ],
)
def test_degenerate_models_fail_as_before(elements, message):
    for derivation in (derive, derive_stiffness):
        with pytest.raises(DegenerateModelError, match=message):
            derivation(SEA(**elements))


def test_raw_impedances_take_the_same_path():
    z = Impedance(expr="(kd*s + 1)/(s**2 + kd*s + 2)", values={"kd": 3.0})
    n_sym, d_sym = sp.fraction(sp.cancel(sp.together(z.expr)))
    n, d, support = evaluate_system(z, None)
    assert n == _sympy_at(n_sym, {"kd": 3.0}) and d == _sympy_at(d_sym, {"kd": 3.0})
    assert support == sympy_support(n_sym, d_sym)


# ---------------------------------------------------------------- random structures and values

_piece = st.sampled_from(
    ["k1", "k1 + b1*s", "kd", "kd + bd*s", "kd + ki/s", "kd/(1 + s/ki)", "bd*s/(1 + s/k2)",
     "(kd*s + ki)/(s + b2)", "0"]
)  # fmt: skip
_value = st.sampled_from([0.5, 1.0, 2.0, 3.0, 10.0, 25.0, 100.0, 1e3, 1e-3, 7.25])


@settings(max_examples=40, deadline=None)
@given(d1=_piece, d2=_piece, ca=_piece, cl=_piece, data=st.data())
def test_random_structures_and_values_agree_with_sympy(d1, d2, ca, cl, data):
    if d1 == "0" and d2 == "0":
        d1 = "k1"
    try:
        sea = SEA(D1=d1, D2=d2, CA=ca, CL=cl)
        _sympy_nd(sea)
    except DegenerateModelError:
        return
    values = {p: data.draw(_value, label=p) for p in sea.parameters}
    sea = SEA(D1=d1, D2=d2, CA=ca, CL=cl, values=values)
    num, den, support = compiled_impedance(sea)
    n_sym, d_sym = _sympy_nd(sea)
    assert sp.expand(_mpoly_to_sympy(num) - n_sym) == 0
    assert sp.expand(_mpoly_to_sympy(den) - d_sym) == 0
    assert exact_support(num, den) == support == sympy_support(n_sym, d_sym)
    n, d, _ = evaluate_system(sea, None)
    if d.is_zero():
        return
    assert n == _sympy_at(n_sym, values) and d == _sympy_at(d_sym, values)
    mine, ref = _both(sea)
    assert (mine.passive, mine.reason, mine.num, mine.den, mine.omega) == (
        ref.passive,
        ref.reason,
        ref.num,
        ref.den,
        ref.omega,
    )


# ---------------------------------------------------------------- size budget of the derivation


@pytest.mark.parametrize(
    "elements",
    [
        {"D1": "k1 + b1*s", "CA": "(s + k1 + k2 + b1 + b2 + kd + bd)**4/(s + k1 + kd + bd + b1)**4",
         "CL": "(kd + bd*s + ki/s)**4/(s + k2 + b2)**3"},
        {"D1": "(k1 + b1*s)**6/(s + k2)**6", "D2": "(b2*s + k2)**6/(s + kd)**5",
         "CA": "(kd + bd*s + ki/s)**6", "CL": "(s + m + b)**6/(s + k1)**6"},
    ],
)  # fmt: skip
def test_models_over_the_exact_budget_are_refused(elements):
    with pytest.raises(SymbolicLimitError, match="model too large for exact derivation"):
        derive(SEA(**elements))


def test_large_models_within_the_budget_are_decided():
    """Degree 25 over 26 with thousands of terms: derived, and decided at values."""
    elements = {
        "D1": "k1",
        "CA": "(s**3 + kd*s**2 + bd*s + ki)**5/(s**2 + k2*s + b2)**5",
        "CL": "(s**3 + kd*s**2 + bd*s + ki)**5/(s**2 + k1*s + b1)**5",
    }
    z = derive(SEA(**elements)).impedance
    assert z.degrees_in_s() == (25, 26) and len(z.num) > 1000
    values = dict(
        m=1.0, b=10.0, k1=1000.0, kd=500.0, bd=25.0, ki=100.0, k2=1000.0, b2=20.0, b1=20.0
    )
    assert is_passive(SEA(**elements, values=values)).reason == "rhp_pole"
