"""The paper's hardware experiment (Section VI), run on the digital twin.

Two protocols:

* :func:`run_sweep` / :func:`run_experiment` — settling experiment: the load
  starts at rest at ``experiment.initial_position`` (20 mm) and is driven to 0
  by LP (load-side P, ``C_L = kd``) or Ours (actuator-side PD,
  ``C_A = kd + bd s``, ``bd = 25``) for ``kd`` in ``[0, kd_max]`` and each
  load mass; settling time (2 % band, capped at 2 s) and steady-state error
  are measured on the encoder signals, and the gain beyond which LP becomes
  unstable is located in the twin and predicted from the continuous-time and
  the sampled (ZOH, delay, filtered finite differences) linear loops.
* :func:`run_impacts` — perceived stiffness ``k_out = F_L/X_L`` under steps in
  load force (the paper's approximation of an impact), its dependence on the
  damper ``b1`` and on the impact time scale, and the stiffness frequency
  response of Eq. (10) from :func:`seapass.model.stiffness.derive_stiffness`.

Findings are compared with the paper's qualitative claims in
:class:`Finding` objects (match or mismatch, with the reason from the model).

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Section VI and Fig. 3.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import expm
from scipy.stats import spearmanr

from ..errors import ParameterError
from ..model.expr import S
from ..model.sea import SEA
from .rigfile import Rig
from ..model.stiffness import derive_stiffness
from .twin import linear_matrices, simulate_loop

__all__ = [
    "DESIGNS",
    "ExperimentResult",
    "Finding",
    "ImpactResult",
    "SweepResult",
    "critical_gain",
    "run_experiment",
    "run_impacts",
    "run_sweep",
    "sampled_loop_matrix",
    "settling_metrics",
    "stiffness_response",
]

DESIGNS = ("LP", "ours")
FINAL_WINDOW = 0.25  # s at the end of the horizon that decide the final value
FloatArray = NDArray[np.float64]


def _design(design: str) -> str:
    key = str(design).strip().lower()
    if key == "lp":
        return "LP"
    if key == "ours":
        return "ours"
    raise ParameterError(f"design must be 'LP' or 'ours', got {design!r}")


def _gains(design: str, kd: ArrayLike, bd: float) -> dict[str, Any]:
    if design == "LP":
        return {"kp_load": kd}
    return {"kp_actuator": kd, "kv_actuator": bd}


# ----------------------------------------------------------------------------- metrics


def settling_metrics(
    t: FloatArray,
    x: FloatArray,
    *,
    x0: float,
    reference: float = 0.0,
    band: float,
    cap: float,
    final_window: float = FINAL_WINDOW,
    diverged: bool = False,
) -> tuple[str, float | None, float | None, float | None]:
    """Classify one response and measure it.

    Returns ``(status, settling_time, final_value, steady_state_error)``.
    ``status`` is ``settled`` (within ``band`` of its final value for good
    before ``cap``), ``slow`` (converged, but later than ``cap``), ``stuck``
    (never left the band around its start: no motion), ``oscillating``
    (bounded, not converged) or ``unstable`` (left the travel, or a sustained
    oscillation larger than 10 % of the initial offset).  The error is
    ``|final − reference|`` for converged runs, else None.
    """
    offset = abs(x0 - reference)
    n_final = max(2, round(final_window / (t[1] - t[0])))
    tail = x[-n_final:]
    if diverged or not np.all(np.isfinite(x)):
        return "unstable", None, None, None
    spread = float(np.ptp(tail))
    if spread > band:
        status = "unstable" if spread >= 0.1 * offset else "oscillating"
        return status, None, None, None
    final = float(np.mean(tail))
    err = abs(final - reference)
    if abs(final - x0) <= band and np.all(np.abs(x - x0) <= band):
        return "stuck", None, final, err
    outside = np.nonzero(np.abs(x - final) > band)[0]
    ts = float(t[outside[-1] + 1]) if outside.size else 0.0
    if ts <= cap:
        return "settled", ts, final, err
    return "slow", None, final, err


# ----------------------------------------------------------------------------- linear predictions


def _zoh(rig: Rig, load_mass: float) -> tuple[FloatArray, FloatArray]:
    a, b = linear_matrices(rig, load_mass=load_mass)
    blk = np.zeros((5, 5))
    blk[:4, :4], blk[:4, 4:] = a, b
    e = expm(blk * rig.period)
    return e[:4, :4], e[:4, 4:]


def sampled_loop_matrix(
    rig: Rig,
    *,
    load_mass: float,
    kp_actuator: float = 0.0,
    kv_actuator: float = 0.0,
    kp_load: float = 0.0,
    kv_load: float = 0.0,
    delay_samples: int | None = None,
    velocity_filter_hz: float | None = None,
    _zoh_cache: tuple[FloatArray, FloatArray] | None = None,
) -> FloatArray:
    """Closed-loop transition matrix of the sampled linear loop (9 states).

    State ``(x, y_{k-1}, v̂_{k-1}, u_{k-1})``: plant ``(x_A, v_A, x_L, v_L)``
    discretised with ZOH at the control period, last measured positions,
    filtered finite-difference velocities and the pending command (used when
    ``delay_samples = 1``).  The loop is stable iff the spectral radius < 1.
    """
    T = rig.period
    delay = rig.control.delay_samples if delay_samples is None else int(delay_samples)
    fc = rig.control.velocity_filter_hz if velocity_filter_hz is None else float(velocity_filter_hz)
    alpha = math.exp(-2.0 * math.pi * fc * T) if fc > 0 else 0.0
    beta = (1.0 - alpha) / T
    ad, bd = _zoh(rig, load_mass) if _zoh_cache is None else _zoh_cache
    c = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
    kp = np.array([[kp_actuator, kp_load]])
    kv = np.array([[kv_actuator, kv_load]])
    gx = -kp @ c - beta * kv @ c
    gy = beta * kv
    gv = -alpha * kv
    m = np.zeros((9, 9))
    # rows: x (0:4), y (4:6), v (6:8), u (8)
    if delay:
        m[0:4, 0:4] = ad
        m[0:4, 8:9] = bd
    else:
        m[0:4, 0:4] = ad + bd @ gx
        m[0:4, 4:6] = bd @ gy
        m[0:4, 6:8] = bd @ gv
    m[4:6, 0:4] = c
    m[6:8, 0:4] = beta * c
    m[6:8, 4:6] = -beta * np.eye(2)
    m[6:8, 6:8] = alpha * np.eye(2)
    m[8:9, 0:4] = gx
    m[8:9, 4:6] = gy
    m[8:9, 6:8] = gv
    return m


def _unstable(
    rig: Rig,
    design: str,
    load_mass: float,
    kd: float,
    bd: float,
    sampled: bool,
    zoh: tuple[FloatArray, FloatArray] | None,
) -> bool:
    g = _gains(design, kd, bd)
    if sampled:
        mat = sampled_loop_matrix(rig, load_mass=load_mass, _zoh_cache=zoh, **g)
        return bool(np.max(np.abs(np.linalg.eigvals(mat))) > 1.0 + 1e-12)
    a, b = linear_matrices(rig, load_mass=load_mass)
    k = np.array(
        [[g.get("kp_actuator", 0.0), g.get("kv_actuator", 0.0), g.get("kp_load", 0.0), 0.0]]
    )
    return bool(np.max(np.linalg.eigvals(a - b @ k).real) > 1e-12)


def critical_gain(
    rig: Rig,
    *,
    design: str,
    load_mass: float,
    sampled: bool,
    bd: float | None = None,
    kd_search: float = 1e5,
    grid: int = 500,
) -> float | None:
    """Smallest ``kd`` at which the linear closed loop becomes unstable.

    ``sampled=False`` uses the continuous-time loop (eigenvalues of ``A − B K``);
    ``sampled=True`` the ZOH loop at the rig's rate with its delay and velocity
    filter (:func:`sampled_loop_matrix`).  The first crossing on a grid over
    ``[0, kd_search]`` is refined by bisection; None when stable throughout.
    """
    d = _design(design)
    bdv = rig.experiment.bd_ours if bd is None else float(bd)
    zoh = _zoh(rig, load_mass) if sampled else None
    grid_kd = np.linspace(0.0, kd_search, grid + 1)
    prev = 0.0
    for kd in grid_kd[1:]:
        if _unstable(rig, d, load_mass, float(kd), bdv, sampled, zoh):
            lo, hi = prev, float(kd)
            for _ in range(50):
                mid = 0.5 * (lo + hi)
                if _unstable(rig, d, load_mass, mid, bdv, sampled, zoh):
                    hi = mid
                else:
                    lo = mid
            return hi
        prev = float(kd)
    return None


# ----------------------------------------------------------------------------- sweep


@dataclass(frozen=True)
class SweepResult:
    """Settling experiment for one design and one load mass.

    Arrays are indexed by gain (axis 0, same order as ``kd``); traces are
    ``(gain, sample)``.  ``NaN`` in ``settling_time`` means "did not settle
    within the cap"; ``NaN`` in ``steady_state_error`` means "did not converge".
    """

    design: str
    load_mass: float
    bd: float
    kd: FloatArray
    settling_time: FloatArray
    steady_state_error: FloatArray
    final_value: FloatArray
    status: tuple[str, ...]
    unstable_gain_twin: float | None
    unstable_gain_continuous: float | None
    unstable_gain_sampled: float | None
    t: FloatArray = field(repr=False)
    x_L: FloatArray = field(repr=False)

    def rows(self) -> list[dict[str, Any]]:
        """One dict per gain (for CSV)."""
        out = []
        for i, kd in enumerate(self.kd):
            ts, err = self.settling_time[i], self.steady_state_error[i]
            out.append(
                {
                    "design": self.design,
                    "load_mass": self.load_mass,
                    "kd": float(kd),
                    "bd": self.bd if self.design == "ours" else 0.0,
                    "status": self.status[i],
                    "settling_time": None if math.isnan(ts) else float(ts),
                    "steady_state_error": None if math.isnan(err) else float(err),
                }
            )
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "design": self.design,
            "load_mass": self.load_mass,
            "bd": self.bd if self.design == "ours" else 0.0,
            "unstable_gain_twin": self.unstable_gain_twin,
            "unstable_gain_continuous": self.unstable_gain_continuous,
            "unstable_gain_sampled": self.unstable_gain_sampled,
            "runs": self.rows(),
        }


def _kd_grid(
    rig: Rig, kd: ArrayLike | None, kd_max: float | None, kd_step: float | None
) -> FloatArray:
    if kd is not None:
        arr = np.atleast_1d(np.asarray(kd, dtype=float))
        if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr < 0):
            raise ParameterError(
                f"kd must be a non-empty 1-D array of gains >= 0, got shape {arr.shape}"
            )
        return arr
    top = rig.experiment.kd_max if kd_max is None else float(kd_max)
    step = rig.experiment.kd_step if kd_step is None else float(kd_step)
    if not (top > 0 and step > 0 and math.isfinite(top) and math.isfinite(step)):
        raise ParameterError("kd_max and kd_step must be positive")
    if top / step > 10_000:
        raise ParameterError(f"kd grid too fine: {top / step:.0f} gains; raise kd_step")
    return np.arange(0.0, top + 0.5 * step, step)


def run_sweep(
    rig: Rig,
    *,
    design: str,
    load_mass: float,
    kd: ArrayLike | None = None,
    kd_max: float | None = None,
    kd_step: float | None = None,
    bd: float | None = None,
    predictions: bool = True,
    seed: int | None = None,
) -> SweepResult:
    """Run the settling experiment for one design and one load mass.

    Parameters
    ----------
    rig : Rig
    design : {"LP", "ours"}
    load_mass : float
        Mass added to the output (kg).
    kd : array_like, optional
        Gains to test (default ``0, kd_step, ..., kd_max`` from the rig file).
    bd : float, optional
        Actuator-side damping of Ours (default ``experiment.bd_ours``).
    predictions : bool
        Also compute the continuous and sampled linear instability gains.
    """
    d = _design(design)
    if not (math.isfinite(load_mass) and load_mass >= 0):
        raise ParameterError(f"load_mass must be >= 0, got {load_mass!r}")
    ex = rig.experiment
    gains = _kd_grid(rig, kd, kd_max, kd_step)
    bdv = ex.bd_ours if bd is None else float(bd)
    res = simulate_loop(
        rig,
        load_mass=load_mass,
        duration=ex.horizon,
        x0=ex.initial_position,
        deflection0=ex.initial_deflection,
        seed=seed,
        **_gains(d, gains, bdv),
    )
    band = ex.settle_band * abs(ex.initial_position)
    ts = np.full(gains.size, np.nan)
    err = np.full(gains.size, np.nan)
    fin = np.full(gains.size, np.nan)
    status = []
    for i in range(gains.size):
        st, t_s, f, e = settling_metrics(
            res.t,
            res.x_L_measured[i],
            x0=ex.initial_position,
            band=band,
            cap=ex.settle_cap,
            diverged=bool(res.diverged[i]),
        )
        status.append(st)
        ts[i] = np.nan if t_s is None else t_s
        fin[i] = np.nan if f is None else f
        err[i] = np.nan if e is None else e
    unstable = [float(g) for g, s in zip(gains, status, strict=True) if s == "unstable"]
    search = max(10.0 * float(gains.max()), 1e4)
    return SweepResult(
        design=d,
        load_mass=float(load_mass),
        bd=bdv,
        kd=gains,
        settling_time=ts,
        steady_state_error=err,
        final_value=fin,
        status=tuple(status),
        unstable_gain_twin=min(unstable) if unstable else None,
        unstable_gain_continuous=critical_gain(
            rig, design=d, load_mass=load_mass, sampled=False, bd=bdv, kd_search=search
        )
        if predictions
        else None,
        unstable_gain_sampled=critical_gain(
            rig, design=d, load_mass=load_mass, sampled=True, bd=bdv, kd_search=search
        )
        if predictions
        else None,
        t=res.t,
        x_L=res.x_L_measured,
    )


# ----------------------------------------------------------------------------- findings


@dataclass(frozen=True)
class Finding:
    """One qualitative claim of the paper checked against the twin."""

    claim: str
    match: bool | None  # None: not tested in this run
    detail: str

    def to_dict(self) -> dict[str, Any]:
        return {"claim": self.claim, "match": self.match, "detail": self.detail}


def _by(sweeps: Sequence[SweepResult], design: str) -> list[SweepResult]:
    return [s for s in sweeps if s.design == design]


def _sweep_findings(sweeps: Sequence[SweepResult]) -> list[Finding]:
    out: list[Finding] = []
    lp, ours = _by(sweeps, "LP"), _by(sweeps, "ours")
    if lp:
        parts = [
            f"m_L={s.load_mass:g} kg: twin {s.unstable_gain_twin}, sampled linear "
            f"{_fmt(s.unstable_gain_sampled)}, continuous {_fmt(s.unstable_gain_continuous)}"
            for s in lp
        ]
        ok = all(s.unstable_gain_twin is not None for s in lp)
        out.append(
            Finding(
                "LP becomes unstable at high gain",
                ok,
                "first unstable kd (N/m) — " + "; ".join(parts) + ". The one-sample delay and "
                "ZOH lower the continuous-time limit; dry friction damps small oscillations, so "
                "the twin tolerates gains slightly above the sampled linear limit.",
            )
        )
    if ours:
        rhos, detail = [], []
        for s in ours:
            ok_idx = ~np.isnan(s.settling_time) & (s.kd > 0)
            if ok_idx.sum() >= 3:
                rho = float(spearmanr(s.kd[ok_idx], s.settling_time[ok_idx]).statistic)
                rhos.append(rho)
                detail.append(f"m_L={s.load_mass:g}: Spearman(kd, t_s) = {rho:+.2f}")
        faster = []
        for s in ours:
            twins = [p for p in lp if p.load_mass == s.load_mass]
            if twins:
                hi = s.kd >= 0.5 * s.kd.max()
                t_o = np.nanmedian(
                    np.where(np.isnan(s.settling_time[hi]), np.inf, s.settling_time[hi])
                )
                p = twins[0]
                hp = p.kd >= 0.5 * p.kd.max()
                t_l = np.nanmedian(
                    np.where(np.isnan(p.settling_time[hp]), np.inf, p.settling_time[hp])
                )
                faster.append(bool(t_o < t_l))
                detail.append(
                    f"m_L={s.load_mass:g}: median t_s over the upper half of gains, Ours "
                    f"{_fmt(t_o)} s vs LP {_fmt(t_l)} s"
                )
        out.append(
            Finding(
                "As the gain rises, Ours settles faster than LP",
                all(faster) if faster else None,
                "; ".join(d for d in detail if "median" in d) + ". LP has no velocity feedback "
                "and its load mode loses damping as kd approaches the stability limit; Ours "
                "keeps the load mode damped through bd and the damper b1.",
            )
        )
        plateau = []
        for s in ours:
            ok_idx = ~np.isnan(s.settling_time) & (s.kd > 0)
            if ok_idx.any():
                i = int(np.argmin(np.where(ok_idx, s.settling_time, np.inf)))
                plateau.append(
                    f"m_L={s.load_mass:g}: fastest {s.settling_time[i]:.3f} s at kd={s.kd[i]:g}"
                )
        out.append(
            Finding(
                "Ours' own settling time falls as the gain rises",
                (all(r < 0 for r in rhos) if rhos else None),
                "; ".join(d for d in detail if "Spearman" in d)
                + "; "
                + "; ".join(plateau)
                + ". In the twin t_s falls steeply up to kd ~ 500-700 N/m and then plateaus "
                "(slightly rising): once the actuator loop is fast, the load mode "
                "(k1, b1, m_L: about 0.15-0.3 s) sets the settling time, and dry-friction "
                "stick-slip makes the last 0.4 mm band ragged.",
            )
        )
        errs, detail = [], []
        for s in ours:
            twins = [p for p in lp if p.load_mass == s.load_mass]
            low = (s.kd > 0) & (s.kd < 200)
            high = s.kd >= 0.5 * s.kd.max()
            e_low = float(np.nanmean(s.steady_state_error[low])) if low.any() else math.nan
            e_high = float(np.nanmean(s.steady_state_error[high])) if high.any() else math.nan
            larger = None
            if twins and low.any():
                p = twins[0]
                pl = (p.kd > 0) & (p.kd < 200)
                e_lp = float(np.nanmean(p.steady_state_error[pl])) if pl.any() else math.nan
                larger = e_low > e_lp
                detail.append(
                    f"m_L={s.load_mass:g}: mean error kd<200 Ours {e_low * 1e3:.2f} mm vs LP "
                    f"{e_lp * 1e3:.2f} mm; Ours at upper half of gains {e_high * 1e3:.2f} mm"
                )
            errs.append((larger, e_high < e_low))
        ok2 = bool(errs) and all(a is not False and b for a, b in errs)
        out.append(
            Finding(
                "Ours has a larger error for kd < 200 that shrinks as the gain rises",
                ok2 if errs else None,
                "; ".join(detail) + ". In the twin the error is set by dry friction: the "
                "actuator stops where kd·|x_A| < F_cA (+ rail friction), so it falls like 1/kd; "
                "bd slows the final approach so Ours sticks further away at low gain. LP "
                "also sticks at ~F_c/kd but overshoots, and its errors scatter around 0; the "
                "damper's Coulomb level leaves up to F_c1/k1 of spring deflection in Ours.",
            )
        )
    return out


def _fmt(x: float | None) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "none" if x is None else "inf"
    return f"{x:.4g}"


@dataclass(frozen=True)
class ExperimentResult:
    """The full settling experiment: one :class:`SweepResult` per (design, mass)."""

    rig_name: str
    sweeps: tuple[SweepResult, ...]
    findings: tuple[Finding, ...]

    def to_dict(self) -> dict[str, Any]:
        return {
            "rig": self.rig_name,
            "sweeps": [s.to_dict() for s in self.sweeps],
            "findings": [f.to_dict() for f in self.findings],
        }


@contextmanager
def _progress(enabled: bool, total: int, label: str) -> Iterator[Any]:
    import sys

    if not enabled or not sys.stderr.isatty():
        yield None
        return
    from rich.progress import Progress

    with Progress(transient=True) as prog:
        task = prog.add_task(label, total=total)
        yield lambda: prog.advance(task)


def run_experiment(
    rig: Rig,
    *,
    designs: Sequence[str] = DESIGNS,
    load_masses: Sequence[float] | None = None,
    kd: ArrayLike | None = None,
    kd_max: float | None = None,
    kd_step: float | None = None,
    progress: bool = True,
) -> ExperimentResult:
    """Settling experiment for every design × load mass (axis order of ``sweeps``)."""
    ds = [_design(d) for d in designs]
    masses = list(rig.experiment.load_masses if load_masses is None else load_masses)
    if not ds or not masses:
        raise ParameterError("give at least one design and one load mass")
    sweeps = []
    with _progress(progress, len(ds) * len(masses), "kd sweep") as tick:
        for d in ds:
            for ml in masses:
                sweeps.append(
                    run_sweep(
                        rig, design=d, load_mass=float(ml), kd=kd, kd_max=kd_max, kd_step=kd_step
                    )
                )
                if tick is not None:
                    tick()
    return ExperimentResult(rig.name, tuple(sweeps), tuple(_sweep_findings(sweeps)))


# ----------------------------------------------------------------------------- impacts


def stiffness_response(
    rig: Rig,
    omega: ArrayLike,
    *,
    kd: float,
    bd: float,
    b1: float | None = None,
    load_mass: float = 0.0,
) -> tuple[FloatArray, FloatArray]:
    """``|F_L/X_L(jω)|`` of Eq. (10) and of the twin's port (Eq. (10) + load mass).

    Eq. (10) is obtained from :func:`seapass.model.stiffness.derive_stiffness` with
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
    findings: tuple[Finding, ...]

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
    mag, mag_l = stiffness_response(rig, w, kd=im.kd, bd=im.bd, load_mass=im.load_mass)
    k_nom = k_b1[nominal]
    k1 = rig.damper.k1
    static = k1 * im.kd / (k1 + im.kd) if im.kd > 0 else 0.0
    mean, std = float(np.mean(k_nom)), float(np.std(k_nom, ddof=1)) if n > 1 else 0.0
    means = k_b1.mean(axis=1)
    monotone = bool(np.all(np.diff(means[np.argsort(b1s)]) > 0))
    findings = (
        Finding(
            "k_out > k1 under impact (paper: 2292 ± 91.6 N/m vs k1 = 1005 N/m)",
            mean > k1,
            f"twin: k_out = {mean:.0f} ± {std:.0f} N/m at {im.window * 1e3:g} ms after a step of "
            f"{im.force_min:g}-{im.force_max:g} N (kd = {im.kd:g}, bd = {im.bd:g}, b1 = {b1_nom:g}); "
            f"static stiffness k1·kd/(k1+kd) = {static:.0f} N/m. Early in an impact the damper "
            "force b1·v and the load inertia carry the force before the spring deflects, so the "
            "ratio exceeds k1; it decays toward the static value as the window grows "
            f"({', '.join(f'{t * 1e3:g} ms: {k:.0f}' for t, k in zip(wins, vs_win, strict=True))}).",
        ),
        Finding(
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
