"""Sampled-data passivity: closed forms, certified verdicts, bounds, Z-width maps, CLI."""

from __future__ import annotations

import json
import math
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from flint import acb, arb, fmpq, fmpq_poly
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers import design_argv
from seapass.cli import main
from seapass.errors import ModelError, NotPassiveError, ParameterError
from seapass.model.expr import S
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.sampled import coupling as smc
from seapass.sampled.alias import alias_sums, zeta_numerators
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.certified import precision
from seapass.sampled.controllers import controller_tfs
from seapass.sampled.passivity import SampledStatus, sampled_passivity, sampled_power_curve
from seapass.sampled.plant import plant_key, plant_of
from seapass.sampled.power import polynomial_degree, power_values, weighted_polynomials
from seapass.sampled.region import default_setups, sampled_region
from seapass.sampled.verdict import cached_sums, point_family

T = 0.002
RIG = {"m": 1.02, "b": 10.0, "k1": 1005.0, "b1": 30.0}
#: The reviewer's counterexample: passive in continuous time, slow transmission pole.
SLOW = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 1e6}
RIG_K1 = {k: v for k, v in RIG.items() if k != "b1"}  # for models without the damper


def lp(**kw: float | None) -> SEA:
    return SEA(D1="k1 + b1*s", CL="kd", values={**RIG, **kw})


def ours(**kw: float | None) -> SEA:
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**RIG, "bd": 25.0, **kw})


# ------------------------------------------------------------------ closed forms


@pytest.mark.parametrize("j", [1, 2, 3, 4, 5])
@pytest.mark.parametrize("p", [complex(-30.0, 0.0), complex(-5.0, 40.0), complex(0.0, 0.0)])
def test_zeta_kernels_match_truncated_sums(j: int, p: complex) -> None:
    """Σ_k 1/(s_k − p)^j = T^j F_j(z/q)/(z/q − 1)^j for every multiplicity."""
    period, w = 0.01, 37.0
    q = np.exp(p * period)
    z = np.exp(1j * w * period)
    x = z / q
    F = zeta_numerators(j)[j - 1]
    closed = period**j * sum(float(c) * x**i for i, c in enumerate(F.coeffs())) / (x - 1) ** j
    k = np.arange(-200000, 200001)
    brute = np.sum(1.0 / (1j * (w + 2 * np.pi * k / period) - p) ** j)
    assert abs(closed - brute) <= 1e-4 * abs(closed)


@settings(max_examples=20, deadline=None, derandomize=True)
@given(p1=st.floats(-300, -1), p2=st.floats(1, 300), c=st.floats(0.1, 100), w=st.floats(1, 1500))
def test_alias_sum_matches_truncated_sum(p1: float, p2: float, c: float, w: float) -> None:
    num = fmpq_poly([fmpq(*Fraction(c).as_integer_ratio())])
    den = fmpq_poly([-fmpq(*Fraction(p1).as_integer_ratio()), 1]) * fmpq_poly(
        [-fmpq(*Fraction(p2).as_integer_ratio()), 1]
    )
    sums = alias_sums({"x": (num, den)}, fmpq(1, 500), 128)
    with precision(128):
        closed = complex(sums.evaluate([acb(0, arb(w) / 500).exp()])["x"][0].mid())
    k = np.arange(-200000, 200001)
    s = 1j * (w + 2 * np.pi * k * 500)
    brute = np.sum(c / ((s - p1) * (s - p2)))
    assert abs(closed - brute) <= 1e-4 * abs(closed) + 1e-12


def test_fourfold_pole_is_handled() -> None:
    """No multiplicity limit: 1/(s + 3)^4 against its truncated alias sum."""
    den = fmpq_poly([3, 1]) ** 4
    sums = alias_sums({"x": (fmpq_poly([1]), den)}, fmpq(1, 100), 128)
    with precision(128):
        closed = complex(sums.evaluate([acb(0, arb("0.37")).exp()])["x"][0].mid())
    k = np.arange(-20000, 20001)
    brute = np.sum(1 / (1j * (37.0 + 2 * np.pi * k * 100) + 3) ** 4)
    assert closed == pytest.approx(brute, rel=1e-9)


