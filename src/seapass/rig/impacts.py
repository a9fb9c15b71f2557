"""Perceived stiffness under impacts (the paper's k_out experiment), run on the twin.

Each impact is a step of load force applied to the output held by Ours; the
ratio ``k_out = F_L/X_L`` read a short time later is compared with the spring
``k1`` and with the stiffness frequency response of Eq. (10).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike, NDArray

from ..errors import ParameterError
from ..model.expr import S
from ..model.sea import SEA
from ..model.stiffness import derive_stiffness
from .findings import ExperimentFinding
from .rigfile import Rig
from .twin import simulate_loop

FloatArray = NDArray[np.float64]

__all__ = [
    "ImpactResult",
    "rig_stiffness_response",
    "run_impacts",
]


def rig_stiffness_response(
    rig: Rig,
    omega: ArrayLike,
    *,
    kd: float,
    bd: float,
    b1: float | None = None,
    load_mass: float = 0.0,
) -> tuple[FloatArray, FloatArray]:
    """``|F_L/X_L(jω)|`` of Eq. (10) and of the twin's port (Eq. (10) + load mass).

    Eq. (10) is obtained from [`seapass.model.stiffness.derive_stiffness`][seapass.model.stiffness.derive_stiffness] with
    ``D1 = k1 + b1 s``, ``C_A = kd + bd s`` and the rig's ``m, b``; the second
    array adds the load-side carriage + load (``m_L s² + b_L s``), which the
    paper's massless port omits.  Axis: frequency.
    """
    w = np.asarray(omega, dtype=float)
    vals = {
        "m": rig.actuator_mass,
        "b": rig.actuator_damping,
        "k1": rig.damper.k1,
        "b1": rig.damper.b1 if b1 is None else float(b1),
        "kd": float(kd),
        "bd": float(bd),
    }
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=vals, name="ours")
    expr = sea.numeric(derive_stiffness(sea).stiffness)
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    pn = np.array([float(c) for c in sp.Poly(num, S).all_coeffs()])
    pd = np.array([float(c) for c in sp.Poly(den, S).all_coeffs()])
    s = 1j * w
    k = np.polyval(pn, s) / np.polyval(pd, s)
    ml = rig.load_side_mass(load_mass)
    return np.abs(k), np.abs(k + ml * s**2 + rig.load.viscous * s)


@dataclass(frozen=True)
class ImpactResult:
    """Perceived stiffness of Ours under steps in load force.

    ``forces`` and ``k_out`` have one entry per impact; ``b1_values`` /
    ``k_out_vs_b1`` (mean, std) are aligned; ``windows`` / ``k_out_vs_window``
    (mean) are aligned and ``k_out_linear_vs_window`` is the friction-free,
    unquantized twin; ``omega`` aligns with both ``eq10_*`` magnitudes.
    """

    kd: float
    bd: float
    load_mass: float
    window: float
    forces: FloatArray
    k_out: FloatArray
    k_out_mean: float
    k_out_std: float
    k1: float
    static_stiffness: float
    b1_values: FloatArray
    k_out_vs_b1: FloatArray
    k_out_vs_b1_std: FloatArray
    windows: FloatArray
    k_out_vs_window: FloatArray
    k_out_linear_vs_window: FloatArray
    omega: FloatArray
    eq10_magnitude: FloatArray
    eq10_with_load: FloatArray
    findings: tuple[ExperimentFinding, ...]

    def to_dict(self) -> dict[str, Any]:
        return {
            "kd": self.kd,
            "bd": self.bd,
            "load_mass": self.load_mass,
            "window": self.window,
            "k1": self.k1,
            "static_stiffness": self.static_stiffness,
            "k_out_mean": self.k_out_mean,
            "k_out_std": self.k_out_std,
            "paper_k_out": [2292.0, 91.6],
            "impacts": [
                {"force": float(f), "k_out": float(k)}
                for f, k in zip(self.forces, self.k_out, strict=True)
            ],
            "vs_b1": [
                {"b1": float(b), "k_out_mean": float(m), "k_out_std": float(s)}
                for b, m, s in zip(
                    self.b1_values, self.k_out_vs_b1, self.k_out_vs_b1_std, strict=True
                )
            ],
            "vs_window": [
                {"window": float(w), "k_out_mean": float(m), "k_out_linear": float(lin)}
                for w, m, lin in zip(
                    self.windows, self.k_out_vs_window, self.k_out_linear_vs_window, strict=True
                )
            ],
            "findings": [f.to_dict() for f in self.findings],
        }


def run_impacts(
    rig: Rig,
    *,
    b1_values: ArrayLike | None = None,
    windows: ArrayLike | None = None,
    omega: ArrayLike | None = None,
    seed: int | None = None,
) -> ImpactResult:
    """Simulate the impacts of the rig file's ``[impacts]`` protocol.

    Each impact is a step of load force ``F_i`` (uniform in
    ``[force_min, force_max]``, drawn with ``impacts.seed``) applied to the
    output held by Ours (``kd + bd s`` on the actuator, reference 0);
    ``k_out,i = F_i / X_L(window)`` with ``X_L`` from the encoders.  The same
    forces are replayed for each ``b1`` in ``b1_values`` and the ratio is read at
    each time in ``windows``.
    """
    im = rig.impacts
    rng = np.random.default_rng(im.seed if seed is None else seed)
    forces = rng.uniform(im.force_min, im.force_max, im.count)
    b1_nom = rig.damper.b1
    b1s = np.asarray(
        b1_values if b1_values is not None else sorted({0.0, 0.5 * b1_nom, b1_nom, 2.0 * b1_nom}),
        dtype=float,
    )
    wins = np.asarray(
        windows if windows is not None else [0.005, 0.01, 0.02, 0.03, 0.05, 0.1, 0.2], dtype=float
    )
    if b1s.ndim != 1 or np.any(b1s < 0):
        raise ParameterError("b1_values must be a 1-D array of damping values >= 0")
    if wins.ndim != 1 or np.any(wins <= 0) or np.any(wins > im.duration):
        raise ParameterError(f"windows must be a 1-D array of times in (0, {im.duration:g}] s")
    nb, n = b1s.size, im.count
    # Batch axis: (b1 value, impact) flattened.
    common: dict[str, Any] = dict(
        load_mass=im.load_mass,
        kp_actuator=im.kd,
        kv_actuator=im.bd,
        duration=im.duration,
    )
    res = simulate_loop(rig, b1=np.repeat(b1s, n), load_force=np.tile(forces, nb), **common)
    x = (res.x_L_measured - res.x_L_measured[:, :1]).reshape(nb, n, -1)
    T = rig.period

    def ratio(xs: FloatArray, f: FloatArray, tau: float) -> FloatArray:
        # xs: (..., impact, sample), f: (impact,); a load that has not moved reads as inf.
        d = xs[..., round(tau / T)]
        safe = np.where(d > 0, d, 1.0)
        return np.where(d > 0, f / safe, np.inf)

    k_b1 = ratio(x, forces, im.window)
    nominal = int(np.argmin(np.abs(b1s - b1_nom)))
    lin = simulate_loop(rig, load_force=forces[:1], friction=False, quantize=False, **common)
    xl = lin.x_L - lin.x_L[:, :1]
    vs_win = np.array([float(np.mean(ratio(x[nominal], forces, w))) for w in wins])
    vs_lin = np.array([float(ratio(xl, forces[:1], w)[0]) for w in wins])
    w = np.logspace(0, 3, 200) if omega is None else np.asarray(omega, dtype=float)
    mag, mag_l = rig_stiffness_response(rig, w, kd=im.kd, bd=im.bd, load_mass=im.load_mass)
    k_nom = k_b1[nominal]
    k1 = rig.damper.k1
    static = k1 * im.kd / (k1 + im.kd) if im.kd > 0 else 0.0
    mean, std = float(np.mean(k_nom)), float(np.std(k_nom, ddof=1)) if n > 1 else 0.0
    means = k_b1.mean(axis=1)
    monotone = bool(np.all(np.diff(means[np.argsort(b1s)]) > 0))
    findings = (
        ExperimentFinding(
            "k_out > k1 under impact (paper: 2292 ± 91.6 N/m vs k1 = 1005 N/m)",
            mean > k1,
            f"twin: k_out = {mean:.0f} ± {std:.0f} N/m at {im.window * 1e3:g} ms after a step of "
            f"{im.force_min:g}-{im.force_max:g} N (kd = {im.kd:g}, bd = {im.bd:g}, b1 = {b1_nom:g}); "
            f"static stiffness k1·kd/(k1+kd) = {static:.0f} N/m. Early in an impact the damper "
            "force b1·v and the load inertia carry the force before the spring deflects, so the "
            "ratio exceeds k1; it decays toward the static value as the window grows "
            f"({', '.join(f'{t * 1e3:g} ms: {k:.0f}' for t, k in zip(wins, vs_win, strict=True))}).",
        ),
        ExperimentFinding(
            "k_out grows with the transmission damping b1",
            monotone,
            ", ".join(f"b1 = {b:g}: {m:.0f} N/m" for b, m in zip(b1s, means, strict=True)),
        ),
    )
    return ImpactResult(
        kd=im.kd,
        bd=im.bd,
        load_mass=im.load_mass,
        window=im.window,
        forces=forces,
        k_out=k_nom,
        k_out_mean=mean,
        k_out_std=std,
        k1=k1,
        static_stiffness=static,
        b1_values=b1s,
        k_out_vs_b1=means,
        k_out_vs_b1_std=k_b1.std(axis=1, ddof=1) if n > 1 else np.zeros(nb),
        windows=wins,
        k_out_vs_window=vs_win,
        k_out_linear_vs_window=vs_lin,
        omega=w,
        eq10_magnitude=mag,
        eq10_with_load=mag_l,
        findings=findings,
    )
