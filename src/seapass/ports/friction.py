"""The friction certificate: cut a static element out of the plant and test the two-port left.

Coulomb friction on the actuator, or a friction damper in the transmission, is
nonlinear; every passive friction law (a force opposing the velocity, ``f v ≥ 0``:
Coulomb, Stribeck, stiction, viscous, any mix, static or with its own passive
dynamics) is a passive one-port.  Cut it out as port 2
([`seapass.ports.derive`][seapass.ports.derive]: at the actuator, port 2 is the
actuator velocity ``s X_A`` and the force the friction puts on the actuator; in
the transmission, the stretch rate ``s (X_L − X_A)`` and minus the friction
force) and hold the controller's reference at zero, as the one-port test does.
If the linear two-port between the person and the friction is passive, the SEA
with any passive friction law is passive at the person's port: a passive
two-port closed by a passive one-port is a passive one-port.

The converse does not hold: a two-port that is not passive is no proof that
friction destabilizes the SEA; then the certificate says nothing either way.

References
----------
.. [1] J. E. Colgate and G. Schenkel, "Passivity of a class of sampled-data
   systems: application to haptic interfaces", J. Robot. Syst. 14(1), 1997.
.. [2] B. D. O. Anderson and S. Vongpanitlerd, *Network Analysis and Synthesis*,
   Prentice-Hall, 1973, sec. 2.8 (interconnections of passive networks).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..errors import ParameterError
from ..model.display import html_card, short_repr
from ..model.expr import S
from ..model.sea import SEA
from ..outcome import Outcome
from .derive import FRICTION_SITES, port_equations
from .forms import Form
from .passivity import MatrixPassivity, matrix_passivity
from .twoport import TwoPort

__all__ = ["FrictionCertificate", "friction_certificate", "friction_two_port"]

NOT_A_PROOF = (
    "not certified: the linear two-port around the friction is not passive; this is no proof "
    "that friction destabilizes the SEA (the test is sufficient, not necessary)"
)


def friction_two_port(sea: SEA, at: str = "actuator") -> TwoPort:
    """The two-port between the person (port 1) and a friction element at ``at`` (port 2).

    ``at`` is ``"actuator"`` (friction on the actuator) or ``"transmission"``
    (a friction element in parallel with ``D1``); z form.
    """
    if not isinstance(sea, SEA):
        raise ParameterError(f"sea: expected an SEA, got {type(sea).__name__}", argument="sea")
    eq = port_equations(sea, at)
    used = {str(x) for e in eq.entries for x in e.free_symbols if x != S}
    return TwoPort(
        entries=eq.entries,
        form=Form.Z,
        values={k: v for k, v in sea.values.items() if k in used},
        name=sea.name,
        ports=("person", eq.port2),
    )


@dataclass(frozen=True, kw_only=True, repr=False)
class FrictionCertificate:
    """Whether every passive friction law at ``site`` keeps the SEA passive (proven, or not shown).

    Attributes
    ----------
    outcome : Outcome
        The exact passivity of the two-port around the friction (``passivity.outcome``).
    certified : bool
        ``outcome`` is ``PASSIVE``: the two-port around the friction is passive,
        proven for every passive friction law.
    site : str
        ``"actuator"`` or ``"transmission"``.
    passivity : MatrixPassivity
        The exact test of the two-port, with its conditions and failing bands.
    two_port : TwoPort
        The two-port tested.
    detail : str
        What was shown, in words.
    """

    site: str
    passivity: MatrixPassivity
    two_port: TwoPort = field(compare=False)
    detail: str = ""

    @property
    def outcome(self) -> Outcome:
        return self.passivity.outcome

    @property
    def certified(self) -> bool:
        return self.outcome.passive

    def to_dict(self) -> dict[str, Any]:
        return {
            "certified": self.certified,
            "site": self.site,
            "outcome": self.outcome.value,
            "detail": self.detail,
            "conditions": [c.to_dict() for c in self.passivity.conditions],
            "entries": self.two_port.to_dict()["entries"],
        }

    def plot(self, *, ax: Any = None, **kwargs: Any) -> Any:
        """The principal minors of the two-port with the failing bands; returns the Axes."""
        return self.passivity.plot(ax=ax, **kwargs)

    def __repr__(self) -> str:
        return short_repr("FrictionCertificate", {"certified": self.certified, "site": self.site})

    def _repr_html_(self) -> str:
        return html_card(
            f"Friction at the {self.site}: {'certified' if self.certified else 'not certified'}",
            [("two-port", self.outcome.label), ("detail", self.detail)],
        )


def friction_certificate(
    sea: SEA, *, at: str = "actuator", values: Mapping[str, float] | None = None
) -> FrictionCertificate:
    """Prove, exactly, that every passive friction law at ``at`` keeps ``sea`` passive, if it does.

    Examples
    --------
    >>> from seapass import SEA
    >>> sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1000, b1=20, kd=500, bd=25))
    >>> friction_certificate(sea).certified
    True
    """
    if at not in FRICTION_SITES:
        raise ParameterError(f"at: {at!r} is not one of {', '.join(FRICTION_SITES)}", argument="at")
    if values:
        sea = sea.with_values(**values)
    tp = friction_two_port(sea, at)
    result = matrix_passivity(tp.exact(), form="z", letter="z")
    if result.passive:
        detail = (
            f"certified: the two-port between the person and the {at} friction is passive, so "
            "the SEA stays passive with every passive friction law there (Coulomb, Stribeck, "
            "stiction, viscous, ...)"
        )
    elif result.outcome is Outcome.UNDECIDED:
        detail = "undecided: the exact test of the two-port could not decide"
    else:
        failing = ", ".join(c.name for c in result.failing)
        detail = f"{NOT_A_PROOF} (fails: {failing})"
    return FrictionCertificate(site=at, passivity=result, two_port=tp, detail=detail)
