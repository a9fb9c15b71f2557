"""Immutable model objects: a 1-DoF series elastic actuator (and, re-exported from
[`seapass.model.impedance`][seapass.model.impedance], a raw impedance).

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
from typing import TYPE_CHECKING, Any, NamedTuple, TypeAlias

from ..errors import DegenerateModelError, ExpressionError, ParameterError, did_you_mean
from .delayatom import model_delays
from .display import html_card, short_repr
from .elements import (
    LazySympy,
    Source,
    check_used,
    element_source,
    exact_of,
    exact_values,
    freeze_values,
    poly_names,
    source_names,
)
from .expr import STANDARD_SYMBOLS, to_fraction, validate_values
from .impedance import Impedance
from .rational import RatFunc, context, univariate, variables

if TYPE_CHECKING:
    import sympy as sp

__all__ = [
    "PLANT_SYMBOLS",
    "SEA",
    "ExprLike",
    "Impedance",
    "check_used",
    "exact_values",
    "unrealizable_controllers",
]

ExprLike: TypeAlias = "str | sp.Expr | int | float"

_ELEMENTS = ("D1", "D2", "CA", "CL")
_ATTRS = (*_ELEMENTS, "m", "b")

PLANT_SYMBOLS: tuple[str, ...] = ("m", "b", "k1", "k2", "b1", "b2")
"""Standard names of the hardware: actuator mass and damping, springs and dampers.

