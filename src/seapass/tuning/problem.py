"""What a tuning run optimizes: the design, the gains and their box, the objective, the limits.

`TuningOptions` holds every setting that does not depend on the design
(objective, load mass, step, limits, the sampled-data period and the optimizer
budget); `resolve_problem` combines it with a design and the gains to tune into
a validated `TuningProblem`, so that every error is raised before the search
starts and names the Python argument at fault (``tune['kdd']``,
``options.load_mass``).

Designs come in four forms: a catalog name (``"LP"``, ``"APD"``, ``"ours"``:
the paper's plant with the catalog's gains and boxes), a
[`CatalogDesign`][seapass.model.catalog.CatalogDesign], a
[`Design`][seapass.model.design_file.Design] from a design file (its values,
``[ranges]`` and ``[simulation]`` settings) or any [`SEA`][seapass.model.sea.SEA].
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, fields, replace
from enum import StrEnum
from types import MappingProxyType
from typing import Any, TypeAlias

from ..errors import ParameterError
from ..files.limits import MAX_HORIZON, MAX_SIM_STEPS
from ..model.catalog import PAPER_VALUES, CatalogDesign
from ..model.catalog import design as catalog_design
from ..model.design_file import Design
from ..model.expr import finite_number, symbol
from ..model.sea import SEA

__all__ = [
    "DEFAULT_LOAD_MASS",
    "DEFAULT_STEP",
    "EDGE_FRACTION",
    "QUICK_OPTIONS",
    "DesignLike",
    "Objective",
    "TuningOptions",
    "TuningProblem",
    "default_box",
    "design_parts",
    "design_sea",
    "resolve_problem",
]

DEFAULT_LOAD_MASS = 10.0
"""Load mass (kg) of the paper's simulation study (Sec. V), used when nothing else says."""
DEFAULT_STEP = 0.5
"""Reference step (m) of the paper's simulation study."""
DEFAULT_HORIZON = 10.0
"""Simulated time (s) of the paper's simulation study."""
EDGE_FRACTION = 0.01
"""A tuned gain within this fraction of its box width from an edge is reported ``on_bound``."""

DesignLike: TypeAlias = SEA | Design | CatalogDesign | str
BoxLike: TypeAlias = Mapping[str, "tuple[float, float] | None"] | Iterable[str]


class Objective(StrEnum):
    """What the tuner minimizes on the step response at the tuning load mass."""

    SETTLING = "settling"
    """The 2 % settling time (s) of the load (default); add ``max_overshoot`` for
    the settling time under an overshoot limit."""
    ITAE = "itae"
    """``∫ t |x_L(t) − θ| dt`` over the horizon (m·s²), from the samples (trapezoidal rule)."""

    @property
    def unit(self) -> str:
        return "s" if self is Objective.SETTLING else "m*s^2"


