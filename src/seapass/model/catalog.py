"""The one catalog of named SEA designs: the paper's three designs and every Table I/II row.

Every module, command and test that needs "LP", "APD", "Ours" or a row of the
paper's tables takes it from here.  An entry holds the *structure* of a design
(its four elements, its controller gains and their default search box); the
paper's printed transfer functions and bounds for the table rows live with the
comparison that uses them, in [`seapass.paper.tables`][seapass.paper.tables].

=========  =====================  ===================  =============  =============
key        structure              D1                   C_A            C_L
=========  =====================  ===================  =============  =============
LP         spring, load-side P    ``k1``               0              ``kd``
APD        spring, act.-side PD   ``k1``               ``kd + bd*s``  0
ours       spring-damper, APD     ``k1 + b1*s``        ``kd + bd*s``  0
=========  =====================  ===================  =============  =============

Keys are looked up case-insensitively (``"Ours"`` and ``"ours"`` are the same).

Examples
--------
>>> from seapass.model.catalog import design
>>> design("LP").sea(PAPER_VALUES).free_parameters
('kd',)
>>> [d.key for d in TABLE_ROWS][:2]
['mech/pure-spring', 'mech/spring-spring']

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Tables I and II, Sec. V.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

from ..errors import ParameterError
from .display import html_card, short_repr
from .sea import SEA

__all__ = [
    "CATALOG",
    "PAPER_VALUES",
    "REFERENCE_VALUES",
    "SIMULATION_DESIGNS",
    "TABLE_ROWS",
    "CatalogDesign",
    "design",
]

PAPER_VALUES: Mapping[str, float] = MappingProxyType({"m": 1.0, "b": 10.0, "k1": 1000.0})
"""The plant of the paper's simulation study (Sec. V): actuator mass and damping, spring."""

REFERENCE_VALUES: Mapping[str, float] = MappingProxyType(
    {"m": 1.0, "b": 10.0, "k1": 1000.0, "k2": 1000.0, "b1": 20.0, "b2": 20.0,
     "kd": 500.0, "bd": 25.0, "ki": 100.0}
)  # fmt: skip
"""Representative values of every standard parameter (the paper's plant; the others chosen to
illustrate) for plots, reports and checks.
"""


@dataclass(frozen=True, repr=False)
class CatalogDesign:
    """The structure of a named design.

    Attributes
    ----------
    key : str
        Catalog key (``"LP"``, ``"ctrl/load-PD"``, ...).
    title : str
        Human-readable name.
    D1, D2, CA, CL : str
        The elements, as safe expression text.
    gains : tuple of str
        The controller gains (what a tuner or a sweep varies).
    ranges : mapping of str to (float, float)
        Default search box of each gain (SI units).
    table : str
        ``"I"``, ``"II"`` or ``"proposed"`` for a row of the paper's tables, ``""`` otherwise.
    label : str
        Short label for legends.
    """

    key: str
    title: str
    D1: str
    D2: str = "0"
    CA: str = "0"
    CL: str = "0"
    gains: tuple[str, ...] = ()
    ranges: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    table: str = ""
    label: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "ranges", MappingProxyType(dict(self.ranges)))
        for name, (lo, hi) in self.ranges.items():
            if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
                raise ParameterError(f"bad range for {name}: ({lo}, {hi})")
        if not self.label:
            object.__setattr__(self, "label", self.title)

    def __repr__(self) -> str:
        elements = {k: v for k, v in self.elements().items() if v != "0"}
        return short_repr("CatalogDesign", {"key": self.key, **elements, "gains": self.gains})

    def _repr_html_(self) -> str:
        rows = [*self.elements().items(), ("gains", ", ".join(self.gains) or "none")]
        rows += [(f"range of {k}", f"[{lo:g}, {hi:g}]") for k, (lo, hi) in self.ranges.items()]
        return html_card(f"{self.key}: {self.title}", rows)

    def sea(self, values: Mapping[str, float | None] | None = None, **more: float | None) -> SEA:
        """The [`SEA`][seapass.model.sea.SEA] with ``values``; gains not given stay free."""
        vals: dict[str, float | None] = {g: None for g in self.gains}
        vals.update(dict(values or {}))
        vals.update(more)
        return SEA(D1=self.D1, D2=self.D2, CA=self.CA, CL=self.CL, values=vals, name=self.key)

    def elements(self) -> dict[str, str]:
        """``{"D1": ..., "D2": ..., "CA": ..., "CL": ...}``."""
        return {"D1": self.D1, "D2": self.D2, "CA": self.CA, "CL": self.CL}


