"""Coupled stability: the physical meaning of passivity, and destabilizing witnesses.

A passive SEA held by any passive environment (mass-spring-damper "humans"
over wide ranges) must never be unstable; a non-passive one must have a
passive environment that destabilizes it.  Every coupled verdict here is
exact; it is cross-checked against python-control's poles of an independently
built transfer function.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers import configs
from seapass.analysis import find_destabilizing_environment, simulate_coupled
from seapass.analysis.coupled import (
    CoupledResult,
    Environment,
    classify_polynomial,
    coupled_polynomial,
    coupled_stability,
)
from seapass.analysis.passivity import is_passive
from seapass.cli import main
from seapass.errors import DegenerateModelError, NotPassiveError, ParameterError
from seapass.model.sea import SEA

control = pytest.importorskip("control")


def logu(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: float(10**e))


# "humans": stiffness 1e1..1e6 N/m, mass 0.05..50 kg, damping 0..1e3 N*s/m (0 drawn often)
humans = st.builds(
    Environment,
    mass=logu(0.05, 50),
    damping=st.one_of(st.just(0.0), logu(1e-3, 1e3)),
    stiffness=logu(1e1, 1e6),
)
actuator = {"m": logu(0.1, 10), "b": st.one_of(st.just(0.0), logu(0.1, 100))}


@st.composite
def passive_designs(draw: st.DrawFn) -> SEA:
    """Designs passive by construction (paper, Table I): LP with kd <= k1, APD, ours."""
    kind = draw(st.sampled_from(["LP", "APD", "ours"]))
    vals = {k: draw(v) for k, v in actuator.items()}
    vals["k1"] = draw(logu(1e2, 1e6))
    if kind == "LP":
        vals["kd"] = vals["k1"] * draw(st.floats(0.0, 1.0))
        return SEA(D1="k1", CL="kd", values=vals)
    vals["kd"] = draw(logu(1e1, 1e7))
    vals["bd"] = draw(st.one_of(st.just(0.0), logu(0.1, 1e3)))
    if kind == "APD":
        return SEA(D1="k1", CA="kd + bd*s", values=vals)
    vals["b1"] = draw(logu(0.1, 1e3))
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values=vals)


def independent_poles(sea_or_z, env: Environment) -> np.ndarray:
    """Poles of X/F = 1/(K + m s^2 + b s + k), K = s Z: python-control, float coefficients."""
    r = is_passive(sea_or_z)
    nz, dz = np.array(r.num), np.array(r.den)
    # K = s Z = s nz / dz  ->  X/F = dz / (s nz + (m s^2 + b s + k) dz)
    ks = np.polymul([1.0, 0.0], nz)
    e = np.polymul([env.mass, env.damping, env.stiffness], dz)
    den = np.polyadd(ks, e)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return np.asarray(control.poles(control.tf(dz, den)))


@settings(max_examples=150, suppress_health_check=[HealthCheck.too_slow])
@given(sea=passive_designs(), envs=st.lists(humans, min_size=1, max_size=4))
def test_passive_design_is_never_destabilized_by_a_passive_human(sea, envs):
    r = is_passive(sea)
    assert r.passive, (sea.values, r.detail)
    for env in envs:
        c = coupled_stability(sea, env)
        assert c.bounded, (sea.values, env, c.poles)
        if env.damping > 0 and sea.values["b"] > 0:
            # a dissipative environment removes every axis root (Re(Z + Z_e)(jw) > 0);
            # with b = 0 a lossless internal mode may cancel from Z and stay on the axis
            assert c.stable, (sea.values, env, c.poles)
        if c.stable:
            assert c.max_real_part < 0
            p = independent_poles(sea, env)
            # the independent float computation agrees up to its own rounding
            scale = max(1.0, float(np.max(np.abs(p))))
            assert np.max(p.real) < 1e-6 * scale


@settings(max_examples=40)
@given(
    k1=logu(1e2, 1e6),
    frac=st.floats(0.0, 1.0),
    m=logu(0.1, 10),
    env=st.builds(Environment, mass=logu(0.05, 50), stiffness=logu(1e1, 1e6)),
)
def test_lossless_sea_with_undamped_human_is_marginal_not_unstable(k1, frac, m, env):
    """b = 0 and b_e = 0: energy is conserved, so the poles sit on the axis.

    The right notion is "marginally stable" (bounded, not decaying): the exact
    test must place every root on the axis as simple, and the simulated
    response must neither grow nor decay.
    """
    sea = SEA(D1="k1", CL="kd", values={"m": m, "b": 0.0, "k1": k1, "kd": frac * k1})
    r = is_passive(sea)
    assert r.passive and r.lossless
    c = coupled_stability(sea, env)
    assert c.status == "marginally stable"
    assert not c.rhp and not c.repeated_axis
    assert np.all(np.abs(c.poles.real) <= 1e-9 * np.maximum(1.0, np.abs(c.poles)))
    sim = simulate_coupled(sea, env)  # default horizon: 50 periods of the slowest mode
    assert 0.2 < sim.growth_factor < 5.0


def test_marginal_status_on_a_known_case():
    # k s/(s^2+k) (a spring in series with a unit mass) held by a 1 kg mass
    c = coupled_stability("k*s/(s**2 + k)", Environment(mass=1.0), values={"k": 4.0})
    assert c.status == "marginally stable" and c.bounded and not c.stable
    np.testing.assert_allclose(sorted(np.abs(c.poles.imag)), [0.0, math.sqrt(8), math.sqrt(8)])


@pytest.mark.parametrize(
    ("poly", "status"),
    [
        ((1, 2, 1), "stable"),  # (s+1)^2
        ((1, 0, 1), "marginally stable"),  # s^2 + 1
        ((0, 1), "marginally stable"),  # s
        ((0, 0, 1), "unstable"),  # s^2: repeated root at 0
        ((1, 0, 2, 0, 1), "unstable"),  # (s^2+1)^2
        ((-1, 1), "unstable"),  # s - 1
        ((1, 0, 0, 1), "unstable"),  # s^3 + 1 has roots with Re = 1/2
        ((5,), "stable"),
    ],
)
def test_classify_polynomial(poly, status):
    from fractions import Fraction

    assert classify_polynomial(tuple(Fraction(c) for c in poly))[0] == status


def test_system_polynomials_make_the_denominator_monic_positive():
    from flint import fmpq_poly

    from seapass.analysis.coupled import system_polynomials

    num, den = system_polynomials(([1.0, 1.0], [-1.0, -2.0]), None)  # (s + 1)/(-s - 2)
    assert den == fmpq_poly([2, 1]) and num == fmpq_poly([-1, -1])


def test_common_pole_at_zero_is_removed():
    # spring port + spring environment: the shared s = 0 pole only encodes the rest position
    chi, common = coupled_polynomial("k/s", Environment(stiffness=3.0), values={"k": 2.0})
    assert [float(c) for c in common] == [0.0, 1.0]
    assert [float(c) for c in chi] == [5.0]
    assert coupled_stability("k/s", Environment(stiffness=3.0), values={"k": 2.0}).stable


def test_environment_validation_and_degenerate_coupling():
    with pytest.raises(ParameterError, match="mass"):
        Environment(mass=-1.0)
    with pytest.raises(ParameterError, match="stiffness"):
        Environment(stiffness=math.nan)
    with pytest.raises(ParameterError, match="damping"):
        Environment(damping=True)  # type: ignore[arg-type]
    with pytest.raises(DegenerateModelError, match="cancels"):
        coupled_stability("-s", Environment(mass=1.0))
    assert Environment().is_free
    d = coupled_stability("(s+1)/(s+2)", Environment(1.0, 2.0, 3.0)).to_dict()
    assert d["status"] == "stable" and json.dumps(d)


def test_result_rejects_unknown_status():
    with pytest.raises(ValueError, match="status"):
        CoupledResult(
            status="fine", rhp=False, repeated_axis=False, characteristic=(), common=(),
            poles=np.zeros(0),
        )  # fmt: skip


# ---------------------------------------------------------------- witnesses


def check_witness(system, w) -> None:
    """The witness is passive, the coupled system has an open-RHP pole, the response grows."""
    assert w.found and not w.passive
    env = w.environment
    assert env.mass >= 0 and env.damping >= 0 and env.stiffness >= 0
    assert w.coupled.rhp and w.coupled.status == "unstable"
    assert w.coupled.max_real_part > 0
    # re-verify exactly from scratch, and independently in floating point
    again = coupled_stability(system, env)
    assert again.rhp
    poles = independent_poles(system, env)
    # floating point resolves a growth rate only above its rounding level (relative to
    # the largest pole); closer to the boundary the exact verdict above is the evidence
    if w.coupled.max_real_part > 1e-9 * np.max(np.abs(poles)):
        assert np.max(poles.real) > 0
        sim = w.simulation
        assert sim is not None and sim.growth_rate > 0 and sim.growth_factor > 2


@st.composite
def non_passive_lp(draw: st.DrawFn) -> SEA:
    """LP with kd > k1 (Table I: not passive), damped actuator."""
    vals = {"m": draw(logu(0.1, 10)), "b": draw(logu(0.1, 100)), "k1": draw(logu(1e2, 1e7))}
    vals["kd"] = vals["k1"] * (1 + draw(logu(1e-3, 10)))
    return SEA(D1="k1", CL="kd", values=vals)


@settings(max_examples=25, deadline=None)
@given(sea=non_passive_lp())
def test_witness_for_random_non_passive_lp(sea):
    w = find_destabilizing_environment(sea, bounds=None)
    check_witness(sea, w)


NON_PASSIVE_CONFIGS = configs(
    "LP",
    "LP-damped",
    "LPD",
    "API",
    "LPI",
    "disjoint-damper",
    "spring-spring",
)


@settings(max_examples=30, deadline=None)
@given(name=st.sampled_from(sorted(NON_PASSIVE_CONFIGS)), data=st.data())
def test_every_non_passive_random_design_has_a_witness(name, data):
    """Any configuration, parameters 1e-2..1e5: not passive => a verified destabilizing
    passive environment (without bounds: it may have to be a very light or stiff one)."""
    sea = SEA(**NON_PASSIVE_CONFIGS[name])
    model = sea.with_values(**{p: data.draw(logu(1e-2, 1e5), label=p) for p in sea.parameters})
    if is_passive(model).passive:
        assert not find_destabilizing_environment(model, simulate=False).found
        return
    check_witness(model, find_destabilizing_environment(model, bounds=None))


@pytest.mark.parametrize(
    ("z", "reason"),
    [
        ("1/(s + 1) - 1e-9", "negative_real_part"),
        ("(s - 1)/(s + 1)", "negative_real_part"),
        ("-5", "negative_real_part"),
        ("1/(s - 1)", "rhp_pole"),
        ("s/(s - 1)", "rhp_pole"),
        ("-1/s", "axis_residue"),
        ("(s + 1)/(s**2 + 1)", "axis_residue"),
        ("1/s**2", "relative_degree"),
        ("s**2 + 1", "relative_degree"),
        ("-s + 10", "infinity_residue"),
        ("(s**3 + 1)/((s**2 + 1)**2)", "repeated_axis_pole"),
    ],
)
def test_witness_for_every_failure_reason(z, reason):
    w = find_destabilizing_environment(z, bounds=None)
    assert w.reason == reason
    assert w.found and w.coupled.status == "unstable"
    env = w.environment
    assert min(env.mass, env.damping, env.stiffness) >= 0
    assert coupled_stability(z, env).status == "unstable"
    assert w.simulation.growth_factor > 2


def test_hidden_unstable_mode_destabilizes_even_a_free_port():
    w = find_destabilizing_environment(((1, -1), (1, -1)), bounds=None)
    assert w.reason == "hidden_unstable_mode" and w.found
    assert w.method == "free port" and w.environment.is_free
    assert w.simulation.output == "characteristic coordinate"
    assert w.simulation.growth_factor > 2


def test_paper_lp_witness_is_a_plausible_hand():
    """LP with kd = 2 k1 (paper values) is destabilized by about half a kilogram, undamped."""
    lp = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=2000))
    w = find_destabilizing_environment(lp)
    check_witness(lp, w)
    assert 0.05 <= w.environment.mass <= 50
    with pytest.raises(NotPassiveError, match="m_e"):
        find_destabilizing_environment(lp, simulate=False, throw=True)


def test_passive_design_has_no_witness():
    ours = SEA(
        D1="k1 + b1*s",
        CA="kd + bd*s",
        values=dict(m=1, b=10, k1=1000, b1=20, bd=25, kd=5000),
    )
    w = find_destabilizing_environment(ours)
    assert w.passive and not w.found and w.environment is None
    assert "passivity theorem" in w.detail
    assert w.to_dict()["environment"] is None


def test_witness_for_stiff_spring_near_the_boundary():
    """k1 = 1e8 with kd 1 % above: tiny relative violation, still a clear witness."""
    lp = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1e8, kd=1.01e8))
    check_witness(lp, find_destabilizing_environment(lp, bounds=None))


# ---------------------------------------------------------------- CLI and figure

LP_ARGS = ["--D1", "k1", "--CL", "kd", "--set", "m=1", "--set", "b=10", "--set", "k1=1000"]


def test_cli_witness_json_and_files(capsys, tmp_path):
    out = tmp_path / "w"
    code = main(["witness", *LP_ARGS, "--set", "kd=2000", "--json", "--out", str(out)])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["found"] and data["max_real_part"] > 0
    env = data["environment"]
    assert min(env.values()) >= 0
    assert data["coupled"]["rhp"] and len(data["coupled"]["poles"]) >= 2
    assert (out / "witness.png").stat().st_size > 1000
    assert json.loads((out / "witness.json").read_text())["found"]
    assert not list(out.glob("*.part"))
    assert [p.name for p in out.glob(".*")] == [".seapass-written"]  # no temporary file left


def test_cli_witness_text_and_passive(capsys):
    assert main(["witness", "--Z", "(s - 1)/(s + 1)", "--unbounded"]) == 0
    text = capsys.readouterr().out
    assert "free port" in text and "grows" in text
    assert main(["witness", *LP_ARGS, "--set", "kd=500"]) == 0
    assert "passivity theorem" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        (["--Z", "1/s", "--D1", "k1"], "either --Z"),
        (["--set", "kd=nan"], "not finite"),
        (["--CL", "kd + __import__('os')"], "not allowed"),
    ],
)
def test_cli_witness_errors(capsys, extra, fragment):
    argv = ["witness", *LP_ARGS, *extra] if "--Z" not in extra else ["witness", *extra]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert fragment in err and err.count("\n") == 1 and "Traceback" not in err


def test_cli_witness_out_must_be_a_directory(capsys, tmp_path):
    f = tmp_path / "file.txt"
    f.write_text("keep")
    assert main(["witness", *LP_ARGS, "--set", "kd=2000", "--out", str(f)]) == 2
    assert "not a directory" in capsys.readouterr().err
    assert f.read_text() == "keep"


def test_plot_needs_a_found_witness():
    from seapass.plot.witness import plot_witness

    w = find_destabilizing_environment("(s + 1)/(s + 2)")
    with pytest.raises(ValueError, match="found witness"):
        plot_witness(w)


def test_witness_two_parts_per_trillion_beyond_the_boundary():
    """Pinned hard case: LP with kd = k1 (1 + 2.3e-12); the coupled pole sits at
    Re s ~ 3e-18, below floating-point resolution, and is still found exactly."""
    sea = SEA(
        D1="k1", CL="kd", values={"b": 1000.0, "k1": 1.0, "kd": 1.0000000000023026, "m": 10.0}
    )
    w = find_destabilizing_environment(sea, bounds=None)
    check_witness(sea, w)
    assert 0 < w.coupled.max_real_part < 1e-12


def test_lossless_hidden_mode_stays_marginal_not_unstable():
    """Pinned: b = 0 and kd = k1 make F_L/X_L = k1 exactly; the actuator mode at
    s = ±j sqrt(k1/m) cancels from Z and a damped human cannot reach it."""
    sea = SEA(D1="k1", CL="kd", values={"m": 1.0, "b": 0.0, "k1": 100.0, "kd": 100.0})
    assert is_passive(sea).passive
    c = coupled_stability(sea, Environment(mass=1.0, damping=1.0, stiffness=10.0))
    assert c.status == "marginally stable" and c.bounded and not c.rhp
