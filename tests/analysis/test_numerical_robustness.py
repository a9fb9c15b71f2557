"""Numerical robustness: parameter spans 1e-6..1e8, units, near-boundary policy, symbolic limits."""

from __future__ import annotations

import threading
import time

import mpmath
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from cpu_budget import cpu_budget
from helpers import configs
from seapass.analysis.conditions import exact_passivity_condition
from seapass.analysis.coupled import Environment, coupled_stability
from seapass.analysis.passivity import MARGINAL_RTOL, TOLERANCE_POLICY, is_passive
from seapass.analysis.region import passive_intervals
from seapass.cli import main
from seapass.errors import ExpressionError, SymbolicLimitError
from seapass.files.limits import MAX_S_DEGREE
from seapass.model.budget import symbolic_size, symbolic_time_limit
from seapass.model.expr import S, parse_expression, symbol
from seapass.model.sea import SEA, Impedance
from seapass.model.stiffness import load_impedance

CONFIGS = configs("LP", "LP-damped", "LPD", "APD", "ours", "disjoint-damper")
# dimension N * s^a / m of every parameter (a: 0 springs/gains, 1 dampers, 2 mass, -1 ki)
ORDER = {"m": 2, "b": 1, "b1": 1, "b2": 1, "bd": 1, "k1": 0, "k2": 0, "kd": 0, "ki": -1}
_COND: dict[str, object] = {}


def condition(name: str):
    if name not in _COND:
        _COND[name] = exact_passivity_condition(SEA(**CONFIGS[name])).condition
    return _COND[name]


wide = st.floats(-6, 8).map(lambda e: float(10**e))


def mp_re_z(sea: SEA, w: float) -> mpmath.mpf:
    """Re Z(jw) at 60 digits from the symbolic impedance with exact rational values."""
    z = load_impedance(sea).xreplace(sea.substitutions())
    f = sp.lambdify(S, z, modules="mpmath")
    with mpmath.workdps(60):
        return mpmath.re(f(mpmath.mpc(0, mpmath.mpf(w))))


@settings(max_examples=80, deadline=None)
@given(name=st.sampled_from(sorted(CONFIGS)), data=st.data())
def test_verdict_across_1e_minus6_to_1e8_matches_symbolic_condition(name, data):
    """Exact verdict == exact symbolic condition evaluated in rationals (no tolerance)."""
    sea = SEA(**CONFIGS[name])
    vals = {p: data.draw(wide, label=p) for p in sea.parameters}
    r = is_passive(sea.with_values(**vals))
    subs = {symbol(k): sp.Rational(v) for k, v in vals.items()}
    assert bool(condition(name).xreplace(subs)) is r.passive, (vals, r.detail)


@settings(max_examples=60, deadline=None)
@given(name=st.sampled_from(sorted(CONFIGS)), data=st.data())
def test_witness_is_confirmed_at_60_digits_across_the_span(name, data):
    """A reported witness w has Re Z(jw) < 0 in 60-digit arithmetic from the symbolic Z."""
    sea = SEA(**CONFIGS[name])
    vals = {p: data.draw(wide, label=p) for p in sea.parameters}
    model = sea.with_values(**vals)
    r = is_passive(model)
    if r.reason == "negative_real_part":
        assert mp_re_z(model, r.omega) < 0, (vals, r.omega)
    elif r.passive:
        # spot checks over 20 decades around the model's scales: never negative
        for e in range(-10, 11, 2):
            w = 10.0**e
            assert mp_re_z(model, w) >= -(mpmath.mpf(10) ** -50), (vals, w)


# Regression: two roots of P(x) closer than 2**-40 (near 1e-12) once left no test
# point in the band where P < 0, and is_passive raised ArithmeticError.
_CLOSE_ROOTS = dict(b=1.0, b2=1000.0, k1=1e-4, kd=0.01, m=1e8)


def test_witness_with_two_close_tiny_roots_of_p():
    sea = SEA(**CONFIGS["disjoint-damper"], values=_CLOSE_ROOTS)
    r = is_passive(sea)
    assert not r.passive and r.reason == "negative_real_part"
    assert mp_re_z(sea, r.omega) < 0


UNITS = st.sampled_from([1e-3, 1.0, 1e3, 2.0**-7, 2.0**7, 0.3])


