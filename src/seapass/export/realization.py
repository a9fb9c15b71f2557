"""The deployed controller of a design as a sum of exact difference equations.

With fixed gains the realization *is* the Python controller: the four
direct-form-II-transposed filters ``(C_A error, C_A measurement, C_L error,
C_L measurement)`` of
[`DiscreteController.from_sea`][seapass.sampled.controllers.DiscreteController.from_sea],
coefficient for
coefficient, summed in the same order, so a faithful C compiler reproduces the
Python output bit for bit.

With runtime gains each controller is split as ``C(s) = F_0(s) + Σ_i g_i F_i(s)``
over the tunable gains ``g_i`` (an exact symbolic check refuses gains that do not
enter affinely), every ``F`` is discretized on its own, and the runtime
multiplies the filter outputs by the current gains: a gain change rescales
outputs and never rewrites filter states.  The sum is checked to equal the
Python controller's transfer functions exactly at the design's gains, and the
split is affine, so it equals them at every gain.
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
from ..sampled.controllers import DiscreteController, DiscreteTF, discretize

__all__ = ["SIGNALS", "FilterSpec", "realize"]

Signal = Literal["error_A", "measurement_A", "error_L", "measurement_L"]
SIGNALS: tuple[Signal, ...] = ("error_A", "measurement_A", "error_L", "measurement_L")


@dataclass(frozen=True)
class FilterSpec:
    """One difference equation of the deployed controller.

    Attributes
    ----------
    signal : {"error_A", "measurement_A", "error_L", "measurement_L"}
        Its input: ``θ_A − x_A``, ``−x_A``, ``θ_L − x_L`` or ``−x_L``.
    tf : DiscreteTF
        Exact coefficients (ascending powers of ``z^-1``, ``den[0] = 1``).
    gain : str or None
        Runtime gain multiplying the output (only with ``set_gains``).
    """

    signal: Signal
    tf: DiscreteTF
    gain: str | None = None

    @property
    def order(self) -> int:
        """Number of states of its direct-form-II-transposed realization."""
        return max(len(self.tf.num), len(self.tf.den)) - 1


def _scaled(tf: DiscreteTF, k: Fraction) -> DiscreteTF:
    return DiscreteTF(tuple(k * c for c in tf.num), tf.den, tf.period)


def _same_tf(a: DiscreteTF, b: DiscreteTF) -> bool:
    return (a + _scaled(b, Fraction(-1))).is_zero


def _fixed_filters(ctrl: DiscreteController) -> list[FilterSpec]:
    tfs = (*ctrl.CA, *ctrl.CL)
    return [FilterSpec(sig, tf) for sig, tf in zip(SIGNALS, tfs, strict=True) if not tf.is_zero]


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
    out: list[FilterSpec] = []
    for side, expr in (("A", sea.CA), ("L", sea.CL)):
        for gain, part in _affine_parts(sp.sympify(expr), tunable, side):
            if part == 0:
                continue
            paths = discretize(
                part, loop.period, method=loop.method, velocity_filter=loop.velocity_filter,
                values=fixed, split=True,
            )  # fmt: skip
            assert isinstance(paths, tuple)  # split=True
            signals: tuple[Signal, Signal] = (
                ("error_A", "measurement_A") if side == "A" else ("error_L", "measurement_L")
            )
            for sig, tf in zip(signals, paths, strict=True):
                if not tf.is_zero:
                    out.append(FilterSpec(sig, tf, gain))
    return out


def _check_realization(
    filters: Sequence[FilterSpec], ctrl: DiscreteController, gains: Mapping[str, float]
) -> None:
    """The split realization equals the Python controller exactly at the certified gains."""
    for sig, ref in zip(SIGNALS, (*ctrl.CA, *ctrl.CL), strict=True):
        total = DiscreteTF((Fraction(0),), (Fraction(1),), ref.period)
        for f in filters:
            if f.signal == sig:
                k = Fraction(1) if f.gain is None else Fraction(gains[f.gain])
                total = total + _scaled(f.tf, k)
        if not _same_tf(total, ref):  # an internal error, not bad input
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
        controller's own four filters).
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