def test_divergent_alias_sum_is_refused() -> None:
    with pytest.raises(ValueError, match="diverges"):
        alias_sums({"x": (fmpq_poly([0, 1]), fmpq_poly([1, 1]))}, fmpq(1, 500), 64)


def _brute_power(sea: SEA, w: float, *, delay: int = 0, K: int = 20000) -> float:
    """N(ω) from truncated alias sums of the Gram entries (independent of the closed forms)."""
    e = {k: sp.lambdify(S, sea.numeric(v)) for k, v in sea.elements().items()}
    m, b = float(sea.numeric(sea.m)), float(sea.numeric(sea.b))
    s = 1j * (w + 2 * np.pi * np.arange(-K, K + 1) / T)
    d1 = np.broadcast_to(e["D1"](s), s.shape)
    d2 = np.broadcast_to(e["D2"](s), s.shape)
    al = m * s**2 + b * s
    a, p = d1 / (al + d1), 1 / (al + d1)
    r = ((d1 * al + d2 * (al + d1)) / (s * (al + d1))).real
    ka, kl = controller_tfs(sea, SampledLoop(period=T, delay=delay))
    z = np.exp(1j * w * T)
    KA, KL = ka(z), kl(z)
    d = 1 + KA * np.sum(p * (1 - 1 / z) / s) / T
    c = a * (1 - 1 / z) / s
    wv = (KA * a + KL) / (T * s)
    g11, g21, g22 = np.sum(abs(c) ** 2 / r), np.sum(wv * c / r), np.sum(abs(wv) ** 2 / r)
    return float(abs(d) ** 2 + (np.conj(d) * g21).real - (g11 * g22 - abs(g21) ** 2) / 4)


@pytest.mark.parametrize("w", [10.0, 300.0, 1500.0])
@pytest.mark.parametrize("design", ["lp", "ours", "ours-delay", "both"])
def test_power_function_matches_brute_force(design: str, w: float) -> None:
    sea = {
        "lp": lp(kd=900.0),
        "ours": ours(kd=2000.0),
        "ours-delay": ours(kd=2000.0),
        "both": SEA(
            D1="k1 + b1*s", CA="kd + bd*s", CL="50", values={**RIG, "bd": 25.0, "kd": 2000.0}
        ),
    }[design]
    delay = 1 if design == "ours-delay" else 0
    ka, kl = controller_tfs(sea, SampledLoop(period=T, delay=delay))
    sums = cached_sums(plant_key(sea), Fraction(1, 500), ("S1", "S2", "S3", "S4", "Sg"), 128)
    (closed,) = power_values(sums, point_family(ka, kl), [w * T])
    assert float(closed.mid()) == pytest.approx(
        _brute_power(sea, w, delay=delay), rel=1e-5, abs=1e-6
    )


def test_weighted_power_is_the_interpolated_polynomial() -> None:
    """P̃ interpolated at Chebyshev nodes reproduces N·weight at other frequencies (balls
    overlap), and its degree is the proven bound: the θ = 0 factor divides out exactly."""
    sea = ours(kd=2000.0)
    ka, kl = controller_tfs(sea, SampledLoop(period=T, delay=1, velocity_filter=50.0))
    fam = point_family(ka, kl)
    sums = cached_sums(plant_key(sea), Fraction(1, 500), ("S1", "S2", "Sg"), 256)
    (poly,) = weighted_polynomials(sums, fam)
    assert poly.degree() <= polynomial_degree(sums, fam)
    with precision(256):
        for theta in (0.013, 0.4, 2.9):
            z = acb(0, arb(theta)).exp()
            (n,) = power_values(sums, fam, [theta])
            v = [sum((c * z**-i for i, c in enumerate(p[0].coeffs())), acb(0)) for p in fam]
            weight = sums.weight(z) * (v[0] * v[0].conjugate()).real
            assert poly(arb(theta).cos()).overlaps(n * weight)


# ------------------------------------------------------------------ certified verdicts


