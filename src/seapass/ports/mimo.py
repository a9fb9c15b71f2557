"""n-ports (multi-DoF): an n×n impedance matrix of expressions, and its exact passivity.

`NPort` is to an n×n impedance matrix what [`TwoPort`][seapass.ports.twoport.TwoPort]
is to a two-port: entries symbolic and cancelled, parameter values alongside.
`mimo_is_passive` decides positive-realness exactly
([`seapass.ports.passivity`][seapass.ports.passivity]): stable entries,
simple imaginary-axis poles with Hermitian positive semidefinite residues, and
*every* principal minor of ``Z(jω) + Z(jω)^H`` non-negative.  Every axis of a
2-DoF joint can be passive on its own while the joint is not (a curl field,
``K`` not symmetric, is the classic case); the minors that mix axes catch it.

References
----------
.. [1] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 5.2.
.. [2] J. Li, M. Tavakoli and Q. Huang, "Absolute stability of multi-DOF
   multilateral haptic systems", IEEE Trans. Control Syst. Technol. 22(6), 2014.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from ..errors import NotPassiveError, ParameterError
from ..model.display import html_card, short_repr
from ..model.sea import check_used
from .entries import (
    entry_parameters,
    freeze_values,
    merged_values,
    no_values,
    parse_entries,
    square_entries,
)
from .matrix import ExactMatrix, exact_matrix
from .passivity import MatrixPassivity, matrix_passivity
from .twoport import TwoPort

__all__ = ["NPort", "mimo_is_passive"]


@dataclass(frozen=True, kw_only=True, repr=False)
class NPort:
    """An n×n impedance matrix ``F = Z(s) v`` of rational functions of ``s``.

    Build it with `NPort.from_matrix` or from coupled axes
    ([`CoupledAxes.n_port`][seapass.ports.axes.CoupledAxes.n_port]).

    Attributes
    ----------
    entries : tuple of sympy.Expr
        Row-major, cancelled.
    n : int
        Number of ports.
    values : mapping of str to float or None
        Parameter values; None declares a free parameter.
    name : str
    """

    entries: tuple[sp.Expr, ...]
    n: int
    values: Mapping[str, float | None] = field(default_factory=no_values)
    name: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "values", freeze_values(self.values))
        if len(self.entries) != self.n * self.n:
            raise ParameterError(
                f"entries: expected {self.n * self.n} entries, got {len(self.entries)}"
            )

    @classmethod
    def from_matrix(
        cls, matrix: Any, *, values: Mapping[str, float | None] | None = None, name: str = ""
    ) -> NPort:
        """An n-port from ``[[z11, ..., z1n], ..., [zn1, ..., znn]]`` (text, sympy or numbers).

        Examples
        --------
        >>> z = NPort.from_matrix([["b + k/s", "c/s"], ["-c/s", "b + k/s"]],
        ...                       values={"b": 10, "k": 100, "c": 50})
        >>> mimo_is_passive(z).passive   # a curl field: not passive
        False
        """
        vals = freeze_values(values)
        raw = square_entries(matrix)
        n = math.isqrt(len(raw))
        labels = [f"Z{i + 1}{j + 1}" for i in range(n) for j in range(n)]
        entries = parse_entries(raw, labels, vals, "the impedance matrix")
        return cls(entries=entries, n=n, values=vals, name=name)

    @functools.cached_property
    def parameters(self) -> tuple[str, ...]:
        return entry_parameters(self.entries)

    @property
    def free_parameters(self) -> tuple[str, ...]:
        return tuple(p for p in self.parameters if self.values.get(p) is None)

    def with_values(self, **values: float | None) -> NPort:
        check_used(values, self.parameters, "the impedance matrix")
        return dataclasses.replace(self, values={**self.values, **values})

    def exact(self, values: Mapping[str, float] | None = None) -> ExactMatrix:
        """The exact rational matrix at the parameter values."""
        merged = merged_values(self.values, values, self.parameters, "the impedance matrix")
        return exact_matrix(self.entries, self.n, merged)

    def to_dict(self) -> dict[str, Any]:
        rows = [[str(self.entries[i * self.n + j]) for j in range(self.n)] for i in range(self.n)]
        return {"ports": self.n, "entries": rows, "values": dict(self.values), "name": self.name}

    def __repr__(self) -> str:
        return short_repr(
            "NPort",
            {"name": self.name or None, "ports": self.n, "values": dict(self.values) or None},
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            (f"Z{i + 1}{j + 1}(s)", str(self.entries[i * self.n + j]))
            for i in range(self.n)
            for j in range(self.n)
        ]
        rows += [(k, "free" if v is None else v) for k, v in self.values.items()]
        return html_card(f"{self.n}-port {self.name}".strip(), rows)


def as_n_port(system: Any, values: Mapping[str, float | None] | None = None) -> NPort:
    """``system`` (an `NPort`, coupled axes, a two-port in z form or a nested matrix) as an `NPort`."""
    from .axes import CoupledAxes

    if isinstance(system, NPort):
        return system.with_values(**values) if values else system
    if isinstance(system, CoupledAxes):
        system = system.n_port()
        return system.with_values(**values) if values else system
    if isinstance(system, TwoPort):
        tp = system.convert("z")
        return NPort(entries=tp.entries, n=2, values={**tp.values, **(values or {})}, name=tp.name)
    return NPort.from_matrix(system, values=values)


def mimo_is_passive(
    system: Any,
    *,
    values: Mapping[str, float] | None = None,
    throw: bool = False,
) -> MatrixPassivity:
    """Decide exactly whether an n×n impedance matrix is positive real (passive).

    Parameters
    ----------
    system : NPort, CoupledAxes, TwoPort or nested sequence
        The impedance matrix ``F = Z v``: an `NPort`, n coupled SEA axes
        ([`CoupledAxes`][seapass.ports.axes.CoupledAxes]), a two-port (converted
        to z form) or ``[[z11, z12], [z21, z22]]`` of expressions.
    values : mapping, optional
        Parameter values (for a nested sequence: every parameter's value).
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] unless certified passive.

    Returns
    -------
    MatrixPassivity
        ``conditions`` hold ``stable_entries``, ``axis_poles`` and one
        ``minor_*`` per principal minor of ``Z + Z^H``, with failing bands.

    Examples
    --------
    >>> mimo_is_passive([["b + k/s", "c/s"], ["c/s", "b + k/s"]],
    ...                 values={"b": 10, "k": 100, "c": 50}).passive
    True
    """
    nport = as_n_port(system, values)
    result = matrix_passivity(nport.exact(), form="z", letter="Z")
    if throw and not result.passive:
        failing = ", ".join(c.name for c in result.failing) or "undecided"
        raise NotPassiveError(f"not passive: {failing}")
    return result
