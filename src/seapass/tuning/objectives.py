"""Interaction-control objectives for tuning: rendering fidelity, force bandwidth, Z-width.

Each objective is a number computed for one candidate (a vector of gains) by an
`ObjectiveFunction`; [`tune_objective`][seapass.tuning.interaction.tune_objective]
optimizes it under exact passivity.  The objective is an optimization *cost*: it is
computed in floating point from the candidate's exact transfer functions (the
elements are evaluated exactly at the candidate's values and combined with exact
rational arithmetic in ``s``; only the evaluation at ``jω`` is floating point).  The
passivity constraint is never decided here: it stays exact
([`ConstraintChecks`][seapass.tuning.cost.ConstraintChecks]).

``rendering``
    The worst relative error of the rendered stiffness to a target over a band,
    ``max |F_L/X_L(jω) − T(jω)| / |T(jω)|`` for ``ω`` in ``[lo, hi]`` rad/s on
    ``points`` log-spaced frequencies (both ends included); minimized.  ``T`` is
    safe text in ``s`` and the design's parameters (``"kv + bv*s"``), with the
    parameters at the design's values *before* tuning (the target does not move
    with the gains).
``force-bandwidth``
    The closed-loop force-tracking bandwidth with the load clamped (``x_L = 0``),
    rad/s; maximized.  Both position references are the command ``θ``
    (``θ_A = θ_L = θ``, as in the step response), so the force on the clamp is
    ``F = G(s) θ`` with ``G = D1 (C_A + C_L) / (m s² + b s + D1 + C_A)``.  The
    measured transfer is ``F/F_ref`` with ``F_ref = G(0) θ``, the static force the
    design commands (for an impedance controller ``G(0)`` is the rendered static
    stiffness, so ``F_ref`` is the force it renders against the clamp).  The
    bandwidth is the first frequency where ``|G(jω)/G(0)|`` falls to ``1/√2``
    (−3 dB): found on ``points`` log-spaced frequencies of the band (default
    ``[1e-2, 1e5]`` rad/s) and refined by bisection.  A response that stays above
    −3 dB to the band's top reports the top; ``G(0) = 0`` reports 0.  A clamped loop
    that is not stable is not a candidate.
``zwidth``
    The largest certified passive value of the virtual stiffness gain (``kv`` when
    the design has it, else ``kd``, else the first controller gain; ``stiffness``
    chooses) under sampled-data control in the tuning loop, by
    [`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound] within
    ``max_boxes`` boxes per candidate; maximized over the other gains.  The value is
    proven (rounded inward); an exhausted budget only makes it smaller.

Rendering and force bandwidth are port quantities and Z-width a port property: none
of them depends on the load.  Robustness over the load masses is therefore the
requirement that every candidate's closed loop is stable with every listed load
mass (the design file's ``[simulation] load_masses``); a candidate that is not is
ranked below every candidate that is.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from flint import fmpq_poly

from ..analysis.freqresp import log_frequencies
from ..errors import ExpressionError, ParameterError, SeapassError, SymbolicLimitError
from ..model.elements import exact_values
from ..model.expr import exact_expression
from ..model.loop import SampledLoop
from ..model.realization import closed_loop_factory
from ..model.sea import SEA
from .objective_spec import (
    DEFAULT_BANDWIDTH_BAND,
    Interaction,
    InteractionObjective,
    squash,
    stiffness_gain,
)

__all__ = [
    "DEFAULT_BANDWIDTH_BAND",
    "Interaction",
    "InteractionObjective",
    "ObjectiveFunction",
    "response_at",
    "squash",
    "static_gain",
    "stiffness_gain",
    "target_rational",
]

HALF_POWER = 1.0 / math.sqrt(2.0)
_BISECTIONS = 40


# ------------------------------------------------------------------ exact rational helpers

_Rat = tuple[fmpq_poly, fmpq_poly]


def _add(a: _Rat, b: _Rat) -> _Rat:
    return (a[0] * b[1] + b[0] * a[1], a[1] * b[1])


def _mul(a: _Rat, b: _Rat) -> _Rat:
    return (a[0] * b[0], a[1] * b[1])


def _div(a: _Rat, b: _Rat) -> _Rat:
    if b[0] == 0:
        raise ZeroDivisionError("division by a zero transfer function")
    return (a[0] * b[1], a[1] * b[0])


def _reduced(a: _Rat) -> _Rat:
    g = a[0].gcd(a[1])
    if g == 0 or g.degree() < 1:
        return a
    return (a[0] // g, a[1] // g)


def _floats(p: fmpq_poly) -> np.ndarray:
    """Descending float coefficients (``[0]`` for the zero polynomial)."""
    c = [float(x) for x in p.coeffs()]
    return np.array(c[::-1] or [0.0])


def response_at(r: _Rat, omega: np.ndarray) -> np.ndarray:
    s = 1j * omega
    return np.polyval(_floats(r[0]), s) / np.polyval(_floats(r[1]), s)


def static_gain(r: _Rat) -> float:
    """``lim_{s→0} r(s)`` (inf for a pole at 0)."""
    num, den = r
    nc, dc = num.coeffs(), den.coeffs()
    if not nc:
        return 0.0
    vn = next(i for i, c in enumerate(nc) if c != 0)
    vd = next(i for i, c in enumerate(dc) if c != 0)
    if vn > vd:
        return 0.0
    if vn < vd:
        return math.inf
    return float(nc[vn] / dc[vd])


class ObjectiveFunction:
    """The objective of one problem, as a function of a candidate's gains.

    Parameters
    ----------
    spec : InteractionObjective
    sea : SEA
        The design with every fixed parameter's value.
    gains : sequence of str
        The names of a candidate's entries (for the Z-width: without the stiffness gain).
    load_masses : sequence of float
        The candidate's closed loop must be stable with each (see the module docstring).
    loop : SampledLoop, optional
        The sampled loop (Z-width only, required there).
    stiffness : str, optional
        The Z-width's stiffness gain; ``stiffness_box`` its range.
    """

    def __init__(
        self,
        spec: InteractionObjective,
        sea: SEA,
        gains: Sequence[str],
        *,
        load_masses: Sequence[float],
        loop: SampledLoop | None = None,
        stiffness: str | None = None,
        stiffness_box: tuple[float, float] | None = None,
    ) -> None:
        self._common(spec, sea, gains, loop, stiffness, stiffness_box)
        self._elements = sea.exact_elements()
        self._fixed = exact_values(
            {k: v for k, v in sea.values.items() if k not in self.full_gains}
        )
        self._stability = [
            closed_loop_factory(sea, self.full_gains, load_mass=float(m)) for m in load_masses
        ]
        self._set_band(*spec.frequency_band)

    def _common(
        self,
        spec: InteractionObjective,
        sea: SEA,
        gains: Sequence[str],
        loop: SampledLoop | None,
        stiffness: str | None,
        stiffness_box: tuple[float, float] | None,
    ) -> None:
        """The attributes every objective function has (continuous or in z)."""
        self.spec = spec
        self.kind = Interaction(spec.kind)
        self.sea = sea
        self.gains = tuple(gains)
        self.loop = loop
        self.stiffness = stiffness
        self.stiffness_box = stiffness_box
        self.boxes_exhausted = 0
        self.bounds_run = 0
        self._zwidths: dict[tuple[float, ...], float] = {}
        self.full_gains = self.gains + ((stiffness,) if stiffness else ())
        self.nyquist: float | None = None  # a controller in z: pi/T (rad/s)

    def _set_band(self, lo: float, hi: float) -> None:
        """The search frequencies and the target on them."""
        spec = self.spec
        self.band = (float(lo), float(hi))
        self.omega = log_frequencies(lo, hi, spec.points)
        self._target: np.ndarray | None = None
        self.target_expression: _Rat | None = None
        if self.kind is Interaction.RENDERING:
            self.target_expression = target_rational(str(spec.target), self.sea)
            self._target = response_at(self.target_expression, self.omega)
            if np.any(self._target == 0) or not np.all(np.isfinite(self._target)):
                raise ParameterError(
                    f"target {spec.target!r} is zero or infinite in the band: the relative "
                    "error is undefined there; choose another band or target",
                    argument="target",
                )

    # ---------------------------------------------------------------- transfer functions

    def _parts(self, full: Sequence[float]) -> dict[str, _Rat]:
        env = {**self._fixed, **exact_values(dict(zip(self.full_gains, full, strict=True)))}
        out = {}
        for key, rf in self._elements.items():
            num, den = rf.evaluate(env)
            out[key] = (num, den)
        return out

    def stiffness_tf(self, full: Sequence[float]) -> _Rat:
        """``F_L/X_L`` at the candidate (exact, cancelled)."""
        e = self._parts(full)
        s = (fmpq_poly([0, 1]), fmpq_poly([1]))
        alpha = _add(_mul(e["m"], _mul(s, s)), _mul(e["b"], s))
        inner = _add(_add(alpha, e["CA"]), e["D1"])
        top = _add(
            _add(_mul(e["D1"], _add(alpha, e["CA"])), _mul(e["D2"], inner)), _mul(e["D1"], e["CL"])
        )
        return _reduced(_div(top, inner))

    def force_tf(self, full: Sequence[float]) -> _Rat:
        """``G = F/θ`` with the load clamped (see the module docstring), exact, cancelled."""
        e = self._parts(full)
        s = (fmpq_poly([0, 1]), fmpq_poly([1]))
        alpha = _add(_mul(e["m"], _mul(s, s)), _mul(e["b"], s))
        inner = _add(_add(alpha, e["CA"]), e["D1"])
        return _reduced(_div(_mul(e["D1"], _add(e["CA"], e["CL"])), inner))

    # ---------------------------------------------------------------- the objectives

    def stable(self, full: Sequence[float]) -> bool:
        """The closed loop is stable with every load mass (floating-point poles)."""
        try:
            for build in self._stability:
                poles = build(list(full)).poles
                if poles.size and float(np.max(poles.real)) >= 0:
                    return False
        except (SeapassError, ArithmeticError, ValueError, np.linalg.LinAlgError):
            return False
        return True

    def stiffness_response(self, full: Sequence[float], omega: np.ndarray) -> np.ndarray:
        """The rendered stiffness ``F_L/X_L(jω)`` of the candidate ``full`` (complex)."""
        return response_at(self.stiffness_tf(full), omega)

    def force_magnitude(self, full: Sequence[float]) -> Callable[[np.ndarray], np.ndarray] | float:
        """``ω ↦ |G(jω)/G(0)|`` of the clamped-load force, or a number when there is no
        such curve: nan (the clamped loop is not stable, or ``G(0)`` is infinite), 0
        (``G(0) = 0``)."""
        g = self.force_tf(full)
        den = _floats(g[1])
        if den.size > 1 and float(np.max(np.roots(den).real)) >= 0:
            return math.nan
        dc = static_gain(g)
        if dc == 0:
            return 0.0
        if not math.isfinite(dc):
            return math.nan
        return lambda w: np.abs(response_at(g, w)) / abs(dc)

    def rendering_error(
        self, full: Sequence[float], omega: np.ndarray | None = None
    ) -> tuple[float, float]:
        """``(worst relative error, its frequency)`` over the band (``omega``: other grid)."""
        if self.target_expression is None:
            raise ParameterError("rendering_error needs a rendering objective with a target")
        w = self.omega if omega is None else omega
        target = response_at(self.target_expression, w) if omega is not None else self._target
        assert target is not None
        rendered = self.stiffness_response(full, w)
        err = np.abs(rendered - target) / np.abs(target)
        if not np.all(np.isfinite(err)):
            return math.inf, float(w[int(np.argmax(~np.isfinite(err)))])
        i = int(np.argmax(err))
        return float(err[i]), float(w[i])

    def force_bandwidth(self, full: Sequence[float], omega: np.ndarray | None = None) -> float:
        """The −3 dB force bandwidth (rad/s), nan when the clamped loop is not stable."""
        curve = self.force_magnitude(full)
        if not callable(curve):
            return float(curve)
        w = self.omega if omega is None else omega

        def low(x: np.ndarray) -> np.ndarray:
            return curve(x) <= HALF_POWER

        below = low(w)
        if not below.any():
            return float(w[-1])
        i = int(np.argmax(below))
        if i == 0:
            return float(w[0])
        a, b = float(w[i - 1]), float(w[i])
        for _ in range(_BISECTIONS):
            mid = math.sqrt(a * b)
            if low(np.array([mid]))[0]:
                b = mid
            else:
                a = mid
        return b

    def zwidth(self, x: Sequence[float]) -> float:
        """The largest certified passive stiffness gain at the other gains ``x`` (0: none)."""
        from ..sampled.bound import sampled_passive_bound

        assert self.stiffness is not None and self.stiffness_box is not None and self.loop
        key = tuple(float(v) for v in x)
        if key in self._zwidths:  # the unconstrained search revisits the constrained one's points
            return self._zwidths[key]
        sea = self.sea.with_values(
            **dict(zip(self.gains, (float(v) for v in x), strict=True)), **{self.stiffness: None}
        )
        lo, hi = self.stiffness_box
        r = sampled_passive_bound(
            sea, self.stiffness, loop=self.loop, lo=lo, hi=hi, rtol=self.spec.rtol,
            max_boxes=self.spec.max_boxes,
        )  # fmt: skip
        self.boxes_exhausted += int(r.budget_exhausted)
        self.bounds_run += 1
        value = float(r.max_passive) if r.max_passive is not None else 0.0
        self._zwidths[key] = value
        return value

    def full(self, x: Sequence[float], value: float) -> tuple[float, ...]:
        """The candidate with the stiffness gain (Z-width: at its value ``value``)."""
        xs = tuple(float(v) for v in x)
        return (*xs, value) if self.stiffness else xs

    def value(self, x: Sequence[float]) -> float:
        """The objective at the candidate ``x`` (nan: no meaningful value)."""
        if self.kind is Interaction.ZWIDTH:
            return self.zwidth(x)
        if self.kind is Interaction.RENDERING:
            return self.rendering_error(x)[0]
        return self.force_bandwidth(x)


def target_rational(text: str, sea: SEA) -> _Rat:
    """The target as an exact rational function of ``s`` at the design's values."""
    allowed = (*sea.parameters, *(k for k in sea.values if k not in sea.parameters))
    try:
        rf = exact_expression(text, allowed)
    except (ExpressionError, SymbolicLimitError) as exc:
        raise ParameterError(f"target: {exc}", argument="target") from None
    names = sorted(rf.parameters())
    missing = [n for n in names if sea.values.get(n) is None]
    if missing:
        raise ParameterError(
            f"target: {text!r} uses {', '.join(missing)}, which has no value in the design; "
            "give numbers or parameters with values",
            argument="target",
        )
    num, den = rf.evaluate(exact_values({n: sea.values[n] for n in names}))
    if num == 0:
        raise ParameterError(f"target: {text!r} is zero", argument="target")
    return (num, den)