def test_slow_pole_counterexample_is_not_passive() -> None:
    """Issue 11, defect 1: passive in continuous time, not passive sampled (N(0) < 0)."""
    r = sampled_passivity(
        SEA(D1="k1 + b1*s", CL="kd", values={**SLOW, "kd": 950.0}), loop=SampledLoop(period=T)
    )
    assert r.status is SampledStatus.NOT_PASSIVE and r.reason == "low_frequency"
    assert r.omega is not None and 0 < r.omega * T < 1e-3
    assert "R_lf" in r.detail and r.precision >= 256
    # just inside the closed-form limit kd <= 2 b k1/(2b + k1 T) = 909.09 it is passive
    assert sampled_passivity(
        SEA(D1="k1 + b1*s", CL="kd", values={**SLOW, "kd": 900.0}), loop=SampledLoop(period=T)
    ).passive


def test_precision_cap_gives_undecided_never_passive() -> None:
    sea = SEA(D1="k1 + b1*s", CL="kd", values={**SLOW, "kd": 950.0})
    r = sampled_passivity(sea, loop=SampledLoop(period=T), max_precision=64)
    # undecided is the outcome, never "marginal" (decided near the boundary)
    assert r.outcome is SampledStatus.UNDECIDED and not r.passive and not r.marginal
    with pytest.raises(NotPassiveError):
        sampled_passivity(sea, loop=SampledLoop(period=T), max_precision=64, throw=True)


def test_colgate_schenkel_virtual_spring_limit() -> None:
    kmax = 2 * RIG["b"] / T
    sea = SEA(D1="k1", CA="kd", values={**RIG_K1, "kd": 0.0})
    assert sampled_passivity(sea, loop=SampledLoop(period=T), values={"kd": 0.95 * kmax}).passive
    assert not sampled_passivity(
        sea, loop=SampledLoop(period=T), values={"kd": 1.05 * kmax}
    ).passive


def test_colgate_schenkel_virtual_damper_limit() -> None:
    sea = SEA(D1="k1", CA="kd + bd*s", values={**RIG_K1, "kd": 100.0, "bd": 0.0})
    assert sampled_passivity(sea, loop=SampledLoop(period=T), values={"bd": 8.0}).passive
    r = sampled_passivity(sea, loop=SampledLoop(period=T), values={"bd": 12.0})
    assert not r.passive and r.omega == pytest.approx(math.pi / T)


def test_lp_approaches_continuous_bound_for_fast_sampling() -> None:
    from seapass.analysis.region import passive_intervals

    kc = passive_intervals(lp(kd=None), "kd", 0, 1e5).intervals[0][1]
    assert kc == pytest.approx(849.148, rel=1e-4)
    assert sampled_passivity(lp(kd=0.97 * kc), loop=SampledLoop(period=1e-4)).passive
    assert not sampled_passivity(lp(kd=1.01 * kc), loop=SampledLoop(period=1e-4)).passive
    assert not sampled_passivity(lp(kd=0.97 * kc), loop=SampledLoop(period=T)).passive


def test_undamped_transmission_with_load_feedback_is_never_passive() -> None:
    r = sampled_passivity(lp(b1=0.0, kd=10.0), loop=SampledLoop(period=T))
    assert not r.passive and r.reason == "alias_injection"
    assert 0 < r.spectral_radius < 1  # always a finite number (strict JSON)
    with pytest.raises(ModelError):
        sampled_power_curve(lp(b1=0.0, kd=10.0), loop=SampledLoop(period=T))


def test_unstable_internal_loop() -> None:
    r = sampled_passivity(ours(kd=3e6), loop=SampledLoop(period=T, delay=1))
    assert not r.passive and r.reason == "unstable" and r.spectral_radius > 1


def test_delay_and_filter_shrink_the_passive_set() -> None:
    sea = ours(kd=30000.0)
    assert sampled_passivity(sea, loop=SampledLoop(period=T)).passive
    assert not sampled_passivity(
        sea, loop=SampledLoop(period=T, delay=1, velocity_filter=50.0)
    ).passive


