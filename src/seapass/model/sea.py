"""Immutable model objects: a 1-DoF series elastic actuator and a raw impedance.

These sit at the bottom of the package: they parse and validate their inputs
and hold data; all analysis lives in the modules above.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import sympy as sp

from ..errors import DegenerateModelError, ExpressionError, ParameterError, did_you_mean
from .display import html_card, short_repr
from .expr import (
    STANDARD_SYMBOLS,
    S,
    check_name,
    check_rational_in_s,
    parse_expression,
    symbol,
    to_fraction,
    validate_values,
)

__all__ = ["PLANT_SYMBOLS", "SEA", "ExprLike", "Impedance", "check_used"]

from typing import TypeAlias

ExprLike: TypeAlias = str | sp.Expr | int | float

_ELEMENTS = ("D1", "D2", "CA", "CL")

PLANT_SYMBOLS: tuple[str, ...] = ("m", "b", "k1", "k2", "b1", "b2")
"""Standard names of the hardware: actuator mass and damping, springs and dampers.

With the parameters of ``D1``, ``D2``, ``m``, ``b`` and those an `SEA` declares in
``plant``, they are its plant parameters (`SEA.plant_parameters`): fixed values,
substituted where a controller uses them (``k1`` in ``C_A = C_f*k1``), never tuned or
swept as gains unless asked for by name.
"""


def _as_expr(value: ExprLike, allowed: Iterable[str], what: str) -> sp.Expr:
    if isinstance(value, sp.Expr):
        return _checked_expr(value, frozenset(allowed), what)
    if isinstance(value, str):
        try:
            return parse_expression(value, allowed)
        except ExpressionError as exc:
            raise ExpressionError(f"{what}: {exc}", argument=what) from None
    if isinstance(value, bool):
        raise ExpressionError(f"{what}: expected an expression, got a boolean")
    if isinstance(value, int | float):
        return sp.Rational(to_fraction(value, what))
    return check_rational_in_s(value, allowed, what)


@functools.lru_cache(maxsize=1024)
def _checked_expr(value: sp.Expr, allowed: frozenset[str], what: str) -> sp.Expr:
    """Validation of sympy input is pure, so it is cached (models are rebuilt often)."""
    return check_rational_in_s(value, allowed, what)


@functools.lru_cache(maxsize=1024)
def _denominator(expr: sp.Expr) -> sp.Expr:
    return sp.fraction(sp.together(expr))[1]


def _freeze_values(values: Mapping[str, Any] | None) -> Mapping[str, float | None]:
    if values is not None and not isinstance(values, Mapping):
        raise ParameterError(
            f"values: expected a mapping of names to numbers, got {type(values).__name__}",
            argument="values",
        )
    out: dict[str, float | None] = {}
    for name, val in (values or {}).items():
        if not isinstance(name, str):
            raise ParameterError(
                f"values: parameter names must be strings, got {name!r}", argument="values"
            )
        key = f"values[{name!r}]"
        try:
            check_name(name)
        except ExpressionError as exc:
            raise ParameterError(f"{key}: {exc}", argument=key) from None
        out[name] = None if val is None else float(to_fraction(val, key))
    return MappingProxyType(out)


def check_used(values: Mapping[str, Any], used: Iterable[str], what: str = "the model") -> None:
    """Raise if a name in ``values`` is not a parameter of the model (a typo, usually).

    The message names the Python argument (``values['kdd']``) and the closest
    parameter the model does use.
    """
    used = sorted(used)
    for name in values:
        if name not in used:
            key = f"values[{name!r}]"
            raise ParameterError(
                f"{key}: {name!r} is not a parameter of {what}{did_you_mean(name, used)}; "
                f"it uses {', '.join(used) or 'no parameters'}",
                argument=key,
            )


@dataclass(frozen=True, repr=False)
class SEA:
    """A 1-DoF series elastic actuator with linear control.

    The actuator (mass ``m``, viscous damping ``b`` to ground) is driven by
    ``f_A = C_A(θ_A − x_A) + C_L(θ_L − x_L)`` and joined to a massless load port
    by the transmission ``D1(s)``; ``D2(s)`` joins the port to ground.  Every
    element is a rational function of ``s``, given as safe text such as
    ``"k1 + b1*s"`` or as a sympy expression.  Elements not given are 0.

    Parameters
    ----------
    D1, D2, CA, CL : str or sympy.Expr or number
        Transmission, load-to-ground element, actuator-side and load-side controllers.
    m, b : str or sympy.Expr or number
        Actuator mass and damping, the symbols ``m`` and ``b`` by default.
    values : mapping of str to float or None
        Parameter values; ``None`` declares a free parameter.  Any name used in
        an expression must be one of ``m b k1 k2 b1 b2 kd bd ki`` or a key here.
    plant : tuple of str
        Parameters that belong to the hardware besides `PLANT_SYMBOLS` and those
        of ``D1``, ``D2``, ``m``, ``b`` (a sensor gain, a gear ratio); see
        `plant_parameters` and `gains`.

    Raises
    ------
    ExpressionError
        For unknown symbols or expressions that are not rational in ``s``.
    ParameterError
        For non-finite values, a name in ``values`` or ``plant`` that the model does
        not use (``values['kdd']``, with the closest name it does use), or a mass
        that is not positive.
    DegenerateModelError
        When the load port is connected to nothing (``D1 = D2 = 0``).
    """

    D1: Any = 0
    D2: Any = 0
    CA: Any = 0
    CL: Any = 0
    m: Any = "m"
    b: Any = "b"
    values: Mapping[str, float | None] = field(default_factory=dict)
    name: str = ""
    plant: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if isinstance(self.plant, str) or not all(isinstance(p, str) for p in self.plant):
            raise ParameterError(
                f"plant: expected a tuple of parameter names, got {self.plant!r}", argument="plant"
            )
        object.__setattr__(self, "plant", tuple(sorted(set(self.plant))))
        vals = _freeze_values(self.values)
        object.__setattr__(self, "values", vals)
        allowed = set(STANDARD_SYMBOLS) | set(vals)
        for attr in (*_ELEMENTS, "m", "b"):
            object.__setattr__(self, attr, _as_expr(getattr(self, attr), allowed, attr))
        for attr in ("m", "b"):
            if S in getattr(self, attr).free_symbols:
                raise ExpressionError(f"{attr} must not depend on s")
        if self.D1 == 0 and self.D2 == 0:
            raise DegenerateModelError(
                "degenerate model: D1 = D2 = 0 leaves the load port connected to nothing; "
                "give a transmission, e.g. --D1 'k1'"
            )
        check_used(vals, self.parameters)
        for name in self.plant:
            if name not in self.parameters:
                raise ParameterError(
                    f"plant: {name!r} is not a parameter of the model"
                    f"{did_you_mean(name, self.parameters)}; it uses {', '.join(self.parameters)}",
                    argument="plant",
                )
        mass = self.numeric(self.m) if not (self.m.free_symbols - self.known) else None
        if mass is not None and mass <= 0:
            raise ParameterError(f"actuator mass m must be positive, got {float(mass):g}")
        for attr in _ELEMENTS:
            den = _denominator(getattr(self, attr))
            if den.free_symbols <= self.known | {S} and sp.expand(self.numeric(den)) == 0:
                raise DegenerateModelError(f"{attr} has a denominator that is identically zero")

    @property
    def known(self) -> set[sp.Symbol]:
        """Symbols whose numeric value is given."""
        return {symbol(k) for k, v in self.values.items() if v is not None}

    @property
    def parameters(self) -> tuple[str, ...]:
        """Names of all parameters the model uses, sorted."""
        syms: set[sp.Basic] = set()
        for attr in (*_ELEMENTS, "m", "b"):
            syms |= getattr(self, attr).free_symbols
        return tuple(sorted(str(x) for x in syms if x != S))

    @property
    def free_parameters(self) -> tuple[str, ...]:
        """Parameters used by the model that have no numeric value."""
        return tuple(p for p in self.parameters if self.values.get(p) is None)

    @property
    def plant_parameters(self) -> tuple[str, ...]:
        """The hardware's parameters the model uses, sorted: `PLANT_SYMBOLS`, those of
        ``D1``, ``D2``, ``m``, ``b`` and the declared ``plant``.

        Examples
        --------
        >>> SEA(D1="k1 + b1*s", CA="(kp + ki/s)*k1 + ba*s", values=dict(kp=2, ba=5)).plant_parameters
        ('b', 'b1', 'k1', 'm')
        """
        hardware = set(PLANT_SYMBOLS) | set(self.plant)
        for attr in ("D1", "D2", "m", "b"):
            hardware |= {str(x) for x in getattr(self, attr).free_symbols}
        return tuple(p for p in self.parameters if p in hardware)

    @property
    def gains(self) -> tuple[str, ...]:
        """The controller gains, sorted: parameters of ``C_A`` and ``C_L`` that are not
        plant parameters (a plant parameter inside a controller is substituted, not tuned).

        Examples
        --------
        >>> SEA(D1="k1 + b1*s", CA="(kp + ki/s)*k1 + ba*s", values=dict(kp=2, ba=5)).gains
        ('ba', 'ki', 'kp')
        """
        plant = set(self.plant_parameters)
        used = {str(x) for x in self.CA.free_symbols | self.CL.free_symbols} - {"s"}
        return tuple(sorted(used - plant))

    def elements(self) -> dict[str, sp.Expr]:
        """The four elements plus ``m`` and ``b`` as sympy expressions."""
        return {a: getattr(self, a) for a in (*_ELEMENTS, "m", "b")}

    def substitutions(
        self, extra: Mapping[str, float] | None = None
    ) -> dict[sp.Symbol, sp.Rational]:
        """Exact rational substitutions for every parameter with a value."""
        vals = {k: v for k, v in self.values.items() if v is not None}
        if extra:
            vals.update(validate_values(extra))
        return {symbol(k): sp.Rational(to_fraction(v, k)) for k, v in vals.items()}

    def numeric(self, expr: sp.Expr) -> sp.Expr:
        """Substitute the known values into ``expr`` exactly."""
        return sp.sympify(expr).xreplace(self.substitutions())

    def with_values(self, **values: float | None) -> SEA:
        """A copy with some parameter values changed or added."""
        merged = dict(self.values)
        merged.update(values)
        return dataclasses.replace(self, values=merged)

    def describe(self) -> dict[str, str]:
        """Element expressions as strings (``0`` for absent elements)."""
        return {k: str(v) for k, v in self.elements().items()}

    def to_control(
        self, kind: str = "impedance", *, values: Mapping[str, float] | None = None
    ) -> Any:
        """The port impedance (``kind="impedance"``) or stiffness as a ``control.TransferFunction``.

        ``"impedance"`` is ``Z_L = F_L/(s X_L)`` (input ``v_L``, output ``F_L``),
        ``"stiffness"`` is ``F_L/X_L`` (input ``x_L``).  Coefficients are exact
        until the final rounding; see [`seapass.model.pycontrol`][seapass.model.pycontrol].
        The closed loop as a ``control.StateSpace``:
        ``closed_loop(sea, load_mass=...).to_control()``.

        Examples
        --------
        >>> sea = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=500))
        >>> sea.to_control("stiffness").den_array[0, 0].tolist()
        [1.0, 10.0, 1000.0]
        """
        from .pycontrol import transfer_function

        return transfer_function(self, kind, values=values)

    def __repr__(self) -> str:
        fields: dict[str, Any] = {"name": self.name or None}
        for attr in _ELEMENTS:
            expr = getattr(self, attr)
            if expr != 0:
                fields[attr] = str(expr)
        for attr in ("m", "b"):
            if str(getattr(self, attr)) != attr:
                fields[attr] = str(getattr(self, attr))
        fields["values"] = dict(self.values) if self.values else None
        fields["plant"] = self.plant or None
        return short_repr("SEA", fields)

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [(a, str(getattr(self, a))) for a in (*_ELEMENTS, "m", "b")]
        rows += [(k, "free" if v is None else v) for k, v in self.values.items()]
        return html_card(f"SEA {self.name}".strip(), rows)


@dataclass(frozen=True, repr=False)
class Impedance:
    """A raw rational impedance ``Z(s)`` with optional parameter values.

    Give either ``expr`` (text or sympy) or ``num`` and ``den``.  Coefficient
    sequences for ``num``/``den`` are in *descending* powers of ``s``, as in
    numpy and python-control.
    """

    expr: Any = None
    num: Any = None
    den: Any = None
    values: Mapping[str, float | None] = field(default_factory=dict)

    def __post_init__(self) -> None:
        vals = _freeze_values(self.values)
        object.__setattr__(self, "values", vals)
        allowed = set(STANDARD_SYMBOLS) | set(vals)
        if self.expr is not None:
            if self.num is not None or self.den is not None:
                raise ExpressionError("give either expr or num/den, not both")
            z = _as_expr(self.expr, allowed, "Z")
        else:
            if self.num is None or self.den is None:
                raise ExpressionError("give Z as an expression or as both num and den")
            z = _poly_expr(self.num, allowed, "num") / _poly_expr(self.den, allowed, "den")
        # before cancelling: a parameter that cancels out was still used
        check_used(vals, (str(x) for x in z.free_symbols if x != S), "Z")
        num, den = sp.fraction(sp.cancel(sp.together(z)))
        if sp.expand(den) == 0:
            raise DegenerateModelError("Z has a zero denominator")
        left = {str(x) for x in (num / den).free_symbols}
        if set(vals) - left:  # a parameter that cancelled out no longer matters
            object.__setattr__(
                self, "values", MappingProxyType({k: v for k, v in vals.items() if k in left})
            )
        object.__setattr__(self, "expr", num / den)
        object.__setattr__(self, "num", None)
        object.__setattr__(self, "den", None)

    @property
    def parameters(self) -> tuple[str, ...]:
        return tuple(sorted(str(x) for x in self.expr.free_symbols if x != S))

    @property
    def free_parameters(self) -> tuple[str, ...]:
        return tuple(p for p in self.parameters if self.values.get(p) is None)

    def substitutions(self) -> dict[sp.Symbol, sp.Rational]:
        return {
            symbol(k): sp.Rational(to_fraction(v, k))
            for k, v in self.values.items()
            if v is not None
        }

    def to_control(self) -> Any:
        """``Z(s)`` as a ``control.TransferFunction`` (input ``v``, output ``F``)."""
        from .pycontrol import impedance_transfer_function

        return impedance_transfer_function(self)

    @classmethod
    def from_control(cls, system: Any) -> Impedance:
        """An `Impedance` from a SISO continuous-time ``control.TransferFunction`` or ``StateSpace``.

        The float coefficients are taken as the exact rationals they represent.

        Examples
        --------
        >>> import control
        >>> Impedance.from_control(control.tf([1, 1], [1, 2]))
        Impedance(Z='(s + 1)/(s + 2)')
        """
        from .pycontrol import impedance_from_control

        return impedance_from_control(system)

    def __repr__(self) -> str:
        return short_repr("Impedance", {"Z": str(self.expr), "values": dict(self.values) or None})

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [("Z(s)", str(self.expr))]
        rows += [(k, "free" if v is None else v) for k, v in self.values.items()]
        return html_card("Impedance", rows)


def _poly_expr(coeffs: Any, allowed: Iterable[str], what: str) -> sp.Expr:
    if isinstance(coeffs, str | sp.Expr):
        return _as_expr(coeffs, allowed, what)
    try:
        seq = list(coeffs)
    except TypeError:
        return _as_expr(coeffs, allowed, what)
    if not seq:
        raise ExpressionError(f"{what}: empty coefficient list")
    n = len(seq) - 1
    terms = [_as_expr(c, allowed, f"{what}[{i}]") * S ** (n - i) for i, c in enumerate(seq)]
    return sp.Add(*terms)
