"""Continuous time delay: certified verdicts and delay margins against a dense frequency grid.

The peer is what a user has today: sample ``Re Z(jω)`` of the delayed design on a dense
log grid (numpy, 4000 points over 0.1 to 10⁴ rad/s) and call it passive when no sample is
negative; its delay margin is the largest delay such that the grid finds no negative
sample, by bisection on the delay.  Times are CPU seconds of this process after a warm-up
with another plant (imports, the parser and the symbolic derivation of the configuration
are start-up, the same for every design of one structure).
"""

from __future__ import annotations

import math

import numpy as np

from _util import Row, timed
from seapass.delay.gainbound import passive_gain_intervals
from seapass.delay.margin import MarginLoss, delay_margin
from seapass.delay.passivity import delayed_passivity
from seapass.exact.rounding import enclosure_text
from seapass.model.catalog import design
from seapass.model.sea import SEA

PLANT = {"m": 1.0, "b": 10.0, "k1": 1000.0}
GAINS = {"LP": {"kd": 500.0}, "APD": {"kd": 500.0, "bd": 25.0},
         "ours": {"kd": 500.0, "bd": 25.0, "b1": 20.0}}  # fmt: skip
GRID = np.geomspace(0.1, 1e4, 4000)


def _delayed(key: str, **extra: float) -> SEA:
    d = design(key)
    wrap = {
        k: (f"({getattr(d, k)})*exp(-tau*s)" if getattr(d, k) != "0" else "0") for k in ("CA", "CL")
    }
    return SEA(D1=d.D1, D2=d.D2, **wrap, values={**PLANT, **GAINS[key], "tau": None, **extra})


def _re_z(sea: SEA, tau: float) -> np.ndarray:
    v = {k: float(x) for k, x in sea.values.items() if x is not None}
    s = 1j * GRID
    e = np.exp(-s * tau)
    d1 = v["k1"] + v.get("b1", 0.0) * s
    ca = (v.get("kd", 0.0) + v.get("bd", 0.0) * s) * e if str(sea.CA) != "0" else 0 * s
    cl = v.get("kd", 0.0) * e if str(sea.CL) != "0" else 0 * s
    alpha = v["m"] * s**2 + v["b"] * s
    return (d1 * (alpha + ca + cl) / (alpha + ca + d1) / s).real


def grid_passive(sea: SEA, tau: float) -> bool:
    return bool(np.all(_re_z(sea, tau) >= 0))


def grid_margin(sea: SEA, hi: float = 1.0) -> float:
    """Largest delay the grid calls passive (bisection from [0, hi]), 0 if none."""
    if grid_passive(sea, hi):
        return math.inf
    lo = 0.0
    for _ in range(50):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if grid_passive(sea, mid) else (lo, mid)
    return lo


def grid_gain_bound(sea: SEA, gain: str, tau: float, lo: float, hi: float) -> float:
    """The largest gain the dense grid calls passive at ``tau`` (bisection, 40 steps)."""
    for _ in range(40):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if grid_passive(sea.with_values(**{gain: mid}), tau) else (lo, mid)
    return lo


def _bound_row(ours: SEA, rows: list[Row], notes: list[str]) -> None:
    sea = ours.with_values(tau=0.01)
    t = timed(lambda: passive_gain_intervals(sea, "kd", 0, 1e4))
    t_grid = timed(lambda: grid_gain_bound(ours, "kd", 0.01, 0.0, 1e4))
    rows.append(Row("bound kd at tau = 10 ms, Ours (0 to 1e4)", "certified set (family in kd)",
                    1 / t.seconds, "dense grid + bisection on kd", 1 / t_grid.seconds,
                    f"{t.seconds:.2f} s CPU, {t.result.steps} steps"))  # fmt: skip
    r, g = t.result, t_grid.result
    ((_, upper),) = r.edges
    if upper is not None:
        side = (
            "above the certified end: it calls non-passive gains passive"
            if g > upper[1]
            else ("inside the certified enclosure" if g >= upper[0] else "below the certified end")
        )
        notes.append(
            f"bound kd of Ours at tau = 10 ms: passive for kd in [0, {r.intervals[0][1]:.10g}] "
            f"(every gain, certified), true end in {enclosure_text(*upper, digits=10)}; the dense "
            f"grid's end {g:.10g} ({side})."
        )


