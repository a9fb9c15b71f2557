"""Controllers given in z (issue 22, item 3): parsing, the model, the design file, run as is.

Cross-checks: a z-controller written as the exact Tustin (or ZOH) discretization of a
continuous design has the same transfer functions, sampled verdict and certified bound as
that design discretized by seapass with the same method; the coefficients also agree with
scipy's ``cont2discrete`` (an independent discretization).
"""

from __future__ import annotations

import pickle
import re
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.signal import cont2discrete

from seapass.analysis.passivity import is_passive
from seapass.errors import (
    ExpressionError,
    FileFormatError,
    ModelError,
    ParameterError,
    UnrealizableError,
)
from seapass.files.limits import MAX_Z_ORDER
from seapass.model.design_file import parse_design
from seapass.model.loop import SampledLoop
from seapass.model.resolve import resolve_design
from seapass.model.sea import SEA
from seapass.model.zcontroller import ZController
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.controllers import DiscreteController
from seapass.sampled.passivity import sampled_passivity

F = Fraction
PLANT = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0}
LOOP = SampledLoop(rate=500.0)


def z_pd(**kw: object) -> ZController:
    """``kd + bd (1 − z⁻¹)/T`` at 500 Hz: seapass's backward-difference PD, written in z."""
    return ZController(CA="kd + bd*500*(1 - z^-1)", rate=500.0, **kw)  # type: ignore[arg-type]


def test_coefficients_are_exact_and_ascending_in_z_inverse() -> None:
    zc = ZController(CA="(b0 + b1*z^-1)/(1 + a1*z^-1)", CL="0.5", rate=1000.0)
    assert zc.names == ("a1", "b0", "b1")
    (na, da), (nl, dl) = zc.coefficients({"b0": 2, "b1": 0.25, "a1": -0.5})
    assert (na, da) == ((F(2), F(1, 4)), (F(1), F(-1, 2)))
    assert (nl, dl) == ((F(1, 2),), (F(1),))
    # the same controller written in z (positive powers) is the same difference equation
    same = ZController(CA="(2*z + 0.25)/(z - 0.5)", CL="1/2", rate=1000.0)
    assert same.coefficients({}) == zc.coefficients({"b0": 2, "b1": 0.25, "a1": -0.5})
    # a leading denominator coefficient other than 1 is normalized
    assert ZController(CA="4/(2 - z^-1)", rate=10.0).coefficients({})[0] == (
        (F(2),),
        (F(1), F(-1, 2)),
    )


@pytest.mark.parametrize(
    ("text", "error", "words"),
    [
        ("kd*z", UnrealizableError, "not causal"),
        ("z^2/(z - 1)", UnrealizableError, "not causal"),
        ("kd*s", ExpressionError, "uses s"),
        ("exp(-kd*s)", ExpressionError, "uses s"),
        ("__import__('os')", ExpressionError, "not allowed"),
        ("abs(z)", ExpressionError, "not allowed"),
        ("kd/(z - z)", ExpressionError, "division by zero"),
        ("1/z^13", ExpressionError, "exceeds the limit"),
    ],
)
def test_bad_expressions_are_refused(text: str, error: type, words: str) -> None:
    with pytest.raises(error, match=words):
        ZController(CA=text, rate=100.0).coefficients({"kd": 1.0})


def test_order_is_bounded() -> None:
    text = "1/((z - 1/2)^12*(z + 1/2)^12*(z - 1/4))"  # 25 poles
    with pytest.raises(ModelError, match=f"limit of {MAX_Z_ORDER}"):
        ZController(CA=text, rate=100.0).coefficients({})
    ok = "1/((z - 1/2)^12*(z + 1/2)^12)"
    assert len(ZController(CA=ok, rate=100.0).coefficients({})[0][1]) == MAX_Z_ORDER + 1


@pytest.mark.parametrize("rate", [0.5, 2e6, float("nan"), float("inf")])
def test_rate_out_of_range(rate: float) -> None:
    with pytest.raises(ParameterError, match="rate"):
        ZController(CA="1", rate=rate)


def test_both_zero_and_table_spellings() -> None:
    with pytest.raises(ParameterError, match="needs CA_z or CL_z"):
        ZController(rate=100.0)
    assert ZController.from_table({"period": 0.002, "CA": "1"}).rate == 500.0
    with pytest.raises(ParameterError, match="not both"):
        ZController.from_table({"period": 0.002, "rate": 500.0, "CA": "1"})


def test_sea_with_a_controller_in_z() -> None:
    sea = SEA(D1="k1 + b1*s", values={**PLANT, "kd": 2000, "bd": 25}, discrete=z_pd())
    assert sea.parameters == ("b", "b1", "bd", "k1", "kd", "m")
    assert sea.gains == ("bd", "kd")
    assert sea.with_values(kd=10).discrete == sea.discrete
    assert pickle.loads(pickle.dumps(sea)) == sea
    assert "discrete" in repr(sea)
    with pytest.raises(ParameterError, match="not both"):
        SEA(D1="k1", CA="kd", values={"kd": 1, "bd": 1}, discrete=z_pd())
    with pytest.raises(ExpressionError, match="unknown symbol 'kq'"):
        SEA(D1="k1", values={"bd": 1.0}, discrete=ZController(CA="kq*z^-1", rate=10.0))
    with pytest.raises(UnrealizableError, match="not causal"):
        SEA(D1="k1", values={"kd": 1.0}, discrete=ZController(CA="kd*z", rate=10.0))


