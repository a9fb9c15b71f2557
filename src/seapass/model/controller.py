"""SEA controller blocks compiled exactly into the two controllers ``C_A(s)``, ``C_L(s)``.

seapass analyses any linear controller in the form

``f_A = C_A (θ − x_A) + C_L (θ − x_L)``

(`seapass.model.sea.SEA`).  The controllers SEA designers draw are block
diagrams instead: a force loop on the measured spring force, an outer loop
rendering a target impedance, an inner motor-velocity loop, damping injected on
the actuator velocity.  A `Controller` holds such a diagram as the expressions
of its blocks; `derive_controller` *solves the diagram* for ``f_A`` with sympy
(no formula per kind is typed in: the diagram's signal equations are
substituted into each other) and reads off ``C_A`` and ``C_L`` exactly.

Sign convention (the one of the paper and of `SEA`): positions ``x_A``,
``x_L`` and the actuator force ``f_A`` are positive in the same direction;
``θ`` is the position reference; the measured force
``f_s = K_s (x_A − x_L)`` (``K_s = k1`` for a spring, the transmission
``k1 + b1 s`` for a load cell) is the force the transmission exerts on the
load, positive pushing it the way ``f_A`` pushes; a force reference ``f_d``
asks for that force.  Positive gains are restoring.  (The port force ``F_L``
of the analysis, applied by the person, is positive stretching the
transmission: at rest ``f_s = −F_L`` when ``D2 = 0``.)

The diagrams (every block acts on errors, so ``θ`` enters only as ``θ − x``):

``force``
    ``f_s = K_s (x_A − x_L)``;
    ``f_A = φ f_d + C_f (f_d − f_s) + b_a s (θ − x_A)``, the force reference
    ``f_d`` an external command (0 at the port: a zero-force, "transparent" mode).
``impedance``
    the same force loop, with ``f_d = Z_v (θ − x_L)`` from an outer loop rendering
    the target impedance ``Z_v`` (``kv + bv s``, optionally ``+ mv s²``).
    With feed-forward (``φ = 1``):
    ``C_A = C_f K_s + b_a s`` and ``C_L = (1 + C_f) Z_v − C_f K_s``.
``velocity-sourced``
    the force loop commands a motor velocity, an inner loop ``C_v`` tracks it:
    ``v_d = C_f (f_d − f_s)``, ``f_A = φ f_d + C_v (v_d + s (θ − x_A)) + b_a s (θ − x_A)``
    with ``f_d = Z_v (θ − x_L)`` (Pratt/Wyeth/Vallery-type cascades).

``φ`` is 1 with ``feedforward`` (the force reference is also applied directly),
else 0; ``b_a`` is the damping injected on the actuator velocity (``damping``).

Examples
--------
>>> d = derive_controller(Controller(kind="impedance", force="kp + ki/s", impedance="kv + bv*s",
...                                  damping="ba", feedforward=True))
>>> d.general["CA"], d.general["CL"]
('C_f*K_s + b_a*s', '-C_f*K_s + Z_v*(C_f + 1)')
>>> d.CA
'(kp + ki/s)*k1 + ba*s'

References
----------
.. [1] G. A. Pratt and M. M. Williamson, "Series elastic actuators", IROS 1995.
.. [2] G. Wyeth, "Control issues for velocity sourced series elastic actuators",
   ACRA 2006.
.. [3] H. Vallery, R. Ekkelenkamp, H. van der Kooij and M. Buss, "Passive and
   accurate torque control of series elastic actuators", IROS 2007.
"""

from __future__ import annotations

import ast
import functools
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from enum import StrEnum
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from ..errors import ExpressionError, FileFormatError, ParameterError, SeapassError
from ..files.schema import Field
from .display import html_card, short_repr
from .expr import STANDARD_SYMBOLS, parse_expression

if TYPE_CHECKING:  # sympy is imported when a diagram is solved, not when a file is read
    import sympy as sp

__all__ = [
    "BLOCKS",
    "CONTROLLER_FIELDS",
    "Controller",
    "ControllerDerivation",
    "ControllerKind",
    "derive_controller",
]


