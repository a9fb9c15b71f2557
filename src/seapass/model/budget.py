"""The symbolic work budget: size bounds of an expression as one fraction, and a time limit.

sympy's cancellation of a rational function can take minutes on adversarial
input (``1/(s + k1 + k2 + kd + bd + m + b)**12``).  So the size of the single
fraction sympy would form is bounded from the expression tree first, without
expanding anything (`fraction_size`, `check_symbolic_size`), and a derivation
that still runs too long is stopped (`symbolic_time_limit`).

What lives here: the size bounds and the time limit.  May import:
[`seapass.errors`][seapass.errors] and [`seapass.files`][seapass.files].
"""

from __future__ import annotations

import math
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import NamedTuple

import sympy as sp

from ..errors import SymbolicLimitError
from ..files.limits import MAX_S_DEGREE, MAX_TERMS, SYMBOLIC_TIME_LIMIT

__all__ = [
    "TERM_CAP",
    "FractionSize",
    "check_symbolic_size",
    "fraction_size",
    "symbolic_size",
    "symbolic_time_limit",
]

_S = sp.Symbol("s")  # the Laplace variable of seapass.model.expr (sympy symbols are equal by name)


def _multinomial(terms: int, n: int) -> int:
    """Number of monomials of ``(t_1 + ... + t_terms)**n``, capped to stay small."""
    return min(math.comb(terms + n - 1, n), TERM_CAP)


class FractionSize(NamedTuple):
    """Upper bounds of ``N`` and ``D`` when an expression is brought to one fraction ``N/D``.

    Degrees are in ``s``; terms count monomials in ``s`` and every parameter.
    """

    num_degree: int
    den_degree: int
    num_terms: int
    den_terms: int

    @property
    def degree(self) -> int:
        """``deg N + deg D``."""
        return self.num_degree + self.den_degree

    @property
    def terms(self) -> int:
        """``terms(N) + terms(D)``."""
        return self.num_terms + self.den_terms


TERM_CAP = 10**12
"""Term counts are capped here (beyond every budget, so capping never hides a refusal)."""


def fraction_size(expr: sp.Expr) -> FractionSize:
    """Upper bounds of ``N`` and ``D`` of ``expr`` brought to one fraction ``N/D``.

    Computed from the expression tree without expanding anything (linear in
    the tree size): sums of fractions multiply denominators, products add
    degrees, powers use the multinomial count.

    Examples
    --------
    >>> from seapass.model.expr import parse_expression
    >>> fraction_size(parse_expression("kd + ki/s"))
    FractionSize(num_degree=1, den_degree=1, num_terms=2, den_terms=1)
    """

    from .symbolic import Delay  # loaded by now: symbolic imports this module

    def walk(e: sp.Basic) -> tuple[int, int, int, int]:  # deg N, deg D, terms N, terms D
        if e == _S:
            return 1, 0, 1, 1
        if e.is_Atom or isinstance(e, Delay):  # a delay e^{-sτ} is a constant generator
            return 0, 0, 1, 1
        if isinstance(e, sp.Add):
            dn, dd, tn, td = walk(e.args[0])
            for a in e.args[1:]:
                an, ad, atn, atd = walk(a)
                dn, dd = max(dn + ad, an + dd), dd + ad
                tn, td = min(tn * atd + atn * td, TERM_CAP), min(td * atd, TERM_CAP)
            return dn, dd, tn, td
        if isinstance(e, sp.Mul):
            dn = dd = 0
            tn = td = 1
            for a in e.args:
                an, ad, atn, atd = walk(a)
                dn, dd = dn + an, dd + ad
                tn, td = min(tn * atn, TERM_CAP), min(td * atd, TERM_CAP)
            return dn, dd, tn, td
        if isinstance(e, sp.Pow) and e.exp.is_Integer:
            n = int(e.exp)
            bn, bd, btn, btd = walk(e.base)
            if n < 0:
                bn, bd, btn, btd, n = bd, bn, btd, btn, -n
            return bn * n, bd * n, _multinomial(btn, n), _multinomial(btd, n)
        # anything else (not produced by the parser): count its atoms
        atoms = sum(1 for _ in sp.preorder_traversal(e))
        return atoms, atoms, atoms, atoms

    return FractionSize(*walk(sp.sympify(expr)))


def symbolic_size(expr: sp.Expr) -> tuple[int, int]:
    """Upper bounds ``(deg N + deg D, terms(N) + terms(D))`` of ``expr`` as one fraction ``N/D``.

    See `fraction_size`, which keeps the numerator and denominator apart.
    """
    size = fraction_size(expr)
    return size.degree, size.terms


def check_symbolic_size(expr: sp.Expr, what: str = "expression") -> None:
    """Raise `SymbolicLimitError` when ``expr`` exceeds the symbolic size budget.

    The budget (`MAX_S_DEGREE`, `MAX_TERMS`) bounds the size of the
    single fraction sympy will form, so that derivations stay fast instead of
    hanging on adversarial input such as ``1/(s + k1 + k2 + kd + bd + m + b)**12``.
    """
    deg, terms = symbolic_size(expr)
    if deg > MAX_S_DEGREE or terms > MAX_TERMS:
        raise SymbolicLimitError(
            f"{what} is too large for symbolic analysis (as one fraction up to degree "
            f"{deg} in s and {terms} terms; limits {MAX_S_DEGREE} and {MAX_TERMS}): "
            "simplify it or multiply out numeric factors"
        )


@contextmanager
def symbolic_time_limit(
    seconds: float = SYMBOLIC_TIME_LIMIT, what: str = "symbolic derivation"
) -> Iterator[None]:
    """Raise `SymbolicLimitError` if the block computes longer than ``seconds`` of CPU time.

    CPU time, not wall-clock time: the same input is accepted or refused however busy
    the machine is.  Uses ``ITIMER_PROF``/``SIGPROF`` and is therefore active only in
    the main thread of a process whose profiling interval timer is unused; elsewhere
    (worker threads, dask workers, inside another CPU budget) the size budget of
    `check_symbolic_size` is the only guard.
    """
    usable = (
        hasattr(signal, "setitimer")
        and threading.current_thread() is threading.main_thread()
        and signal.getitimer(signal.ITIMER_PROF) == (0.0, 0.0)
        and signal.getsignal(signal.SIGPROF) in (signal.SIG_DFL, None)
    )
    if not usable:
        yield
        return

    def _expired(signum: int, frame: object) -> None:
        raise SymbolicLimitError(
            f"{what} exceeded its time budget of {seconds:g} s of CPU time: simplify the model"
        )

    old = signal.signal(signal.SIGPROF, _expired)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0.0)
        signal.signal(signal.SIGPROF, old)