@dataclass(frozen=True)
class TuningOptions:
    """Settings of [`tune`][seapass.tuning.optimize.tune] that do not depend on the design.

    Attributes
    ----------
    objective : Objective or str
        ``"settling"`` (default) or ``"itae"``.
    max_overshoot : float, optional
        Largest overshoot allowed, as a fraction of the step (``0.05`` is 5 %).
    force_limit : float or None
        Largest peak actuator force ``|f_A|`` (N) during the step, default 1000 N
        (an average stiffness of 2000 N/m over the 0.5 m step: without a force
        limit a stiffer controller is always faster and the optimum runs to the
        edge of the box); None for no limit.
    load_mass, step, horizon : float, optional
        Tuning load mass (kg), reference step (m) and simulated time (s); None
        takes them from a design file's ``[simulation]`` (``tune_mass``, ``step``,
        ``horizon``), else the paper's 10 kg, 0.5 m and 10 s.
    period : float, optional
        Also require passivity under sampled-data control with this period (s),
        decided by [`seapass.sampled.sampled_passivity`][seapass.sampled.passivity.sampled_passivity].
    delay, velocity_filter : optional
        Samples of delay and the velocity filter cut-off (Hz) of that digital
        controller; None takes them from a design file's ``[control]``, else 0
        and no filter.
    tolerance : float
        Settling band, a fraction of the step (2 %).
    dt_search, dt_verify : float
        Time steps (s) of the search and of the final verification.
    maxiter, popsize, seed : int
        Differential-evolution generations, population per gain and seed.
    """

    objective: Objective | str = Objective.SETTLING
    max_overshoot: float | None = None
    force_limit: float | None = 1000.0
    load_mass: float | None = None
    step: float | None = None
    horizon: float | None = None
    period: float | None = None
    delay: int | None = None
    velocity_filter: float | None = None
    tolerance: float = 0.02
    dt_search: float = 5e-3
    dt_verify: float = 1e-3
    maxiter: int = 60
    popsize: int = 12
    seed: int = 0

    def __post_init__(self) -> None:
        try:
            object.__setattr__(self, "objective", Objective(str(self.objective).lower()))
        except ValueError:
            choices = ", ".join(o.value for o in Objective)
            raise ParameterError(
                f"objective must be one of {choices}, got {self.objective!r}"
            ) from None
        for name in ("dt_search", "dt_verify"):
            finite_number(getattr(self, name), name, positive=True)
        for name in ("load_mass", "horizon", "force_limit", "period", "velocity_filter"):
            if getattr(self, name) is not None:
                finite_number(getattr(self, name), name, positive=True)
        if self.horizon is not None and self.horizon > MAX_HORIZON:
            raise ParameterError(
                f"horizon: {self.horizon:g} s is longer than the limit of {MAX_HORIZON:g} s of "
                "simulated time (seapass.files.limits.MAX_HORIZON); give a shorter horizon",
                argument="horizon",
            )
        if self.step is not None and not (finite_number(self.step, "step") != 0):
            raise ParameterError("step must be nonzero")
        if (
            self.max_overshoot is not None
            and finite_number(self.max_overshoot, "max_overshoot") < 0
        ):
            raise ParameterError(f"max_overshoot must be >= 0, got {self.max_overshoot}")
        if not 0 < finite_number(self.tolerance, "tolerance") < 1:
            raise ParameterError(f"tolerance must be in (0, 1), got {self.tolerance}")
        for name, low in (("maxiter", 1), ("popsize", 2), ("delay", 0)):
            v = getattr(self, name)
            if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < low):
                raise ParameterError(f"{name} must be an integer >= {low}, got {v!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int):
            raise ParameterError(f"seed must be an integer, got {self.seed!r}")

    def replace(self, **changes: Any) -> TuningOptions:
        """A copy with ``changes``; an unknown name is an error with a did-you-mean."""
        known = [f.name for f in fields(self)]
        for name in changes:
            if name not in known:
                raise ParameterError(f"unknown tuning option {name!r}{_did_you_mean(name, known)}")
        return replace(self, **changes)


def _did_you_mean(name: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(choices), n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


QUICK_OPTIONS = TuningOptions(maxiter=12, popsize=6, dt_search=1e-2)
"""A small optimizer budget for tests and previews (about 10x cheaper)."""


@dataclass(frozen=True)
class TuningProblem:
    """A validated tuning problem (from `resolve_problem`).

    Attributes
    ----------
    name : str
        The design's name (catalog key, design-file name or ``SEA.name``).
    sea : SEA
        The design with every fixed parameter's value; the tuned gains keep
        whatever value they had (ignored).
    gains : tuple of str
        The tuned gains, in search order.
    box : mapping of str to (float, float)
        The search box of every tuned gain.
    options : TuningOptions
        With ``load_mass``, ``step``, ``horizon``, ``delay`` resolved to numbers.
    """

    name: str
    sea: SEA
    gains: tuple[str, ...]
    box: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    options: TuningOptions = field(default_factory=TuningOptions)

    def candidate(self, x: Iterable[float]) -> SEA:
        """The design with the tuned gains set to ``x`` (in the order of `gains`)."""
        return self.sea.with_values(**dict(zip(self.gains, (float(v) for v in x), strict=True)))

    def on_bound(self, gains: Mapping[str, float]) -> dict[str, str]:
        """``{name: "lower" | "upper"}`` for gains within `EDGE_FRACTION` of a box edge."""
        out = {}
        for name in self.gains:
            lo, hi = self.box[name]
            tol = EDGE_FRACTION * (hi - lo)
            if gains[name] - lo <= tol:
                out[name] = "lower"
            elif hi - gains[name] <= tol:
                out[name] = "upper"
        return out


def design_sea(
    design: str,
    *,
    m: float = PAPER_VALUES["m"],
    b: float = PAPER_VALUES["b"],
    k1: float = PAPER_VALUES["k1"],
    gains: Mapping[str, float | None] | None = None,
) -> SEA:
    """The [`SEA`][seapass.model.sea.SEA] of a catalog ``design`` with plant values and gains.

    Gains not given are free parameters (value None).
    """
    return catalog_design(design).sea({"m": m, "b": b, "k1": k1, **dict(gains or {})})


def default_box(name: str, value: float | None) -> tuple[float, float] | None:
    """The default search box of a gain with a value: ``[0, max(10·|value|, 1000)]``.

    The same rule as a design file without a ``[ranges]`` entry
    ([`Design.analysis_ranges`][seapass.model.design_file.Design.analysis_ranges]);
    None for a gain without a value (its box must be given).
    """
    if value is None:
        return None
    return (0.0, max(10.0 * abs(float(value)), 1000.0))


def design_parts(
    design: DesignLike,
) -> tuple[str, SEA, tuple[str, ...], dict[str, tuple[float, float]]]:
    """Name, SEA, default gains to tune and known boxes of ``design`` (see `resolve_problem`)."""
    if isinstance(design, str):
        design = catalog_design(design)
    if isinstance(design, CatalogDesign):
        sea = design.sea(PAPER_VALUES)
        return design.key, sea, design.gains, dict(design.ranges)
    if isinstance(design, Design):
        sea = design.sea()
        boxes = {**design.analysis_ranges(), **design.ranges}
        return design.name, sea, design.gains, boxes
    if isinstance(design, SEA):
        controller = {str(x) for x in design.CA.free_symbols | design.CL.free_symbols}
        gains = design.free_parameters or tuple(p for p in design.parameters if p in controller)
        return design.name or "design", design, tuple(gains), {}
    raise ParameterError(
        f"design: expected an SEA, a Design, a CatalogDesign or a catalog name, "
        f"got {type(design).__name__}"
    )


def _gain_boxes(
    tune: BoxLike | None,
    defaults: tuple[str, ...],
    boxes: Mapping[str, tuple[float, float]],
    sea: SEA,
) -> dict[str, tuple[float, float]]:
    if tune is None:
        wanted: dict[str, Any] = dict.fromkeys(defaults)
    elif isinstance(tune, Mapping):
        wanted = dict(tune)
    elif isinstance(tune, str):
        raise ParameterError(f"tune: expected a mapping {{name: (lo, hi)}} or names, got {tune!r}")
    else:
        wanted = dict.fromkeys(tune)
    if not wanted:
        raise ParameterError("tune: no gains to tune; give e.g. tune={'kd': (0, 5000)}")
    out: dict[str, tuple[float, float]] = {}
    for name, given in wanted.items():
        where = f"tune[{name!r}]"
        if name not in sea.parameters:
            raise ParameterError(
                f"{where}: {name!r} is not a parameter of the design "
                f"({', '.join(sea.parameters)}){_did_you_mean(str(name), sea.parameters)}"
            )
        if symbol(name) in sea.m.free_symbols | sea.b.free_symbols:
            raise ParameterError(
                f"{where}: {name} sets the actuator mass or damping (the plant); tune the "
                "controller gains or the transmission instead"
            )
        box = given if given is None else _box(given, where)
        box = box or boxes.get(name) or default_box(name, sea.values.get(name))
        if box is None:
            raise ParameterError(
                f"{where}: {name} has no value and no search box; give one, "
                f"e.g. tune={{{name!r}: (0, 1000)}}"
            )
        out[name] = box
    return out


def _box(given: Any, where: str) -> tuple[float, float]:
    try:
        lo, hi = given
    except (TypeError, ValueError):
        raise ParameterError(f"{where}: expected (lo, hi), got {given!r}") from None
    lo, hi = finite_number(lo, f"{where} lower bound"), finite_number(hi, f"{where} upper bound")
    if not lo < hi:
        raise ParameterError(f"{where}: need lo < hi, got ({lo:g}, {hi:g})")
    return (lo, hi)


def resolve_problem(
    design: DesignLike,
    tune: BoxLike | None = None,
    options: TuningOptions | None = None,
    values: Mapping[str, float] | None = None,
) -> TuningProblem:
    """Validate a tuning problem before any work starts.

    Parameters
    ----------
    design : SEA, Design, CatalogDesign or str
        See the module docstring.
    tune : mapping of str to (lo, hi) or None, or iterable of str, optional
        The gains to tune and their boxes.  A name without a box takes it from
        the design (a catalog entry's box, the file's ``[ranges]``, else
        `default_box` for a gain with a value).  Default: the catalog's gains,
        a design file's controller gains (the parameters of ``C_A`` and ``C_L``),
        or an SEA's free parameters (else its controller gains).
    options : TuningOptions, optional
    values : mapping of str to float, optional
        Values of fixed parameters overriding the design's (a catalog design's
        plant, say).

    Raises
    ------
    ParameterError
        Naming the argument: an unknown gain or value (with a did-you-mean), an
        empty or inverted box, a value for a tuned gain, a fixed parameter
        without a value.
    """
    opts = options or TuningOptions()
    name, sea, defaults, boxes = design_parts(design)
    for key in values or {}:
        if key not in sea.parameters:
            raise ParameterError(
                f"values[{key!r}]: {key!r} is not a parameter of the design "
                f"({', '.join(sea.parameters)}){_did_you_mean(key, sea.parameters)}"
            )
    if values:
        sea = sea.with_values(**values)
    box = _gain_boxes(tune, defaults, boxes, sea)
    clash = sorted(set(values or {}) & set(box))
    if clash:
        raise ParameterError(
            f"values[{clash[0]!r}]: {clash[0]} is tuned, so its value would be ignored; "
            "drop the value or tune other gains"
        )
    gains = tuple(box)
    missing = [p for p in sea.parameters if p not in box and sea.values.get(p) is None]
    if missing:
        raise ParameterError(
            f"no value for {', '.join(missing)}: give it in the design's values "
            f"(values[{missing[0]!r}]) or tune it (tune={{{missing[0]!r}: (lo, hi)}})"
        )
    file = design if isinstance(design, Design) else None
    resolved = replace(
        opts,
        load_mass=_pick(opts.load_mass, file and file.tuning_mass, DEFAULT_LOAD_MASS),
        step=_pick(opts.step, file and file.step, DEFAULT_STEP),
        horizon=_pick(opts.horizon, file and file.horizon, DEFAULT_HORIZON),
        delay=_pick(opts.delay, file and file.control_delay, 0),
        velocity_filter=_pick(opts.velocity_filter, file and file.velocity_filter, None),
    )
    horizon = float(resolved.horizon or DEFAULT_HORIZON)
    if horizon < max(resolved.dt_search, resolved.dt_verify):
        raise ParameterError("horizon is shorter than the time step")
    dt = min(resolved.dt_search, resolved.dt_verify)
    if horizon / dt > MAX_SIM_STEPS:
        raise ParameterError(
            f"horizon / dt = {horizon:g} s / {dt:g} s is {horizon / dt:.3g} time steps, over the "
            f"limit of {MAX_SIM_STEPS:,} of one simulation; shorten the horizon or enlarge "
            "dt_search/dt_verify"
        )
    return TuningProblem(
        name=name, sea=sea, gains=gains, box=MappingProxyType(box), options=resolved
    )


def _pick(given: Any, from_file: Any, default: Any) -> Any:
    if given is not None:
        return given
    if from_file is not None and from_file is not False:
        return from_file
    return default
