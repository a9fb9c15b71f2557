"""A design file merged with what the caller says: the model, loop, experiment, ranges, units.

Every command that takes a design file runs what [`resolve_design`][seapass.model.resolve.resolve_design]
returns.  The one rule: a value the caller gives wins, then the design file's, then the
command's default (for the loop) or the paper's experiment
([`Experiment.pick`][seapass.model.experiment.Experiment.pick]).

* model: the file's elements, each replaced by one the caller gives; the file's
  values of the parameters the (new) model uses, then the caller's values; the
  ``free`` parameters lose their value.
* loop: the file's ``[control]`` (else ``default_loop``), with the caller's
  ``period``, ``delay``, ``velocity_filter``, ``method``; no loop without a period.
* step response: ``load_mass``, ``step``, ``horizon`` given, else the file's
  (``tune_mass``, ``step``, ``horizon``), else None (the library's default).
* ranges: `ResolvedDesign.range_of` (given, else ``[ranges]``, else
  ``[0, max(10·value, 1000)]`` around the file's value, else `DEFAULT_RANGE`).
* units: ``units`` given, else ``[units]``, else the defaults
  ([`unit_map`][seapass.model.units.unit_map]).
* loop latency: ``delay_time`` given, else ``[control] delay_time``; when ``> 0`` the
  model's ``C_A`` and ``C_L`` are times ``exp(-delay_time*s)`` with ``delay_time = τ``
  ([`seapass.model.latency`][seapass.model.latency]), so ``sea`` is a delayed design.

Examples
--------
>>> r = resolve_design(elements={"D1": "k1", "CL": "kd"},
...                    values={"m": 1, "b": 10, "k1": 1000}, free=["kd"])
>>> r.sea.free_parameters, r.loop, r.range_of("kd")
(('kd',), None, (0.0, 100000.0))
>>> r.units["kd"]
'N/m'
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ..errors import FileFormatError, ParameterError
from .design_file import Design
from .display import html_card, short_repr
from .experiment import PAPER_EXPERIMENT, Experiment
from .expr import STANDARD_SYMBOLS, parse_expression
from .latency import check_latency, latency_elements, latency_values
from .loop import SampledLoop
from .sea import SEA
from .units import unit_map
from .zcontroller import ZController, discrete_loop

__all__ = [
    "DEFAULT_RANGE",
    "ELEMENTS",
    "ResolvedDesign",
    "default_range",
    "resolve_design",
    "resolve_loop",
]

DEFAULT_RANGE: tuple[float, float] = (0.0, 1e5)
"""Search range of a parameter without a file range or a value to scale from."""

ELEMENTS: tuple[str, ...] = ("D1", "D2", "CA", "CL")
"""The model's elements."""

_LOOP_KEYS = ("period", "delay", "velocity_filter", "method")


def default_range(value: float | None) -> tuple[float, float]:
    """``[0, max(10·|value|, 1000)]``, or `DEFAULT_RANGE` without a value.

    >>> default_range(50.0), default_range(500.0), default_range(None)
    ((0.0, 1000.0), (0.0, 5000.0), (0.0, 100000.0))
    """
    if value is None:
        return DEFAULT_RANGE
    return (0.0, max(10.0 * abs(value), 1000.0))


def _empty() -> Mapping[str, Any]:
    """A read-only empty mapping (the default of the mapping fields)."""
    return MappingProxyType({})