With the parameters of ``D1``, ``D2``, ``m``, ``b`` and those an `SEA` declares in
``plant``, they are its plant parameters (`SEA.plant_parameters`): fixed values,
substituted where a controller uses them (``k1`` in ``C_A = C_f*k1``), never tuned or
swept as gains unless asked for by name.
"""


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


def _rebuild(
    given: dict[str, Any],
    values: dict[str, float | None],
    name: str,
    plant: tuple[str, ...] = (),
    discrete: Any = None,
) -> SEA:
    return SEA(**given, values=values, name=name, plant=plant, discrete=discrete)


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
    D1 : str or sympy.Expr or number, default 0
        Transmission from the actuator to the load port, e.g. ``"k1 + b1*s"``
        (a spring with a damper in parallel).
    D2 : str or sympy.Expr or number, default 0
        Element from the load port to ground, e.g. ``"k2"``.
    CA : str or sympy.Expr or number, default 0
        Actuator-side controller, acting on the actuator error ``θ_A − x_A``,
        e.g. ``"kd + bd*s"``.
    CL : str or sympy.Expr or number, default 0
        Load-side controller, acting on the load error ``θ_L − x_L``, e.g. ``"kd"``.
    m : str or sympy.Expr or number, default "m"
        Actuator mass [kg], the symbol ``m`` unless given.
    b : str or sympy.Expr or number, default "b"
        Actuator viscous damping to ground [N·s/m], the symbol ``b`` unless given.
    values : mapping of str to float or None
        Parameter values; ``None`` declares a free parameter.  Any name used in
        an expression must be one of ``m b k1 k2 b1 b2 kd bd ki`` or a key here.
    name : str, default ""
        A label for reports and legends.
    plant : tuple of str
        Parameters that belong to the hardware besides `PLANT_SYMBOLS` and those
        of ``D1``, ``D2``, ``m``, ``b`` (a sensor gain, a gear ratio); see
        `plant_parameters` and `gains`.
    discrete : ZController, optional
        The controller given in ``z`` at its rate
        ([`ZController`][seapass.model.zcontroller.ZController]) instead of ``CA``/``CL``
        (which stay 0): the sampled analyses, the twin and the export run it as is; the
        continuous analyses refuse it.

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

    # descriptors: a field holds the element as given, reading it gives sympy (built lazily)
    D1: Any = LazySympy(0)  # noqa: RUF009
    D2: Any = LazySympy(0)  # noqa: RUF009
    CA: Any = LazySympy(0)  # noqa: RUF009
    CL: Any = LazySympy(0)  # noqa: RUF009
    m: Any = LazySympy("m")  # noqa: RUF009
    b: Any = LazySympy("b")  # noqa: RUF009
    values: Mapping[str, float | None] = field(default_factory=dict)
    name: str = ""
    plant: tuple[str, ...] = ()
    discrete: Any = None

    def __post_init__(self) -> None:
        if isinstance(self.plant, str) or not all(isinstance(p, str) for p in self.plant):
            raise ParameterError(
                f"plant: expected a tuple of parameter names, got {self.plant!r}", argument="plant"
            )
        object.__setattr__(self, "plant", tuple(sorted(set(self.plant))))
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
        if self.discrete is not None:
            self._check_discrete(facts, allowed)
        check_used(vals, self.parameters)
        for name in self.plant:
            if name not in self.parameters:
                raise ParameterError(
                    f"plant: {name!r} is not a parameter of the model"
                    f"{did_you_mean(name, self.parameters)}; "
                    f"it uses {', '.join(self.parameters)}",
                    argument="plant",
                )
        known = exact_values(vals)
        if facts.mass.parameters() <= set(known):
            m_num, m_den = facts.mass.evaluate(known)
            mass = m_num[0] / m_den[0]
            if mass <= 0:
                raise ParameterError(f"actuator mass m must be positive, got {float(mass):g}")
        for attr, den, names in facts.denominators:
            if names <= set(known) and univariate(den, known).is_zero():
                raise DegenerateModelError(f"{attr} has a denominator that is identically zero")

    def _check_discrete(self, facts: _Facts, allowed: frozenset[str]) -> None:
        """A controller in z: CA, CL absent, its names known, causal at known values."""
        from .zcontroller import ZController

        if not isinstance(self.discrete, ZController):
            raise ParameterError(
                f"discrete: expected a ZController, got {self.discrete!r}", argument="discrete"
            )
        exact = self.exact_elements()
        if not (exact["CA"].is_zero and exact["CL"].is_zero):
            raise ParameterError(
                "give the controller either in s (CA, CL) or in z (discrete), not both",
                argument="discrete",
            )
        for name in self.discrete.names:
            if name not in allowed or name == "z":
                raise ExpressionError(
                    f"unknown symbol {name!r} in the controller in z{did_you_mean(name, allowed)}"
                    f"; a new parameter needs a value, e.g. values={{{name!r}: 1.0}}"
                )
        if set(self.discrete.names) <= {k for k, v in self.values.items() if v is not None}:
            self.discrete.coefficients(self.values)  # causal, bounded order, nonzero denominator

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickle the elements as given (caches are rebuilt on the other side)."""
        given = {a: self.__dict__[f"_given_{a}"] for a in _ATTRS}
        return (_rebuild, (given, dict(self.values), self.name, self.plant, self.discrete))

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
        """Names of all parameters the model uses, sorted (a controller in z's included)."""
        names = _model_facts(self.sources(), self.__dict__["_allowed"]).parameters
        if self.discrete is None:
            return names
        return tuple(sorted({*names, *self.discrete.names}))

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
            hardware |= self._names_of(attr)
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
        zc = set(self.discrete.names) if self.discrete is not None else set()
        return tuple(sorted((self._names_of("CA") | self._names_of("CL") | zc) - plant))

    def _names_of(self, attr: str) -> frozenset[str]:
        """The parameters element ``attr`` uses as written (no sympy)."""
        return source_names(self.__dict__[f"_source_{attr}"], self.__dict__["_allowed"])

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
        return SEA(**given, values=merged, name=self.name, plant=self.plant, discrete=self.discrete)

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
        if self.discrete is not None:
            fields["discrete"] = self.discrete.to_table()
        return short_repr("SEA", fields)

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [(a, str(getattr(self, a))) for a in (*_ELEMENTS, "m", "b")]
        rows += [(k, "free" if v is None else v) for k, v in self.values.items()]
        return html_card(f"SEA {self.name}".strip(), rows)


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