@pytest.mark.parametrize(
    ("make", "inside", "outside"), [(lp, 720.0, 880.0), (ours, 30000.0, 37000.0)]
)
def test_bound_agrees_with_coupled_stability(make, inside: float, outside: float) -> None:  # type: ignore[no-untyped-def]
    good, bad = make(kd=inside), make(kd=outside)
    assert sampled_passivity(good, loop=SampledLoop(period=T)).passive
    assert not sampled_passivity(bad, loop=SampledLoop(period=T)).passive
    assert smc.worst_sampled_environment(good, loop=SampledLoop(period=T)).stable
    found = smc.worst_sampled_environment(bad, loop=SampledLoop(period=T))
    assert not found.stable and found.env_mass > 0 and found.env_stiffness >= 0


def test_structure_outside_the_supported_class_is_refused() -> None:
    with pytest.raises(ModelError, match="static stiffness"):
        plant_of(
            SEA(
                D1="b1*s",
                CL="kd",
                values={**{k: v for k, v in RIG.items() if k != "k1"}, "kd": 1.0},
            )
        )
    with pytest.raises(ModelError, match="dissipative"):
        sampled_passivity(lp(kd=100.0, b=0.0), loop=SampledLoop(period=T))
    with pytest.raises(ParameterError):
        sampled_passivity(lp(kd=None), loop=SampledLoop(period=T))
    with pytest.raises(ParameterError, match="period"):
        sampled_passivity(lp(kd=1.0), loop=SampledLoop(period=1e-9))
    with pytest.raises(ParameterError, match="delay"):  # bounded work, before any is done
        sampled_passivity(lp(kd=1.0), loop=SampledLoop(period=T, delay=10**6))


# ------------------------------------------------------------------ bounds


def test_bound_edges_are_enclosures() -> None:
    r = sampled_passive_bound(lp(kd=None), "kd", loop=SampledLoop(period=T), lo=0, hi=5000)
    assert r.intervals[0][0] == 0.0 and len(r.intervals) == 1
    (edge,) = r.edges
    assert 798 < edge.lo <= edge.hi < 799
    assert edge.hi - edge.lo <= 1e-9 * edge.hi
    assert r.intervals[0][1] == edge.lo and r.max_passive == edge.lo
    assert sampled_passivity(lp(kd=edge.lo * (1 - 1e-7)), loop=SampledLoop(period=T)).passive
    assert not sampled_passivity(lp(kd=edge.hi * (1 + 1e-7)), loop=SampledLoop(period=T)).passive
    out = r.to_dict()
    assert out["edges"][0]["lo"] == edge.lo and out["range"] == [0.0, 5000.0]


def test_range_from_zero_on_the_textbook_spring() -> None:
    """Issue 11, defect 2: the plain virtual spring from kd = 0; the limit is 2b/T."""
    r = sampled_passive_bound(
        SEA(D1="k1", CA="kd", values={**RIG_K1, "kd": None}),
        "kd",
        loop=SampledLoop(period=T),
        lo=0,
        hi=2e4,
    )
    assert r.intervals[0][0] == 0.0
    assert r.max_passive == pytest.approx(2 * RIG["b"] / T, rel=1e-9)
    assert r.edges[0].kind == "low_frequency"


def test_narrow_island_is_found_and_design_value_covered() -> None:
    """Issue 11, defect 3: lead filter at 1 kHz, the passive tz form an island far narrower
    than the range; the design's own value (outside the range given) is covered."""
    sea = SEA(
        D1="k1 + b1*s",
        CA="kd*(1 + tz*s)/(1 + tp*s)",
        values={
            "m": 1.0,
            "b": 10.0,
            "k1": 1000.0,
            "b1": 20.0,
            "kd": 20000.0,
            "tp": 0.002,
            "tz": None,
        },
    )
    r = sampled_passive_bound(
        sea, "tz", loop=SampledLoop(period=0.001), lo=0.05, hi=1000, design_value=0.01
    )
    assert r.lo == 0.01 and r.design_passive is True
    ((a, b),) = r.intervals
    assert a == 0.01 and 0.0999 < b < 0.1
    r = sampled_passive_bound(sea, "tz", loop=SampledLoop(period=0.001), lo=0, hi=1000)
    ((a, b),) = r.intervals
    assert 0.00199 < a < 0.002 and 0.0999 < b < 0.1


