"""Perceived stiffness under impacts (the paper's k_out experiment), run on the twin.

Each impact is a step of load force applied to the output held by Ours; the
ratio ``k_out = F_L/X_L`` read a short time later is compared with the spring
``k1`` and with the stiffness frequency response of Eq. (10), and, on the
paper's own bench only, with the paper's measurement.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike, NDArray

from ..errors import ParameterError
from ..files.csvtext import rows_csv
from ..model.design_file import Design
from ..model.display import html_card, short_repr
from ..model.expr import S
from ..model.sea import SEA
from ..model.stiffness import derive_stiffness
from ..sampled.controllers import DiscreteController
from .design_sweep import design_loop
from .findings import ExperimentFinding
from .packaged import is_paper_hardware
from .rigfile import Rig
from .twin import simulate_loop

FloatArray = NDArray[np.float64]

__all__ = [
    "DEFAULT_WINDOWS",
    "PAPER_K_OUT",
    "ImpactResult",
    "impact_forces",
    "k_out_ratio",
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
    vals = {
        "m": rig.actuator_mass,
        "b": rig.actuator_damping,
        "k1": rig.damper.k1,
        "b1": rig.damper.b1 if b1 is None else float(b1),
        "kd": float(kd),
        "bd": float(bd),
    }
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=vals, name="ours")
    return _stiffness_response(rig, sea, omega, load_mass)[:2]


def _stiffness_polys(sea: SEA) -> tuple[FloatArray, FloatArray]:
    """Numerator and denominator coefficients (highest power first) of Eq. (10) of ``sea``."""
    expr = sea.numeric(derive_stiffness(sea).stiffness)
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    pn = np.array([float(c) for c in sp.Poly(num, S).all_coeffs()])
    pd = np.array([float(c) for c in sp.Poly(den, S).all_coeffs()])
    return pn, pd


def _stiffness_response(
    rig: Rig, sea: SEA, omega: ArrayLike, load_mass: float
) -> tuple[FloatArray, FloatArray, float | None]:
    """``|F_L/X_L(jω)|`` of ``sea`` (massless port, and with the load side) and its static
    value ``F_L/X_L(0)`` (None when it is not finite: integral action)."""
    w = np.asarray(omega, dtype=float)
    pn, pd = _stiffness_polys(sea)
    s = 1j * w
    k = np.polyval(pn, s) / np.polyval(pd, s)
    ml = rig.load_side_mass(load_mass)
    static = None if pd[-1] == 0 else abs(float(pn[-1] / pd[-1]))
    return np.abs(k), np.abs(k + ml * s**2 + rig.load.viscous * s), static


PAPER_K_OUT = (2292.0, 91.6)
"""The paper's perceived stiffness under impacts, mean and std [N/m] (Sec. VI).