def _robust_row(rows: list[Row], notes: list[str], quick: bool) -> None:
    """Robust delay margin of examples/ours.toml over m, b1 +-10 % against box sampling."""
    from seapass.robust.delayed import robust_delay_margin

    ours = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
               values=dict(m=1.0, b=10.0, k1=1000.0, b1=300.0, kd=1708.0, bd=300.0, tau=None))  # fmt: skip
    box = {"m": (0.9, 1.1), "b1": (270.0, 330.0)}
    t = timed(lambda: robust_delay_margin(ours, "tau", box=box, rtol=1e-3))
    k = 3 if quick else 5
    grid = [(m, b1) for m in np.linspace(0.9, 1.1, k) for b1 in np.linspace(270, 330, k)]

    def sampled() -> float:
        out = math.inf
        for m, b1 in grid:
            r = delay_margin(ours, "tau", values=dict(m=float(m), b1=float(b1)), rtol=1e-3)
            if r.tau_star is not None:
                out = min(out, r.tau_star[1])
        return out

    t_s = timed(sampled)
    r = t.result
    nominal = delay_margin(ours, "tau").tau_star
    rows.append(Row("robust delay margin, Ours m, b1 +-10 %", "certified (robust.delayed)",
                    1 / t.seconds, f"box sampling ({k * k} per-plant margins)", 1 / t_s.seconds,
                    f"{t.seconds:.1f} s CPU, {r.cells} cells"))  # fmt: skip
    notes.append(
        f"Robust delay margin of Ours (examples/ours.toml, nominal tau* in "
        f"{enclosure_text(*nominal, digits=7)} s) over m in [0.9, 1.1], b1 in [270, 330]: "
        f"tau* in {enclosure_text(*r.tau_star, digits=7)} s for every plant (worst plant "
        f"{dict(r.worst_values)}), {t.seconds:.1f} s CPU; box sampling of {k * k} plants gives "
        f"{t_s.result:.7g} s, an upper bound only (it certifies no plant between its samples)."
    )


def _robust_bound_row(rows: list[Row], notes: list[str], quick: bool) -> None:
    """Robust delayed gain set of a delayed virtual wall over b +-10 % against box sampling."""
    from seapass.delay.gainbound import passive_gain_intervals
    from seapass.robust.intervals import robust_passive_intervals

    wall = SEA(D1="k1", CA="kd*exp(-tau*s)",
               values=dict(m=1.0, b=None, k1=1000.0, kd=None, tau=0.002))  # fmt: skip
    box = {"b": (9.0, 11.0)}
    t = timed(lambda: robust_passive_intervals(wall, "kd", 0, 8000, box=box, rtol=1e-2))
    k = 3 if quick else 5

    def sampled() -> float:
        ends = []
        for b in np.linspace(9.0, 11.0, k):
            r = passive_gain_intervals(wall, "kd", 0, 8000, values={"b": float(b)}, points=9)
            ends.append(r.intervals[-1][1] if r.intervals else 0.0)
        return min(ends)

    t_s = timed(sampled)
    r = t.result
    rows.append(Row("robust delayed bound kd, wall tau = 2 ms, b +-10 %",
                    "certified (robust.delayedgains)", 1 / t.seconds,
                    f"box sampling ({k} per-plant delayed bounds)", 1 / t_s.seconds,
                    f"{t.seconds:.1f} s CPU"))  # fmt: skip
    notes.append(
        f"Robust delayed gain set of a virtual wall (kd*exp(-tau*s), tau = 2 ms) over b in "
        f"[9, 11] (exact answer kd <= min b/tau = 4500): inner {r.intervals}, outer {r.outer}, "
        f"{t.seconds:.1f} s CPU; sampling {k} plants gives an upper end {t_s.result:.7g}, "
        "an outer bound only (nothing between its samples is certified)."
    )