def test_isolated_special_values() -> None:
    """kd = 0 is passive even where every kd > 0 injects aliased energy."""
    r = sampled_passive_bound(lp(b1=0.0, kd=None), "kd", loop=SampledLoop(period=T), lo=0, hi=100)
    assert r.intervals == ((0.0, 0.0),)


@pytest.mark.parametrize("rtol", [0.0, -1.0, 1e-15, 0.5, float("nan")])
def test_bad_rtol_is_one_clear_error(rtol: float) -> None:
    with pytest.raises(ParameterError, match="rtol"):
        sampled_passive_bound(lp(kd=None), "kd", loop=SampledLoop(period=T), lo=0, hi=10, rtol=rtol)


def test_bound_errors() -> None:
    with pytest.raises(ParameterError, match="plant parameter"):
        sampled_passive_bound(lp(kd=10.0, b1=None), "b1", loop=SampledLoop(period=T), lo=0, hi=10)
    with pytest.raises(ParameterError):
        sampled_passive_bound(lp(kd=None), "kd", loop=SampledLoop(period=T), lo=5, hi=1)
    with pytest.raises(ParameterError, match="does not appear"):
        sampled_passive_bound(lp(kd=None), "zz", loop=SampledLoop(period=T), lo=0, hi=1)


@pytest.mark.parametrize(
    ("ca", "cl", "free", "given", "loop"),
    [
        ("0", "kd", "kd", {}, {}),
        ("kd + bd*s", "0", "kd", {"bd": 25.0}, {"delay": 1, "velocity_filter": 50.0}),
        ("kd + bd*s", "0", "bd", {"kd": 2000.0}, {"velocity_filter": 50.0}),
        ("kd*(1 + tz*s)/(1 + tp*s)", "0", "tz", {"kd": 2000.0, "tp": 0.001}, {}),
        ("kd*(1 + tz*s)/(1 + tp*s)", "0", "tp", {"kd": 2000.0, "tz": 0.01}, {"method": "backward"}),
        ("kd + ki/s", "5", "ki", {"kd": 2000.0}, {"delay": 2}),
    ],
)
def test_parametric_controllers_equal_the_deployed_ones(
    ca: str, cl: str, free: str, given: dict[str, float], loop: dict[str, object]
) -> None:
    """The bound's controllers in λ are the deployed ones at every value (normalized)."""
    from seapass.sampled.family import controller_family

    sea = SEA(D1="k1 + b1*s", CA=ca, CL=cl, values={**RIG, **given, free: None})
    fam = controller_family(sea, free, SampledLoop(period=T, **loop))  # type: ignore[arg-type]
    for v in (1e-4, 0.37, 3.0, 7.0e3):
        ka, kl = controller_tfs(sea.with_values(**{free: v}), SampledLoop(period=T, **loop))  # type: ignore[arg-type]
        for tf, polys in ((ka, fam.actuator), (kl, fam.load)):
            num, den = polys.at(Fraction(v))
            lead = den[0]
            got = [Fraction(str(c / lead)) for c in num.coeffs()]
            want = list(tf.num)
            while want and want[-1] == 0:
                want.pop()
            assert got == want and [Fraction(str(c / lead)) for c in den.coeffs()] == list(tf.den)
    assert all(isinstance(x, Fraction) for x in fam.special)


# ------------------------------------------------------------------ Z-width


@pytest.fixture(scope="module")
def zmap():  # type: ignore[no-untyped-def]
    return sampled_region(
        SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG),
        "kd", "bd", loop=SampledLoop(period=T, delay=1, velocity_filter=50.0),
        p1_range=(0, 1e5), p2_range=(0, 50), n=3,
    )  # fmt: skip


def test_zwidth_map_matches_bounds(zmap) -> None:  # type: ignore[no-untyped-def]
    z = zmap
    ideal, delayed, filtered = (z.upper_boundary(s.label) for s in z.setups)
    assert ideal[1] == pytest.approx(33450.2, rel=1e-5)
    assert np.all(filtered <= delayed) and np.all(delayed < ideal)
    csv = z.to_csv().splitlines()
    assert csv[0] == "setup,delay,velocity_filter,bd,kd_lo,kd_hi" and len(csv) == 10
    assert z.to_dict()["setups"][2]["velocity_filter"] == 50.0


