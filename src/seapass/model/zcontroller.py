"""A discrete controller given directly in ``z``, at its own rate: `ZController`.

A controller that already runs on a microcontroller is known by its difference
equation, i.e. by its z-transfer functions at the loop rate.  seapass takes them as
they are (nothing is re-discretized)::

    f_A[k] = K_A(z) (θ_A − x_A)[k] + K_L(z) (θ_L − x_L)[k]

with the same sign convention as ``C_A``/``C_L`` of [`SEA`][seapass.model.sea.SEA].
Each of ``K_A``, ``K_L`` is safe text (the whitelist parser of
[`seapass.model.expr`][seapass.model.expr], never ``eval``): numbers, parameter names,
``+ - * /``, integer powers and the variable ``z`` (``z^-1`` is the unit delay), e.g.
``"(b0 + b1*z^-1)/(1 + a1*z^-1)"`` or ``"kp + ki*T*z/(z - 1)"``.  It must be *causal*
(proper in ``z``: no more zeros than poles, so the command at sample ``k`` uses inputs up
to ``k`` only) and of order at most [`MAX_Z_ORDER`][seapass.files.limits.MAX_Z_ORDER].

A `ZController` runs only at its ``rate``: a sampled loop at another rate is refused
(`ZController.check_loop`), naming both rates.  The continuous analyses (``check``,
``bound``, ``region``, the witness, ...) need ``C_A(s)``, ``C_L(s)`` and refuse a design
whose controller is given in ``z`` (`continuous_only`).

Examples
--------
>>> zc = ZController(CA="(kp + 2*z^-1)/(1 - z^-1/2)", rate=1000.0)
>>> zc.names
('kp',)
>>> ka, kl = zc.coefficients({"kp": 3})
>>> ka
((Fraction(3, 1), Fraction(2, 1)), (Fraction(1, 1), Fraction(-1, 2)))
>>> kl
((Fraction(0, 1),), (Fraction(1, 1),))
>>> ZController(CA="z", rate=1000.0).coefficients({})
Traceback (most recent call last):
...
seapass.errors.UnrealizableError: CA_z: not causal (more zeros than poles in z): z
"""

from __future__ import annotations

import ast
import functools
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from ..errors import (
    ContinuousOnlyError,
    ExpressionError,
    FileFormatError,
    ModelError,
    ParameterError,
    SeapassError,
    UnrealizableError,
)
from ..files.limits import MAX_Z_ORDER
from ..files.schema import Field
from .display import html_card, short_repr
from .expr import parse_tree, to_fraction
from .values import RESERVED

if TYPE_CHECKING:
    import sympy as sp

__all__ = [
    "Z_FIELDS",
    "ZCoefficients",
    "ZController",
    "continuous_only",
    "discrete_from_file",
    "discrete_loop",
    "z_coefficients",
]

ZCoefficients = tuple[tuple[Fraction, ...], tuple[Fraction, ...]]
"""``(num, den)`` ascending in ``z⁻¹``, ``den[0] == 1``: one z-transfer function."""

_RATE_RANGE = (1.0, 1e6)  # Hz, as SampledLoop accepts them
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_SIDES = ("CA", "CL")

Z_FIELDS: Mapping[str, Field] = MappingProxyType(
    {
        k: Field(str if k[0] == "C" else float, required=False)
        for k in ("rate", "period", "CA", "CL")
    }
)
"""The keys of a design file's ``[discrete]`` table (``rate`` Hz or ``period`` s, ``CA``, ``CL``)."""


def _names(text: str) -> frozenset[str]:
    """Every identifier of ``text`` (the whitelist check of `parse_tree` comes after)."""
    return frozenset(_NAME.findall(text))


