"""Robust (box) passivity: ``robust_check`` vs vertex enumeration and dense box sampling.

Three ways to answer "is the design passive for every plant in the box?":

* **ours**: `seapass.robust.robust_check` (exact for one uncertain parameter,
  certified Bernstein branch and bound for several);
* **vertices**: the exact test at every corner of the box (2^k tests); right only
  when the conditions are multi-affine in the parameters, which they are not
  (the mass enters quadratically);
* **dense sampling**: 10,000 random plants of the box (plus the corners), each
  checked in floating point on a 400-point frequency grid with ``np.roots`` for
  the poles, vectorized with numpy.

Timed on the paper's three designs (LP, APD, ours) with a one-parameter box
(``m`` ±10 %) and a three-parameter box (``m``, ``b``, ``k1`` ±10 %), then judged on
designs whose non-passive plants lie strictly inside the box (no vertex is
non-passive), where the right answer is known.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping

import numpy as np
import sympy as sp

from _util import Row, rate, timed
from seapass.analysis.passivity import is_passive
from seapass.model.catalog import design
from seapass.model.expr import S, symbol
from seapass.model.sea import SEA, Impedance
from seapass.model.stiffness import load_impedance
from seapass.ports.llewellyn import llewellyn_conditions
from seapass.ports.passivity import matrix_passivity
from seapass.ports.twoport import two_port
from seapass.robust import robust_check, robust_two_port_check

NOMINAL = {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 20.0, "kd": 500.0, "bd": 25.0}
ONE = {"m": (0.9, 1.1)}
THREE = {"m": (0.9, 1.1), "b": (9.0, 11.0), "k1": (900.0, 1100.0)}
# non-passive plants only near the centre of the box: every vertex is passive
INTERIOR = {
    "interior-1 (m)": (
        Impedance(expr="(s**2 + (10*(m - 1)**2 - 1/100)*s + 1)/(s**2 + s + 1)", values={"m": 1.0}),
        {"m": (0.9, 1.1)},
    ),
    "interior-2 (m, k2)": (
        Impedance(
            expr="(s**2 + (10*((m - 1)**2 + (k2 - 1)**2) - 1/1000000)*s + 1)/(s**2 + s + 1)",
            values={"m": 1.0, "k2": 1.0},
        ),
        {"m": (0.9, 1.1), "k2": (0.9, 1.1)},
    ),
}


def _paper(key: str) -> SEA:
    d = design(key)
    return d.sea({k: v for k, v in NOMINAL.items() if k in d.sea().parameters})


def vertices(system: SEA | Impedance, box: Mapping[str, tuple[float, float]]) -> bool:
    corners = itertools.product(*box.values())
    return all(is_passive(system, values=dict(zip(box, c, strict=True))).passive for c in corners)


class DenseSampler:
    """Float check of ``n`` random plants of a box (built once, like a user's script)."""

    def __init__(self, system: SEA | Impedance, box: Mapping[str, tuple[float, float]]) -> None:
        names = sorted(box)
        fixed = {k: v for k, v in system.values.items() if k not in box and v is not None}
        if isinstance(system, SEA):
            z = load_impedance(system.with_values(**dict.fromkeys(names)))
        else:
            z = system.expr
        z = z.subs({symbol(k): sp.nsimplify(v) for k, v in fixed.items()})
        num, den = sp.fraction(sp.together(z))
        syms = [symbol(k) for k in names]
        self.z = sp.lambdify([S, *syms], num / den, "numpy")
        self.den = [sp.lambdify(syms, c, "numpy") for c in sp.Poly(den, S).all_coeffs()]
        self.names, self.box = names, box

    def __call__(self, n: int = 10_000, seed: int = 0) -> bool:
        rng = np.random.default_rng(seed)
        lo = np.array([self.box[k][0] for k in self.names])
        hi = np.array([self.box[k][1] for k in self.names])
        pts = np.vstack(
            [np.array(list(itertools.product(*[self.box[k] for k in self.names]))),
             lo + (hi - lo) * rng.random((n, len(self.names)))]
        )  # fmt: skip
        w = np.logspace(-3, 5, 400)[:, None]
        vals = self.z(1j * w, *[pts[:, i][None, :] for i in range(len(self.names))])
        if (vals.real < -1e-9 * np.abs(vals)).any():
            return False
        coeffs = np.array([np.broadcast_to(c(*pts.T), (pts.shape[0],)) for c in self.den]).T
        return not any(np.any(np.roots(c).real > 1e-9) for c in coeffs)


def _port_sampling(sea: SEA, box: Mapping[str, tuple[float, float]], n: int) -> bool:
    """The ordinary exact two-port verdicts (Llewellyn and passivity) at the corners and
    ``n`` random plants of the box: True when every one passes both."""
    tp = two_port(sea)
    rng = np.random.default_rng(0)
    names = sorted(box)
    corners = list(itertools.product(*[box[k] for k in names]))
    plants = corners + [tuple(box[k][0] + (box[k][1] - box[k][0]) * rng.random() for k in names)
                        for _ in range(n)]  # fmt: skip
    for plant in plants:
        m = tp.exact(dict(zip(names, plant, strict=True)))
        if any(c.outcome.value != "passive" for c in llewellyn_conditions(m)):
            return False
        if not matrix_passivity(m).passive:
            return False
    return True


def _two_port_rows(quick: bool) -> list[Row]:
    """``twoport check --uncertain``: the certified verdict against dense exact sampling."""
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**NOMINAL, "kl": 300.0})
    n = 200 if quick else 1_000
    rows = []
    for label, box in (("1-parameter", ONE), ("2-parameter", {**ONE, "b": (8.0, 12.0)}),
                       ("3-parameter", THREE)):  # fmt: skip
        two_port(sea)  # start-up: the symbolic two-port, as `twoport check` pays it too
        ours = timed(lambda box=box: robust_two_port_check(sea, box=box))
        dense = timed(lambda box=box: _port_sampling(sea, box, n))
        r = ours.result
        rows.append(
            Row(
                f"robust two-port check, ours + kl = 300, {label} box",
                f"robust_two_port_check ({r.stability.method}; {r.stability.outcome.value}, "
                f"{r.passivity.outcome.value})",
                rate(1, ours.seconds),
                f"exact verdicts at {n:,} sampled plants + corners",
                rate(1, dense.seconds),
                f"ours {ours.seconds:.3f} s (a proof for every plant); sampling "
                f"{dense.seconds:.3f} s (evidence only), says "
                f"{'both hold' if dense.result else 'a plant FAILS'}",
            )
        )
    return rows


