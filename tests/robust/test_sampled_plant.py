"""Ball alias sums over a box of plants (issue 26, item 4): enclosures checked against the
exact per-plant pipeline of seapass.sampled (a separate implementation: exact factorization
and FLINT root isolation at each plant) and root disks against numpy."""

from __future__ import annotations

from fractions import Fraction as F

import numpy as np
import pytest
from flint import acb, arb

from seapass.errors import ParameterError
from seapass.model.sea import SEA
from seapass.robust.sampled_plant import ParametricPlant, ball_of, isolate
from seapass.sampled.certified import precision
from seapass.sampled.plant import plant_key
from seapass.sampled.verdict import cached_sums

OURS = dict(b=10, k1=1000, b1=300, kd=1708, bd=300)
NAMES = ("S1", "S2", "Sg")


def _ours(**values: float) -> SEA:
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values={**OURS, **values})


@pytest.mark.parametrize("names", [("m",), ("m", "b1")])
def test_ball_sums_contain_the_sums_of_every_sampled_plant_of_the_box(names: tuple) -> None:
    box = {"m": (F(9999, 10000), F(10001, 10000)), "b1": (F(29999, 100), F(30001, 100))}
    pp = ParametricPlant(_ours(**{n: None for n in names}), names)
    period = F(1, 500)
    with precision(128):
        ball = {n: ball_of(*box[n]) for n in names}
        sums = pp.sums(ball, period, NAMES, 128)
        assert sums is not None
        zs = [acb(0, t).exp() for t in (0.3, 1.1, 2.9)]
        enclosed = sums.evaluate(zs)
    rng = np.random.default_rng(7)
    for _ in range(6):
        point = {n: float(F(box[n][0]) + F(rng.random()) * (box[n][1] - box[n][0])) for n in names}
        exact = cached_sums(plant_key(_ours(**point)), period, NAMES, 128)
        with precision(128):
            values = exact.evaluate(zs)
        for k in NAMES:
            for big, small in zip(enclosed[k], values[k], strict=True):
                assert big.contains(small), (k, point)


def test_ball_sums_are_narrow_for_a_degenerate_box() -> None:
    pp = ParametricPlant(_ours(m=None), ("m",))
    with precision(128):
        sums = pp.sums({"m": ball_of(F(1), F(1))}, F(1, 500), NAMES, 128)
        assert sums is not None
        exact = cached_sums(plant_key(_ours(m=1)), F(1, 500), NAMES, 128)
        z = [acb(0, 0.7).exp()]
        a, b = sums.evaluate(z)["S1"][0], exact.evaluate(z)["S1"][0]
        assert a.overlaps(b) and float(a.rad()) < 1e-20


def test_isolate_encloses_the_roots_of_every_member_of_a_ball_polynomial() -> None:
    rng = np.random.default_rng(3)
    with precision(128):
        for _ in range(20):
            roots = -5.0 * np.arange(1, 5) + rng.uniform(-1, 1, size=4)
            coeffs = np.poly(roots)[::-1]
            rad = 1e-6
            ball = [arb(float(c), rad * max(1.0, abs(c))) for c in coeffs]
            disks = isolate(ball)
            assert disks is not None and len(disks) == 4
            for _m in range(5):
                member = [float(c) + rad * max(1.0, abs(c)) * rng.uniform(-1, 1) for c in coeffs]
                for r in np.roots(member[::-1]):
                    inside = [d for d in disks if d.contains(acb(complex(r)))]
                    assert len(inside) == 1


def test_isolate_refuses_roots_it_cannot_separate() -> None:
    with precision(128):
        # (s + 1)^2 with a wide ball: the two roots cannot be told apart
        assert isolate([arb(1, 0.1), arb(2), arb(1)]) is None


def test_gains_and_names_the_plant_does_not_use_are_refused() -> None:
    with pytest.raises(ParameterError, match="not a plant parameter"):
        ParametricPlant(_ours(kd=None), ("kd",))
    with pytest.raises(ParameterError, match="also used by a controller"):
        ParametricPlant(SEA(D1="k1", CA="k1*s", values=dict(m=1, b=10)), ("k1",))