def test_region_errors() -> None:
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG)
    with pytest.raises(ParameterError):
        sampled_region(
            sea, "kd", "kd", loop=SampledLoop(period=T), p1_range=(0, 1), p2_range=(0, 1)
        )
    with pytest.raises(ParameterError, match="rows"):
        sampled_region(
            sea, "kd", "bd", loop=SampledLoop(period=T), p1_range=(0, 1), p2_range=(0, 1), n=10**6
        )
    assert [s.delay for s in default_setups(SampledLoop(period=T, delay=2))] == [0, 2]
    assert [s.label for s in default_setups(SampledLoop(period=T, velocity_filter=50.0))] == [
        "ideal ZOH",
        "1-sample delay",
        "1-sample delay + 50 Hz filter",
    ]


# ------------------------------------------------------------------ CLI

RIG_PLANT = {"m": 1.02, "b": 10, "k1": 1005, "b1": 30}
LP_ARGS = design_argv("LP-damped", RIG_PLANT)
OURS_ARGS = design_argv("ours", RIG_PLANT, bd=25)


def test_cli_check_counterexample(capsys) -> None:  # type: ignore[no-untyped-def]
    argv = ["sampled", "check", "--period", "0.002", "--D1", "k1 + b1*s", "--CL", "kd",
            "--set", "m=1", "--set", "b=10", "--set", "k1=1000", "--set", "b1=1e6",
            "--set", "kd=950", "--json"]  # fmt: skip
    assert main(argv) == 1  # a check: exit 1 on a negative verdict
    out = json.loads(capsys.readouterr().out)
    assert out["passive"] is False and out["status"] == "not_passive"
    assert out["reason"] == "low_frequency" and out["low_frequency"]["violated"] is True


def test_cli_bound_json_and_out(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    argv = ["sampled", "bound", "kd", "--period", "0.002", *LP_ARGS, "--range", "kd=0:2000",
            "--json", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert (
        798.6 < out["max_passive"] < 798.7 and out["edges"][0]["hi"] - out["edges"][0]["lo"] < 1e-6
    )
    assert (tmp_path / "sampled_bound_kd.png").stat().st_size > 0
    rows = (tmp_path / "sampled_bound_kd.csv").read_text().splitlines()
    assert rows[0] == "kd_lo,kd_hi,status" and rows[1].endswith(",passive")


def test_cli_region(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    argv = ["sampled", "region", "kd", "bd", "--period", "0.002", *OURS_ARGS[:-2],
            "--range", "kd=0:1e5", "--range", "bd=0:50", "--points", "2", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "ideal ZOH" in text and "delay" in text
    assert (tmp_path / "sampled_region_kd_bd.png").stat().st_size > 0
    assert (tmp_path / "sampled_region_kd_bd.csv").read_text().startswith("setup,delay,")


def test_cli_errors_are_one_line(capsys) -> None:  # type: ignore[no-untyped-def]
    base = ["sampled", "bound", "kd", *LP_ARGS]
    assert main([*base, "--range", "kd=5:1"]) == 2
    assert main([*base, "--range", "kd=0:10", "--rtol", "0"]) == 2
    assert main(["sampled", "bound", "zz", "--range", "zz=0:1", *LP_ARGS]) == 2
    assert main(["sampled", "check", "--D1", "k1", "--CA", "kd"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 4 and "Traceback" not in err and "rtol" in err


def test_plots(tmp_path, zmap) -> None:  # type: ignore[no-untyped-def]
    from seapass.plot.sampled import plot_bound, plot_zwidth
    from seapass.plot.style import figure_of, save_figure

    r = sampled_passive_bound(
        lp(kd=None), "kd", loop=SampledLoop(period=T), lo=0, hi=2000, rtol=1e-6
    )
    save_figure(figure_of(plot_bound(r)), tmp_path / "b.png")
    save_figure(figure_of(plot_zwidth(zmap)), tmp_path / "z.png")
    assert (tmp_path / "b.png").stat().st_size > 0 and (tmp_path / "z.png").stat().st_size > 0