@dataclass(frozen=True, kw_only=True, repr=False)
class ResolvedDesign:
    """What a command runs: the file merged with the caller's values (see `resolve_design`).

    Attributes
    ----------
    sea : SEA
        The model, ``free`` parameters without a value.
    loop : SampledLoop or None
        The digital controller's loop, None for a continuous controller.
    load_mass, step, horizon : float or None
        Given, else the file's (its tuning mass), else None: the library's default.
    load_masses : tuple of float
        The file's load masses, else the paper's.
    ranges : mapping of str to (float, float)
        The file's ``[ranges]`` (empty without a file).
    values : mapping of str to float
        Every known value (the file's and the caller's), the free parameters' included,
        for default ranges.
    units : mapping of str to str
        The unit of every parameter of the model and of ``m_L`` (``""``: none).
    environment : mapping of str to (float, float)
        The file's ``[environment]`` bounds (empty: the default).
    design : Design or None
        The design file, if any.
    delay_time : float or None
        The loop latency [s] (given, else the file's; None: none stated); when ``> 0``,
        ``sea`` holds it as ``exp(-delay_time*s)`` on ``C_A`` and ``C_L``.
    """

    sea: SEA
    loop: SampledLoop | None = None
    load_mass: float | None = None
    step: float | None = None
    horizon: float | None = None
    load_masses: tuple[float, ...] = PAPER_EXPERIMENT.load_masses
    ranges: Mapping[str, tuple[float, float]] = field(default_factory=_empty)
    values: Mapping[str, float] = field(default_factory=_empty)
    units: Mapping[str, str] = field(default_factory=_empty)
    environment: Mapping[str, tuple[float, float]] = field(default_factory=_empty)
    design: Design | None = None
    delay_time: float | None = None

    def __post_init__(self) -> None:
        for name in ("ranges", "values", "units", "environment"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name))))

    @property
    def experiment(self) -> Experiment:
        """The step-response experiment: what is given, else the paper's."""
        pick = PAPER_EXPERIMENT.pick
        return Experiment(
            step=pick("step", self.step),
            horizon=pick("horizon", self.horizon),
            load_mass=pick("load_mass", self.load_mass),
            load_masses=self.load_masses,
        )

    def range_of(self, name: str, given: tuple[float, float] | None = None) -> tuple[float, float]:
        """The search range of ``name``: ``given``, else the file's, else `default_range`.

        The same rule for every command (``bound``, ``region``, ``sampled bound``, ...).
        """
        if given is not None:
            return given
        if name in self.ranges:
            return self.ranges[name]
        return default_range(self.values.get(name))

    def to_dict(self) -> dict[str, Any]:
        return {
            "design": None if self.design is None else self.design.name,
            "values": dict(self.sea.values),
            "loop": None if self.loop is None else self.loop.to_dict(),
            "load_mass": self.load_mass,
            "step": self.step,
            "horizon": self.horizon,
            "units": dict(self.units),
            **({} if self.delay_time is None else {"delay_time": self.delay_time}),
        }

    def __repr__(self) -> str:
        return short_repr("ResolvedDesign", self.to_dict())

    def _repr_html_(self) -> str:
        return html_card("Resolved design", list(self.to_dict().items()))


