"""n SEA axes with a coupled PD controller, and their TOML file.

Axis ``i`` is an SEA of [`seapass.model.sea`][seapass.model.sea] (actuator mass
``m_i``, damping ``b_i``, transmission ``D1_i``, load-to-ground ``D2_i``); one
controller acts on all of them with gain matrices ``K`` and ``B``:

* actuator ``i``: ``(m_i s² + b_i s) X_Ai = F_Ai + D1_i (X_Li − X_Ai)``
* load port ``i``: ``F_Li = D1_i (X_Li − X_Ai) + D2_i X_Li``
* controller: ``F_A = −(K + B s) X``, ``X = X_A`` (``side = "actuator"``) or
  ``X = X_L`` (``side = "load"``).

The n×n impedance ``F_L = Z(s) v_L`` is derived from these equations in code
(exact elimination, [`seapass.ports.derive`][seapass.ports.derive]).  A
non-symmetric ``K`` is a curl field: it injects energy around a loop, so the
axes are not passive together however passive each is alone.

The file form (``seapass mimo check --axes FILE``)::

    name = "planar-2dof"
    [controller]
    side = "actuator"                    # or "load"
    K = [["kd", "kc"], ["-kc", "kd"]]    # expressions or numbers, n×n
    B = [["bd", 0], [0, "bd"]]
    [[axis]]                             # one table per axis
    m = "m"                              # expressions or numbers
    b = "b"
    D1 = "k1 + b1*s"
    D2 = "0"                             # optional
    [[axis]]
    m = 2.0
    b = "b"
    D1 = "k1"
    [parameters]                         # a value for every name used
    m = 1.0
    b = 10.0
    k1 = 1000.0
    b1 = 20.0
    kd = 500.0
    bd = 25.0
    kc = 100.0

Validation is strict: unknown keys, wrong shapes, more than
[`MAX_PORTS`][seapass.files.limits.MAX_PORTS] axes and unused or missing
parameters are errors naming the key.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import sympy as sp

from ..errors import FileFormatError, ParameterError, SeapassError
from ..files.limits import MAX_PORTS
from ..files.toml import load_toml_file
from ..model.display import html_card, short_repr
from ..model.expr import STANDARD_SYMBOLS, S
from ..model.sea import check_used
from .derive import equation, solve_ports
from .entries import freeze_values, no_values, parse_entry, square_entries
from .mimo import NPort

__all__ = ["SIDES", "CoupledAxes", "load_axes", "parse_axes"]

SIDES = ("actuator", "load")
"""Which positions the coupled controller feeds back."""


@dataclass(frozen=True, kw_only=True, repr=False)
class CoupledAxes:
    """n SEA axes joined by one PD controller with gain matrices ``K`` and ``B``.

    Attributes
    ----------
    axes : tuple of mappings
        Per axis the elements ``m``, ``b``, ``D1``, ``D2`` (text, sympy or numbers).
    K, B : n×n nested sequences
        Stiffness and damping gain matrices (expressions or numbers).
    side : str
        ``"actuator"`` (feed back the actuator positions) or ``"load"``.
    values : mapping of str to float or None
        Parameter values; None declares a free parameter.
    name : str
    """

    axes: tuple[Mapping[str, Any], ...]
    K: Any
    B: Any
    side: str = "actuator"
    values: Mapping[str, float | None] = field(default_factory=no_values)
    name: str = ""

    def __post_init__(self) -> None:
        vals = freeze_values(self.values)
        object.__setattr__(self, "values", vals)
        n = len(self.axes)
        if not 1 <= n <= MAX_PORTS:
            raise ParameterError(f"axes: need 1 to {MAX_PORTS} axes, got {n}", argument="axes")
        if self.side not in SIDES:
            raise ParameterError(
                f"side: {self.side!r} is not one of {', '.join(SIDES)}", argument="side"
            )
        allowed = set(STANDARD_SYMBOLS) | set(vals)
        parsed = []
        for i, axis in enumerate(self.axes):
            unknown = set(axis) - {"m", "b", "D1", "D2"}
            if unknown:
                raise ParameterError(f"axes[{i}]: unknown element {sorted(unknown)[0]!r}")
            elems = {
                k: parse_entry(axis.get(k, default), allowed, f"axes[{i}].{k}")
                for k, default in (("m", "m"), ("b", "b"), ("D1", "0"), ("D2", "0"))
            }
            if elems["D1"] == 0 and elems["D2"] == 0:
                raise ParameterError(
                    f"axes[{i}]: D1 = D2 = 0 leaves the load port connected to nothing"
                )
            parsed.append(MappingProxyType(elems))
        object.__setattr__(self, "axes", tuple(parsed))
        for key in ("K", "B"):
            raw = square_entries(getattr(self, key), n)
            object.__setattr__(
                self,
                key,
                tuple(
                    parse_entry(v, allowed, f"{key}[{k // n}][{k % n}]") for k, v in enumerate(raw)
                ),
            )
        check_used(vals, self.parameters, "the coupled axes")

    @property
    def n(self) -> int:
        return len(self.axes)

    @property
    def parameters(self) -> tuple[str, ...]:
        exprs = [e for a in self.axes for e in a.values()] + list(self.K) + list(self.B)
        return tuple(sorted({str(x) for e in exprs for x in e.free_symbols if x != S}))

    def n_port(self) -> NPort:
        """The n×n impedance ``F_L = Z(s) v_L``, derived from the free-body equations."""
        n = self.n
        xa = sp.symbols(f"X_A0:{n}")
        fa = sp.symbols(f"F_A0:{n}")
        fl = sp.symbols(f"F_L0:{n}")
        xl = sp.symbols(f"X_L0:{n}")
        fb = xa if self.side == "actuator" else xl
        eqs = []
        for i, a in enumerate(self.axes):
            alpha = a["m"] * S**2 + a["b"] * S
            eqs.append(equation(alpha * xa[i], fa[i] + a["D1"] * (xl[i] - xa[i])))
            eqs.append(equation(fl[i], a["D1"] * (xl[i] - xa[i]) + a["D2"] * xl[i]))
            ctrl = sum(
                ((self.K[i * n + j] + self.B[i * n + j] * S) * fb[j] for j in range(n)), sp.S.Zero
            )
            eqs.append(equation(fa[i], -ctrl))
        entries = solve_ports(eqs, [*xa, *fa, *fl], fl, xl)
        used = {str(x) for e in entries for x in e.free_symbols if x != S}
        vals = {k: v for k, v in self.values.items() if k in used}
        return NPort(entries=tuple(entries), n=n, values=vals, name=self.name)

    def to_dict(self) -> dict[str, Any]:
        n = self.n
        return {
            "name": self.name,
            "side": self.side,
            "axes": [{k: str(v) for k, v in a.items()} for a in self.axes],
            "K": [[str(self.K[i * n + j]) for j in range(n)] for i in range(n)],
            "B": [[str(self.B[i * n + j]) for j in range(n)] for i in range(n)],
            "parameters": dict(self.values),
        }

    def __repr__(self) -> str:
        return short_repr(
            "CoupledAxes", {"name": self.name or None, "axes": self.n, "side": self.side}
        )

    def _repr_html_(self) -> str:
        n = self.n
        rows: list[tuple[str, Any]] = [("side", self.side)]
        rows += [
            (f"axis {i + 1}", ", ".join(f"{k} = {v}" for k, v in a.items()))
            for i, a in enumerate(self.axes)
        ]
        rows += [("K", str([[str(self.K[i * n + j]) for j in range(n)] for i in range(n)]))]
        rows += [("B", str([[str(self.B[i * n + j]) for j in range(n)] for i in range(n)]))]
        return html_card(f"{n} coupled axes {self.name}".strip(), rows)


def _matrix(value: Any, key: str) -> list[list[Any]]:
    if not isinstance(value, list) or not all(isinstance(r, list) for r in value):
        raise FileFormatError(f"{key}: expected a matrix [[...], [...]]")
    for i, row in enumerate(value):
        for j, v in enumerate(row):
            if isinstance(v, bool) or not isinstance(v, int | float | str):
                raise FileFormatError(f"{key}[{i}][{j}]: expected a number or an expression")
    return value


def parse_axes(data: Mapping[str, Any]) -> CoupledAxes:
    """Validate a parsed TOML document of coupled axes (module docstring) and build them."""
    unknown = set(data) - {"name", "title", "axis", "controller", "parameters"}
    if unknown:
        raise FileFormatError(f"unknown key {sorted(unknown)[0]}")
    for key in ("axis", "controller", "parameters"):
        if key not in data:
            raise FileFormatError(f"missing required key {key}")
    axes = data["axis"]
    if not isinstance(axes, list) or not all(isinstance(a, dict) for a in axes):
        raise FileFormatError("axis: expected [[axis]] tables, one per axis")
    if not 1 <= len(axes) <= MAX_PORTS:
        raise FileFormatError(f"axis: need 1 to {MAX_PORTS} axes, got {len(axes)}")
    for i, a in enumerate(axes):
        for k, v in a.items():
            if k not in ("m", "b", "D1", "D2"):
                raise FileFormatError(f"axis[{i}].{k}: unknown key (use m, b, D1, D2)")
            if isinstance(v, bool) or not isinstance(v, int | float | str):
                raise FileFormatError(f"axis[{i}].{k}: expected a number or an expression")
        if "D1" not in a and "D2" not in a:
            raise FileFormatError(f'missing axis[{i}].D1 (the transmission, e.g. "k1 + b1*s")')
    ctl = data["controller"]
    if not isinstance(ctl, dict):
        raise FileFormatError("controller: expected a table")
    bad = set(ctl) - {"side", "K", "B"}
    if bad:
        raise FileFormatError(f"controller.{sorted(bad)[0]}: unknown key (use side, K, B)")
    params = data["parameters"]
    if not isinstance(params, dict):
        raise FileFormatError("parameters: expected a table")
    for k, v in params.items():
        if isinstance(v, bool) or not isinstance(v, int | float):
            raise FileFormatError(f"parameters.{k}: expected a number")
    n = len(axes)
    zero = [[0] * n for _ in range(n)]
    try:
        ca = CoupledAxes(
            axes=tuple(axes),
            K=_matrix(ctl.get("K", zero), "controller.K"),
            B=_matrix(ctl.get("B", zero), "controller.B"),
            side=str(ctl.get("side", "actuator")),
            values=dict(params),
            name=str(data.get("name", "")),
        )
    except SeapassError as exc:
        raise FileFormatError(str(exc).replace("values[", "parameters[")) from None
    missing = [p for p in ca.parameters if ca.values.get(p) is None]
    if missing:
        raise FileFormatError(
            f"missing parameters.{missing[0]}: the axes use {', '.join(ca.parameters)}"
        )
    return ca


def load_axes(path: str | os.PathLike[str]) -> CoupledAxes:
    """Read and validate a TOML file of coupled axes (module docstring)."""
    return load_toml_file(Path(path), parse_axes, what="axes file")
