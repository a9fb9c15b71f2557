"""Properties of the two-port verdicts: unit scaling, swapping the ports, reciprocity, passive ⇒ stable."""

from __future__ import annotations

import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.model.sea import SEA
from seapass.ports import TwoPort, two_port
from seapass.ports.check import check_two_port, reciprocity

BASE = dict(m=1.0, b=10.0, k1=1000.0)

gains = st.fixed_dictionaries(
    {
        "b1": st.sampled_from([0.0, 2.0, 20.0]),
        "kd": st.sampled_from([100.0, 500.0, 2000.0]),
        "bd": st.sampled_from([1.0, 25.0, 100.0]),
        "kl": st.sampled_from([-500.0, 0.0, 300.0, 1000.0, 3000.0, 8000.0]),
    }
)


def _tp(g: dict[str, float]) -> TwoPort:
    return two_port(SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**BASE, **g}))


def _scaled(tp: TwoPort, a: float, c: float) -> TwoPort:
    """A transformer of ratio ``a`` on port 2 (F2 → a F2, v2 → v2/a) and impedance scaling ``c``."""
    z11, z12, z21, z22 = tp.entries
    ra, rc = sp.Rational(a), sp.Rational(c)
    return TwoPort(
        entries=(rc * z11, rc * ra * z12, rc * ra * z21, rc * ra**2 * z22), values=tp.values
    )


def _summary(tp: TwoPort) -> tuple:
    ch = check_two_port(tp, witness=False)
    return (
        ch.stability.outcome,
        ch.passivity.outcome,
        ch.stability.eta.kind,
        ch.stability.eta.lower,
        ch.stability.eta.upper,
    )


@settings(max_examples=15)
@given(gains, st.sampled_from([0.01, 0.5, 3.0, 1000.0]), st.sampled_from([1e-3, 0.25, 7.0]))
def test_verdicts_and_eta_are_invariant_to_units(g: dict[str, float], a: float, c: float) -> None:
    tp = _tp(g)
    base, scaled = _summary(tp), _summary(_scaled(tp, a, c))
    assert base[:3] == scaled[:3]
    if base[3] is not None:  # η is invariant exactly; its enclosure only up to its width
        assert abs(float(base[3]) - float(scaled[3])) <= 1e-15 * max(1.0, abs(float(base[3])))


@settings(max_examples=15)
@given(gains)
def test_swapping_the_ports_changes_nothing(g: dict[str, float]) -> None:
    tp = _tp(g)
    a, b = _summary(tp), _summary(tp.swapped())
    assert a[:3] == b[:3]
    if a[3] is not None:
        assert a[3] == b[3] and a[4] == b[4]
    h = tp.convert("h")
    assert _summary(h.swapped())[:2] == a[:2]  # h swapped is a g form


@settings(max_examples=20)
@given(gains, st.sampled_from(["z", "y", "h", "g"]))
def test_reciprocal_iff_z12_equals_z21(g: dict[str, float], form: str) -> None:
    tp = _tp(g)
    subs = {sp.Symbol(k, positive=True): sp.Rational(v) for k, v in tp.values.items()}
    z12, z21 = (e.xreplace(subs) for e in tp.entries[1:3])
    expected = sp.cancel(z12 - z21) == 0
    assert expected == (g["kl"] == 0.0)  # load-side feedback breaks reciprocity
    other = tp.convert(form)
    assert reciprocity(other.exact(), form) == expected


@settings(max_examples=20)
@given(gains)
def test_passive_implies_absolutely_stable(g: dict[str, float]) -> None:
    ch = check_two_port(_tp(g), witness=False)
    if ch.passive:
        assert ch.absolutely_stable
    if not ch.absolutely_stable:
        assert not ch.passive