class ControllerKind(StrEnum):
    """The block diagrams `derive_controller` compiles."""

    FORCE = "force"
    """A force loop on the measured force; its reference is an external command."""
    IMPEDANCE = "impedance"
    """An outer loop rendering a target impedance around a force loop."""
    VELOCITY_SOURCED = "velocity-sourced"
    """A target impedance around a force loop around an inner motor-velocity loop."""

    @property
    def description(self) -> str:
        """One line saying what the diagram is."""
        return {
            "force": "force loop on the measured force, external force reference",
            "impedance": "target impedance around a force loop",
            "velocity-sourced": "target impedance around a force loop commanding a "
            "motor-velocity loop",
        }[self.value]


BLOCKS: Mapping[str, tuple[str, str, int]] = MappingProxyType(
    {
        "force": ("C_f", "force-loop compensator", 0),
        "impedance": ("Z_v", "target impedance of the outer loop", -2),
        "velocity": ("C_v", "motor-velocity loop compensator", 0),
        "damping": ("b_a", "damping injected on the actuator velocity", 0),
        "sensor": ("K_s", "measured force per unit deflection", -1),
    }
)
"""Each block of a `Controller`: its symbol in the diagram, what it is, and the least
relative degree (poles minus zeros) it may have."""

_NEEDS = {  # kind -> blocks it must have; blocks no kind but these may have
    ControllerKind.FORCE: ("force",),
    ControllerKind.IMPEDANCE: ("force", "impedance"),
    ControllerKind.VELOCITY_SOURCED: ("force", "impedance", "velocity"),
}
_ONLY = {"impedance": (ControllerKind.IMPEDANCE, ControllerKind.VELOCITY_SOURCED),
         "velocity": (ControllerKind.VELOCITY_SOURCED,)}  # fmt: skip
_EXAMPLE = {"force": "kp + ki/s", "impedance": "kv + bv*s", "velocity": "kvp + kvi/s"}

CONTROLLER_FIELDS: Mapping[str, Field] = MappingProxyType(
    {
        "kind": Field(str, choices=tuple(k.value for k in ControllerKind),
                      hint='"force", "impedance" or "velocity-sourced"'),
        **{k: Field(str, required=False) for k in BLOCKS},
        "feedforward": Field(bool, required=False),
    }
)  # fmt: skip
"""The keys of a design file's ``[controller]`` table (checked by
[`check_table`][seapass.files.schema.check_table], then `Controller.from_table`)."""

_RESERVED = {"s", "w", "I", "E", "pi", "oo", "nan", "zoo"}


@functools.cache
def _symbols() -> tuple[Any, dict[str, Any]]:
    """The diagrams' signals ``θ x_A x_L e_A e_L f_ref f_d f_s v_d f_A`` and the block symbols."""
    import sympy as sp

    signals = sp.symbols("theta x_A x_L e_A e_L f_ref f_d f_s v_d f_A")
    return signals, {arg: sp.Symbol(sym) for arg, (sym, _, _) in BLOCKS.items()}