_BOX = {"kd": (0.0, 5000.0), "bd": (0.0, 300.0), "b1": (0.0, 300.0)}

SIMULATION_DESIGNS: tuple[CatalogDesign, ...] = (
    CatalogDesign("LP", "Spring, load-side P", D1="k1", CL="kd", gains=("kd",),
                  ranges={"kd": _BOX["kd"]}, label="LP: spring, load-side P"),
    CatalogDesign("APD", "Spring, actuator-side PD", D1="k1", CA="kd + bd*s",
                  gains=("kd", "bd"), ranges={k: _BOX[k] for k in ("kd", "bd")},
                  label="APD: spring, actuator-side PD"),
    CatalogDesign("ours", "Spring-damper, actuator-side PD", D1="k1 + b1*s", CA="kd + bd*s",
                  gains=("kd", "bd", "b1"), ranges=_BOX,
                  label="Ours: spring-damper, actuator-side PD"),
)  # fmt: skip
"""The three designs of the paper's simulation study (Sec. V), in the paper's order."""

TABLE_ROWS: tuple[CatalogDesign, ...] = (
    CatalogDesign("mech/pure-spring", "Pure spring", D1="k1", CL="kd", gains=("kd",), table="I"),
    CatalogDesign("mech/spring-spring", "Disjointed spring-spring", D1="k1", D2="k2", CL="kd",
                  gains=("kd",), table="I"),
    CatalogDesign("mech/parallel-spring-damper", "Parallel spring-damper", D1="k1 + b1*s",
                  CL="kd", gains=("kd",), table="I"),
    CatalogDesign("mech/disjoint-spring-damper", "Disjointed spring-damper", D1="k1", D2="b2*s",
                  CL="kd", gains=("kd",), table="I"),
    CatalogDesign("ctrl/load-P", "Load-side P", D1="k1", CL="kd", gains=("kd",), table="II"),
    CatalogDesign("ctrl/load-PD", "Load-side PD", D1="k1", CL="kd + bd*s", gains=("kd", "bd"),
                  table="II"),
    CatalogDesign("ctrl/load-PI", "Load-side PI", D1="k1", CL="kd + ki/s", gains=("kd", "ki"),
                  table="II"),
    CatalogDesign("ctrl/act-P", "Actuator-side P", D1="k1", CA="kd", gains=("kd",), table="II"),
    CatalogDesign("ctrl/act-PD", "Actuator-side PD", D1="k1", CA="kd + bd*s", gains=("kd", "bd"),
                  table="II"),
    CatalogDesign("ctrl/act-PI", "Actuator-side PI", D1="k1", CA="kd + ki/s", gains=("kd", "ki"),
                  table="II"),
    CatalogDesign("proposed", "Proposed: damped transmission + actuator-side PD",
                  D1="k1 + b1*s", CA="kd + bd*s", gains=("kd", "bd"), table="proposed"),
)  # fmt: skip
"""Every row of the paper's Tables I and II, then the proposed design, in the paper's order."""

CATALOG: Mapping[str, CatalogDesign] = MappingProxyType(
    {d.key: d for d in (*SIMULATION_DESIGNS, *TABLE_ROWS)}
)
"""Every named design by key."""


def design(key: str) -> CatalogDesign:
    """The catalog entry named ``key`` (case-insensitive).

    Raises
    ------
    ParameterError
        If there is no such design; the message lists the keys.
    """
    wanted = str(key).strip().lower()
    for k, d in CATALOG.items():
        if k.lower() == wanted:
            return d
    raise ParameterError(f"unknown design {key!r}; choose one of {', '.join(CATALOG)}")
