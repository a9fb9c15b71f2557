"""Interaction-control objectives of a controller given in z: the sampled loop's own responses.

A controller in ``z`` (``SEA.discrete``) exists only at its rate ``1/T``, so
[`tune_objective`][seapass.tuning.interaction.tune_objective] computes its objectives on
the sampled loop (the controller's difference equation, the force held over the period,
the loop's delay of ``d`` samples, ``K_X`` below include ``z^-d``), and certifies every
candidate that could become the best with
[`sampled_passivity`][seapass.sampled.passivity.sampled_passivity] at the rate (``undecided``
counts as not passive):

``rendering``
    The *fundamental-harmonic* rendered stiffness: a port motion ``x_L = Re(X e^{jωt})``
    meets the force ``F_L = Re(F e^{jωt}) + (aliases at ω + 2πk/T)``, and ``F/X`` is
    exactly (``s = jω``, ``z = e^{jωT}``; ``α = m s² + b s``, ``a = D1/(α + D1)``,
    ``P = 1/(α + D1)``, ``g(z)`` the ZOH pulse transfer of ``P``)

    ``F/X = s Z0(s) + a(s) (1 − z⁻¹)/(sT) · (K_A(z) a(s) + K_L(z)) / (1 + K_A(z) g(z))``

    with ``s Z0 = D1 α/(α + D1) + D2`` (the derivation of
    [`seapass.sampled.passivity`][seapass.sampled.passivity] with one alias; as ``T → 0``
    it is the continuous ``F_L/X_L``).  The objective is the worst relative error to the
    target over the band, which must lie below the Nyquist frequency ``π/T``.
``force-bandwidth``
    The load clamped, both references the sampled command ``θ_k``: the force on the clamp
    at the instants is ``F_k = G(z) θ_k``, the exact discrete transfer of the sampled loop
    (the clamped plant discretized exactly, closed by the controller's realization and
    the delay).  The bandwidth is the first frequency where ``|G(e^{jωT})/G(1)|`` falls to
    ``1/√2``, searched below the Nyquist frequency (the default band is cut there).
``zwidth``
    As for a continuous controller: the largest certified passive stiffness gain by
    [`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound] (whose family is
    built from the z-expression).

Every candidate must make the sampled loop stable with every load mass (the spectral
radius of its one-period transition matrix, any rational ``D1``, ``D2``:
[`seapass.sampled.plantloop`][seapass.sampled.plantloop]).  These values are optimization
costs in floating point; the passivity constraint is the certified verdict.

References
----------
.. [1] J. E. Colgate, G. G. Schenkel, "Passivity of a class of sampled-data systems:
   application to haptic interfaces", J. Robotic Systems 14(1), 1997.
.. [2] G. F. Franklin, J. D. Powell, M. Workman, *Digital Control of Dynamic Systems*,
   3rd ed., Addison-Wesley, 1998, §4.3 (ZOH equivalent).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..errors import ParameterError, SeapassError
from ..model.loop import SampledLoop
from ..model.sea import SEA
from ..outcome import Outcome
from ..sampled.controllers import DiscreteController
from ..sampled.passivity import sampled_passivity
from ..sampled.plant import numeric_element
from ..sampled.plantloop import DiscretePlant, discrete_plant, loop_matrix
from .objectives import Interaction, InteractionObjective, ObjectiveFunction

__all__ = ["SampledChecks", "SampledObjectiveFunction", "zoh_pulse_transfer"]


def _floats(p: object) -> np.ndarray:
    c = [float(x) for x in p.coeffs()]  # type: ignore[attr-defined]
    return np.array(c[::-1] or [0.0])


def zoh_pulse_transfer(
    nums: Sequence[np.ndarray], den: np.ndarray, period: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(Φ, Γ, C)`` of the ZOH equivalents of ``num_i/den`` (strictly proper, descending).

    One companion realization of ``den`` with one output row per numerator, discretized
    exactly over ``period`` (block matrix exponential): ``G_i(z) = C_i (zI − Φ)^{-1} Γ``.
    """
    from scipy.linalg import expm

    den = np.trim_zeros(np.asarray(den, float), "f")
    lead = float(den[0])
    den = den / lead
    n = den.size - 1
    A = np.zeros((n, n))
    A[:-1, 1:] = np.eye(n - 1)
    A[-1, :] = -den[::-1][:n]
    B = np.zeros((n, 1))
    B[-1, 0] = 1.0
    rows = []
    for num in nums:
        num = np.trim_zeros(np.asarray(num, float), "f") / lead
        if num.size > n:
            raise ParameterError("zoh_pulse_transfer needs strictly proper numerators")
        c = np.zeros(n)
        c[: num.size] = num[::-1]
        rows.append(c)
    big = np.zeros((n + 1, n + 1))
    big[:n, :n], big[:n, n:] = A * period, B * period
    E = expm(big)
    return E[:n, :n], E[:n, n:], np.array(rows)