@functools.lru_cache(maxsize=256)
def _tree(text: str, side: str) -> tuple[ast.expr, tuple[str, ...]]:
    """The checked tree of one z-expression and its parameter names (sorted)."""
    names = _names(text) - {"z"}
    for name in sorted(names):
        if name == "s":
            raise ExpressionError(
                f"{side}_z: {text!r} uses s; a controller in z uses z (z^-1 is one sample "
                "of delay), a continuous one goes in CA/CL"
            )
        if name in RESERVED or name.startswith("_"):
            raise ExpressionError(f"{side}_z: {name!r} is not allowed in {text!r}")
    tree = parse_tree(text, names | {"z"})
    if any(isinstance(n, ast.Call) for n in ast.walk(tree)):
        raise ExpressionError(
            f"{side}_z: {text!r} calls a function; use numbers, parameters, z, + - * / and "
            "integer powers"
        )
    return tree, tuple(sorted(n for n in names if n in _used(tree)))


def _used(tree: ast.AST) -> frozenset[str]:
    return frozenset(n.id for n in ast.walk(tree) if isinstance(n, ast.Name)) - {"z"}


def _sympy(text: str, side: str) -> sp.Expr:
    from .symbolic import sympy_expression

    return sympy_expression(_tree(text, side)[0], text)


@functools.lru_cache(maxsize=1024)
def _coefficients(text: str, side: str, values: tuple[tuple[str, Fraction], ...]) -> ZCoefficients:
    import sympy as sp

    from .symbolic import symbol

    expr = _sympy(text, side).xreplace(
        {symbol(k): sp.Rational(v.numerator, v.denominator) for k, v in values}
    )
    return z_coefficients(expr, f"{side}_z", text)


def z_coefficients(expr: sp.Expr, what: str, text: str = "") -> ZCoefficients:
    """``(num, den)`` ascending in ``z⁻¹`` (``den[0] = 1``) of a sympy rational function of
    the symbol ``z`` with numeric coefficients, checked causal and of bounded order.

    Raises
    ------
    ParameterError
        A symbol other than ``z`` left (naming ``values['x']``).
    UnrealizableError, ModelError
        Not causal; a zero denominator or an order above the limit.
    """
    import sympy as sp

    from .symbolic import symbol

    text = text or str(expr)
    side = what
    z = symbol("z")
    left = sorted(str(x) for x in expr.free_symbols - {z})
    if left:
        raise ParameterError(
            f"{side}: no value for {', '.join(left)}; give it, e.g. values={{{left[0]!r}: 1.0}}",
            argument=f"values[{left[0]!r}]",
        )
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    if den == 0 or sp.Poly(den, z).is_zero:
        raise ModelError(f"{side}: {text!r} has a zero denominator for these values")
    pn, pd = sp.Poly(num, z), sp.Poly(den, z)
    if not pn.is_zero and pn.degree() > pd.degree():
        raise UnrealizableError(f"{side}: not causal (more zeros than poles in z): {text}")
    n = pd.degree()
    if n > MAX_Z_ORDER:
        raise ModelError(
            f"{side}: order {n} in z exceeds the limit of {MAX_Z_ORDER}; use a lower-order "
            "controller"
        )
    if pn.is_zero:
        return (Fraction(0),), (Fraction(1),)

    def ascending(p: sp.Poly) -> list[Fraction]:  # coefficient of z^(n-k) at index k
        c = [Fraction(0)] * (n + 1)
        for (e,), a in p.terms():
            r = sp.Rational(a)
            c[n - e] = Fraction(int(r.p), int(r.q))
        return c

    bn, an = ascending(pn), ascending(pd)
    while len(bn) > 1 and bn[-1] == 0:  # 4z/(2z - 1) is 2/(1 - z^-1/2): no trailing zeros
        bn.pop()
    lead = an[0]
    return tuple(x / lead for x in bn), tuple(x / lead for x in an)