@dataclass(frozen=True, kw_only=True, repr=False)
class Controller:
    """An SEA controller as blocks (see the module docstring for the diagrams).

    Parameters
    ----------
    kind : ControllerKind or str
        ``"force"``, ``"impedance"`` or ``"velocity-sourced"``.
    force : str
        The force-loop compensator ``C_f`` (P, PI, PID with a filtered derivative,
        any proper expression), e.g. ``"kp + ki/s"``.  Every kind has one.
    impedance : str, optional
        The target impedance ``Z_v`` of the outer loop, e.g. ``"kv + bv*s"``
        (``+ mv*s**2`` for a target mass); required by ``impedance`` and
        ``velocity-sourced``, refused by ``force``.
    velocity : str, optional
        The motor-velocity loop ``C_v``, e.g. ``"kvp + kvi/s"``; only (and
        required) for ``velocity-sourced``.
    damping : str, optional
        The damping ``b_a`` injected on the actuator velocity, e.g. ``"ba"``.
    feedforward : bool
        Also apply the force reference directly (``f_A += f_d``).
    sensor : str
        The measured force per unit deflection ``x_A − x_L``: ``"k1"`` (the
        spring's deflection, the default) or the transmission ``"k1 + b1*s"`` for
        a load cell.

    Raises
    ------
    ParameterError
        For an unknown kind, a block the kind needs but is not given, a block it
        does not have, or a block that is not a string; the message names the
        argument.  The expressions themselves are checked by `derive_controller`.
    """

    kind: ControllerKind  # a str is converted (ControllerKind("impedance"))
    force: str
    impedance: str | None = None
    velocity: str | None = None
    damping: str | None = None
    feedforward: bool = False
    sensor: str = "k1"

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "kind", ControllerKind(self.kind))
        except ValueError:
            known = ", ".join(repr(k.value) for k in ControllerKind)
            raise ParameterError(
                f"kind: unknown controller kind {self.kind!r}; choose one of {known}",
                argument="kind",
            ) from None
        if not isinstance(self.feedforward, bool):
            raise ParameterError(
                f"feedforward: expected true or false, got {self.feedforward!r}",
                argument="feedforward",
            )
        for arg in BLOCKS:
            text = getattr(self, arg)
            if text is not None and (not isinstance(text, str) or not text.strip()):
                raise ParameterError(
                    f"{arg}: expected an expression in s (text), got {text!r}", argument=arg
                )
        for arg in _NEEDS[self.kind]:
            if getattr(self, arg) is None:
                raise ParameterError(
                    f"{arg}: kind {self.kind.value!r} needs the {BLOCKS[arg][1]} "
                    f"{BLOCKS[arg][0]}, e.g. {_EXAMPLE[arg]!r}",
                    argument=arg,
                )
        for arg, kinds in _ONLY.items():
            if getattr(self, arg) is not None and self.kind not in kinds:
                others = " or ".join(repr(k.value) for k in kinds)
                raise ParameterError(
                    f"{arg}: kind {self.kind.value!r} has no {BLOCKS[arg][1]}; "
                    f"it belongs to kind {others}",
                    argument=arg,
                )

    @classmethod
    def from_table(cls, table: Mapping[str, Any], *, where: str = "controller") -> Controller:
        """A `Controller` from a ``[controller]`` table checked against `CONTROLLER_FIELDS`;
        errors name ``where.key``."""
        try:
            return cls(**dict(table))
        except SeapassError as exc:
            raise FileFormatError(file_words(exc, where)) from None

    def elements(self, parameters: Iterable[str], *, where: str = "controller") -> tuple[str, str]:
        """``(CA, CL)`` of `derive_controller` for a file; errors name ``where.key``."""
        try:
            d = derive_controller(self, parameters=parameters)
        except SeapassError as exc:
            raise FileFormatError(file_words(exc, where)) from None
        return d.CA, d.CL

    def blocks(self) -> dict[str, str]:
        """The blocks given, by argument name (``{"force": "kp + ki/s", ...}``)."""
        return {a: getattr(self, a) for a in BLOCKS if getattr(self, a) is not None}

    def to_table(self) -> dict[str, Any]:
        """The ``[controller]`` table of a design file (what `from_table` reads)."""
        out: dict[str, Any] = {"kind": self.kind.value, **self.blocks()}
        if self.feedforward:
            out["feedforward"] = True
        if self.sensor == "k1":
            del out["sensor"]
        return out

    def to_dict(self) -> dict[str, Any]:
        return {"kind": str(self.kind), **self.blocks(), "feedforward": self.feedforward}

    def __repr__(self) -> str:
        fields_: dict[str, Any] = {"kind": str(self.kind), **self.blocks()}
        if self.feedforward:
            fields_["feedforward"] = True
        return short_repr("Controller", fields_)

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [("kind", self.kind.description)]
        rows += [(f"{BLOCKS[a][0]} ({BLOCKS[a][1]})", t) for a, t in self.blocks().items()]
        rows.append(("force feed-forward", "yes" if self.feedforward else "no"))
        return html_card(f"Controller ({self.kind.value})", rows)


def file_words(exc: SeapassError, where: str = "controller") -> str:
    """An error of `Controller` or `derive_controller` in the words of a file:
    ``controller.force: ...`` (a new parameter: add it to ``[parameters]``)."""
    msg, arg = str(exc), exc.argument or ""
    if arg and msg.startswith(f"{arg}: "):
        msg = msg[len(arg) + 2 :]
    msg = re.sub(r"e\.g\. values=\{'(\w+)': [^}]*\}", r"add \1 to [parameters]", msg)
    return f"{where}.{arg}: {msg}" if arg else f"{where}: {msg}"


