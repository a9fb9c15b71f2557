"""The discrete controller as one difference equation over the exact common denominator.

Independent checks: the realization's transfer functions against the per-element
discretization (``discretize``, exact), its float run against scipy's ``lfilter`` of the
summed transfer functions, the batched runner of the twin against the single one (bit for
bit), and the joint ZOH against scipy's per-element ``cont2discrete``.
"""

from __future__ import annotations

import random
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.signal import cont2discrete, lfilter

from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.sampled.controllers import DiscreteController, DiscreteTF, discretize
from seapass.sampled.emulation import zoh_row
from seapass.sampled.joint import BatchDifferenceEquation, JointDifferenceEquation, JointRealization

VALUES = dict(m=0.4, b=3, k1=2500, b1=2, kf=0.5, ki=10, kv=1000, bv=5, ba=5)
CASCADE = SEA(
    D1="k1 + b1*s",
    CA="(kf + ki/s)*k1 + ba*s",
    CL="(1 + kf + ki/s)*(kv + bv*s) - (kf + ki/s)*k1",
    values=VALUES,
)


def _sum(tfs: tuple[DiscreteTF, DiscreteTF]) -> DiscreteTF:
    return tfs[0] + tfs[1]


def _equal(a: DiscreteTF, b: DiscreteTF) -> bool:
    minus = DiscreteTF(tuple(-c for c in b.num), b.den, b.period)
    return (a + minus).is_zero


@pytest.mark.parametrize("method", ["tustin", "backward"])
@pytest.mark.parametrize("vf", [None, 40.0])
def test_the_cascade_runs_as_one_difference_equation(method: str, vf: float | None) -> None:
    loop = SampledLoop(period=0.001, velocity_filter=vf, method=method)  # type: ignore[arg-type]
    ctrl = DiscreteController.for_loop(CASCADE, loop)
    # one integrator and one velocity state (the last sample, or the filter), shared by both
    # sides: 2 states where four separate filters had 4
    assert ctrl.order == 2 and ctrl.realization.is_minimal()
    assert ctrl.hidden_modes() == (1,)
    ka, kl = ctrl.transfer_functions()
    for got, attr in ((ka, "CA"), (kl, "CL")):
        ref = discretize(getattr(CASCADE, attr), 0.001, method=method, velocity_filter=vf,
                         values=dict(CASCADE.values))  # fmt: skip
        assert isinstance(ref, DiscreteTF) and _equal(got, ref)


def test_the_run_matches_lfilter_of_the_transfer_functions() -> None:
    ctrl = DiscreteController.for_loop(CASCADE, SampledLoop(period=0.001, velocity_filter=40.0))
    rng = np.random.default_rng(3)
    xa, xl = rng.normal(0, 1e-3, 2000), rng.normal(0, 1e-3, 2000)
    got = np.array([ctrl.step((a, b)) for a, b in zip(xa, xl, strict=True)])
    ka, kl = ctrl.transfer_functions()
    want = -lfilter([float(c) for c in ka.num], [float(c) for c in ka.den], xa) - lfilter(
        [float(c) for c in kl.num], [float(c) for c in kl.den], xl
    )
    assert np.max(np.abs(got - want)) <= 1e-9 * np.max(np.abs(want))


def _random_entries(rng: random.Random) -> list[tuple[tuple[Fraction, ...], tuple[Fraction, ...]]]:
    shared = [Fraction(1), Fraction(-rng.choice([1, Fraction(1, 2), Fraction(9, 10)]))]
    out = []
    for _ in range(rng.randint(1, 4)):
        den = [Fraction(1)]
        if rng.random() < 0.7:
            den = list(np.convolve(den, shared).tolist())
        if rng.random() < 0.4:
            den = list(np.convolve(den, [Fraction(1), Fraction(-rng.randint(1, 9), 10)]).tolist())
        num = tuple(
            Fraction(rng.randint(-9, 9), rng.randint(1, 5)) for _ in range(rng.randint(1, 3))
        )
        out.append((num, tuple(Fraction(c) for c in den)))
    return out


def test_random_rows_are_minimal_and_give_their_entries_back() -> None:
    rng = random.Random(22)
    for _ in range(60):
        entries = _random_entries(rng)
        names = [f"x{i}" for i in range(len(entries))]
        r = JointRealization.of(entries, names, Fraction(1, 100))
        assert r.is_minimal()
        for (num, den), name in zip(entries, names, strict=True):
            got = DiscreteTF(*r.entry(name), Fraction(1, 100))
            assert _equal(got, DiscreteTF(num, den, Fraction(1, 100)))


@given(seed=st.integers(0, 10_000))
def test_the_batched_runner_is_the_single_runner_bit_for_bit(seed: int) -> None:
    rng = random.Random(seed)
    entries = [_random_entries(rng)[0] for _ in range(3)]
    reals = [JointRealization.of([e, entries[-1]], ["a", "b"], Fraction(1, 100)) for e in entries]
    batch = BatchDifferenceEquation(reals, ["a", "b"])
    singles = [JointDifferenceEquation(r) for r in reals]
    x = np.random.default_rng(seed).normal(size=(50, 2))
    for row in x:
        out = batch.step([np.full(len(reals), row[0]), np.full(len(reals), row[1])])
        want = [
            s.step([row[["a", "b"].index(n)] for n in r.inputs])
            for s, r in zip(singles, reals, strict=True)
        ]
        assert out.tolist() == want


def test_the_joint_zoh_matches_scipy_per_element() -> None:
    import sympy as sp

    s = sp.Symbol("s")
    row = [25000 / s + 3 / (s + 40), -15000 / s + 2 * s / (s**2 + 3 * s + 900)]
    T = Fraction(1, 500)
    got = zoh_row(row, T)
    z = sp.Symbol("q")
    for expr, zq in zip(row, got, strict=True):
        num, den = sp.fraction(sp.cancel(sp.together(expr)))
        nd, dd, _ = cont2discrete(
            ([float(c) for c in sp.Poly(num, s).all_coeffs()],
             [float(c) for c in sp.Poly(den, s).all_coeffs()]), float(T), method="zoh",
        )  # fmt: skip
        for w in (0.3, 1.1, 2.9):
            zz = complex(np.exp(1j * w))
            ours = complex(sp.N(zq.subs(z, 1 / zz)))
            theirs = np.polyval(np.ravel(nd), zz) / np.polyval(dd, zz)
            assert abs(ours - theirs) <= 1e-8 * abs(theirs)
    # the shared integrator is one pole of the one discrete realization
    ctrl = DiscreteController.for_loop(
        SEA(D1="k1", CA=row[0], CL=row[1], values=dict(m=1, b=1, k1=1)),
        SampledLoop(period=0.002, method="zoh"),
    )
    assert ctrl.order == 4 and ctrl.realization.is_minimal()


def test_a_controller_given_in_z_runs_as_is() -> None:
    T = Fraction(1, 1000)
    ka = DiscreteTF((Fraction(3), Fraction(-2)), (Fraction(1), Fraction(-1)), T)
    kl = DiscreteTF((Fraction(1),), (Fraction(1), Fraction(-1)), T)
    ctrl = DiscreteController.from_z(ka, kl)
    assert ctrl.order == 1
    got_a, got_l = ctrl.transfer_functions()
    assert _equal(got_a, ka) and _equal(got_l, kl)