def run(quick: bool) -> tuple[list[Row], list[str]]:
    rows: list[Row] = []
    notes: list[str] = []
    n = 2_000 if quick else 10_000
    for key in ("LP", "APD", "ours"):
        sea = _paper(key)
        is_passive(sea)  # start-up: the model's symbolic derivation, as `check` pays it too
        for label, box in (("1-parameter", ONE), ("3-parameter", THREE)):
            cold = timed(lambda sea=sea, box=box: robust_check(sea, box=box))
            warm = timed(lambda sea=sea, box=box: robust_check(sea, box=box), repeat=3)
            vert = timed(lambda sea=sea, box=box: vertices(sea, box), repeat=3)
            sampler = DenseSampler(sea, box)
            dense = timed(lambda sampler=sampler: sampler(n), repeat=1)
            verdict = cold.result.outcome.value
            rows.append(
                Row(
                    f"robust check, {key}, {label} box",
                    f"robust_check ({cold.result.method}; {verdict})",
                    rate(1, warm.seconds),
                    f"dense sampling, {n:,} plants",
                    rate(1, dense.seconds),
                    f"first call {cold.seconds:.3f} s, repeat {warm.seconds:.3f} s; vertices "
                    f"(exact, {2 ** len(box)} tests) {vert.seconds:.3f} s; all three say "
                    f"{'passive' if vert.result and dense.result else 'NOT the same'}",
                )
            )
    for label, (system, box) in INTERIOR.items():
        ours = timed(lambda system=system, box=box: robust_check(system, box=box))
        vert = vertices(system, box)
        dense = DenseSampler(system, box)(n)
        right = ours.result.outcome.value == "not_passive"
        worst = ours.result.worst
        where = ", ".join(f"{k}={v:.4g}" for k, v in worst.values.items()) if worst else "-"
        notes.append(
            f"interior worst case, {label}: robust_check says "
            f"{ours.result.outcome.value} ({'right' if right else 'WRONG'}; worst plant {where}, "
            f"inside the box) in {ours.seconds:.3f} s; vertex enumeration says "
            f"{'passive (wrong)' if vert else 'not passive'}; dense sampling of {n:,} plants says "
            f"{'passive (wrong)' if dense else 'not passive (right)'}"
        )
    rows += _two_port_rows(quick)
    rows.append(_sampled_row(quick))
    rows += _sampled_box_rows(quick)
    return rows, notes