def test_continuous_analyses_refuse_and_sampled_ones_run_it_as_is() -> None:
    sea = SEA(D1="k1 + b1*s", values={**PLANT, "kd": 2000, "bd": 25}, discrete=z_pd())
    with pytest.raises(ModelError, match=r"needs a continuous controller.*500 Hz"):
        is_passive(sea)
    with pytest.raises(ModelError, match="needs a continuous controller"):
        DiscreteController.from_sea(sea, 0.002)
    ctrl = DiscreteController.for_loop(sea, LOOP.replace(method="zoh", velocity_filter=50.0))
    ka, kl = ctrl.transfer_functions()
    assert ka.num == (F(2000 + 12500), F(-12500)) and ka.den == (F(1),) and kl.is_zero
    assert ctrl.order == 1
    with pytest.raises(ParameterError, match="runs at 500 Hz but the sampled loop at 1000 Hz"):
        DiscreteController.for_loop(sea, SampledLoop(rate=1000.0))


def test_tustin_pi_written_in_z_equals_seapass_discretization() -> None:
    """``kp + ki/s`` by Tustin is ``kp + ki T/2 (1 + z⁻¹)/(1 − z⁻¹)``: same controller, verdict."""
    vals = {**PLANT, "kd": 300.0, "ki": 40.0}
    cont = SEA(D1="k1 + b1*s", CA="kd + ki/s", values=vals)
    # T/2 = 1/1000 written as a fraction: a decimal literal is its exact binary double
    zc = ZController(CA="kd + ki/1000*(1 + z^-1)/(1 - z^-1)", rate=500.0)
    disc = SEA(D1="k1 + b1*s", values=vals, discrete=zc)
    py = DiscreteController.for_loop(cont, LOOP)
    mine = DiscreteController.for_loop(disc, LOOP)
    assert py.transfer_functions() == mine.transfer_functions()
    # scipy's bilinear transform (independent, float) gives the same coefficients
    b, a, _dt = cont2discrete(([300.0, 40.0], [1.0, 0.0]), 0.002, method="bilinear")
    ka = mine.transfer_functions()[0]
    assert np.allclose(np.ravel(b) / a[0], [float(c) for c in ka.num], rtol=1e-12)
    assert np.allclose(np.asarray(a) / a[0], [float(c) for c in ka.den], rtol=1e-12)
    a1 = sampled_passivity(cont, loop=LOOP, continuous_gate=False)
    a2 = sampled_passivity(disc, loop=LOOP)
    assert (a1.outcome, a1.reason) == (a2.outcome, a2.reason)


def test_zoh_integrator_written_in_z_equals_seapass_zoh() -> None:
    vals = {**PLANT, "kd": 300.0, "ki": 40.0}
    cont = SEA(D1="k1 + b1*s", CA="kd + ki/s", values=vals)
    zc = ZController(CA="kd + ki/500*z^-1/(1 - z^-1)", rate=500.0)
    loop = LOOP.replace(method="zoh")
    disc = SEA(D1="k1 + b1*s", values=vals, discrete=zc)
    got = DiscreteController.for_loop(disc, loop).transfer_functions()[0]
    want = DiscreteController.for_loop(cont, loop).transfer_functions()[0]  # expm in floats
    assert got.den == want.den and np.allclose(
        [float(c) for c in got.num], [float(c) for c in want.num], rtol=1e-13, atol=0
    )
    assert (
        sampled_passivity(disc, loop=loop).outcome
        == sampled_passivity(cont, loop=loop, continuous_gate=False).outcome
    )
    b, a, _dt = cont2discrete(([40.0], [1.0, 0.0]), 0.002, method="zoh")
    assert np.allclose(np.ravel(b), [0.0, 0.08]) and np.allclose(a, [1.0, -1.0])


@pytest.mark.parametrize("delay", [0, 1])
def test_bound_of_a_gain_in_z_equals_the_continuous_designs(delay: int) -> None:
    """The certified bound of kd: the family built from the z-expression equals seapass's own."""
    loop = LOOP.replace(delay=delay)
    vals = {**PLANT, "bd": 25.0, "kd": None}
    cont = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=vals)
    disc = SEA(D1="k1 + b1*s", values=vals, discrete=z_pd())
    a = sampled_passive_bound(cont, "kd", loop=loop, lo=0.0, hi=1e5, rtol=1e-6)
    b = sampled_passive_bound(disc, "kd", loop=loop, lo=0.0, hi=1e5, rtol=1e-6)
    assert a.intervals == b.intervals and a.intervals
    assert [e.kind for e in a.edges] == [e.kind for e in b.edges]
    # the bound is honest: just inside is passive, just outside is not (decided alone)
    hi = b.intervals[0][1]
    assert sampled_passivity(disc.with_values(kd=hi), loop=loop).passive
    assert not sampled_passivity(disc.with_values(kd=hi * 1.001), loop=loop).passive