@settings(max_examples=60, deadline=None)
@given(
    name=st.sampled_from(sorted(CONFIGS)),
    data=st.data(),
    force=UNITS,
    length=UNITS,
    time_=UNITS,
)
def test_verdict_and_coupled_stability_invariant_under_force_length_time_units(
    name, data, force, length, time_
):
    """N -> mN, m -> mm, s -> ms: a parameter of dimension N s^a / m scales by L/(F T^a).

    The passivity verdict and reason, and the coupled status with a human
    (scaled the same way), must not change; the coupled poles scale by 1/T.
    """
    sea = SEA(**CONFIGS[name])
    vals = {
        p: data.draw(st.floats(-3, 5).map(lambda e: float(10**e)), label=p) for p in sea.parameters
    }
    scale = {p: length / (force * time_ ** ORDER[p]) for p in vals}
    scaled = {p: v * scale[p] for p, v in vals.items()}
    r1, r2 = is_passive(sea.with_values(**vals)), is_passive(sea.with_values(**scaled))
    assert r1.passive is r2.passive and r1.reason == r2.reason
    env = Environment(mass=2.0, damping=data.draw(st.sampled_from([0.0, 30.0])), stiffness=5e3)
    env2 = Environment(
        mass=env.mass * length / (force * time_**2),
        damping=env.damping * length / (force * time_),
        stiffness=env.stiffness * length / force,
    )
    c1 = coupled_stability(sea.with_values(**vals), env)
    c2 = coupled_stability(sea.with_values(**scaled), env2)
    assert c1.status == c2.status


# ---------------------------------------------------------------- near boundaries


def _damped_lp_boundary() -> tuple[SEA, str, float]:
    sea = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1, b=10, k1=1000, b1=20, kd=None))
    ((_, hi),) = passive_intervals(sea, "kd", 0, 1e4).intervals
    return sea, "kd", hi


def _disjoint_damper_boundary() -> tuple[SEA, str, float]:
    sea = SEA(D1="k1", D2="b2*s", CL="kd", values=dict(m=1, b=10, k1=1000, b2=5, kd=None))
    ((_, hi),) = passive_intervals(sea, "kd", 0, 1e5).intervals
    return sea, "kd", hi


def _raw_boundary() -> tuple[Impedance, str, float]:
    # Re Z(jw) ~ (1 - w^2)^2 + a w^2: passive iff a >= 0, touching zero at w = 1 when a = 0
    return Impedance(expr="(s**2 + a*s + 1)/(s**2 + s + 1)", values={"a": None}), "a", 0.0


@pytest.mark.parametrize("make", [_damped_lp_boundary, _disjoint_damper_boundary, _raw_boundary])
@pytest.mark.parametrize("rel", [1e-13, 1e-11, 1e-6, 1e-3])
def test_near_boundary_policy(make, rel):
    """Within MARGINAL_RTOL of a boundary: exact verdict on each side, flagged marginal;
    farther away: not flagged.  (The margin is about ``rel`` times a constant of order 1.)"""
    system, p, at = make()
    delta = rel * (abs(at) or 1.0)
    inside = _with(system, p, at - delta if at else delta)
    outside = _with(system, p, at + delta if at else -delta)
    r_in, r_out = is_passive(inside), is_passive(outside)
    assert r_in.passive and not r_out.passive
    assert r_out.reason == "negative_real_part" and r_out.omega is not None
    near = rel * 10 < MARGINAL_RTOL
    assert r_in.marginal is near and r_out.marginal is near
    assert r_in.margin > 0 > r_out.margin
    assert "exact" in TOLERANCE_POLICY


def _with(system, p, v):
    if isinstance(system, SEA):
        return system.with_values(**{p: v})
    return Impedance(expr=system.expr, values={p: v})


def test_boundary_itself_is_passive_and_marginal():
    r = is_passive(Impedance(expr="(s**2 + 1)/(s**2 + s + 1)"))
    assert r.passive and r.marginal and r.margin == 0.0


@pytest.mark.parametrize("eps", [1e-15, 1e-12, 1e-9])
def test_tiny_high_frequency_negative_resistance_is_not_passive(eps):
    """1/(s+1) - eps: not passive for every eps > 0 (python-control says passive at 1e-9).

    The margin is -1 (at high frequency Re Z = -eps is *all* of Re Z), so it is
    not flagged marginal although the coefficients are eps away from a passive Z.
    """
    r = is_passive(Impedance(expr="1/(s + 1) - e", values={"e": eps}))
    assert not r.passive and r.reason == "negative_real_part"
    with mpmath.workdps(60):
        z = 1 / (mpmath.mpc(0, r.omega) + 1) - mpmath.mpf(eps)
        assert z.real < 0


# ---------------------------------------------------------------- symbolic limits

ADVERSARIAL = [
    "(s + k1 + k2 + b1 + b2 + kd + bd + m + b)**12",  # ~10^5 monomials if expanded
    "1/(s + k1 + k2 + b1 + b2 + kd + bd + m + b)**12",  # simplify() here used to hang
    "*".join(f"(s + {i})**12" for i in range(1, 9)),  # degree 96
    "1/(" + "*".join(f"(s + k1 + {i})**12" for i in range(1, 5)) + ")",
    "(k1 + b1*s)**12 * (kd + bd*s)**12 / (k2 + b2*s)**12",
]