def _sampled_row(quick: bool) -> Row:
    """The sampled-data robust verdict (Ours, kd = 500, 500 Hz, one sample of delay) on a
    narrow mass box against the ordinary certified verdict at N plants of the box."""
    from seapass.model.loop import SampledLoop
    from seapass.robust import robust_sampled_check
    from seapass.sampled.passivity import sampled_passivity

    loop = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s",
              values=dict(m=1.0, b=10, k1=1000, b1=300, kd=500, bd=300))  # fmt: skip
    box = {"m": (0.99, 1.01)}
    ours = timed(lambda: robust_sampled_check(sea, loop=loop, box=box, budget=8))
    n = 20 if quick else 200
    masses = np.linspace(0.99, 1.01, n)
    dense = timed(
        lambda: all(
            sampled_passivity(sea, loop=loop, values={"m": float(m)}).passive for m in masses
        )
    )
    r = ours.result
    return Row(
        "robust sampled check, ours kd=500 at 500 Hz, m in 1 +/- 1 %",
        f"robust_sampled_check ({r.outcome.value}, {r.boxes} sub-boxes, certified)",
        rate(1, ours.seconds),
        f"ordinary sampled verdict at {n} plants (not a proof)",
        rate(1, dense.seconds),
        f"robust {ours.seconds:.2f} s, {n} plants {dense.seconds:.2f} s; the plants say "
        f"{'passive' if dense.result else 'NOT passive'}; the robust verdict is "
        f"{'right' if (r.outcome.value == 'passive') == dense.result else 'NOT the same'}",
    )


def _sampled_box_rows(quick: bool) -> list[Row]:
    """The sampled-data robust verdict on a box of three plant parameters and on a box of a
    gain and a plant parameter (second-order Taylor enclosures), against the ordinary
    certified verdict at N plants drawn from the box (uniformly, seeded)."""
    from seapass.model.loop import SampledLoop
    from seapass.robust import robust_sampled_check
    from seapass.sampled.passivity import sampled_passivity

    loop = SampledLoop(period=0.002, delay=1, velocity_filter=50.0)
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s",
              values=dict(m=1.0, b=10, k1=1000, b1=300, kd=500, bd=300))  # fmt: skip
    w = 0.001 if quick else 0.01
    boxes = [
        (f"m, b, b1 in +/- {w:.1%}", {"m": (1 - w, 1 + w), "b": (10 * (1 - w), 10 * (1 + w)),
                                     "b1": (300 * (1 - w), 300 * (1 + w))}),
        ("kd in [400, 500] x m in [1, 1.0001]", {"kd": (400.0, 500.0), "m": (1.0, 1.0001)}),
    ]  # fmt: skip
    n = 20 if quick else 200
    rows = []
    for label, box in boxes:
        ours = timed(lambda box=box: robust_sampled_check(sea, loop=loop, box=box, budget=64))
        rng = np.random.default_rng(26)
        plants = [{k: float(rng.uniform(lo, hi)) for k, (lo, hi) in box.items()} for _ in range(n)]
        dense = timed(
            lambda plants=plants: all(
                sampled_passivity(sea, loop=loop, values=p).passive for p in plants
            )
        )
        r = ours.result
        rows.append(
            Row(
                f"robust sampled check, ours at 500 Hz, {label}",
                f"robust_sampled_check ({r.outcome.value}, {r.boxes} sub-boxes, certified)",
                rate(1, ours.seconds),
                f"ordinary sampled verdict at {n} plants of the box (not a proof)",
                rate(1, dense.seconds),
                f"robust {ours.seconds:.2f} s, {n} plants {dense.seconds:.2f} s; the plants say "
                f"{'passive' if dense.result else 'NOT passive'}; the robust verdict is "
                f"{'right' if (r.outcome.value == 'passive') == dense.result else 'NOT the same'}",
            )
        )
    return rows


if __name__ == "__main__":  # pragma: no cover - manual run
    r, notes_ = run(quick=True)
    for row in r:
        print(row)
    for note in notes_:
        print(note)