@dataclass(frozen=True, kw_only=True, repr=False)
class ControllerDerivation:
    """``C_A`` and ``C_L`` of a `Controller`, derived from its block diagram.

    Attributes
    ----------
    controller : Controller
    diagram : tuple of (str, str)
        The signal equations solved, ``("f_d", "Z_v*(theta - x_L)")``, in order.
    general : mapping of str to str
        ``{"CA": ..., "CL": ...}`` in the block symbols (``C_f``, ``Z_v``, ...).
    blocks : mapping of str to str
        Each block symbol used and its expression, ``{"C_f": "kp + ki/s", ...}``.
    CA, CL : str
        The controllers: the general forms with the blocks put in (text that
        [`SEA`][seapass.model.sea.SEA] parses exactly).
    reference : str or None
        For ``kind = "force"``: the gain from the external force command
        ``f_ref`` to ``f_A`` (``C_f``, or ``C_f + 1`` with feed-forward); it does
        not change the port.
    """

    controller: Controller
    diagram: tuple[tuple[str, str], ...]
    general: Mapping[str, str]
    blocks: Mapping[str, str]
    CA: str
    CL: str
    reference: str | None = None

    def lines(self) -> list[str]:
        """The derivation as text lines (what ``seapass check --explain`` prints)."""
        c = self.controller
        out = [f"controller: {c.kind.value} ({c.kind.description})"]
        out += [f"  {name} = {text}" for name, text in self.blocks.items()]
        out.append(f"  force feed-forward: {'yes' if c.feedforward else 'no'}")
        out.append("block diagram (e_A = theta - x_A, e_L = theta - x_L):")
        out += [f"  {sig} = {rhs}" for sig, rhs in self.diagram]
        out.append("solved for f_A = C_A*e_A + C_L*e_L:")
        out += [f"  C_A = {self.general['CA']}", f"  C_L = {self.general['CL']}"]
        if self.reference is not None:
            out.append(f"  (the force command f_ref enters as ({self.reference})*f_ref)")
        out += [f"  C_A = {self.CA}", f"  C_L = {self.CL}"]
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "controller": self.controller.to_dict(),
            "diagram": [{"signal": s, "equals": r} for s, r in self.diagram],
            "general": dict(self.general),
            "blocks": dict(self.blocks),
            "CA": self.CA,
            "CL": self.CL,
            "reference": self.reference,
        }

    def __repr__(self) -> str:
        return short_repr(
            "ControllerDerivation",
            {"kind": str(self.controller.kind), "CA": self.CA, "CL": self.CL},
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [(s, r) for s, r in self.diagram]
        rows += [("C_A", f"{self.general['CA']} = {self.CA}")]
        rows += [("C_L", f"{self.general['CL']} = {self.CL}")]
        return html_card(f"Controller ({self.controller.kind.value}) → C_A, C_L", rows)


def _diagram(c: Controller) -> list[tuple[sp.Symbol, sp.Expr]]:
    """The signal equations of ``c``'s diagram in the block symbols, in order."""
    import sympy as sp

    S = sp.Symbol("s")  # the s of every expression (seapass.model.symbolic.S)
    (_THETA, _XA, _XL, _, _, _FREF, _FD, _FS, _VD, _FA), y = _symbols()
    phi = sp.Integer(1 if c.feedforward else 0)
    cf, zv, ks, cv, ba = (y[a] for a in ("force", "impedance", "sensor", "velocity", "damping"))
    damp = ba * S * (_THETA - _XA) if c.damping is not None else sp.Integer(0)
    eqs = [(_FD, _FREF if c.kind is ControllerKind.FORCE else zv * (_THETA - _XL)),
           (_FS, ks * (_XA - _XL))]  # fmt: skip
    if c.kind is ControllerKind.VELOCITY_SOURCED:
        eqs.append((_VD, cf * (_FD - _FS)))
        eqs.append((_FA, phi * _FD + cv * (_VD + S * (_THETA - _XA)) + damp))
    else:
        eqs.append((_FA, phi * _FD + cf * (_FD - _FS) + damp))
    return eqs


def _solve(eqs: list[tuple[sp.Symbol, sp.Expr]]) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """``(C_A, C_L, ∂f_A/∂f_ref)`` of a diagram, by substituting its equations."""
    import sympy as sp

    (_THETA, _XA, _XL, _EA, _EL, _FREF, _, _, _, _FA), y = _symbols()
    known: dict[sp.Symbol, sp.Expr] = {}
    for sig, rhs in eqs:
        known[sig] = rhs.xreplace(known)
    f_a = known[_FA].xreplace({_XA: _THETA - _EA, _XL: _THETA - _EL})
    ca, cl, ref = (sp.expand(f_a.diff(x)) for x in (_EA, _EL, _FREF))
    rest = sp.expand(f_a - ca * _EA - cl * _EL - ref * _FREF)
    if rest != 0:  # every block acts on errors: nothing else may be left
        raise AssertionError(f"the diagram is not of the form C_A e_A + C_L e_L: {rest}")
    outer = [y["velocity"], y["impedance"]]  # grouped as the diagram nests them
    ca, cl = (sp.factor_terms(sp.collect(x, outer, func=sp.factor_terms)) for x in (ca, cl))
    return ca, cl, ref


def _put(general: str, texts: Mapping[str, str]) -> str:
    """``general`` with each block symbol replaced by its text (parenthesized unless atomic)."""

    def repl(m: re.Match[str]) -> str:
        text = texts[m.group(0)].strip()
        return text if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*|[0-9.]+", text) else f"({text})"

    names = "|".join(sorted(texts, key=len, reverse=True))
    return re.sub(rf"\b(?:{names})\b", repl, general) if texts else general


def derive_controller(
    controller: Controller, *, parameters: Iterable[str] | None = None
) -> ControllerDerivation:
    """Solve the block diagram of ``controller`` for ``C_A`` and ``C_L``.

    Parameters
    ----------
    controller : Controller
    parameters : iterable of str, optional
        Parameter names the blocks may use besides the standard ones
        (``m b k1 k2 b1 b2 kd bd ki``); default: any name.

    Returns
    -------
    ControllerDerivation

    Raises
    ------
    ExpressionError
        For a block that does not parse, uses an unknown name, or has more zeros
        than its kind allows (an improper force or velocity compensator, say);
        the message names the block's argument (``force: ...``).

    Examples
    --------
    >>> d = derive_controller(Controller(kind="velocity-sourced", force="kf",
    ...                                  impedance="kv + bv*s", velocity="kvp + kvi/s"))
    >>> d.general["CA"], d.general["CL"]
    ('C_v*(C_f*K_s + s)', 'C_f*C_v*(-K_s + Z_v)')
    """
    if not isinstance(controller, Controller):
        raise ParameterError(
            f"controller: expected a Controller, got {type(controller).__name__}",
            argument="controller",
        )
    texts: dict[str, str] = {}
    for arg, text in controller.blocks().items():
        sym, what, least = BLOCKS[arg]
        allowed = {*STANDARD_SYMBOLS, *(_names(text) if parameters is None else parameters)}
        try:
            expr = parse_expression(text, allowed)
        except ExpressionError as exc:
            raise ExpressionError(f"{arg}: {exc}", argument=arg) from None
        _check_degree(arg, text, expr, what, least)
        texts[sym] = text
    ca, cl, ref = _solve(_diagram(controller))
    general = {"CA": str(ca), "CL": str(cl)}
    used = {str(x) for e in (ca, cl) for x in e.free_symbols}
    blocks = {s: t for s, t in texts.items() if s in used}
    diagram = tuple((str(sig), str(rhs)) for sig, rhs in _diagram(controller))
    return ControllerDerivation(
        controller=controller,
        diagram=diagram,
        general=MappingProxyType(general),
        blocks=MappingProxyType(blocks),
        CA=_put(general["CA"], blocks),
        CL=_put(general["CL"], blocks),
        reference=_put(str(ref), blocks) if controller.kind is ControllerKind.FORCE else None,
    )


def _names(text: str) -> set[str]:
    """The identifiers of ``text`` (parsed by `ast`, never evaluated); none if it does not parse."""
    try:
        tree = ast.parse(text.replace("^", "**"), mode="eval")
    except (SyntaxError, ValueError):
        return set()
    return {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)} - _RESERVED


def _check_degree(arg: str, text: str, expr: sp.Expr, what: str, least: int) -> None:
    """Refuse a block with more excess zeros than ``least`` allows (``-least`` derivatives)."""
    import sympy as sp

    S = sp.Symbol("s")  # the s of every expression (seapass.model.symbolic.S)
    num, den = sp.fraction(sp.together(expr))
    if num == 0:
        return
    excess = sp.degree(num, S) - sp.degree(den, S)
    if -excess >= least:
        return
    if least == 0:
        raise ExpressionError(
            f"{arg}: the {what} {text!r} is improper ({excess} more zero(s) than poles): it "
            "would differentiate a measured signal; filter the derivative, e.g. "
            f"'kp + ki/s + kd*s/(1 + s/N)'",
            argument=arg,
        )
    raise ExpressionError(
        f"{arg}: the {what} {text!r} has {excess} more zeros than poles; at most {-least} "
        "(add filter poles)",
        argument=arg,
    )
