"""The certified sampled-data verdicts against an independent energy check (lifting).

``lifting_energy`` is written apart from ``seapass.sampled`` (no alias sums, no
Colgate–Schenkel formula): it integrates the plant exactly over one period with a
piecewise-constant port velocity and looks for a lifted input that extracts energy.
"""

from __future__ import annotations

import math
import random
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lifting_energy import sea_port, wall_port
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.controllers import DiscreteTF, controller_tfs
from seapass.sampled.passivity import sampled_passivity

NEGATIVE = -1e-9  # relative lifted energy below this is a proven extraction (rounding ~1e-13)


def random_design(rng: random.Random) -> tuple[SEA, float, int, float | None]:
    """LP, Ours, APD or both sides; a third of them with a slow pole, |p| T in [1e-8, 1]."""
    T = 10 ** rng.uniform(-4, -2)
    m, b = 10 ** rng.uniform(-1, 1), 10 ** rng.uniform(-0.5, 1.5)
    kind = rng.choice(["LP", "Ours", "APD", "both", "slow LP", "slow Ours"])
    if kind.startswith("slow"):
        b1 = 10 ** rng.uniform(0, 3)
        k1 = 10 ** rng.uniform(-8, 0) / T * (b + b1)  # slow pole |p| ~ k1/(b + b1)
        kind = kind[5:]
    else:
        k1 = 10 ** rng.uniform(1, 4)
        b1 = 0.0 if kind == "APD" else 10 ** rng.uniform(-1, 2.5)
    vals = {"m": m, "b": b, "k1": k1, "b1": b1}
    delay = rng.choice([0, 0, 1, 2])
    filt = rng.choice([None, None, 10 ** rng.uniform(0.5, 2.5)])
    if filt is not None and filt > 0.4 / T:
        filt = None
    if kind == "LP":
        sea = SEA(D1="k1 + b1*s", CL="kd", values={**vals, "kd": k1 * 10 ** rng.uniform(-1.5, 0.3)})
    elif kind in ("Ours", "APD"):
        bd = 0.0 if rng.random() < 0.3 else b * 10 ** rng.uniform(-1, 1)
        kd = 2 * (b + bd) / T * 10 ** rng.uniform(-1.5, 0.3)
        sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**vals, "kd": kd, "bd": bd})
    else:
        bd = b * 10 ** rng.uniform(-1, 0.5)
        vals = {**vals, "kd": 2 * (b + bd) / T * 10 ** rng.uniform(-2, 0), "bd": bd}
        vals["kl"] = k1 * 10 ** rng.uniform(-2, -0.3)
        sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values=vals)
    return sea, T, int(delay), filt


def lifted_verdict(
    sea: SEA, T: float, delay: int, filt: float | None, witness: float | None
) -> str:
    ka, kl = controller_tfs(sea, SampledLoop(period=T, delay=delay, velocity_filter=filt))
    lifted = sea_port(sea, ka, kl, T, M=8)
    # port held: remove the port position; the redundant transmission integrator sits at 1
    eig = [abs(e) for e in lifted.loop_eigenvalues(held=[2]) if abs(e - 1) > 1e-9]
    if eig and max(eig) > 1 + 1e-12:
        return "unstable"
    best, _theta = lifted.search(extra=() if witness is None else (witness,))
    return "extracts" if best < NEGATIVE else "no extraction"


def test_agreement_on_random_designs() -> None:
    """≥ 200 random designs, a third with slow poles: the two methods agree on every one."""
    rng = random.Random(20261123)
    tally: dict[tuple[str, str], int] = {}
    slow = 0
    for _ in range(210):
        sea, T, delay, filt = random_design(rng)
        r = sampled_passivity(
            sea,
            loop=SampledLoop(period=T, delay=delay, velocity_filter=filt),
            continuous_gate=False,
        )
        witness = None if r.omega is None else r.omega * T
        lifted = lifted_verdict(sea, T, delay, filt, witness)
        expected = {
            "": "no extraction",
            "unstable": "unstable",
            "negative_power": "extracts",
            "low_frequency": "extracts",
        }[r.reason]
        assert lifted == expected, (dict(sea.values), T, delay, filt, r.reason, lifted)
        tally[(r.reason, lifted)] = tally.get((r.reason, lifted), 0) + 1
        vals = sea.values
        slow += vals["k1"] / (vals["b"] + vals["b1"]) * T < 1e-2
    assert sum(tally.values()) >= 200
    assert slow >= 40 and tally.get(("low_frequency", "extracts"), 0) >= 5
    assert tally.get(("", "no extraction"), 0) >= 60


