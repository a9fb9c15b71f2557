"""The passive set of a gain, sampled at period T with d samples of delay versus continuous
at ``τ = (d + ½) T``: which direction the shared low-frequency condition implies.

Both loops share the low-frequency condition exactly (`test_consistency`): for the
actuator-side wall ``C_A = kd + bd s`` behind the spring it reads ``b + bd - kd τ ≥ 0``.
For the continuous loop it is the binding one (its passive set of ``kd`` is
``[0, (b + bd)/τ]``, certified by ``passive_gain_intervals``); the sampled loop must
satisfy it too, so

* **sampled passive ⇒ continuously passive at τ = (d + ½)T**: the certified sampled set of
  ``kd`` lies inside the certified continuous one;
* with ``bd = 0`` they coincide (Colgate–Schenkel ``kd ≤ 2b/((2d + 1)T) = b/τ``);
* the converse fails with a virtual damper: sampling aliases, and at ``d = 0`` the sampled
  bound is Colgate–Schenkel's ``2(b - bd)/T``, below the continuous ``(b + bd)/τ``.
"""

from __future__ import annotations

import pytest

from seapass.delay.gainbound import passive_gain_intervals
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.sampled.bound import sampled_passive_bound

T, B = 0.002, 10.0


@pytest.mark.parametrize(("d", "bd"), [(0, 0.0), (1, 0.0), (0, 5.0), (1, 2.0), (1, 5.0)])
def test_sampled_set_inside_the_continuous_set(d, bd):
    tau = (d + 0.5) * T
    values = dict(m=1, b=B, k1=1000, kd=None, bd=bd)
    sampled = sampled_passive_bound(SEA(D1="k1", CA="kd + bd*s", values=values), "kd",
                                    loop=SampledLoop(period=T, delay=d), lo=0, hi=3e4, rtol=1e-9)  # fmt: skip
    delayed = SEA(D1="k1", CA="(kd + bd*s)*exp(-tau*s)", values={**values, "tau": tau})
    cont = passive_gain_intervals(delayed, "kd", 0, 3e4, points=9, rtol=1e-7)
    ((lo, hi),) = cont.intervals
    ((_, upper),) = cont.edges
    assert cont.outcome is Outcome.PASSIVE and lo == 0.0 and upper is not None
    limit = (B + bd) / tau  # the shared low-frequency condition, binding for the continuous loop
    assert hi <= limit * (1 + 1e-12) and upper[0] <= limit <= upper[1] * (1 + 1e-12)
    # sampled passive => continuously passive at tau = (d + 1/2) T
    assert sampled.max_passive <= upper[1]
    if bd == 0:  # Colgate-Schenkel: the two coincide
        assert sampled.max_passive == pytest.approx(limit, rel=1e-6)
    elif d == 0:  # the converse fails: aliasing makes the sampled bound 2(b - bd)/T
        assert sampled.max_passive == pytest.approx(2 * (B - bd) / T, rel=1e-6)
        assert sampled.max_passive < 0.9 * hi