Measured on the paper's bench: set beside the twin's only for that bench
([`is_paper_hardware`][seapass.rig.packaged.is_paper_hardware])."""

DEFAULT_WINDOWS = (0.005, 0.01, 0.02, 0.03, 0.05, 0.1, 0.2)
"""Read-out times after impact onset [s] of the time-scale study."""


@dataclass(frozen=True, repr=False, kw_only=True)
class ImpactResult:
    """Perceived stiffness of Ours under steps in load force.

    ``forces`` and ``k_out`` have one entry per impact; ``b1_values`` /
    ``k_out_vs_b1`` (mean, std) are aligned; ``windows`` / ``k_out_vs_window``
    (mean) are aligned and ``k_out_linear_vs_window`` is the friction-free,
    unquantized twin; ``omega`` aligns with both ``eq10_*`` magnitudes.
    ``paper_k_out`` is the paper's measurement (`PAPER_K_OUT`) for the paper's
    bench and None for any other rig, whose ``findings`` are then empty: the
    paper's claims are about its own bench.  ``design`` is None for Ours (the rig's
    ``impacts.kd``, ``impacts.bd``) or the name of the design file whose controller
    held the output (``kd``, ``bd`` are then the rig's and unused; no findings; a
    controller in z has no Eq. (10): ``omega`` and ``eq10_*`` are empty).
    ``static_stiffness`` is ``F_L/X_L(0)`` of Eq. (10), None when not finite or
    without Eq. (10).
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
    static_stiffness: float | None
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
    paper_k_out: tuple[float, float] | None = None
    design: str | None = None

    def plot(self, *, axes: Any = None) -> Any:
        """Eq. (10) response, ``k_out`` against time scale and against ``b1``; three Axes."""
        from ..plot.rig import plot_impacts

        return plot_impacts(self, axes=axes)

    def __repr__(self) -> str:
        return short_repr(
            "ImpactResult",
            {
                "impacts": self.forces.size,
                "k_out_mean": self.k_out_mean,
                "k_out_std": self.k_out_std,
                "k1": self.k1,
                "window": self.window,
            },
        )

    def _repr_html_(self) -> str:
        rows: list[tuple[str, Any]] = [
            (
                "k_out",
                f"{self.k_out_mean:.0f} ± {self.k_out_std:.0f} N/m ({self.forces.size} impacts)",
            ),
            ("read at", f"{self.window * 1e3:g} ms after onset"),
            ("spring k1 / static", f"{self.k1:g} / {_static_text(self.static_stiffness)} N/m"),
        ]
        if self.paper_k_out is not None:
            rows.append(("paper (its bench)", "{:g} ± {:g} N/m".format(*self.paper_k_out)))
        return html_card("Perceived stiffness under impacts", rows)

    def to_csv(self) -> str:
        """One line per impact: its index, step force (N) and the ``k_out`` read (N/m)."""
        return rows_csv(
            [
                {"impact": i, "force": float(f), "k_out": float(k)}
                for i, (f, k) in enumerate(zip(self.forces, self.k_out, strict=True))
            ]
        )

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "design": self.design,
            "kd": self.kd,
            "bd": self.bd,
            "load_mass": self.load_mass,
            "window": self.window,
            "k1": self.k1,
            "static_stiffness": self.static_stiffness,
            "k_out_mean": self.k_out_mean,
            "k_out_std": self.k_out_std,
        }
        if self.paper_k_out is not None:
            out["paper_k_out"] = list(self.paper_k_out)
        out.update(
            {
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
                        self.windows,
                        self.k_out_vs_window,
                        self.k_out_linear_vs_window,
                        strict=True,
                    )
                ],
                "findings": [f.to_dict() for f in self.findings],
            }
        )
        return out


def _static_text(value: float | None) -> str:
    return "none" if value is None else f"{value:.0f}"


def impact_forces(rig: Rig, seed: int | None = None) -> FloatArray:
    """The step magnitudes of the ``[impacts]`` protocol [N], shape (count,)."""
    im = rig.impacts
    rng = np.random.default_rng(im.seed if seed is None else seed)
    return rng.uniform(im.force_min, im.force_max, im.count)


def _checked_grid(
    rig: Rig, b1_values: ArrayLike | None, windows: ArrayLike | None
) -> tuple[FloatArray, FloatArray]:
    """``b1`` values (default 0, b1/2, b1, 2 b1) and read-out times, validated."""
    b1 = rig.damper.b1
    b1s = np.asarray(
        b1_values if b1_values is not None else sorted({0.0, 0.5 * b1, b1, 2.0 * b1}), dtype=float
    )
    duration = rig.impacts.duration
    if windows is None:  # the default times that fit in the rig's impact duration
        windows = [w for w in DEFAULT_WINDOWS if w <= duration] or [rig.impacts.window]
    wins = np.asarray(windows, dtype=float)
    if b1s.ndim != 1 or np.any(b1s < 0):
        raise ParameterError("b1_values must be a 1-D array of damping values >= 0")
    if wins.ndim != 1 or np.any(wins <= 0) or np.any(wins > duration):
        raise ParameterError(f"windows must be a 1-D array of times in (0, {duration:g}] s")
    return b1s, wins


def _loop_options(rig: Rig, design: Design | None = None) -> dict[str, Any]:
    """The twin's options of an impact run: Ours' PD, or the design's controller."""
    im = rig.impacts
    out: dict[str, Any] = {"load_mass": im.load_mass, "duration": im.duration}
    if design is None:
        return {**out, "kp_actuator": im.kd, "kv_actuator": im.bd}
    loop = design_loop(design, rig)  # one controller for every run (reset per run)
    return {**out, "loop": loop, "controllers": [DiscreteController.for_loop(design.sea(), loop)]}