DESIGN = """
name = "zpd"
[model]
D1 = "k1 + b1*s"
[parameters]
m = 1.02
b = 10.0
k1 = 1005.0
b1 = 30.0
kd = 2000.0
bd = 25.0
[discrete]
rate = 500.0
CA = "kd + bd*500*(1 - z^-1)"
"""


def parse(text: str) -> object:
    import tomllib

    return parse_design(tomllib.loads(text))


def test_design_file_discrete_table() -> None:
    d = parse(DESIGN)
    assert d.discrete == z_pd() and d.loop == SampledLoop(rate=500.0)  # type: ignore[attr-defined]
    assert d.sea().discrete == z_pd() and d.gains == ("bd", "kd")  # type: ignore[attr-defined]
    assert d.to_dict()["discrete"] == {"rate": 500.0, "CA": z_pd().CA, "CL": "0"}  # type: ignore[attr-defined]
    # a [control] table without a rate takes the controller's
    with_delay = parse(DESIGN + "[control]\ndelay = 1\n")
    assert with_delay.loop == SampledLoop(rate=500.0, delay=1)  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ("[control]\nrate = 1000.0\n", "discrete.rate: the controller in z runs at 500 Hz but "
         "the sampled loop at 1000 Hz"),
        ('[controller]\nkind = "force"\nforce = "kd"\n', "either [discrete] or [controller]"),
        ('CL = "kd*z"\n', "discrete.CL: not causal"),
        ('CL = "kd*s"\n', "discrete.CL: 'kd*s' uses s"),
        ("period = 0.002\n", "discrete.rate: give the controller's rate"),
        ('CL = "kq"\n', "discrete.CL: no value for kq; give it, add kq to"),
        ("[control]\ndelay_time = 0.004\n", "control.delay_time: the controllers are given "
         "in z; state the loop latency in samples as [control] delay"),
    ],
)  # fmt: skip
def test_design_file_bad_discrete(extra: str, words: str) -> None:
    with pytest.raises(FileFormatError, match=re.escape(words)):
        parse(DESIGN + extra)


def test_design_file_discrete_with_model_ca() -> None:
    text = DESIGN.replace('D1 = "k1 + b1*s"', 'D1 = "k1 + b1*s"\nCA = "kd"')
    with pytest.raises(FileFormatError, match=r"either \[discrete\] or model.CA"):
        parse(text)


def test_resolve_design_rules() -> None:
    d = parse(DESIGN)
    r = resolve_design(d, loop={"delay": 1})  # type: ignore[arg-type]
    assert r.loop == SampledLoop(rate=500.0, delay=1) and r.sea.discrete == z_pd()
    # the caller's continuous controller replaces the file's z-controller
    r2 = resolve_design(d, elements={"CA": "kd + bd*s"})  # type: ignore[arg-type]
    assert r2.sea.discrete is None and r2.sea.parameters == ("b", "b1", "bd", "k1", "kd", "m")
    # and a z-controller given by the caller replaces the file's CA/CL
    z = ZController(CL="kd", rate=500.0)
    r3 = resolve_design(d, discrete=z)  # type: ignore[arg-type]
    assert r3.sea.discrete == z and "bd" not in r3.sea.parameters
    with pytest.raises(ParameterError, match="runs at 500 Hz but the sampled loop at 250 Hz"):
        resolve_design(d, loop={"period": 0.004})  # type: ignore[arg-type]
    # without a file the loop runs at the controller's rate, not a command's default period
    r4 = resolve_design(
        elements={"D1": "k1"}, values={"m": 1, "b": 1, "k1": 1, "kd": 1}, discrete=z,
        default_loop=SampledLoop(period=0.002 / 4),
    )  # fmt: skip
    assert r4.loop == SampledLoop(rate=500.0)


@settings(max_examples=25, deadline=None)
@given(
    b0=st.fractions(-50, 50, max_denominator=64),
    b1=st.fractions(-50, 50, max_denominator=64),
    a1=st.fractions(F(-63, 64), F(63, 64), max_denominator=64),
    theta=st.floats(0.01, 3.1),
)
def test_running_controller_is_the_text_evaluated(
    b0: Fraction, b1: Fraction, a1: Fraction, theta: float
) -> None:
    """Independent: the text evaluated at ``z = e^{jθ}`` by complex arithmetic."""
    zc = ZController(CA="(b0 + b1*z^-1)/(1 + a1*z^-1)", rate=100.0)
    sea = SEA(D1="k1", values={"k1": 1.0, "b0": b0, "b1": b1, "a1": a1}, discrete=zc)
    ka, _kl = DiscreteController.for_loop(sea, SampledLoop(rate=100.0)).transfer_functions()
    z = complex(np.cos(theta), np.sin(theta))
    want = (float(b0) + float(b1) / z) / (1 + float(a1) / z)
    assert abs(ka(z) - want) <= 1e-9 * max(1.0, abs(want))