def _pd(K: float, B: float, delay: int, T: Fraction) -> DiscreteTF:
    num = [Fraction(K) + Fraction(B) / T, -Fraction(B) / T]
    return DiscreteTF(tuple([Fraction(0)] * delay + num), (Fraction(1),), T)


@pytest.mark.parametrize(
    ("B", "delay"), [(0.0, 0), (0.5, 0), (-0.5, 0), (0.0, 1), (0.0, 2), (0.0, 3)]
)
def test_lifted_wall_reproduces_colgate_schenkel(B: float, delay: int) -> None:
    """Rigid virtual wall: K ≤ 2(b − |B|)/T (PD), K ≤ 2b/((2d + 1)T) with d samples of delay."""
    b, T = 2.0, Fraction(1, 1000)
    kmax = 2 * (b - abs(B)) / float(T) if delay == 0 else 2 * b / ((2 * delay + 1) * float(T))
    inside = wall_port(b, _pd(0.98 * kmax, B, delay, T), float(T))
    outside = wall_port(b, _pd(1.02 * kmax, B, delay, T), float(T))
    assert inside.search()[0] > 0
    assert outside.search()[0] < NEGATIVE


@pytest.mark.parametrize(("bd", "delay"), [(0.0, 0), (0.5, 0), (-0.5, 0), (0.0, 1), (0.0, 2)])
def test_certified_bound_reproduces_colgate_schenkel(bd: float, delay: int) -> None:
    """An SEA whose actuator is nearly massless and whose spring is nearly rigid is the
    Colgate–Schenkel device: its certified kd bound is the closed form."""
    b, T = 2.0, 0.001
    sea = SEA(D1="k1", CA="kd + bd*s", values={"m": 1e-4, "b": b, "k1": 1e10, "bd": bd, "kd": None})
    r = sampled_passive_bound(
        sea, "kd", loop=SampledLoop(period=T, delay=delay), lo=0, hi=1e4, rtol=1e-9
    )
    kmax = 2 * (b - abs(bd)) / T if delay == 0 else 2 * b / ((2 * delay + 1) * T)
    assert r.max_passive == pytest.approx(kmax, rel=1e-6)


@settings(max_examples=25, deadline=None, derandomize=True)
@given(
    b=st.floats(1.0, 30.0),
    k1=st.floats(200.0, 5000.0),
    b1=st.floats(0.5, 1e6),
    period=st.floats(2e-4, 5e-3),
    ratio=st.floats(1.001, 1.5),
)
def test_low_frequency_condition_is_necessary(
    b: float, k1: float, b1: float, period: float, ratio: float
) -> None:
    """Load-side P beyond kd = 2 b k1/(2b + k1 T) is never passive, whatever b1: the certified
    verdict says so (reason: low frequency, with R_lf < 0), and the independent lifted check
    extracts energy at a slow frequency."""
    kd_lf = 2 * b * k1 / (2 * b + k1 * period)
    sea = SEA(
        D1="k1 + b1*s", CL="kd", values={"m": 1.0, "b": b, "k1": k1, "b1": b1, "kd": ratio * kd_lf}
    )
    r = sampled_passivity(sea, loop=SampledLoop(period=period), continuous_gate=False)
    assert not r.passive
    assert r.low_frequency is not None and r.low_frequency.violated
    if r.reason == "low_frequency":
        ka, kl = controller_tfs(sea, SampledLoop(period=period))
        lifted = sea_port(sea, ka, kl, period, M=4)
        assert lifted.min_energy(max(r.omega * period, 1e-12)) < NEGATIVE
    else:
        assert r.reason in ("negative_power", "unstable")


def test_low_frequency_closed_form_is_exact() -> None:
    """R_lf of load-side P is b − kd T/2 − b kd/k1, exactly (rationals)."""
    vals = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 1e6, "kd": 950.0}
    r = sampled_passivity(SEA(D1="k1 + b1*s", CL="kd", values=vals), loop=SampledLoop(period=0.002))
    b, k1, kd = (Fraction(vals[k]) for k in ("b", "k1", "kd"))
    T = Fraction(1, 500)
    assert r.low_frequency is not None
    assert r.low_frequency.resistance == b - kd * T / 2 - b * kd / k1
    assert math.isclose(float(r.low_frequency.resistance), -0.45)