@dataclass(frozen=True, kw_only=True, repr=False)
class ZController:
    """``f_A = K_A(z)(θ_A − x_A) + K_L(z)(θ_L − x_L)``, given in ``z`` at ``rate`` Hz.

    Parameters
    ----------
    CA, CL : str, default "0"
        ``K_A(z)`` and ``K_L(z)`` as safe text in ``z`` (``z^-1`` = one sample of delay),
        numbers and parameter names, e.g. ``"(b0 + b1*z^-1)/(1 + a1*z^-1)"``.
    rate : float
        The rate (Hz) the controller was designed for; the sampled loop must run at it.

    Raises
    ------
    ExpressionError
        For text the parser refuses, or that uses ``s``.
    ParameterError
        For a rate outside 1 Hz to 1 MHz, or both controllers zero.

    Examples
    --------
    >>> ZController(CA="2 - 2*z^-1", rate=500.0).period
    0.002
    """

    CA: str = "0"
    CL: str = "0"
    rate: float

    def __post_init__(self) -> None:
        r = self.rate
        lo, hi = _RATE_RANGE
        if isinstance(r, bool) or not isinstance(r, int | float) or not math.isfinite(r):
            raise ParameterError(f"rate: must be a number of Hz, got {r!r}", argument="rate")
        if not lo <= r <= hi:
            raise ParameterError(
                f"rate: {r!r} Hz is outside the supported range [{lo:g}, {hi:g}] Hz",
                argument="rate",
            )
        object.__setattr__(self, "rate", float(r))
        for side in _SIDES:
            text = getattr(self, side)
            if not isinstance(text, str):
                raise ExpressionError(f"{side}_z: expected text in z, got {type(text).__name__}")
            _tree(text.strip() or "0", side)
            object.__setattr__(self, side, text.strip() or "0")
        if self.CA == "0" and self.CL == "0":
            raise ParameterError("a controller in z needs CA_z or CL_z (both are 0)")

    @property
    def period(self) -> float:
        """``1/rate`` (s)."""
        return 1.0 / self.rate

    @property
    def names(self) -> tuple[str, ...]:
        """The parameters the two expressions use, sorted."""
        return tuple(sorted({n for side in _SIDES for n in _tree(getattr(self, side), side)[1]}))

    def coefficients(self, values: Mapping[str, Any]) -> tuple[ZCoefficients, ZCoefficients]:
        """``(K_A, K_L)`` exactly, each ``(num, den)`` ascending in ``z⁻¹`` with ``den[0] = 1``.

        ``values`` gives every parameter of `names` (floats convert exactly).

        Raises
        ------
        ParameterError
            A parameter without a value (naming ``values['x']``).
        UnrealizableError
            An expression that is not causal for these values.
        ModelError
            A zero denominator, or an order above the limit.
        """
        out = []
        for side in _SIDES:
            text = getattr(self, side)
            used = _tree(text, side)[1]
            vals = tuple(
                (k, to_fraction(values[k], k))
                for k in used
                if k in values and values[k] is not None
            )
            out.append(_coefficients(text, side, vals))
        return out[0], out[1]

    def symbolic(self, side: str) -> sp.Expr:
        """``K_A`` (``side="CA"``) or ``K_L`` as a sympy expression in ``z`` and the parameters."""
        return _sympy(getattr(self, side), side)

    def check_loop(self, period: float) -> None:
        """Refuse a sampled loop whose period is not ``1/rate`` (naming both rates).

        Raises
        ------
        ParameterError
        """
        if not math.isclose(float(period) * self.rate, 1.0, rel_tol=1e-9):
            raise ParameterError(
                f"the controller in z runs at {self.rate:g} Hz but the sampled loop at "
                f"{1.0 / float(period):g} Hz (period {float(period):g} s); a z-controller is used "
                "as is, at its own rate: run the loop at that rate (or leave the period out)"
            )

    @classmethod
    def from_table(cls, table: Mapping[str, Any]) -> ZController:
        """From a design file's ``[discrete]`` table (``rate`` Hz or ``period`` s, ``CA``, ``CL``)."""
        if ("rate" in table) == ("period" in table):
            raise ParameterError(
                "rate: give the controller's rate (rate = 1000.0, Hz) or its period "
                "(period = 0.001, s), not both",
                argument="rate",
            )
        rate = table["rate"] if "rate" in table else _inverse(table["period"])
        return cls(CA=table.get("CA", "0"), CL=table.get("CL", "0"), rate=rate)

    def to_table(self) -> dict[str, Any]:
        return {"rate": self.rate, "CA": self.CA, "CL": self.CL}

    def to_dict(self) -> dict[str, Any]:
        return {"kind": "discrete", **self.to_table()}

    def __repr__(self) -> str:
        return short_repr("ZController", self.to_table())

    def _repr_html_(self) -> str:
        return html_card(
            "Controller in z",
            [("K_A(z)", self.CA), ("K_L(z)", self.CL), ("rate", f"{self.rate:g} Hz")],
        )


