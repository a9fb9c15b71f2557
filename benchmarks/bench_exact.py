"""The exact polynomial kernel before (hand-written Fractions) and after (python-flint).

Two measurements, each on the same inputs for every implementation, with the
answers compared:

* counting the positive real roots of random polynomials of degree 6, 12 and
  16 whose coefficients are floats spread over 12 decades, converted exactly
  (as SEA models produce them): the old kernel (`legacy_exactpoly`, Sturm
  sequences in Fractions), sympy ``Poly.count_roots`` over QQ, and
  ``seapass.exact.poly.count_real_roots``;
* every catalogued design of the paper at its reference values: the exact
  positive-real test before (`legacy_passivity`) and after
  (``seapass.analysis.passivity.positive_real_test``) on the same exact
  ``(N, D)``, and ``is_passive`` end to end.
"""

from __future__ import annotations

import random
from fractions import Fraction
from typing import Any

import sympy as sp

import legacy_exactpoly
import legacy_passivity
from _util import Row, rate, timed
from seapass.analysis.impedance import evaluate_system
from seapass.analysis.passivity import is_passive, positive_real_test
from seapass.exact import poly as ep
from seapass.model.catalog import CATALOG, REFERENCE_VALUES
from seapass.model.sea import SEA

DEGREES = (6, 12, 16)
_X = sp.Symbol("x")


def random_polys(degree: int, n: int, seed: int) -> list[tuple[Fraction, ...]]:
    """``n`` polynomials, float coefficients over 12 decades converted exactly, ascending."""
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        c = [Fraction(rng.uniform(-1, 1) * 10 ** rng.uniform(-3, 9)) for _ in range(degree)]
        out.append((*c, Fraction(rng.uniform(0.1, 10))))
    return out


def _sympy_positive(p: sp.Poly) -> int:
    return int(p.count_roots(0)) - (1 if p.eval(0) == 0 else 0)  # (0, inf), like the others