def resolve_design(
    design: Design | None = None,
    *,
    elements: Mapping[str, str] | None = None,
    values: Mapping[str, float] | None = None,
    free: Iterable[str] = (),
    units: Mapping[str, str] | None = None,
    loop: Mapping[str, Any] | None = None,
    default_loop: SampledLoop | None = None,
    load_mass: float | None = None,
    step: float | None = None,
    horizon: float | None = None,
    plant: Iterable[str] = (),
    delay_time: float | None = None,
    discrete: ZController | None = None,
) -> ResolvedDesign:
    """Merge a design file with the caller's model, values, loop, experiment and units.

    Parameters
    ----------
    design : Design, optional
        The design file; None: everything comes from the other arguments.
    elements : mapping of str to str, optional
        Elements (``D1``, ``D2``, ``CA``, ``CL``) replacing the file's.
    values : mapping of str to float, optional
        Parameter values replacing the file's; each must be used by the model.
    free : iterable of str
        Parameters left free (bounded, swept): they get no value.
    units : mapping of str to str, optional
        Units replacing the file's and the defaults (parameters of the model or ``m_L``).
    loop : mapping, optional
        ``period``, ``delay``, ``velocity_filter``, ``method`` (None: not given)
        changing the file's ``[control]`` loop, else ``default_loop``.
    default_loop : SampledLoop, optional
        The loop when the file has none (a sampled command's default period).
    load_mass, step, horizon : float, optional
        The step response's, replacing the file's.
    plant : iterable of str
        Hardware parameters besides the file's ``[plant]`` (never gains).
    delay_time : float, optional
        The loop latency [s] replacing the file's ``[control] delay_time`` (0: none).
    discrete : ZController, optional
        A controller given in ``z``, replacing the file's controller (its ``CA``/``CL``
        or ``[discrete]``); the file's ``CA``/``CL`` given here replace its ``[discrete]``.
        With a controller in z the loop runs at its rate (another rate is an error).

    Returns
    -------
    ResolvedDesign

    Raises
    ------
    ParameterError
        For an unknown element, a value the model does not use (``values['x']``), a
        unit that is not one (``units['x']``), a bad loop or a bad ``delay_time``.
    """
    given_elements = {k: v for k, v in (elements or {}).items() if v is not None}
    unknown = sorted(set(given_elements) - set(ELEMENTS))
    if unknown:
        raise ParameterError(f"elements: unknown element {unknown[0]!r}", argument="elements")
    free = tuple(free)
    base: dict[str, str] = {k: "0" for k in ELEMENTS}
    file_values: dict[str, float] = {}
    zc = design.discrete if design is not None else None
    if design is not None:
        base = {k: getattr(design, k) for k in ELEMENTS}
        file_values = dict(design.values)
    if discrete is not None or given_elements.keys() & {"CA", "CL"}:
        zc = discrete  # the caller's controller replaces the file's, in s or in z
        if discrete is not None:
            base.update(CA="0", CL="0")
    base.update(given_elements)
    kept = file_values
    if (
        given_elements or discrete is not None
    ) and design is not None:  # the file's values of the parameters still used
        allowed = {*STANDARD_SYMBOLS, *file_values, *(values or {}), *free}
        used = {"m", "b"}
        for text in base.values():
            used |= {str(x) for x in parse_expression(text, allowed).free_symbols} - {"s"}
        used |= set(zc.names) if zc is not None else set()
        kept = {k: v for k, v in file_values.items() if k in used}
    known: dict[str, float] = {**kept, **dict(values or {})}
    model_values: dict[str, float | None] = {**known, **dict.fromkeys(free)}
    hardware = (*(design.plant if design is not None else ()), *plant)
    sea = SEA(
        **base,
        values=model_values,
        name=design.name if design is not None else "",
        plant=tuple(dict.fromkeys(hardware)),
        discrete=zc,
    )
    latency = delay_time if delay_time is not None else _file(design, "delay_time")
    if latency is not None:
        latency = _latency(latency, sea, given=delay_time is not None)
    if latency and zc is not None:
        raise ParameterError(
            "delay_time: a continuous loop latency needs a continuous controller; a controller "
            "given in z states its delay itself (z^-1 factors)",
            argument="delay_time",
        )
    if latency:  # the loop latency on C_A and C_L
        sea = SEA(
            **latency_elements(base, latency),
            values=latency_values(model_values, latency),
            name=sea.name,
            plant=sea.plant,
        )
    names = (*sea.parameters, "m_L")
    declared = dict(design.units) if design is not None else {}
    for name in units or {}:
        if name not in names:
            raise ParameterError(
                f"units['{name}']: not a parameter of the model ({', '.join(names)})",
                argument=f"units['{name}']",
            )
    declared.update(units or {})
    file_loop = design.loop if design is not None else None
    if zc is not None:  # the controller's rate, not a command's default period
        file_loop = discrete_loop(zc, file_loop)
    resolved_loop = resolve_loop(file_loop, default_loop, loop or {})
    if zc is not None and resolved_loop is not None:
        zc.check_loop(resolved_loop.period)
    return ResolvedDesign(
        sea=sea,
        loop=resolved_loop,
        load_mass=load_mass if load_mass is not None else _file(design, "tuning_mass"),
        step=step if step is not None else _file(design, "step"),
        horizon=horizon if horizon is not None else _file(design, "horizon"),
        load_masses=design.load_masses if design is not None else PAPER_EXPERIMENT.load_masses,
        ranges=dict(design.ranges) if design is not None else {},
        values=known,
        units=unit_map(declared, names),
        environment=dict(design.environment) if design is not None else {},
        design=design,
        delay_time=latency,
    )


def _latency(value: float, sea: SEA, *, given: bool) -> float:
    """The latency checked against the (merged) model: `ParameterError` naming ``delay_time``."""
    key = "delay_time" if given else "control.delay_time"
    try:
        tau = check_latency(value, sea, key=key)
    except FileFormatError as exc:
        raise ParameterError(str(exc), argument="delay_time") from None
    assert tau is not None
    return tau


def _file(design: Design | None, name: str) -> Any:
    return None if design is None else getattr(design, name)


def resolve_loop(
    file: SampledLoop | None, default: SampledLoop | None, changes: Mapping[str, Any]
) -> SampledLoop | None:
    """The file's loop (else ``default``) with the given ``changes``; no period: no loop.

    ``changes`` holds ``period``, ``delay``, ``velocity_filter``, ``method`` (None: not
    given).

    >>> resolve_loop(SampledLoop(rate=1000.0), None, {"delay": 1}).summary
    'T = 0.001 s, delay 1 samples, velocity filter none'
    """
    unknown = sorted(set(changes) - set(_LOOP_KEYS))
    if unknown:
        raise ParameterError(f"loop: unknown setting {unknown[0]!r}", argument="loop")
    given = {k: v for k, v in changes.items() if v is not None}
    base = file if file is not None else default
    if base is None:
        return SampledLoop(**given) if "period" in given else None
    return base.replace(**given) if given else base
