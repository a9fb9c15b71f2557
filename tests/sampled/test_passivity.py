"""Sampled-data passivity of controllers whose elements share poles (issue 22, item 1).

A PI force loop inside an impedance loop puts the integrator in both ``C_A`` and ``C_L``.
Realized as two filters, the loop with the port held had an uncontrollable mode at
``z = 1`` ("unstable, spectral radius about 1") and the power polynomial a spurious zero
at ``ω = 0`` (a bound that ran for minutes).  Over the common denominator both go away.
The verdicts are checked against the independent lifting/energy method of
``tests/lifting_energy.py`` and the work is counted (boxes), never timed.
"""

from __future__ import annotations

import contextlib
import io
import json
import random

import pytest

import seapass.sampled.boxes as boxes_module
from lifting_energy import sea_port
from seapass.cli import main
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.sampled.bound import sampled_passive_bound
from seapass.sampled.controllers import controller_tfs
from seapass.sampled.passivity import sampled_passivity

VALUES = dict(m=0.4, b=3, k1=2500, b1=2, kf=0.5, ki=10, kv=1000, bv=5, ba=5)
CA = "(kf + ki/s)*k1 + ba*s"
CL = "(1 + kf + ki/s)*(kv + bv*s) - (kf + ki/s)*k1"
CASCADE = SEA(D1="k1 + b1*s", CA=CA, CL=CL, values=VALUES)
LOOP = SampledLoop(period=0.001)
NEGATIVE = -1e-9


def test_the_cascade_is_passive_at_1_khz_and_decided_at_the_first_precision() -> None:
    r = sampled_passivity(CASCADE, loop=LOOP)
    assert r.passive and r.reason == ""
    assert r.precision == 128  # no climb up the precision ladder
    assert r.spectral_radius < 1.0  # the port-held loop is the real, minimal one


def test_cli_sampled_check_of_the_cascade() -> None:
    args = ["sampled", "check", "--D1", "k1 + b1*s", "--CA", CA, "--CL", CL, "--period", "0.001",
            *[a for k, v in VALUES.items() for a in ("--set", f"{k}={v}")], "--json"]  # fmt: skip
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(args) == 0
    assert json.loads(out.getvalue())["status"] == "passive"


@pytest.mark.parametrize(
    ("param", "lo", "hi", "edge"), [("kv", 0.0, 5000.0, 1973.2573), ("ki", 1.0, 200.0, None)]
)
def test_bounds_of_the_cascade_are_decided_with_few_boxes(
    monkeypatch: pytest.MonkeyPatch, param: str, lo: float, hi: float, edge: float | None
) -> None:
    calls = []
    original = boxes_module._classify

    def counted(*args, **kwargs):  # type: ignore[no-untyped-def]
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(boxes_module, "_classify", counted)
    base = CASCADE.with_values(**{param: None})
    r = sampled_passive_bound(base, param, loop=LOOP, lo=lo, hi=hi)
    assert r.undecided == ()
    assert len(calls) < 400  # the two-filter version ran into the 20000-box cap
    assert r.design_value is None and r.intervals
    if edge is not None:
        assert abs(r.max_passive - edge) < 1e-3
    # the bound agrees with point verdicts on both sides of its edges
    for e in r.edges:
        for v, want in ((e.lo * (1 - 1e-4), True), (e.hi * (1 + 1e-4), False)):
            if lo < v < hi:
                got = sampled_passivity(base.with_values(**{param: v}), loop=LOOP,
                                        continuous_gate=False)  # fmt: skip
                assert got.passive is want, (param, v)


def _lifted(sea: SEA, loop: SampledLoop, witness: float | None) -> str:
    ka, kl = controller_tfs(sea, loop)
    lifted = sea_port(sea, ka, kl, loop.period, M=8)
    # port held; the lifting realizes K_A and K_L apart, so the copy of a shared integrator
    # that K_L gets sits at exactly 1 (uncontrollable there): left out like the transmission's
    eig = [abs(e) for e in lifted.loop_eigenvalues(held=[2]) if abs(e - 1) > 1e-9]
    if eig and max(eig) > 1 + 1e-12:
        return "unstable"
    best, _theta = lifted.search(extra=() if witness is None else (witness,))
    return "extracts" if best < NEGATIVE else "no extraction"


def test_shared_integrator_verdicts_agree_with_the_lifting_energy_check() -> None:
    rng = random.Random(20261125)
    tally: dict[tuple[str, str], int] = {}
    for i in range(16):
        T = 10 ** rng.uniform(-3.5, -2.5)
        vals = {
            "m": 10 ** rng.uniform(-1, 0.5), "b": 10 ** rng.uniform(0, 1.3),
            "k1": 10 ** rng.uniform(2.5, 4), "b1": 10 ** rng.uniform(-1, 1.5),
            "kf": 10 ** rng.uniform(-1.5, 0.5), "ki": 10 ** rng.uniform(0, 2),
            "kv": 10 ** rng.uniform(2, 3.5), "bv": 10 ** rng.uniform(0, 1.5),
            "ba": 10 ** rng.uniform(-0.5, 1.5), "wf": 10 ** rng.uniform(2, 3),
        }  # fmt: skip
        if i % 4 == 3:  # PID force loop with a filtered derivative: filter pole shared too
            cf = "(kf + ki/s + kf*s/(wf*(1 + s/wf)))"
        else:
            cf, vals = "(kf + ki/s)", {k: v for k, v in vals.items() if k != "wf"}
        sea = SEA(D1="k1 + b1*s", CA=f"{cf}*k1 + ba*s",
                  CL=f"(1 + {cf})*(kv + bv*s) - {cf}*k1", values=vals)  # fmt: skip
        loop = SampledLoop(
            period=T, delay=rng.choice([0, 1]), velocity_filter=rng.choice([None, 50.0])
        )
        r = sampled_passivity(sea, loop=loop, continuous_gate=False)
        witness = None if r.omega is None else r.omega * T
        expected = {"": "no extraction", "unstable": "unstable", "negative_power": "extracts",
                    "low_frequency": "extracts"}[r.reason]  # fmt: skip
        got = _lifted(sea, loop, witness)
        assert got == expected, (vals, T, loop, r.reason, got)
        tally[(r.reason, got)] = tally.get((r.reason, got), 0) + 1
    assert tally.get(("", "no extraction"), 0) >= 5  # passive ones are among them
    assert sum(n for (reason, _g), n in tally.items() if reason != "") >= 5
