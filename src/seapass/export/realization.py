"""The deployed controller of a design as exact difference equations over common denominators.

With fixed gains the realization *is* the Python controller: the one joint difference
equation of [`DiscreteController`][seapass.sampled.controllers.DiscreteController]
(the four paths ``C_A`` error, ``C_A`` measurement, ``C_L`` error, ``C_L``
measurement over their exact least common denominator, see
[`seapass.sampled.joint`][seapass.sampled.joint]), coefficient for coefficient, run in
the same order of operations, so a faithful C compiler reproduces the Python output bit
for bit.  A pole ``C_A`` and ``C_L`` share (a force loop's integrator) is one state.

With runtime gains each controller is split as ``C(s) = F_0(s) + Σ_i g_i F_i(s)``
over the tunable gains ``g_i`` (an exact symbolic check refuses gains that do not
enter affinely), every ``F`` is discretized on its own, the paths that share a gain are
realized together (one joint difference equation per gain) and the runtime multiplies
their outputs by the current gains: a gain change rescales outputs and never rewrites
filter states.  The sum is checked to equal the Python controller's transfer functions
exactly at the design's gains, and the split is affine, so it equals them at every gain.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Literal

import sympy as sp

from ..errors import ParameterError
from ..model.design_file import Design
from ..model.expr import symbol
from ..model.loop import SampledLoop
from ..model.zcontroller import z_coefficients
from ..sampled.controllers import DiscreteController, DiscreteTF, discretize
from ..sampled.joint import JointRealization, poly_add, poly_mul, q_reduce

__all__ = ["SIGNALS", "FilterSpec", "realize"]

Signal = Literal["error_A", "measurement_A", "error_L", "measurement_L"]
SIGNALS: tuple[Signal, ...] = ("error_A", "measurement_A", "error_L", "measurement_L")


@dataclass(frozen=True)
class FilterSpec:
    """One joint difference equation of the deployed controller.

    Attributes
    ----------
    realization : JointRealization
        Its inputs (of ``θ_A − x_A``, ``−x_A``, ``θ_L − x_L``, ``−x_L``), its exact
        numerators over one common denominator (ascending powers of ``z^-1``).
    gain : str or None
        Runtime gain multiplying the output (only with ``set_gains``).
    """

    realization: JointRealization
    gain: str | None = None

    @property
    def inputs(self) -> tuple[str, ...]:
        """The signals it reads, in the order of its numerators."""
        return self.realization.inputs

    @property
    def order(self) -> int:
        """Number of states of its direct-form-II-transposed realization."""
        return self.realization.order

    def transfer_function(self, signal: str) -> DiscreteTF:
        """Its exact transfer function from ``signal`` (reduced; ``0`` for an unused one)."""
        num, den = self.realization.entry(signal)
        return DiscreteTF(num, den, self.realization.period)


def _total(filters: Sequence[FilterSpec], signal: str, gains: Mapping[str, float]) -> DiscreteTF:
    num: tuple[Fraction, ...] = (Fraction(0),)
    den: tuple[Fraction, ...] = (Fraction(1),)
    for f in filters:
        k = Fraction(1) if f.gain is None else Fraction(gains[f.gain])
        n2, d2 = f.realization.entry(signal)
        num = poly_add(poly_mul(num, d2), poly_mul(tuple(k * c for c in n2), den))
        den = poly_mul(den, d2)
    period = filters[0].realization.period if filters else Fraction(1)
    return DiscreteTF(*q_reduce(num, den), period)


def _fixed_filters(ctrl: DiscreteController) -> list[FilterSpec]:
    return [FilterSpec(ctrl.realization)] if ctrl.realization.inputs else []


def _affine_parts(expr: sp.Expr, tunable: Sequence[str], side: str) -> list[tuple[str | None, Any]]:
    """``[(None, F_0), (g, F_g), ...]`` with ``expr = F_0 + Σ g F_g``; refuses non-affine gains."""
    syms = [symbol(g) for g in tunable if symbol(g) in expr.free_symbols]
    parts: list[tuple[str | None, Any]] = [(None, expr.xreplace({g: 0 for g in syms}))]
    for g in syms:
        d = sp.diff(expr, g)
        for h in syms:
            if sp.cancel(sp.together(sp.diff(d, h))) != 0:
                raise ParameterError(
                    f"gain {g} does not enter C_{side} = {expr} linearly"
                    + (f" (its term also depends on {h})" if h != g else "")
                    + "; runtime gain changes need C = F0 + sum(g*F(s)); "
                    "choose the tunable gains with tunable=[...]"
                )
        parts.append((str(g), d))
    return parts


def _tunable_filters(design: Design, tunable: Sequence[str], loop: SampledLoop) -> list[FilterSpec]:
    sea = design.sea()
    fixed = {k: v for k, v in design.values.items() if k not in tunable}
    groups: dict[str | None, dict[str, DiscreteTF]] = {}
    zc = sea.discrete
    for side, expr in (("A", sea.CA), ("L", sea.CL)):
        if zc is not None:  # a controller in z: its own coefficients, split over the gains
            expr = zc.symbolic(f"C{side}")
        for gain, part in _affine_parts(sp.sympify(expr), tunable, side):
            if part == 0:
                continue
            if zc is not None:
                num, den = z_coefficients(part.xreplace(_subs(fixed)), f"C{side}_z")
                tf = DiscreteTF(num, den, loop.exact_period)
                groups.setdefault(gain, {})[f"error_{side}"] = tf
                continue
            paths = discretize(
                part, loop.period, method=loop.method, velocity_filter=loop.velocity_filter,
                values=fixed, split=True,
            )  # fmt: skip
            assert isinstance(paths, tuple)  # split=True
            for sig, tf in zip((f"error_{side}", f"measurement_{side}"), paths, strict=True):
                if not tf.is_zero:
                    groups.setdefault(gain, {})[sig] = tf
    out = []
    for gain, tfs in groups.items():
        entries = [(tfs[s].num, tfs[s].den) for s in SIGNALS if s in tfs]
        names = [s for s in SIGNALS if s in tfs]
        period = next(iter(tfs.values())).period
        out.append(FilterSpec(JointRealization.of(entries, names, period), gain))
    return out


def _subs(values: Mapping[str, float]) -> dict[Any, Any]:
    return {symbol(k): sp.Rational(Fraction(v)) for k, v in values.items()}


def _check_realization(
    filters: Sequence[FilterSpec], ctrl: DiscreteController, gains: Mapping[str, float]
) -> None:
    """The split realization equals the Python controller exactly at the certified gains."""
    for sig in SIGNALS:
        num, den = ctrl.realization.entry(sig)
        ref = DiscreteTF(num, den, ctrl.realization.period)
        total = _total(filters, sig, gains)
        if total.num != ref.num or total.den != ref.den:  # an internal error, not bad input
            raise AssertionError(f"split realization of {sig} differs from the controller")


def realize(
    design: Design, *, tunable: Sequence[str] = (), controller: DiscreteController | None = None
) -> tuple[FilterSpec, ...]:
    """The difference equations of the deployed controller of ``design``.

    Parameters
    ----------
    design : Design
        Needs a ``[control] rate``; its loop's velocity filter and discretization are used.
    tunable : sequence of str
        Gains that scale filter outputs at runtime (empty: the Python
        controller's own joint difference equation).
    controller : DiscreteController, optional
        The Python controller of the design, if already built.

    Raises
    ------
    ParameterError
        When a tunable gain does not enter ``C_A`` or ``C_L`` affinely.
    """
    if design.loop is None:
        raise ParameterError(f"design {design.name!r} has no [control] rate")
    ctrl = controller or DiscreteController.for_loop(design.sea(), design.loop)
    if not tunable:
        return tuple(_fixed_filters(ctrl))
    filters = _tunable_filters(design, tunable, design.loop)
    _check_realization(filters, ctrl, design.values)
    return tuple(filters)
