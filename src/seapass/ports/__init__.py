"""Two-ports and n-ports: can this SEA render *any* passive environment to *any* passive person?

What lives here: the SEA as a two-port between the person (port 1: ``F_L``,
``v_L = s x_L``) and the virtual environment (port 2: ``F_2 = f_A``,
``v_2 = s θ``), derived from the free-body equations
([`derive`][seapass.ports.derive]), any 2×2 immittance in the forms z, y, h, g
with exact conversions ([`forms`][seapass.ports.forms],
[`twoport`][seapass.ports.twoport], [`entries`][seapass.ports.entries]); exact
rational functions on FLINT's multivariate polynomials
([`ratfunc`][seapass.ports.ratfunc]); the exact rational matrix at given values
and its poles ([`matrix`][seapass.ports.matrix], [`poles`][seapass.ports.poles]),
polynomials on the imaginary axis and exact failing bands
([`onaxis`][seapass.ports.onaxis], [`bands`][seapass.ports.bands]); the verdicts:
Llewellyn's absolute stability ([`llewellyn`][seapass.ports.llewellyn]) with
Haddadi and Hashtrudi-Zaad's η ([`eta`][seapass.ports.eta]) gathered in
[`stability`][seapass.ports.stability], passivity of an
n×n immittance (Raisbeck; [`passivity`][seapass.ports.passivity]), the closed
loop with two terminations and a destabilizing pair of them
([`closedloop`][seapass.ports.closedloop], [`witness`][seapass.ports.witness]),
the combined check ([`check`][seapass.ports.check]), exact gain intervals and
regions ([`bound`][seapass.ports.bound], [`criticals`][seapass.ports.criticals]),
n coupled SEA axes and matrices of expressions
([`mimo`][seapass.ports.mimo], [`axes`][seapass.ports.axes],
[`matrixtext`][seapass.ports.matrixtext]) and the friction certificate
([`friction`][seapass.ports.friction]).

Every verdict is a `seapass.outcome.Outcome`, decided
exactly (rational arithmetic, certified root isolation); nothing is decided on a
frequency grid or in unbounded floating point.

May import: [`seapass.errors`][seapass.errors], `seapass.outcome`,
[`seapass.files`][seapass.files], [`seapass.exact`][seapass.exact],
[`seapass.model`][seapass.model] and [`seapass.analysis`][seapass.analysis].
"""

from .forms import Form
from .twoport import TwoPort, two_port

__all__ = ["Form", "TwoPort", "two_port"]