def _at(phi: np.ndarray, gamma: np.ndarray, c: np.ndarray, z: np.ndarray) -> np.ndarray:
    """``C (zI − Φ)^{-1} Γ`` at every ``z`` (rows of ``C`` → rows of the result)."""
    n = phi.shape[0]
    out = np.empty((c.shape[0], z.size), dtype=complex)
    eye = np.eye(n)
    for i, zi in enumerate(z):
        out[:, i] = c @ np.linalg.solve(zi * eye - phi, gamma[:, 0])
    return out


def _poly_at(coeffs: Sequence[Any], zinv: np.ndarray) -> np.ndarray:
    """``Σ c_i z^{-i}`` (ascending powers of ``z^-1``)."""
    return np.polyval(np.array([float(c) for c in coeffs])[::-1], zinv)


class SampledChecks:
    """The certified sampled verdicts of the candidates of a z-design (cached, counted);
    the constraint of [`tune_objective`][seapass.tuning.interaction.tune_objective] there."""

    def __init__(self, *, candidate: Callable[[Sequence[float]], SEA], loop: SampledLoop) -> None:
        self.candidate = candidate
        self.loop = loop
        self.sampled: dict[tuple[float, ...], bool] = {}
        self.continuous: dict[tuple[float, ...], bool] = {}  # none: the controller is in z

    def outcome(self, x: Sequence[float]) -> Outcome:
        """The certified verdict at ``x`` (an error is undecided)."""
        try:
            return sampled_passivity(self.candidate(x), loop=self.loop).outcome
        except (SeapassError, ArithmeticError, ValueError):
            return Outcome.UNDECIDED

    def passive(self, x: tuple[float, ...]) -> bool:
        if x not in self.sampled:
            self.sampled[x] = self.outcome(x) is Outcome.PASSIVE
        return self.sampled[x]


