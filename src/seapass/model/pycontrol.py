"""Conversions to and from python-control: transfer functions and the closed-loop state space.

``SEA.to_control()`` hands the port impedance ``Z_L = F_L/(s X_L)`` or the
rendered stiffness ``F_L/X_L`` to python-control as a
``control.TransferFunction``; ``ClosedLoop.to_control()`` gives the closed loop
as a ``control.StateSpace`` with named inputs, outputs and states;
``Impedance.from_control(sys)`` brings a SISO continuous-time system back for
an exact passivity test.  The coefficients are computed exactly (values
substituted as the rationals they represent, common factors cancelled, the
denominator made monic) and rounded to floats only at the end.

python-control is imported only when one of these is called, so
``import seapass`` stays light.

References
----------
.. [1] python-control developers, *python-control* library,
   https://python-control.readthedocs.io (``TransferFunction``, ``StateSpace``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy as sp

from ..errors import ExpressionError, ParameterError
from .expr import S

if TYPE_CHECKING:
    from .realization import ClosedLoop
    from .sea import SEA, Impedance

__all__ = [
    "CONTROL_KINDS",
    "impedance_from_control",
    "impedance_transfer_function",
    "state_space",
    "transfer_function",
]

CONTROL_KINDS: dict[str, tuple[str, str, str]] = {
    "impedance": ("v_L", "F_L", "Z_L"),
    "stiffness": ("x_L", "F_L", "K_L"),
}
"""``kind -> (input name, output name, system name)`` of `transfer_function`."""


def _exact_coefficients(expr: sp.Expr) -> tuple[list[float], list[float]]:
    """Descending float coefficients of a cancelled, monic-denominator ``expr``."""
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    pn, pd = sp.Poly(num, S), sp.Poly(den, S)
    lead = pd.LC()
    return [float(c / lead) for c in pn.all_coeffs()], [float(c / lead) for c in pd.all_coeffs()]


def _require_values(expr: sp.Expr, what: str) -> None:
    missing = sorted(str(x) for x in expr.free_symbols if x != S)
    if missing:
        raise ParameterError(
            f"{what}: no value for parameter(s) {', '.join(missing)}; give them in "
            f"values, e.g. values={{'{missing[0]}': 1.0}}"
        )


def transfer_function(
    sea: SEA, kind: str = "impedance", *, values: Mapping[str, float] | None = None
) -> Any:
    """The port impedance or the rendered stiffness of ``sea`` as a ``control.TransferFunction``.

    Parameters
    ----------
    sea : SEA
        The design; every parameter needs a value.
    kind : {"impedance", "stiffness"}
        ``"impedance"``: ``Z_L = F_L/(s X_L)`` from the load velocity ``v_L``
        to the port force ``F_L`` (the function whose positive realness is
        passivity); ``"stiffness"``: ``F_L/X_L`` from the load position ``x_L``.
    values : mapping, optional
        Parameter values overriding those stored in ``sea``.

    Returns
    -------
    control.TransferFunction
        SISO, continuous time, with named input, output and system (see
        `CONTROL_KINDS`).
    """
    from .stiffness import derive_stiffness

    if kind not in CONTROL_KINDS:
        raise ParameterError(f"kind must be one of {', '.join(CONTROL_KINDS)}; got {kind!r}")
    model = sea.with_values(**values) if values else sea
    stiffness = derive_stiffness(model).stiffness
    expr = stiffness if kind == "stiffness" else stiffness / S
    expr = model.numeric(expr)
    _require_values(expr, f"SEA.to_control(kind={kind!r})")
    num, den = _exact_coefficients(expr)
    inp, out, name = CONTROL_KINDS[kind]
    import control

    return control.tf(num, den, inputs=inp, outputs=out, name=sea.name or name)


def impedance_transfer_function(impedance: Impedance, *, name: str = "Z") -> Any:
    """A raw `Impedance` as a ``control.TransferFunction`` from ``v`` to ``F``."""
    import control

    subs = impedance.substitutions()
    expr = impedance.expr.xreplace(subs)
    _require_values(expr, "Impedance.to_control()")
    num, den = _exact_coefficients(expr)
    return control.tf(num, den, inputs="v", outputs="F", name=name)


def state_space(loop: ClosedLoop, *, name: str = "closed_loop") -> Any:
    """``loop`` as a ``control.StateSpace`` with named inputs, outputs and states.

    Inputs are ``INPUTS`` of [`seapass.model.realization`][seapass.model.realization]
    (``theta_A``, ``theta_L``, ``f_ext``), outputs its ``OUTPUTS`` (``x_A``,
    ``v_A``, ``x_L``, ``v_L``, ``f_A``, ``f_D1``, ``a_L``) and states ``loop.states``.
    """
    import control

    from .realization import INPUTS, OUTPUTS

    return control.ss(
        np.array(loop.A),
        np.array(loop.B),
        np.array(loop.C),
        np.array(loop.D),
        inputs=list(INPUTS),
        outputs=list(OUTPUTS),
        states=list(loop.states),
        name=name,
    )


def impedance_from_control(system: Any) -> Impedance:
    """An `Impedance` from a SISO continuous-time python-control system.

    Parameters
    ----------
    system : control.TransferFunction or control.StateSpace
        ``Z(s)``, force over velocity.  Its float coefficients are taken as
        the exact rationals they represent.

    Raises
    ------
    ParameterError
        For a system that is not SISO, is discrete-time or has non-finite
        coefficients.
    ExpressionError
        For an object that is not a python-control LTI system.
    """
    import control

    from .sea import Impedance

    if not isinstance(system, control.LTI):
        raise ExpressionError(
            f"system: expected a control.TransferFunction or StateSpace, got {type(system).__name__}"
        )
    if system.ninputs != 1 or system.noutputs != 1:
        raise ParameterError(
            f"system: an impedance is SISO; got {system.ninputs} inputs and "
            f"{system.noutputs} outputs (select one channel, e.g. sys[0, 0])"
        )
    if system.isdtime(strict=True):
        raise ParameterError(
            f"system is discrete-time (dt = {system.dt}); give the continuous-time impedance "
            "(for sampled control use seapass.sampled_passivity)"
        )
    tf = system if isinstance(system, control.TransferFunction) else control.tf(system)
    num = np.atleast_1d(np.asarray(tf.num_array[0, 0], dtype=float))
    den = np.atleast_1d(np.asarray(tf.den_array[0, 0], dtype=float))
    for what, c in (("numerator", num), ("denominator", den)):
        if not np.all(np.isfinite(c)):
            raise ParameterError(f"system: the {what} has non-finite coefficients")
    if not np.any(den):
        raise ParameterError("system: the denominator is identically zero")
    return Impedance(num=[float(c) for c in num], den=[float(c) for c in den])
