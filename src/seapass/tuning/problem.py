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

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import InitVar, dataclass, field, fields, replace
from enum import StrEnum
from types import MappingProxyType
from typing import Any, TypeAlias

from ..errors import ParameterError, did_you_mean
from ..files.limits import MAX_HORIZON, MAX_SIM_STEPS
from ..model.catalog import PAPER_VALUES, CatalogDesign
from ..model.catalog import design as catalog_design
from ..model.design_file import Design
from ..model.experiment import PAPER_EXPERIMENT
from ..model.expr import finite_number, symbol
from ..model.loop import SampledLoop, loop_argument
from ..model.sea import SEA
from .masses import MassPolicy, check_masses, resolve_masses

__all__ = [
    "DEFAULT_LOAD_MASS",
    "DEFAULT_STEP",
    "EDGE_FRACTION",
    "QUICK_OPTIONS",
    "DesignLike",
    "Objective",
    "ResolvedTuning",
    "TuningOptions",
    "TuningProblem",
    "default_box",
    "design_parts",
    "design_sea",
    "resolve_problem",
]

DEFAULT_LOAD_MASS = PAPER_EXPERIMENT.load_mass
"""Load mass (kg) of the paper's simulation study (Sec. V), used when nothing else says."""
DEFAULT_STEP = PAPER_EXPERIMENT.step
"""Reference step (m) of the paper's simulation study."""
DEFAULT_HORIZON = PAPER_EXPERIMENT.horizon
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
        """The unit of the objective's value: ``"s"`` or ``"m*s^2"``."""
        return "s" if self is Objective.SETTLING else "m*s^2"

    @property
    def label(self) -> str:
        """What the value is: ``"settling time"`` or ``"ITAE"``."""
        return "settling time" if self is Objective.SETTLING else "ITAE"


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
        Largest peak actuator force ``|f_A|`` (N) during the step, default the
        experiment's 1000 N (an average stiffness of 2000 N/m over the 0.5 m step:
        without a force limit a stiffer controller is always faster and the optimum
        runs to the edge of the box); None for no limit.
    load_mass, step, horizon : float, optional
        Tuning load mass (kg), reference step (m) and simulated time (s); None
        takes them from a design file's ``[simulation]`` (``tune_mass``, ``step``,
        ``horizon``), else from the paper's experiment
        ([`PAPER_EXPERIMENT`][seapass.model.experiment.PAPER_EXPERIMENT]: 10 kg, 0.5 m, 10 s).
    loop : SampledLoop, optional
        Also require passivity under sampled-data control in this loop, decided by
        [`seapass.sampled.sampled_passivity`][seapass.sampled.passivity.sampled_passivity].
        The old fields ``period``, ``delay`` and ``velocity_filter`` are accepted for one
        release (with a warning) and build it.
    tolerance : float
        Settling band, a fraction of the step (2 %).
    dt_search, dt_verify : float
        Time steps (s) of the search and of the final verification.
    maxiter, popsize, seed : int
        Differential-evolution generations, population per gain and seed.
    masses : "worst", "tune", sequence of float or None
        The load masses a candidate is judged on, the worst case over several (default:
        a design file's ``load_masses``), see [`resolve_masses`][seapass.tuning.masses.resolve_masses].
    """

    objective: Objective | str = Objective.SETTLING
    max_overshoot: float | None = None
    force_limit: float | None = PAPER_EXPERIMENT.force_limit
    load_mass: float | None = None
    step: float | None = None
    horizon: float | None = None
    loop: SampledLoop | None = None
    tolerance: float = PAPER_EXPERIMENT.tolerance
    dt_search: float = 5e-3
    dt_verify: float = 1e-3
    maxiter: int = 60
    popsize: int = 12
    seed: int = 0
    period: InitVar[float | None] = None
    delay: InitVar[int | None] = None
    velocity_filter: InitVar[float | None] = None
    masses: Sequence[float] | str | None = None

    def __post_init__(
        self, period: float | None, delay: int | None, velocity_filter: float | None
    ) -> None:
        object.__setattr__(self, "masses", check_masses(self.masses))
        old = {"period": period, "delay": delay, "velocity_filter": velocity_filter}
        object.__setattr__(self, "loop", _old_loop(self.loop, old))
        if self.loop is not None and not isinstance(self.loop, SampledLoop):
            raise ParameterError(f"loop: expected a SampledLoop, got {self.loop!r}")
        try:
            object.__setattr__(self, "objective", Objective(str(self.objective).lower()))
        except ValueError:
            choices = ", ".join(o.value for o in Objective)
            raise ParameterError(
                f"objective must be one of {choices}, got {self.objective!r}"
            ) from None
        for name in ("dt_search", "dt_verify"):
            _positive(self, name)
        for name in ("load_mass", "horizon", "force_limit"):
            if getattr(self, name) is not None:
                _positive(self, name)
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
        for name, low in (("maxiter", 1), ("popsize", 2)):
            v = getattr(self, name)
            if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < low):
                raise ParameterError(f"{name} must be an integer >= {low}, got {v!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int):
            raise ParameterError(f"seed must be an integer, got {self.seed!r}")

    def replace(self, **changes: Any) -> TuningOptions:
        """A copy with ``changes``; an unknown name is an error with a did-you-mean."""
        known = [f.name for f in fields(self)]
        old = {k: changes.pop(k) for k in _OLD_LOOP_FIELDS if k in changes}
        for name in changes:
            if name not in known:
                raise ParameterError(f"unknown tuning option {name!r}{did_you_mean(name, known)}")
        if old:
            changes["loop"] = _old_loop(changes.get("loop", self.loop), old)
        return replace(self, **changes)


_OLD_LOOP_FIELDS = ("period", "delay", "velocity_filter")


def _old_loop(loop: SampledLoop | None, old: Mapping[str, Any]) -> SampledLoop | None:
    """``loop`` changed by the old fields ``period, delay, velocity_filter`` (None: not given)."""
    given = {k: v for k, v in old.items() if v is not None}
    if not given:
        return loop
    return loop_argument(None, given, where="TuningOptions", base=loop)


def _positive(options: TuningOptions, name: str) -> None:
    """A positive finite option, or an error naming it (the CLI shows its flag)."""
    try:
        finite_number(getattr(options, name), name, positive=True)
    except ParameterError as exc:
        raise ParameterError(str(exc), argument=name) from None


QUICK_OPTIONS = TuningOptions(maxiter=12, popsize=6, dt_search=1e-2)
"""A small optimizer budget for tests and previews (about 10x cheaper)."""


@dataclass(frozen=True, kw_only=True)
class ResolvedTuning(TuningOptions):
    """`TuningOptions` with the design-dependent settings resolved (`resolve_problem`).

    ``load_mass``, ``step`` and ``horizon`` are numbers: the option when given, else the
    design file's ``[simulation]``, else the paper's experiment (10 kg, 0.5 m, 10 s).
    ``masses``: the load masses a candidate is judged on (the worst case when several).
    """

    load_mass: float = DEFAULT_LOAD_MASS
    step: float = DEFAULT_STEP
    horizon: float = DEFAULT_HORIZON
    masses: tuple[float, ...] = (DEFAULT_LOAD_MASS,)

    @property
    def mass_policy(self) -> MassPolicy:
        """``worst`` when candidates are judged on several masses, else ``tune``."""
        return MassPolicy.of(self.masses)


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
    options : ResolvedTuning
        With ``load_mass``, ``step``, ``horizon`` resolved to numbers.
    """

    name: str
    sea: SEA
    gains: tuple[str, ...]
    box: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    options: ResolvedTuning = field(default_factory=ResolvedTuning)

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
        return design.name or "design", design, design.gains, {}
    raise ParameterError(
        f"design: expected an SEA, a Design, a CatalogDesign or a catalog name, "
        f"got {type(design).__name__}"
    )


def _design_variables(design: DesignLike) -> set[str]:
    """Plant parameters the design itself offers for tuning: a catalog entry's gains (the
    paper's damper ``b1``), a design file's ``[ranges]``."""
    if isinstance(design, str):
        design = catalog_design(design)
    if isinstance(design, CatalogDesign):
        return set(design.gains)
    if isinstance(design, Design):
        return set(design.ranges)
    return set()


def _check_plant(name: str, sea: SEA, design: DesignLike, allow_plant: bool) -> None:
    """Refuse to tune a plant parameter the user did not ask for on purpose."""
    where = f"tune[{name!r}]"
    if symbol(name) in sea.m.free_symbols | sea.b.free_symbols:
        raise ParameterError(
            f"{where}: {name} sets the actuator mass or damping (the plant); tune the "
            "controller gains or the transmission instead"
        )
    if allow_plant or name not in sea.plant_parameters or name in _design_variables(design):
        return
    value = sea.values.get(name)
    at = "" if value is None else f" ({name} = {value:g})"
    ranges = (
        " (or give it a [ranges] entry in the design file)" if isinstance(design, Design) else ""
    )
    raise ParameterError(
        f"{where}: {name} is a plant parameter{at}, part of the hardware, not a controller "
        f"gain; to redesign the hardware, tune it on purpose with allow_plant=True{ranges}"
    )


def _wanted(tune: BoxLike | None, defaults: tuple[str, ...], sea: SEA) -> dict[str, Any]:
    """The gains to tune, each with its box as given (checked; None: from the design)."""
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
    for name in wanted:
        where = f"tune[{name!r}]"
        if name not in sea.parameters:
            raise ParameterError(
                f"{where}: not a parameter of the design "
                f"({', '.join(sea.parameters)}){did_you_mean(str(name), sea.parameters)}"
            )
        if wanted[name] is not None:
            wanted[name] = _box(wanted[name], where)
    return wanted


def _gain_box(
    name: str, given: tuple[float, float] | None, boxes: Mapping[str, tuple[float, float]], sea: SEA
) -> tuple[float, float]:
    box = given or boxes.get(name) or default_box(name, sea.values.get(name))
    if box is None:
        raise ParameterError(
            f"tune[{name!r}]: {name} has no value and no search box; give one, "
            f"e.g. tune={{{name!r}: (0, 1000)}}"
        )
    return box


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
    *,
    allow_plant: bool = False,
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
        else the controller gains of a design file or an SEA (the parameters of
        ``C_A`` and ``C_L`` that are not plant parameters,
        [`SEA.gains`][seapass.model.sea.SEA.gains]).  Every other parameter keeps its value.
    options : TuningOptions, optional
    values : mapping of str to float, optional
        Values of fixed parameters overriding the design's (a catalog design's
        plant, say).
    allow_plant : bool
        Allow tuning plant parameters
        ([`SEA.plant_parameters`][seapass.model.sea.SEA.plant_parameters]: the
        springs and dampers of the hardware, ``[plant]``) named in ``tune``.
        Without it only those the design offers may be tuned (a catalog entry's
        gains, a design file's ``[ranges]``); ``m`` and ``b`` never.

    Raises
    ------
    ParameterError
        Naming the argument: an unknown gain or value (with a did-you-mean), an
        empty or inverted box, a value for a tuned gain, a fixed parameter
        without a value, a plant parameter without ``allow_plant``.
    """
    opts = options or TuningOptions()
    name, sea, defaults, boxes = design_parts(design)
    for key in values or {}:
        if key not in sea.parameters:
            raise ParameterError(
                f"values[{key!r}]: not a parameter of the design "
                f"({', '.join(sea.parameters)}){did_you_mean(key, sea.parameters)}"
            )
    if values:
        sea = sea.with_values(**values)
    wanted = _wanted(tune, defaults, sea)
    for gain in wanted:
        _check_plant(gain, sea, design, allow_plant)
    clash = sorted(set(values or {}) & set(wanted))
    if clash:
        raise ParameterError(
            f"values[{clash[0]!r}]: {clash[0]} is tuned, so its value would be ignored; "
            "drop the value or tune other gains"
        )
    missing = [p for p in sea.parameters if p not in wanted and sea.values.get(p) is None]
    if missing:
        raise ParameterError(
            f"no value for {', '.join(missing)}: give it in the design's values "
            f"(values[{missing[0]!r}]) or tune it (tune={{{missing[0]!r}: (lo, hi)}})"
        )
    box = {name: _gain_box(name, given, boxes, sea) for name, given in wanted.items()}
    gains = tuple(box)
    file = design if isinstance(design, Design) else None
    given = {f.name: getattr(opts, f.name) for f in fields(TuningOptions)}
    load_mass = PAPER_EXPERIMENT.pick("load_mass", opts.load_mass, file and file.tuning_mass)
    listed = None if file is None else file.load_masses
    given_mass = opts.load_mass is not None
    masses = resolve_masses(opts.masses, load_mass=load_mass, given_mass=given_mass, listed=listed)
    resolved = ResolvedTuning(
        **{
            **given,
            "load_mass": load_mass,
            "masses": masses,
            "step": PAPER_EXPERIMENT.pick("step", opts.step, file and file.step),
            "horizon": PAPER_EXPERIMENT.pick("horizon", opts.horizon, file and file.horizon),
        }
    )
    horizon = resolved.horizon
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