def _kernel(quick: bool) -> tuple[list[Row], list[str]]:
    rows: list[Row] = []
    lines = [
        "| degree | polynomials timed | before: exactpoly [ms] | sympy `Poly` over QQ [ms] "
        "| after: `exact.poly` [ms] | before/after | sympy/after | same counts |",
        "|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for deg in DEGREES:
        n = 40 if quick else 200
        n_old = max(4, n // (5 if deg <= 6 else 20))
        polys = random_polys(deg, n, seed=deg)
        flint_polys = [ep.as_poly(p) for p in polys]
        sym = [
            sp.Poly([sp.Rational(c.numerator, c.denominator) for c in reversed(p)], _X, domain="QQ")
            for p in polys
        ]
        t_new = timed(lambda fp=flint_polys: [ep.count_real_roots(p, 0) for p in fp], repeat=3)
        t_sym = timed(lambda s=sym: [_sympy_positive(p) for p in s])
        t_old = timed(
            lambda o=polys[:n_old]: [
                legacy_exactpoly.count_real_roots(p, Fraction(0), None) for p in o
            ]
        )
        same = t_new.result == t_sym.result and t_old.result == t_new.result[:n_old]
        ms_new, ms_sym, ms_old = (
            1e3 * t_new.seconds / n,
            1e3 * t_sym.seconds / n,
            1e3 * t_old.seconds / n_old,
        )
        lines.append(
            f"| {deg} | {n} ({n_old} before) | {ms_old:.3g} | {ms_sym:.3g} | {ms_new:.3g} "
            f"| {ms_old / ms_new:,.0f}x | {ms_sym / ms_new:,.1f}x | {same} |"
        )
        rows.append(
            Row(
                task=f"count positive real roots, degree {deg}",
                ours="exact.poly.count_real_roots (python-flint)",
                ours_rate=rate(n, t_new.seconds),
                peer=f"before: exactpoly, {n_old} polynomials",
                peer_rate=rate(n_old, t_old.seconds),
                note=f"sympy Poly.count_roots over QQ {ms_sym:.3g} ms each; same counts: {same}",
            )
        )
    return rows, lines


def paper_designs() -> list[tuple[str, SEA]]:
    """Every catalogued design with its gains at the catalog's reference values."""
    out = []
    for key, d in CATALOG.items():
        used = d.sea().parameters  # values are strict: only the names this model uses
        out.append((key, d.sea({k: v for k, v in REFERENCE_VALUES.items() if k in used})))
    return out


def _legacy(num: Any, den: Any, support: Any) -> Any:
    return legacy_passivity.positive_real_test(
        ep.to_fractions(num), ep.to_fractions(den), support=support
    )


def _passivity(quick: bool) -> tuple[list[Row], list[str]]:
    designs = paper_designs()
    exact = [evaluate_system(sea, None) for _, sea in designs]
    reps = 5 if quick else 20
    n = reps * len(designs)
    t_new = timed(
        lambda: [positive_real_test(a, b, support=s) for _ in range(reps) for a, b, s in exact],
        repeat=3,
    )
    t_old = timed(
        lambda: [_legacy(a, b, s) for _ in range(reps) for a, b, s in exact],
        repeat=3,
    )
    t_front = timed(lambda: [evaluate_system(sea, None) for _ in range(reps) for _, sea in designs])
    t_full = timed(lambda: [is_passive(sea) for _ in range(reps) for _, sea in designs], repeat=3)
    new = [(r.passive, r.reason, r.omega, r.margin) for r in t_new.result[: len(designs)]]
    old = [(r.passive, r.reason, r.omega, r.margin) for r in t_old.result[: len(designs)]]
    same = new == old
    lines = [
        "| design | passive | reason | before = after (verdict, reason, witness, margin) |",
        "|---|---|---|---|",
    ]
    for (key, _), a, b in zip(designs, new, old, strict=True):
        lines.append(f"| {key} | {a[0]} | {a[1] or '-'} | {a == b} |")
    rows = [
        Row(
            task=f"exact positive-real test, {len(designs)} paper designs",
            ours="positive_real_test (python-flint)",
            ours_rate=rate(n, t_new.seconds),
            peer="before: positive_real_test on exactpoly",
            peer_rate=rate(n, t_old.seconds),
            note=f"identical verdicts, reasons, witnesses and margins: {same}",
        ),
        Row(
            task=f"is_passive end to end, {len(designs)} paper designs",
            ours="is_passive (python-flint)",
            ours_rate=rate(n, t_full.seconds),
            peer="before: is_passive on exactpoly",
            peer_rate=rate(n, t_front.seconds + t_old.seconds),
            note="before = the same front end (values, exact N/D) + the old test",
        ),
    ]
    return rows, lines


def run(quick: bool) -> tuple[list[Row], list[str], list[str]]:
    """Rows for the results table, notes, and a markdown section on the kernel."""
    k_rows, k_lines = _kernel(quick)
    p_rows, p_lines = _passivity(quick)
    section = [
        "## Exact polynomial kernel: before and after python-flint",
        "",
        "Counting the positive real roots (`count_real_roots(p, 0)`) of random "
        "polynomials whose coefficients are floats spread over 12 decades, converted "
        "exactly to rationals as SEA models produce them.  *Before* is the hand-written "
        "kernel (Sturm sequences in Python Fractions, frozen in "
        "`benchmarks/legacy_exactpoly.py`); *after* is `seapass.exact.poly` (FLINT's "
        "certified root isolation plus exact checks; see "
        "[Verification](verification.md#5-the-exact-polynomial-kernel-and-its-certification)).  "
        "CPU milliseconds per polynomial; fewer polynomials are timed for the slow old "
        "kernel.",
        "",
        *k_lines,
        "",
        "Every catalogued paper design at the catalog's reference values: the exact "
        "positive-real test before (`benchmarks/legacy_passivity.py`, on the old kernel) "
        "and after, on the same exact `(N, D)`:",
        "",
        *p_lines,
        "",
    ]
    return k_rows + p_rows, [], section