@pytest.mark.parametrize("text", ADVERSARIAL)
def test_adversarial_expressions_fail_fast_with_symbolic_limit_error(text):
    with cpu_budget(5.0), pytest.raises(SymbolicLimitError, match="too large"):
        parse_expression(text)  # fails fast: within 5 s of CPU time, however busy the machine


@pytest.mark.parametrize("text", ADVERSARIAL[:2])
def test_adversarial_expressions_through_the_cli_are_one_line(capsys, text):
    code = main(["check", "--D1", "k1", "--CA", text, "--set", "m=1", "--set", "b=1"])
    err = capsys.readouterr().err
    assert code == 2 and "too large" in err and err.count("\n") == 1


def test_model_size_budget_before_sympy_solve():
    """Each element within the parser's budget, but the model too large to derive."""
    big = "(s + k1 + kd)**4*(s + bd + b1)**4"  # degree 8 per element
    with pytest.raises(SymbolicLimitError, match="model too large"):
        load_impedance(SEA(D1="k1 + b1*s", CA=big, CL=f"1/({big})"))


def test_sympy_input_is_size_checked_too():
    big = (S + symbol("k1")) ** 30
    with pytest.raises(SymbolicLimitError):
        SEA(D1=big)


def test_valid_but_large_expressions_still_work():
    text = "*".join(f"(s + {i})**4" for i in range(1, 4))  # degree 12, numeric
    z = parse_expression(text)
    assert sp.Poly(z, S).degree() == 12
    assert symbolic_size(z)[0] <= MAX_S_DEGREE
    # division by an expression that is zero only after expansion is still caught
    with pytest.raises(ExpressionError, match="division by zero"):
        parse_expression("1/((s + 1)**2 - s**2 - 2*s - 1)")


def test_time_limit_interrupts_a_runaway_computation():
    with pytest.raises(SymbolicLimitError, match="time budget"):
        with symbolic_time_limit(0.05, what="test"):
            while True:
                pass


def test_time_limit_is_inert_outside_the_main_thread():
    out: list[str] = []

    def work() -> None:
        with symbolic_time_limit(0.01):
            time.sleep(0.05)
        out.append("done")

    th = threading.Thread(target=work)
    th.start()
    th.join()
    assert out == ["done"]


def test_symbolic_condition_has_a_time_budget():
    """The lead's condition derivation runs inside the budget (a no-op when fast)."""
    c = exact_passivity_condition(SEA(D1="k1", CL="kd"))
    assert c.explicit


# structural bound is an upper bound of the real size
_atoms = st.sampled_from(["s", "k1", "kd", "2", "3", "0.5"])


@st.composite
def small_exprs(draw: st.DrawFn, depth: int = 3) -> str:
    if depth == 0:
        return draw(_atoms)
    kind = draw(st.sampled_from(["atom", "add", "mul", "div", "pow"]))
    if kind == "atom":
        return draw(_atoms)
    a, b = draw(small_exprs(depth - 1)), draw(small_exprs(depth - 1))
    if kind == "pow":
        return f"({a})**{draw(st.integers(-3, 3))}"
    return f"({a}){'+' if kind == 'add' else '*' if kind == 'mul' else '/'}({b})"


@settings(max_examples=80, deadline=None)
@given(text=small_exprs())
def test_symbolic_size_is_an_upper_bound(text):
    try:
        expr = parse_expression(text)
    except ExpressionError:
        return  # e.g. division by zero
    deg, terms = symbolic_size(expr)
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    actual_deg = sp.Poly(num, S).degree() + sp.Poly(den, S).degree() if num != 0 else 0
    actual_terms = len(sp.Add.make_args(sp.expand(num))) + len(sp.Add.make_args(sp.expand(den)))
    assert actual_deg <= deg
    assert actual_terms <= terms


@pytest.mark.parametrize("k1", [1e-3, 1.0, 1e3, 1e8])
def test_lp_interior_is_not_marginal(k1):
    """LP with kd = k1/2 is well inside the passive set; only kd = k1 is marginal."""
    vals = {"m": 1.0, "b": 10.0, "k1": k1}
    inside = is_passive(SEA(**CONFIGS["LP"], values={**vals, "kd": k1 / 2}))
    edge = is_passive(SEA(**CONFIGS["LP"], values={**vals, "kd": k1}))
    assert inside.passive and not inside.marginal and inside.margin > 0.1
    assert edge.passive and edge.marginal