def _inverse(period: Any) -> float:
    if isinstance(period, bool) or not isinstance(period, int | float) or not period > 0:
        raise ParameterError(
            f"discrete.period: must be a positive number of seconds, got {period!r}",
            argument="period",
        )
    return 1.0 / float(period)


def continuous_only(system: Any, what: str) -> None:
    """Refuse ``system`` (an SEA) when its controller is given in ``z``.

    Raises
    ------
    ContinuousOnlyError
        Saying that ``what`` needs ``C_A(s)``, ``C_L(s)`` and what runs a z-controller.
    """
    zc = getattr(system, "discrete", None)
    if zc is not None:
        raise ContinuousOnlyError(
            f"{what} needs a continuous controller (CA, CL in s); this design's controller "
            f"is given in z at {zc.rate:g} Hz: use the sampled analyses (sampled check|bound|"
            "region), simulate, the rig twin or export c, which run it as is"
        )


def discrete_loop(zc: ZController | None, loop: Any, *, file: bool = False) -> Any:
    """The sampled loop of a design whose controller is given in z: ``loop`` (a
    [`SampledLoop`][seapass.model.loop.SampledLoop]) if it runs at the controller's rate,
    else the controller's rate alone when ``loop`` is None.  Without a controller in z
    (``zc`` None): ``loop``.

    Raises
    ------
    ParameterError
        When ``loop`` runs at another rate (naming both rates); `FileFormatError`
        naming ``discrete.rate`` with ``file=True``.
    """
    from .loop import SampledLoop

    if zc is None:
        return loop
    if loop is None:
        return SampledLoop(rate=zc.rate)
    try:
        zc.check_loop(loop.period)
    except ParameterError as exc:
        if file:
            raise FileFormatError(f"discrete.rate: {exc} ([control])") from None
        raise
    return loop


def discrete_from_file(doc: dict[str, Any]) -> ZController:
    """The ``[discrete]`` table of a checked design document; a ``[control]`` table without
    a rate gets the controller's.

    Raises
    ------
    FileFormatError
        Naming the key (``discrete.CA``), or ``[discrete]`` with ``CA``/``CL``/``[controller]``.
    """
    given = [f"model.{k}" for k in ("CA", "CL") if k in doc["model"]] + ["[controller]"] * (
        "controller" in doc
    )
    if given:
        raise FileFormatError(f"give either [discrete] or {given[0]}, not both")
    values = {**doc["parameters"], **doc.get("plant", {})}
    try:
        zc = ZController.from_table(doc["discrete"])
        zc.coefficients(values)  # causal, bounded, every name with a value: said in file terms
    except SeapassError as exc:
        exc = type(exc)(
            re.sub(r"e\.g\. values=\{'(\w+)': [^}]*\}", r"add \1 to [parameters]", str(exc))
        )
        raise FileFormatError(
            re.sub(r"^(?:discrete\.)?(\w+?)(?:_z)?: ", r"discrete.\1: ", str(exc))
        ) from None
    control = doc.get("control")
    if control is not None and "rate" not in control and "period" not in control:
        doc["control"] = {**control, "rate": zc.rate}
    return zc
