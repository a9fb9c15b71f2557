"""Immutable model objects: a 1-DoF series elastic actuator and a raw impedance.

These sit at the bottom of the package: they parse and validate their inputs
and hold data; all analysis lives in the modules above.  An element given as text
is parsed once into a checked tree and, from it, into an exact rational function
([`seapass.model.rational`][seapass.model.rational]; no sympy); the sympy
expression (``sea.CA``, ``sea.elements()``) is built on first access, for the
symbolic analyses.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, NamedTuple, TypeAlias

from ..errors import DegenerateModelError, ExpressionError, ParameterError
from .delayatom import delay_of_variable, model_delays
from .display import html_card, short_repr
from .elements import (
    LazySympy,
    Source,
    check_used,
    element_source,
    exact_of,
    exact_values,
    freeze_values,
    is_sympy,
    poly_names,
    source_names,
    sympy_of,
)
from .expr import STANDARD_SYMBOLS, to_fraction, validate_values
from .rational import RatFunc, context, univariate, variables

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["SEA", "ExprLike", "Impedance", "check_used", "exact_values", "unrealizable_controllers"]

ExprLike: TypeAlias = "str | sp.Expr | int | float"

_ELEMENTS = ("D1", "D2", "CA", "CL")
_ATTRS = (*_ELEMENTS, "m", "b")


class _ImpedanceExpr(LazySympy):
    """The ``expr`` field of `Impedance`: reading it gives the cancelled sympy ``Z``."""

    def __init__(self) -> None:
        super().__init__(None)

    def __get__(self, obj: Any, objtype: Any = None) -> Any:
        if obj is None:
            return self.default
        state = obj.__dict__
        if "_sympy_expr" not in state:
            state["_sympy_expr"] = _impedance_sympy(obj)
        return state["_sympy_expr"]


@functools.lru_cache(maxsize=512)
def _model_elements(sources: tuple[Source, ...], allowed: frozenset[str]) -> tuple[RatFunc, ...]:
    """The exact elements of one model, lifted into the context of all its names (cached)."""
    parts = [exact_of(src, allowed, what) for src, what in zip(sources, _ATTRS, strict=True)]
    names: set[str] = set()
    for f in parts:
        names |= f.parameters()
    ctx = context(variables(names))
    return tuple(f.to_context(ctx) for f in parts)


class _Facts(NamedTuple):
    """What the checks of a model need, computed once per model (cached on its sources)."""

    parameters: tuple[str, ...]
    s_in_mass_or_damping: str
    port_unconnected: bool
    mass: RatFunc
    denominators: tuple[tuple[str, Any, frozenset[str]], ...]  # with parameters only


@functools.lru_cache(maxsize=512)
def _model_facts(sources: tuple[Source, ...], allowed: frozenset[str]) -> _Facts:
    exact = dict(zip(_ATTRS, _model_elements(sources, allowed), strict=True))
    used: set[str] = set()
    for src in sources:  # as written: a name that cancels out is still a parameter
        used |= source_names(src, allowed)
    dens = []
    for attr in _ELEMENTS:
        names = frozenset(poly_names(exact[attr].den) - {"s"})
        if names:  # a denominator in s alone is nonzero: the fraction is reduced
            dens.append((attr, exact[attr].den, names))
    return _Facts(
        parameters=tuple(sorted(used)),
        s_in_mass_or_damping=next(
            (a for a in ("m", "b") if "s" in exact[a].names() or model_delays(exact[a])), ""
        ),
        port_unconnected=exact["D1"].is_zero and exact["D2"].is_zero,
        mass=exact["m"],
        denominators=tuple(dens),
    )


def _rebuild(given: dict[str, Any], values: dict[str, float | None], name: str) -> SEA:
    return SEA(**given, values=values, name=name)


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

    Raises
    ------
    ExpressionError
        For unknown symbols or expressions that are not rational in ``s``.
    ParameterError
        For non-finite values, a name in ``values`` that the model does not use
        (``values['kdd']``, with the closest name it does use), or a mass that is
        not positive.
    DegenerateModelError
        When the load port is connected to nothing (``D1 = D2 = 0``).
    """

    # descriptors: a field holds the element as given, reading it gives sympy (built lazily)
    D1: Any = LazySympy(0)  # noqa: RUF009
    D2: Any = LazySympy(0)  # noqa: RUF009
    CA: Any = LazySympy(0)  # noqa: RUF009
    CL: Any = LazySympy(0)  # noqa: RUF009
    m: Any = LazySympy("m")  # noqa: RUF009
    b: Any = LazySympy("b")  # noqa: RUF009
    values: Mapping[str, float | None] = field(default_factory=dict)
    name: str = ""

    def __post_init__(self) -> None:
        vals = freeze_values(self.values)
        object.__setattr__(self, "values", vals)
        state = self.__dict__
        allowed = frozenset(STANDARD_SYMBOLS) | frozenset(vals)
        state["_allowed"] = allowed
        for attr in _ATTRS:
            state[f"_source_{attr}"] = element_source(state[f"_given_{attr}"], allowed, attr)
        facts = _model_facts(self.sources(), allowed)
        if facts.s_in_mass_or_damping:
            raise ExpressionError(f"{facts.s_in_mass_or_damping} must not depend on s")
        if facts.port_unconnected:
            raise DegenerateModelError(
                "degenerate model: D1 = D2 = 0 leaves the load port connected to nothing; "
                "give a transmission, e.g. --D1 'k1'"
            )
        check_used(vals, facts.parameters)
        known = exact_values(vals)
        if facts.mass.parameters() <= set(known):
            m_num, m_den = facts.mass.evaluate(known)
            mass = m_num[0] / m_den[0]
            if mass <= 0:
                raise ParameterError(f"actuator mass m must be positive, got {float(mass):g}")
        for attr, den, names in facts.denominators:
            if names <= set(known) and univariate(den, known).is_zero():
                raise DegenerateModelError(f"{attr} has a denominator that is identically zero")

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickle the elements as given (caches are rebuilt on the other side)."""
        given = {a: self.__dict__[f"_given_{a}"] for a in _ATTRS}
        return (_rebuild, (given, dict(self.values), self.name))

    def sources(self) -> tuple[Source, ...]:
        """The six elements ``D1 D2 CA CL m b`` as parsed, in a hashable form (cache keys)."""
        return tuple(self.__dict__[f"_source_{a}"] for a in _ATTRS)

    def exact_elements(self) -> dict[str, RatFunc]:
        """The elements ``D1 D2 CA CL m b`` as exact rational functions in one context.

        The context's variables are ``s`` and every parameter of the model; no
        value is substituted (see [`seapass.model.rational`][seapass.model.rational]).

        Examples
        --------
        >>> SEA(D1="k1", CA="kd + ki/s").exact_elements()["CA"]
        RatFunc('(s*kd + ki)/(s)')
        """
        parts = _model_elements(self.sources(), self.__dict__["_allowed"])
        return dict(zip(_ATTRS, parts, strict=True))

    @property
    def known(self) -> set[sp.Symbol]:
        """Symbols whose numeric value is given."""
        from .expr import symbol

        return {symbol(k) for k, v in self.values.items() if v is not None}

    @property
    def parameters(self) -> tuple[str, ...]:
        """Names of all parameters the model uses, sorted."""
        return _model_facts(self.sources(), self.__dict__["_allowed"]).parameters

    @property
    def free_parameters(self) -> tuple[str, ...]:
        """Parameters used by the model that have no numeric value."""
        return tuple(p for p in self.parameters if self.values.get(p) is None)

    def elements(self) -> dict[str, sp.Expr]:
        """The four elements plus ``m`` and ``b`` as sympy expressions."""
        return {a: getattr(self, a) for a in _ATTRS}

    def substitutions(
        self, extra: Mapping[str, float] | None = None
    ) -> dict[sp.Symbol, sp.Rational]:
        """Exact rational substitutions for every parameter with a value."""
        import sympy as sp

        from .expr import symbol

        vals = {k: v for k, v in self.values.items() if v is not None}
        if extra:
            vals.update(validate_values(extra))
        return {symbol(k): sp.Rational(to_fraction(v, k)) for k, v in vals.items()}

    def numeric(self, expr: sp.Expr) -> sp.Expr:
        """Substitute the known values into ``expr`` exactly."""
        import sympy as sp

        return sp.sympify(expr).xreplace(self.substitutions())

    def with_values(self, **values: float | None) -> SEA:
        """A copy with some parameter values changed or added."""
        merged = dict(self.values)
        merged.update(values)
        given = {a: self.__dict__[f"_given_{a}"] for a in _ATTRS}
        return SEA(**given, values=merged, name=self.name)

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

    expr: Any = _ImpedanceExpr()
    num: Any = None
    den: Any = None
    values: Mapping[str, float | None] = field(default_factory=dict)

    def __post_init__(self) -> None:
        vals = freeze_values(self.values)
        object.__setattr__(self, "values", vals)
        state = self.__dict__
        allowed = frozenset(STANDARD_SYMBOLS) | frozenset(vals)
        state["_allowed"] = allowed
        given = state.get("_given_expr")
        if given is not None:
            if self.num is not None or self.den is not None:
                raise ExpressionError("give either expr or num/den, not both")
            sources: Any = ("expr", element_source(given, allowed, "Z"))
        else:
            if self.num is None or self.den is None:
                raise ExpressionError("give Z as an expression or as both num and den")
            sources = ("coeffs", _coefficients(self.num, allowed, "num"))
            sources += (_coefficients(self.den, allowed, "den"),)
        state["_sources"] = sources
        state["_given"] = (given, self.num, self.den)
        # before cancelling: a parameter that cancels out was still used
        check_used(vals, _impedance_parts(sources, allowed)[1], "Z")
        left = _user_names(self.exact().parameters())
        if set(vals) - left:  # a parameter that cancelled out no longer matters
            object.__setattr__(
                self, "values", MappingProxyType({k: v for k, v in vals.items() if k in left})
            )
        object.__setattr__(self, "num", None)
        object.__setattr__(self, "den", None)

    def __reduce__(self) -> tuple[Any, ...]:
        expr, num, den = self.__dict__["_given"]
        return (_rebuild_impedance, (expr, num, den, dict(self.values)))

    def exact(self) -> RatFunc:
        """``Z`` as an exact rational function in lowest terms (no values substituted)."""
        return _impedance_parts(self.__dict__["_sources"], self.__dict__["_allowed"])[0]

    def sources(self) -> tuple[Any, ...]:
        """``Z`` as parsed, in a hashable form (cache keys)."""
        return tuple(self.__dict__["_sources"])

    def with_values(self, **values: float | None) -> Impedance:
        """A copy with some parameter values changed or added."""
        expr, num, den = self.__dict__["_given"]
        return Impedance(expr=expr, num=num, den=den, values={**self.values, **values})

    @property
    def parameters(self) -> tuple[str, ...]:
        return tuple(sorted(_user_names(self.exact().parameters())))

    @property
    def free_parameters(self) -> tuple[str, ...]:
        return tuple(p for p in self.parameters if self.values.get(p) is None)

    def substitutions(self) -> dict[sp.Symbol, sp.Rational]:
        import sympy as sp

        from .expr import symbol

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


def _user_names(names: frozenset[str]) -> frozenset[str]:
    """Parameter names as a user writes them: the delay variable ``_E_tau`` is ``tau``."""
    return frozenset(delay_of_variable(n) or n for n in names)


def _coefficients(coeffs: Any, allowed: frozenset[str], what: str) -> tuple[Source, ...]:
    """Sources of a coefficient sequence (descending powers), or of one expression."""
    if isinstance(coeffs, str) or is_sympy(coeffs):
        return (element_source(coeffs, allowed, what),)
    try:
        seq = list(coeffs)
    except TypeError:
        return (element_source(coeffs, allowed, what),)
    if not seq:
        raise ExpressionError(f"{what}: empty coefficient list")
    return tuple(element_source(c, allowed, f"{what}[{i}]") for i, c in enumerate(seq))


@functools.lru_cache(maxsize=512)
def _impedance_parts(
    sources: tuple[Any, ...], allowed: frozenset[str]
) -> tuple[RatFunc, frozenset[str]]:
    """``Z`` in lowest terms and the names its parts use before cancelling (cached)."""
    if sources[0] == "expr":
        whole = exact_of(sources[1], allowed, "Z")
        return whole, source_names(sources[1], allowed)
    parts = {
        what: [exact_of(src, allowed, f"{what}[{i}]") for i, src in enumerate(srcs)]
        for what, srcs in (("num", sources[1]), ("den", sources[2]))
    }
    names: set[str] = set()
    for src in (*sources[1], *sources[2]):
        names |= source_names(src, allowed)
    exact_names: set[str] = set()
    for fs in parts.values():
        for f in fs:
            exact_names |= f.parameters()
    ctx = context(variables(exact_names))
    s = RatFunc.variable(ctx, "s")
    total = {}
    for what, fs in parts.items():
        acc = RatFunc.constant(ctx, 0)
        for i, f in enumerate(fs):
            acc = acc + f.to_context(ctx) * s ** (len(fs) - 1 - i)
        total[what] = acc
    if total["den"].is_zero:
        raise DegenerateModelError("Z has a zero denominator")
    return total["num"] / total["den"], frozenset(names)


def _impedance_sympy(obj: Impedance) -> Any:
    """``Z`` as sympy, cancelled, exactly as it was built before the exact path existed."""
    import sympy as sp

    from .symbolic import S

    sources, allowed = obj.__dict__["_sources"], obj.__dict__["_allowed"]

    def poly(srcs: tuple[Source, ...]) -> Any:
        n = len(srcs) - 1
        return sp.Add(*[sympy_of(src, allowed) * S ** (n - i) for i, src in enumerate(srcs)])

    if sources[0] == "expr":
        z = sympy_of(sources[1], allowed)
    else:
        z = poly(sources[1]) / poly(sources[2])
    num, den = sp.fraction(sp.cancel(sp.together(z)))
    return num / den


def _rebuild_impedance(expr: Any, num: Any, den: Any, values: dict[str, Any]) -> Impedance:
    return Impedance(expr=expr, num=num, den=den, values=values)


def unrealizable_controllers(sea: SEA) -> dict[str, int]:
    """Controllers that need more than one derivative: ``{name: zeros minus poles}``.

    The controllers see measured positions and velocities, so ``C(s)`` may have
    at most one more zero than poles (``kd + bd*s``).  ``kd*s**3`` needs the
    third derivative of a measurement: it is not realizable, and a verdict on it
    describes an ideal model only.  Degrees are those for generic parameter values.

    >>> unrealizable_controllers(SEA(D1="k1", CA="kd*s**3"))
    {'CA': 3}
    """
    out: dict[str, int] = {}
    exact = sea.exact_elements()
    for name in ("CA", "CL"):
        if exact[name].is_zero:
            continue
        num, den = exact[name].degrees_in_s()
        if num - den > 1:
            out[name] = num - den
    return out