def k_out_ratio(x: FloatArray, forces: FloatArray, tau: float, period: float) -> FloatArray:
    """``F / X_L`` read ``tau`` after onset; a load that has not moved reads as ``inf``.

    ``x``: load displacement since onset, axes ``(..., impact, sample)``;
    ``forces``: axis ``impact``.
    """
    d = x[..., round(tau / period)]
    safe = np.where(d > 0, d, 1.0)
    return np.where(d > 0, forces / safe, np.inf)


def _displacements(
    rig: Rig, forces: FloatArray, b1s: FloatArray, options: dict[str, Any]
) -> FloatArray:
    """Encoder load displacement of every (b1 value, impact) run, axes (b1, impact, sample)."""
    nb, n = b1s.size, forces.size
    res = simulate_loop(rig, b1=np.repeat(b1s, n), load_force=np.tile(forces, nb), **options)
    return (res.x_L_measured - res.x_L_measured[:, :1]).reshape(nb, n, -1)


def _linear_by_window(
    rig: Rig, force: float, windows: FloatArray, options: dict[str, Any]
) -> FloatArray:
    """``k_out`` of the friction-free, unquantized twin at each read-out time (one impact)."""
    lin = simulate_loop(rig, load_force=[force], friction=False, quantize=False, **options)
    xl = lin.x_L - lin.x_L[:, :1]
    f = np.array([force])
    return np.array([float(k_out_ratio(xl, f, w, rig.period)[0]) for w in windows])


def _paper_findings(
    rig: Rig,
    stats: dict[str, Any],
    windows: FloatArray,
    by_window: FloatArray,
    b1s: FloatArray,
    by_b1: FloatArray,
) -> tuple[ExperimentFinding, ...]:
    """The paper's two claims about impacts, checked on its bench's twin."""
    im, k1 = rig.impacts, rig.damper.k1
    mean, std, static = stats["mean"], stats["std"], stats["static"]
    paper_mean, paper_std = PAPER_K_OUT
    scale = ", ".join(f"{t * 1e3:g} ms: {k:.0f}" for t, k in zip(windows, by_window, strict=True))
    return (
        ExperimentFinding(
            claim=f"k_out > k1 under impact (paper: {paper_mean:g} ± {paper_std:g} N/m vs "
            f"k1 = {k1:g} N/m)",
            match=mean > k1,
            detail=f"twin: k_out = {mean:.0f} ± {std:.0f} N/m at {im.window * 1e3:g} ms after a step of "
            f"{im.force_min:g}-{im.force_max:g} N (kd = {im.kd:g}, bd = {im.bd:g}, "
            f"b1 = {rig.damper.b1:g}); static stiffness k1·kd/(k1+kd) = {static:.0f} N/m. Early "
            "in an impact the damper force b1·v and the load inertia carry the force before the "
            "spring deflects, so the ratio exceeds k1; it decays toward the static value as the "
            f"window grows ({scale}).",
        ),
        ExperimentFinding(
            claim="k_out grows with the transmission damping b1",
            match=bool(np.all(np.diff(by_b1[np.argsort(b1s)]) > 0)),
            detail=", ".join(f"b1 = {b:g}: {m:.0f} N/m" for b, m in zip(b1s, by_b1, strict=True)),
        ),
    )


def _design_stiffness(
    rig: Rig, design: Design, w: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, float | None]:
    """Eq. (10) of the design's model at the rig's ``m, b, k1, b1`` (those it uses); a
    controller in z has none (empty arrays, no static value)."""
    if design.discrete is not None:
        empty = np.zeros(0)
        return empty, empty, empty, None
    sea = design.sea()
    plant = {"m": rig.actuator_mass, "b": rig.actuator_damping,
             "k1": rig.damper.k1, "b1": rig.damper.b1}  # fmt: skip
    sea = sea.with_values(**{k: v for k, v in plant.items() if k in (*sea.parameters, "m", "b")})
    mag, mag_l, static = _stiffness_response(rig, sea, w, rig.impacts.load_mass)
    return w, mag, mag_l, static


