"""The explorer's panels, computed from an `seapass.explore.state.ExploreState`.

One pure function per panel returns plain JSON data (lists, numbers, text);
drawing happens in the browser.  Every verdict comes from seapass's exact
entry points: nothing here decides passivity from a grid.  Results that do not
depend on the value being dragged are cached: the passive interval of a gain
does not change while that gain moves, nor the 2-D region while one of its
axes moves.

Axes: every array is one-dimensional over its grid (frequency, time or
slider position), ``region.passive`` is ``(len(y), len(x))``.

The ``twoport`` panel is the SEA between the person and the virtual environment
it renders ([`seapass.ports`][seapass.ports]): Llewellyn's absolute stability
with its exact failing bands and the certified infimum of η, decided exactly;
η(ω) is sampled only to draw it.  The search for a destabilizing pair of
terminations is left to ``seapass twoport check`` (it is a search of up to
hundreds of closed loops; the panel stays within the explorer's latency).
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Callable
from typing import Any

import numpy as np
from flint import fmpq

from ..analysis.impedance import exact_rational_function
from ..analysis.passivity import is_passive
from ..analysis.region import passive_intervals
from ..analysis.witness import find_destabilizing_environment
from ..batch import batch_is_passive
from ..errors import SeapassError
from ..exact import poly as ep
from ..exact.axis import real_part_polynomial
from ..exact.rounding import inward_text
from ..ports.bands import Band
from ..ports.check import reciprocity
from ..ports.stability import absolute_stability, eta_text
from ..ports.twoport import two_port
from ..sampled import sampled_passivity
from ..sim.metrics import tracking_metrics
from ..sim.scenarios import Step
from ..sim.simulate import simulate
from .delay_panel import delay_panel
from .robustview import robust_key, robust_panel
from .state import ExploreState, slider_scale

__all__ = [
    "KINDS",
    "REGION_CHUNK",
    "REGION_RESOLUTIONS",
    "check_rows",
    "compute",
    "failing_bands",
    "slider_grid",
    "stiffness_limits",
]

#: Step-response samples (the simulation is exact at every sample, whatever the step).
STEP_SAMPLES = 1000
FREQUENCY_POINTS = 400
#: Grid sizes of the 2-D region: a coarse one first, then a refined one.
REGION_RESOLUTIONS = (24, 48, 96)
#: Rows of the refined region computed per request, so a refinement never holds a worker long.
REGION_CHUNK = 16
_CACHE_SIZE = 256


def slider_grid(lo: float, hi: float, n: int) -> np.ndarray:
    """``n`` values at equally spaced slider positions (log scale: 0 is the first stop)."""
    if slider_scale(lo, hi) == "lin":
        return np.linspace(lo, hi, n)
    if lo > 0:
        return np.geomspace(lo, hi, n)
    return np.concatenate([[0.0], np.geomspace(hi * 1e-4, hi, n - 1)])


def _verdict(state: ExploreState) -> dict[str, Any]:
    r = is_passive(state.sea())
    return {
        "passive": r.passive,
        "status": r.status,
        "reason": r.reason,
        "detail": r.detail,
        "omega": r.omega,
        "marginal": r.marginal,
        "margin": None if math.isnan(r.margin) else r.margin,
    }


def _sampled(state: ExploreState) -> dict[str, Any]:
    loop = state.loop
    if loop is None:
        return {"analysed": False, "detail": "no control period set: continuous control only"}
    r = sampled_passivity(state.sea(), loop=loop)
    return {
        "analysed": True,
        "passive": r.passive,
        "status": r.outcome.label,
        "reason": r.reason,
        "detail": r.detail,
        "omega": r.omega,
        "period": r.period,
        "delay": r.delay,
        "velocity_filter": r.velocity_filter,
        "spectral_radius": r.spectral_radius,
    }


def _interval(state: ExploreState) -> dict[str, Any]:
    lo, hi = state.ranges[state.gain]
    r = passive_intervals(state.sea(), state.gain, lo, hi)
    return {
        "param": state.gain,
        "lo": lo,
        "hi": hi,
        "scale": slider_scale(lo, hi),
        "intervals": [list(iv) for iv in r.intervals],
        # the ends as text, rounded inward: every number shown is passive (issue 20)
        "shown": [list(inward_text(a, b, 6)) for a, b in r.intervals],
        "critical_values": list(r.critical_values),
    }


def _region(state: ExploreState, resolution: int, rows: tuple[int, int] | None) -> dict[str, Any]:
    px, py = state.region
    xs = slider_grid(*state.ranges[px], resolution)
    ys = slider_grid(*state.ranges[py], resolution)
    r0, r1 = rows if rows is not None else (0, resolution)
    free = state.sea().with_values(**{px: None, py: None})
    r = batch_is_passive(free, {px: xs[None, :], py: ys[r0:r1, None]}, margin=False)
    return {
        "x": px,
        "y": py,
        "xs": xs.tolist(),
        "ys": ys.tolist(),
        "x_range": list(state.ranges[px]),
        "y_range": list(state.ranges[py]),
        "x_scale": slider_scale(*state.ranges[px]),
        "y_scale": slider_scale(*state.ranges[py]),
        "rows": [r0, r1],
        "passive": ["".join("1" if v else "0" for v in row) for row in r.passive],
        "resolution": resolution,
        "exact_fallbacks": r.n_exact,
        "undefined": int(np.count_nonzero(r.undefined)),
    }


def failing_bands(num: ep.PolyLike, den: ep.PolyLike) -> list[tuple[float, float]]:
    """Frequency bands ``[ω1, ω2]`` (rad/s; ``ω2`` may be ``inf``) where ``Re Z(jω) < 0``.

    Decided exactly: ``P(x) = Re N(jω) D(−jω)`` with ``x = ω²`` has the sign of
    ``Re Z`` away from poles; its positive real roots are isolated exactly
    ([`seapass.exact.poly`][seapass.exact.poly]) and the sign between them is
    evaluated at rational points.
    """
    px = real_part_polynomial(ep.as_poly(num), ep.as_poly(den))
    if not px:
        return []
    roots = [
        ep.refine(px, (a, b), fmpq(1, 2**50) * max(fmpq(1), abs(b)))
        for a, b in ep.isolate_real_roots(px, 0)
    ]
    edges = [fmpq(0)] + [(a + b) / 2 for a, b in roots]
    bands: list[tuple[float, float]] = []
    for i, x0 in enumerate(edges):
        x1 = edges[i + 1] if i + 1 < len(edges) else None
        probe = (x0 + x1) / 2 if x1 is not None else x0 + 1 + abs(x0)
        if px(probe) < 0:
            w0 = math.sqrt(float(x0))
            w1 = math.inf if x1 is None else math.sqrt(float(x1))
            if bands and bands[-1][1] == w0:
                bands[-1] = (bands[-1][0], w1)
            else:
                bands.append((w0, w1))
    return bands


def _frequency_grid(num: np.ndarray, den: np.ndarray, marks: list[float]) -> np.ndarray:
    mags = [abs(r) for p in (num, den) if p.size > 1 for r in np.roots(p) if abs(r) > 0]
    mags += [w for w in marks if 0 < w < math.inf]
    lo, hi = (min(mags) / 30, max(mags) * 30) if mags else (0.1, 1e4)
    lo, hi = max(lo, 1e-4), min(hi, 1e8)
    if hi <= lo * 100:
        mid = math.sqrt(lo * hi)
        lo, hi = mid / 100, mid * 100
    return np.geomspace(lo, hi, FREQUENCY_POINTS)


def _frequency(state: ExploreState) -> dict[str, Any]:
    num, den = exact_rational_function(state.sea())
    bands = failing_bands(num, den)
    n = np.array([float(c) for c in reversed(num)]) if num else np.zeros(1)
    d = np.array([float(c) for c in reversed(den)])
    w = _frequency_grid(n, d, [w for band in bands for w in band])
    with np.errstate(all="ignore"):
        z = np.polyval(n, 1j * w) / np.polyval(d, 1j * w)
        h = 1j * w * z  # F_L/X_L = s Z(s): the same rational function as the stiffness
    static, high = stiffness_limits(num, den)
    return {
        "omega": w.tolist(),
        "magnitude": _finite_list(np.abs(h)),
        "phase": _finite_list(np.degrees(np.unwrap(np.angle(h)))),
        "re_z": _finite_list(z.real),
        "bands": [[a, None if math.isinf(b) else b] for a, b in bands],
        "static": static if math.isfinite(static) else None,
        "high_frequency": high if math.isfinite(high) else None,
    }


def stiffness_limits(num: ep.PolyLike, den: ep.PolyLike) -> tuple[float, float]:
    """``F_L/X_L`` at ``ω = 0`` and ``|F_L/X_L|`` as ``ω → ∞`` from ``Z = N/D`` (``inf`` if unbounded).

    The stiffness is ``s Z(s)``; its behaviour at 0 and at infinity is read from the
    lowest and the highest coefficients of ``N`` and ``D``, as
    `seapass.analysis.freqresp.stiffness_response` does from the stiffness itself.
    """
    num, den = ep.as_poly(num), ep.as_poly(den)
    if not num:
        return 0.0, 0.0
    low_n = next(i for i, c in enumerate(num) if c != 0)
    low_d = next(i for i, c in enumerate(den) if c != 0)
    order = 1 + low_n - low_d
    static = float(num[low_n] / den[low_d]) if order == 0 else (0.0 if order > 0 else math.inf)
    gap = 1 + ep.degree(num) - ep.degree(den)
    lead = num.leading_coefficient() / den.leading_coefficient()
    high = abs(float(lead)) if gap == 0 else (math.inf if gap > 0 else 0.0)
    return static, high


def _finite_list(a: np.ndarray, digits: int | None = None) -> list[float | None]:
    """Plot data with non-finite values as None; ``digits``: round to that many significant
    digits of the largest entry (for linear plots: shorter JSON, no visible change)."""
    arr = np.asarray(a, dtype=float)
    finite = np.isfinite(arr)
    top = float(np.max(np.abs(arr[finite]), initial=0.0))
    if digits is not None and top > 0:
        arr = np.round(arr, max(0, digits - 1 - math.floor(math.log10(top))))
    return [float(v) if ok else None for v, ok in zip(arr.tolist(), finite.tolist(), strict=True)]


def _step(state: ExploreState) -> dict[str, Any]:
    sim = simulate(
        state.sea(),
        load_mass=state.load_mass,
        scenario=Step(state.step),
        horizon=state.horizon,
        dt=state.horizon / STEP_SAMPLES,
    )
    met = tracking_metrics(sim)
    return {
        "t": _finite_list(sim.time, 7),
        "x_L": _finite_list(sim.x_L, 6),
        "x_A": _finite_list(sim.x_A, 6),
        "f_A": _finite_list(sim.f_A, 6),
        "target": sim.target,
        "band": met.band,
        "status": met.status,
        "stability": sim.status,
        "settling_time": met.settling_time,
        "overshoot": met.overshoot,
        "peak_force": met.peak_force,
        "final_error": met.final_error if math.isfinite(met.final_error) else None,
        "load_mass": state.load_mass,
        "step": state.step,
    }


def _witness(state: ExploreState) -> dict[str, Any]:
    w = find_destabilizing_environment(state.sea(), simulate=True)
    out: dict[str, Any] = {"passive": w.passive, "found": w.found, "detail": w.detail}
    if w.environment is not None:
        env = w.environment
        out["environment"] = {"mass": env.mass, "damping": env.damping, "stiffness": env.stiffness}
        out["method"] = w.method
        out["omega"] = w.omega
        out["growth_rate"] = w.coupled.max_real_part if w.coupled else None
    if w.simulation is not None and w.simulation.t.size:
        sim = w.simulation
        idx = np.unique(np.linspace(0, sim.t.size - 1, min(sim.t.size, 800)).astype(int))
        out["simulation"] = {
            "t": sim.t[idx].tolist(),
            "y": _finite_list(sim.y[idx]),
            "output": sim.output,
            "growth_rate": sim.growth_rate,
            "growth_factor": sim.growth_factor,
        }
    return out


def _band_list(bands: tuple[Band, ...]) -> list[list[float | None]]:
    return [[b.lo, None if math.isinf(b.hi) else b.hi] for b in bands]


def _twoport(state: ExploreState) -> dict[str, Any]:
    stab = absolute_stability(two_port(state.sea()), witness=False)
    m = stab.matrix
    assert m is not None
    bands = stab.bands
    edges = [e for b in bands for e in (b.lo, b.hi) if 0 < e < math.inf]
    poles = m.common_denominator()
    d = np.array([float(c) for c in reversed(poles.coeffs())])
    marks = [*edges, *(w for w in (stab.eta.omega, stab.eta.limit) if w and math.isfinite(w))]
    w = _frequency_grid(d, np.ones(1), marks)
    w = np.unique(np.concatenate([w, edges]))
    eta = stab.response(w)["eta"]
    finite = eta[np.isfinite(eta)]
    top = max(float(np.percentile(finite, 95)), 2.0) * 1.1 if finite.size else 2.0
    bottom = min(float(finite.min()), 0.5) if finite.size else 0.0
    eta_min = stab.eta.value
    return {
        "outcome": stab.outcome.value,
        "absolutely_stable": stab.absolutely_stable,
        "reciprocal": reciprocity(m, stab.form),
        "eta_min": eta_min if math.isfinite(eta_min) else None,
        "eta_kind": stab.eta.kind.value,
        "eta_text": eta_text(stab.eta),
        "eta_min_frequency": stab.eta.to_dict()["eta_min_frequency"],
        "failing": [
            {"name": c.name, "detail": c.detail, "bands": _band_list(c.bands)}
            for c in stab.conditions
            if c.holds is not True
        ],
        "omega": w.tolist(),
        "eta": _finite_list(eta),
        "eta_range": [bottom - 0.1 * abs(bottom), top],
        "bands": _band_list(bands),
    }


#: panel kind -> (function, cache key of the state)
_PANELS: dict[str, tuple[Callable[..., dict[str, Any]], Callable[[ExploreState], str]]] = {
    "verdict": (_verdict, lambda s: s.key()),
    "sampled": (_sampled, lambda s: s.key(extra=("period", "delay", "velocity_filter"))),
    "interval": (
        _interval,
        lambda s: s.key(without=(s.gain,)) + repr((s.gain, s.ranges[s.gain])),
    ),
    "region": (
        _region,
        lambda s: s.key(without=s.region) + repr((s.region, [s.ranges[p] for p in s.region])),
    ),
    "frequency": (_frequency, lambda s: s.key()),
    "step": (_step, lambda s: s.key(extra=("load_mass", "step", "horizon"))),
    "witness": (_witness, lambda s: s.key()),
    "twoport": (_twoport, lambda s: s.key()),
    "delay": (delay_panel, lambda s: s.key(extra=("delay_time",))),  # tau*: explore.delay_panel
    "robust": (robust_panel, robust_key),  # the box verdict (seapass.explore.robustview)
}
KINDS: tuple[str, ...] = tuple(_PANELS)
_cache: OrderedDict[str, dict[str, Any]] = OrderedDict()


def compute(
    kind: str,
    state: ExploreState,
    *,
    resolution: int = REGION_RESOLUTIONS[0],
    rows: tuple[int, int] | None = None,
) -> dict[str, Any]:
    """Data of panel ``kind`` for ``state`` (cached; raises `SeapassError` on bad input).

    Parameters
    ----------
    kind : str
        One of `KINDS`.
    state : ExploreState
    resolution : int
        Grid size of the 2-D region (one of `REGION_RESOLUTIONS`).
    rows : (int, int), optional
        Only these rows ``[start, stop)`` of the region (at most `REGION_CHUNK`).
    """
    if kind not in _PANELS:
        raise KeyError(kind)
    func, keyfunc = _PANELS[kind]
    extra: dict[str, Any] = {}
    if kind == "region":
        extra = {"resolution": resolution, "rows": check_rows(resolution, rows)}
    key = f"{kind}|{keyfunc(state)}|{sorted(extra.items())}"
    hit = _cache.get(key)
    if hit is not None:
        _cache.move_to_end(key)
        return hit
    data = func(state, **extra)
    _cache[key] = data
    while len(_cache) > _CACHE_SIZE:
        _cache.popitem(last=False)
    return data


def check_rows(resolution: Any, rows: Any) -> tuple[int, int] | None:
    """Validated region grid and row range (raises ValueError naming the bad one)."""
    if isinstance(resolution, bool) or resolution not in REGION_RESOLUTIONS:
        raise ValueError(
            f"resolution must be one of {list(REGION_RESOLUTIONS)}, got {resolution!r}"
        )
    if rows is None:
        if resolution > REGION_CHUNK * 2:
            raise ValueError(
                f"give rows [start, stop] (at most {REGION_CHUNK}) for resolution {resolution}"
            )
        return None
    ok = (
        isinstance(rows, list | tuple)
        and len(rows) == 2
        and all(isinstance(r, int) and not isinstance(r, bool) for r in rows)
    )
    if not ok or not 0 <= rows[0] < rows[1] <= resolution or rows[1] - rows[0] > REGION_CHUNK:
        raise ValueError(
            f"rows must be [start, stop] with 0 <= start < stop <= {resolution}, "
            f"at most {REGION_CHUNK} rows, got {rows!r}"
        )
    return int(rows[0]), int(rows[1])


def error_message(exc: BaseException) -> str:
    """One line for a panel that could not be computed."""
    if isinstance(exc, SeapassError | ValueError | ArithmeticError):
        return " ".join(str(exc).split()) or type(exc).__name__
    return f"internal error ({type(exc).__name__}): {exc}"