class SampledObjectiveFunction(ObjectiveFunction):
    """[`ObjectiveFunction`][seapass.tuning.objectives.ObjectiveFunction] of a design whose
    controller is given in z (see the module docstring); ``loop`` is required."""

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
        if loop is None or sea.discrete is None:
            raise ParameterError("SampledObjectiveFunction needs a controller in z and its loop")
        self._common(spec, sea, gains, loop, stiffness, stiffness_box)
        plant = sorted(set(self.full_gains) & set(sea.plant_parameters))
        if plant:
            raise ParameterError(
                f"tune[{plant[0]!r}]: {plant[0]} is a plant parameter; the objectives of a "
                "controller in z tune the controller's parameters only",
                argument="tune",
            )
        self.period = T = float(loop.period)
        self.nyquist = math.pi / T
        lo, hi = spec.frequency_band
        if spec.band is None:  # the default search band ends below the Nyquist frequency
            hi = min(hi, 0.999 * self.nyquist)
        elif self.kind is not Interaction.ZWIDTH and hi >= self.nyquist:
            raise ParameterError(
                f"band: the controller runs at {1 / T:g} Hz, so its sampled responses are "
                f"defined below the Nyquist frequency pi/T = {self.nyquist:.6g} rad/s; give "
                f"a band whose upper end is below {self.nyquist:.6g} rad/s",
                argument="band",
            )
        if not lo < hi:
            raise ParameterError(
                f"band: the lower end {lo:g} rad/s is not below the Nyquist frequency "
                f"{self.nyquist:.6g} rad/s of the controller's rate",
                argument="band",
            )
        self._set_band(lo, hi)
        self._plants: list[DiscretePlant] = [
            discrete_plant(sea, T, load_mass=float(m)) for m in load_masses
        ]
        e = {k: numeric_element(sea, k) for k in ("m", "b", "D1", "D2")}
        m = float(e["m"][0][0] / e["m"][1][0])
        b = float(e["b"][0][0] / e["b"][1][0])
        n1, d1 = (_floats(p) for p in e["D1"])
        n2, d2 = (_floats(p) for p in e["D2"])
        alpha = np.array([m, b, 0.0])
        delta = np.polyadd(np.polymul(alpha, d1), n1)  # α d1 + n1: α + D1 over d1
        self._rationals = {  # (num, den), descending: a, P, s Z0
            "a": (n1, delta),
            "P": (d1, delta),
            "sZ0": (np.polyadd(np.polymul(np.polymul(n1, alpha), d2), np.polymul(n2, delta)),
                    np.polymul(delta, d2)),
        }  # fmt: skip
        self._zoh = zoh_pulse_transfer([d1, n1], delta, T)  # G_P, G_a of the clamped plant
        self._grids: dict[bytes, dict[str, np.ndarray]] = {}

    # ---------------------------------------------------------------- the loop pieces

    def controller(self, full: Sequence[float]) -> DiscreteController:
        """The candidate's difference equation, run as is at the rate."""
        sea = self.sea.with_values(**dict(zip(self.full_gains, map(float, full), strict=True)))
        return DiscreteController.of_z(sea, self.period)

    def _grid(self, omega: np.ndarray) -> dict[str, np.ndarray]:
        """The plant's responses on ``omega`` (they do not depend on the gains: cached)."""
        key = omega.tobytes()
        if key not in self._grids:
            s = 1j * omega
            out = {k: np.polyval(n, s) / np.polyval(d, s) for k, (n, d) in self._rationals.items()}
            z = np.exp(s * self.period)
            gp, ga = _at(*self._zoh, z)
            out.update(z=z, zinv=1.0 / z, s=s, gP=gp, ga=ga)
            self._grids[key] = out
        return self._grids[key]

    def _paths(
        self, ctrl: DiscreteController, zinv: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``K_A``, ``K_L`` (on ``−x``) and ``R`` (on the common command θ) at ``zinv``,
        each with the loop's delay ``z^-d``."""
        real = ctrl.realization
        delay = zinv ** int(self.loop.delay) if self.loop is not None else 1.0
        val = {}
        for name in ("error_A", "measurement_A", "error_L", "measurement_L"):
            num, den = real.entry(name)
            val[name] = _poly_at(num, zinv) / _poly_at(den, zinv) * delay
        return (
            val["error_A"] + val["measurement_A"],
            val["error_L"] + val["measurement_L"],
            val["error_A"] + val["error_L"],
        )

    # ---------------------------------------------------------------- the objectives

    def stable(self, full: Sequence[float]) -> bool:
        """The sampled loop is stable with every load mass (spectral radius below 1)."""
        try:
            ctrl = self.controller(full)
            delay = int(self.loop.delay) if self.loop is not None else 0
            for plant in self._plants:
                acl = loop_matrix(plant, ctrl, delay)
                if not float(np.max(np.abs(np.linalg.eigvals(acl)))) < 1.0:
                    return False
        except (SeapassError, ArithmeticError, ValueError, np.linalg.LinAlgError):
            return False
        return True

    def stiffness_response(self, full: Sequence[float], omega: np.ndarray) -> np.ndarray:
        """The fundamental-harmonic rendered stiffness ``F/X`` of the sampled loop."""
        g = self._grid(np.asarray(omega, float))
        ka, kl, _r = self._paths(self.controller(full), g["zinv"])
        a, hold = g["a"], (1.0 - g["zinv"]) / (g["s"] * self.period)
        with np.errstate(divide="ignore", invalid="ignore"):
            return g["sZ0"] + a * hold * (ka * a + kl) / (1.0 + ka * g["gP"])

    def clamped_loop(self, full: Sequence[float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(A, B, C)`` of the clamped sampled loop, ``F_k = C ξ_k``, ``ξ⁺ = A ξ + B θ_k``."""
        phi, gamma, rows = self._zoh
        cp, ca = rows
        ctrl = self.controller(full)
        Ak, Bk, Ck, Dk = ctrl.realization.state_space()
        names = ctrl.realization.inputs
        s_theta = np.array([1.0 if n.startswith("error") else 0.0 for n in names])
        s_x = np.array([-1.0 if n.endswith("_A") else 0.0 for n in names])  # x_L = 0
        n, nk = phi.shape[0], Ak.shape[0]
        d = int(self.loop.delay) if self.loop is not None else 0
        size = n + nk + d
        A, B = np.zeros((size, size)), np.zeros(size)
        # controller output v = Ck ξ + Dk (s_θ θ + s_x x_A), x_A = cp x
        v_x, v_k, v_t = float(Dk @ s_x) * cp, Ck, float(Dk @ s_theta)
        A[n : n + nk, :n] = np.outer(Bk @ s_x, cp)
        A[n : n + nk, n : n + nk] = Ak
        B[n : n + nk] = Bk @ s_theta
        A[:n, :n] = phi
        if d == 0:
            A[:n, :n] += np.outer(gamma[:, 0], v_x)
            A[:n, n : n + nk] += np.outer(gamma[:, 0], v_k)
            B[:n] = gamma[:, 0] * v_t
        else:
            r = n + nk  # shift register: w_1⁺ = v, w_(i+1)⁺ = w_i, the plant gets w_d
            A[r, :n], A[r, n : n + nk], B[r] = v_x, v_k, v_t
            for i in range(1, d):
                A[r + i, r + i - 1] = 1.0
            A[:n, r + d - 1] = gamma[:, 0]
        C = np.zeros(size)
        C[:n] = ca
        return A, B, C

    def force_magnitude(self, full: Sequence[float]) -> Callable[[np.ndarray], np.ndarray] | float:
        """``ω ↦ |G(e^{jωT})/G(1)|`` of the clamped sampled loop (nan: not stable)."""
        A, B, C = self.clamped_loop(full)
        if A.size and not float(np.max(np.abs(np.linalg.eigvals(A)))) < 1.0:
            return math.nan
        eye = np.eye(A.shape[0])
        dc = float(C @ np.linalg.solve(eye - A, B))
        if dc == 0:
            return 0.0
        T = self.period

        def curve(w: np.ndarray) -> np.ndarray:
            z = np.exp(1j * np.asarray(w, float) * T)
            return np.array([abs(C @ np.linalg.solve(zi * eye - A, B)) for zi in z]) / abs(dc)

        return curve