def run(quick: bool) -> tuple[list[Row], list[str]]:
    rows: list[Row] = []
    notes: list[str] = []
    n = 5 if quick else 20
    ours = _delayed("ours")
    # warm-up: another plant of the same structure (start-up cost: imports, derivation)
    delayed_passivity(ours.with_values(k1=999.0, tau=0.001))
    delay_margin(ours.with_values(k1=999.0), "tau")
    kds = [400.0 + 10 * i for i in range(n)]
    t_check = timed(lambda: [delayed_passivity(ours.with_values(kd=k, tau=0.001)) for k in kds])
    t_grid = timed(lambda: [grid_passive(ours.with_values(kd=k), 0.001) for k in kds])
    rows.append(Row("check, Ours with a 1 ms controller delay", "certified (seapass.delay)",
                    n / t_check.seconds, "dense grid (4000 points)", n / t_grid.seconds,
                    f"{1000 * t_check.seconds / n:.0f} ms per certified verdict"))  # fmt: skip
    m = max(2, n // 4)
    t_margin = timed(lambda: [delay_margin(ours.with_values(kd=k), "tau") for k in kds[:m]])
    t_gmargin = timed(lambda: [grid_margin(ours.with_values(kd=k)) for k in kds[:m]])
    rows.append(Row("delay margin tau*, Ours (rtol 1e-6)", "certified enclosure", m / t_margin.seconds,
                    "dense grid + bisection on tau", m / t_gmargin.seconds,
                    f"{1000 * t_margin.seconds / m:.0f} ms per certified margin"))  # fmt: skip
    for key in ("LP", "APD", "ours"):
        sea = _delayed(key)
        t = timed(lambda sea=sea: delay_margin(sea, "tau"))
        r = t.result
        g = grid_margin(sea)
        lo, hi = r.tau_star if r.tau_star is not None else (math.nan, math.nan)
        if hi == 0.0:
            verdict = ("wrong: it calls every delay below that passive, but every delay > 0 "
                       "fails above its highest frequency") if g > 0 else "agrees"  # fmt: skip
        else:
            err = (g - hi) / hi
            verdict = (f"relative error {err:+.1e}" + (": it calls non-passive delays passive"
                                                      if g > hi else ""))  # fmt: skip
        where = (
            f" at {r.frequency:.4g} rad/s"
            if r.frequency
            else (" as w -> 0" if r.loss is MarginLoss.LOW_FREQUENCY else "")
        )
        notes.append(
            f"Delay margin of {design(key).label} with a delay on the controller "
            f"({', '.join(f'{k} = {v:g}' for k, v in GAINS[key].items())}; m = 1, b = 10, "
            f"k1 = 1000): tau* in {enclosure_text(*r.exact, digits=9) if r.exact else [lo, hi]} s, loss {r.loss}{where}, certified in "
            f"{1000 * t.seconds:.0f} ms CPU; the dense grid says {g:.6g} s ({verdict})."
        )
    _bound_row(ours, rows, notes)
    _robust_row(rows, notes, quick)
    _robust_bound_row(rows, notes, quick)
    r = delay_margin(ours, "tau")
    g = grid_margin(ours)
    if r.tau_star is not None and g > r.tau_star[1]:
        tau = (g + r.tau_star[1]) / 2
        grid_says = grid_passive(ours, tau)
        cert = delayed_passivity(ours.with_values(tau=tau))
        notes.append(
            f"At tau = {tau:.9g} s (between the certified margin and the grid's), the grid calls "
            f"Ours {'passive' if grid_says else 'not passive'}; the certified test says "
            f"{cert.status} with a witness at {cert.omega:.6g} rad/s."
        )
    return rows, notes
