"""Every two-port verdict at once: absolute stability, passivity, reciprocity, η and a witness.

`two_port_passivity` is Raisbeck's passivity of the two-port
([`seapass.ports.passivity`][seapass.ports.passivity]); `reciprocity` compares
``p12`` with ``±p21`` exactly; `check_two_port` gathers them with
[`absolute_stability`][seapass.ports.stability.absolute_stability] into one
`TwoPortCheck`, the result behind ``seapass twoport check``.

A passive two-port is absolutely stable (a passive network closed by passive
terminations is passive, hence stable); the converse fails for non-reciprocal
two-ports, which is why both are reported.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..analysis.environment_box import HUMAN_LIMB, EnvironmentBounds
from ..errors import NotPassiveError
from ..model.display import html_card, short_repr
from ..model.sea import SEA
from ..outcome import Outcome
from .forms import reciprocity_sign
from .matrix import ExactMatrix
from .passivity import MatrixPassivity, matrix_passivity
from .stability import AbsoluteStability, absolute_stability, as_two_port
from .twoport import TwoPort
from .witness import VIRTUAL_ENVIRONMENT

__all__ = ["TwoPortCheck", "check_two_port", "reciprocity", "two_port_passivity"]


def reciprocity(m: ExactMatrix, form: str = "z") -> bool:
    """``p12 = p21`` (z, y) or ``p12 = −p21`` (h, g), exactly, at the given values."""
    from .forms import form_of

    sign = reciprocity_sign(form_of(form))
    n12, d12 = m.entry(0, 1)
    n21, d21 = m.entry(1, 0)
    return bool(n12 * d21 - sign * n21 * d12 == 0)


def two_port_passivity(
    system: TwoPort | SEA,
    *,
    values: Mapping[str, float] | None = None,
    throw: bool = False,
) -> MatrixPassivity:
    """Decide exactly whether a two-port is passive (its immittance matrix positive real).

    Parameters
    ----------
    system : TwoPort or SEA
        The two-port in any form, or an SEA (its person–environment two-port).
    values : mapping, optional
        Parameter values overriding those stored in ``system``.
    throw : bool, default False
        Raise [`NotPassiveError`][seapass.errors.NotPassiveError] unless certified passive.

    Returns
    -------
    MatrixPassivity

    Examples
    --------
    >>> from seapass import SEA
    >>> sea = SEA(D1="k1", CA="kd", CL="kl", values=dict(m=1, b=10, k1=1000, kd=500, kl=5000))
    >>> two_port_passivity(sea).passive
    False
    """
    tp = as_two_port(system, values)
    result = matrix_passivity(tp.exact(), form=tp.form.value, letter=tp.form.value)
    if throw and not result.passive:
        failing = ", ".join(c.name for c in result.failing) or "undecided"
        raise NotPassiveError(f"two-port not passive: {failing}")
    return result


@dataclass(frozen=True, kw_only=True, repr=False)
class TwoPortCheck:
    """Absolute stability, passivity and reciprocity of one two-port.

    Attributes
    ----------
    outcome : Outcome
        The two-port's passivity (``passivity.outcome``; ``passive`` is
        ``outcome.passive``).  Absolute stability, which decides the exit code
        of ``seapass twoport check``, is ``stability.outcome``
        (``absolutely_stable`` is ``stability.outcome.passive``).
    stability : AbsoluteStability
        Llewellyn's criterion, η and the witness pair.
    passivity : MatrixPassivity
        Raisbeck's passivity of the immittance matrix.
    reciprocal : bool
        ``p12 = p21`` (z, y) or ``p12 = −p21`` (h, g) exactly.
    two_port : TwoPort
        What was checked.
    """

    stability: AbsoluteStability
    passivity: MatrixPassivity
    reciprocal: bool
    two_port: TwoPort = field(compare=False)

    @property
    def outcome(self) -> Outcome:
        return self.passivity.outcome

    @property
    def absolutely_stable(self) -> bool:
        return self.stability.absolutely_stable

    @property
    def passive(self) -> bool:
        return self.outcome.passive

    def to_dict(self) -> dict[str, Any]:
        """The JSON of ``seapass twoport check``."""
        stab = self.stability.to_dict()
        conditions = [
            {"criterion": "absolute_stability", **c.to_dict()} for c in self.stability.conditions
        ]
        conditions += [{"criterion": "passivity", **c.to_dict()} for c in self.passivity.conditions]
        passive = None if self.outcome is Outcome.UNDECIDED else self.passive
        return {
            "absolutely_stable": stab["absolutely_stable"],
            "passive": passive,
            "reciprocal": self.reciprocal,
            "eta_min": stab["eta_min"],
            "eta_min_frequency": stab["eta_min_frequency"],
            "eta_min_kind": stab["eta_min_kind"],
            "eta_min_limit": stab["eta_min_limit"],
            "eta_min_enclosure": stab["eta_min_enclosure"],
            "absolute_stability": self.stability.outcome.value,
            "passivity": self.passivity.outcome.value,
            "form": self.two_port.form.value,
            "entries": self.two_port.to_dict()["entries"],
            "conditions": conditions,
            "witness": stab["witness"],
        }

    def plot(self, kind: str = "eta", *, ax: Any = None, **kwargs: Any) -> Any:
        """``kind="eta"``: η(ω) (`AbsoluteStability.plot`); ``"minors"``: the passivity minors."""
        if kind == "minors":
            return self.passivity.plot(ax=ax, **kwargs)
        if kind != "eta":
            raise ValueError(f"kind must be 'eta' or 'minors', got {kind!r}")
        return self.stability.plot(ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr(
            "TwoPortCheck",
            {
                "absolute_stability": self.stability.outcome.value,
                "passivity": self.passivity.outcome.value,
                "reciprocal": self.reciprocal,
                "eta_min": self.stability.eta.value,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            ("absolute stability", self.stability.outcome.label),
            ("two-port passivity", self.passivity.outcome.label),
            ("reciprocal", "yes" if self.reciprocal else "no"),
            ("inf η", f"{self.stability.eta.value:.6g}"),
        ]
        if self.stability.witness is not None and self.stability.witness.found:
            rows.append(("witness", self.stability.witness.detail))
        return html_card(f"Two-port {self.two_port.name}".strip(), rows)


def check_two_port(
    system: TwoPort | SEA,
    *,
    values: Mapping[str, float] | None = None,
    witness: bool = True,
    bounds: tuple[EnvironmentBounds | None, EnvironmentBounds | None] = (
        HUMAN_LIMB,
        VIRTUAL_ENVIRONMENT,
    ),
) -> TwoPortCheck:
    """Absolute stability (with η and a witness), passivity and reciprocity of a two-port.

    Examples
    --------
    >>> from seapass import SEA
    >>> sea = SEA(D1="k1", CA="kd", values=dict(m=1, b=10, k1=1000, kd=500))
    >>> c = check_two_port(sea)
    >>> c.absolutely_stable, c.passive, c.reciprocal
    (True, True, True)
    """
    tp = as_two_port(system, values)
    stab = absolute_stability(tp, witness=witness, bounds=bounds)
    m = stab.matrix
    assert m is not None
    pas = matrix_passivity(m, form=tp.form.value, letter=tp.form.value)
    return TwoPortCheck(
        stability=stab, passivity=pas, reciprocal=reciprocity(m, tp.form.value), two_port=tp
    )