def run_impacts(
    rig: Rig,
    *,
    design: Design | None = None,
    b1_values: ArrayLike | None = None,
    windows: ArrayLike | None = None,
    omega: ArrayLike | None = None,
    seed: int | None = None,
) -> ImpactResult:
    """Simulate the impacts of the rig file's ``[impacts]`` protocol.

    Each impact is a step of load force ``F_i`` (uniform in
    ``[force_min, force_max]``, drawn with ``impacts.seed``) applied to the
    output held by Ours (``kd + bd s`` on the actuator, reference 0), or by the
    controller of ``design``; ``k_out,i = F_i / X_L(window)`` with ``X_L`` from
    the encoders.  The same forces are replayed for each ``b1`` in ``b1_values``
    and the ratio is read at each time in ``windows``.  The paper's claims are
    checked only on the paper's bench with Ours (see `ImpactResult`).

    Parameters
    ----------
    rig : Rig
        The twin and its ``[impacts]`` protocol.
    design : Design, optional
        A design file whose controller (continuous or in z, ``[discrete]``) holds the
        output instead of Ours, realized at the rig's loop as ``rig sweep --design``
        does ([`design_loop`][seapass.rig.design_sweep.design_loop]); its
        controller parameters are the file's, the physical plant is the rig's.
    b1_values, windows, omega : array_like, optional
        Damping values of the ``b1`` study, read-out times [s] and the frequencies of
        Eq. (10) [rad/s].
    seed : int or None
        Seed of the impact forces (default ``impacts.seed``).

    Returns
    -------
    ImpactResult

    Raises
    ------
    ParameterError
        For bad ``b1_values`` or ``windows``, or a design without a controller.
    """
    im, k1 = rig.impacts, rig.damper.k1
    if design is not None and design.discrete is None and design.CA == design.CL == "0":
        raise ParameterError(
            f"design: {design.name!r} has no controller (C_A = C_L = 0) to hold the output",
            argument="design",
        )
    forces = impact_forces(rig, seed)
    b1s, wins = _checked_grid(rig, b1_values, windows)
    options = _loop_options(rig, design)
    x = _displacements(rig, forces, b1s, options)
    k_b1 = k_out_ratio(x, forces, im.window, rig.period)  # (b1, impact)
    nominal = int(np.argmin(np.abs(b1s - rig.damper.b1)))
    k_nom = k_b1[nominal]
    vs_win = np.array(
        [float(np.mean(k_out_ratio(x[nominal], forces, w, rig.period))) for w in wins]
    )
    w = np.logspace(0, 3, 200) if omega is None else np.asarray(omega, dtype=float)
    if design is None:
        mag, mag_l = rig_stiffness_response(rig, w, kd=im.kd, bd=im.bd, load_mass=im.load_mass)
        static: float | None = k1 * im.kd / (k1 + im.kd) if im.kd > 0 else 0.0
    else:
        w, mag, mag_l, static = _design_stiffness(rig, design, w)
    n = forces.size
    stats: dict[str, Any] = {
        "mean": float(np.mean(k_nom)),
        "std": float(np.std(k_nom, ddof=1)) if n > 1 else 0.0,
        "static": static,
    }
    means = k_b1.mean(axis=1)
    paper = is_paper_hardware(rig) and design is None
    return ImpactResult(
        kd=im.kd,
        bd=im.bd,
        load_mass=im.load_mass,
        window=im.window,
        forces=forces,
        k_out=k_nom,
        k_out_mean=stats["mean"],
        k_out_std=stats["std"],
        k1=k1,
        static_stiffness=static,
        b1_values=b1s,
        k_out_vs_b1=means,
        k_out_vs_b1_std=k_b1.std(axis=1, ddof=1) if n > 1 else np.zeros(b1s.size),
        windows=wins,
        k_out_vs_window=vs_win,
        k_out_linear_vs_window=_linear_by_window(rig, float(forces[0]), wins, options),
        omega=w,
        eq10_magnitude=mag,
        eq10_with_load=mag_l,
        findings=_paper_findings(rig, stats, wins, vs_win, b1s, means) if paper else (),
        paper_k_out=PAPER_K_OUT if paper else None,
        design=None if design is None else design.name,
    )
