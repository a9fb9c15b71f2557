"""A design file on every command: ``DESIGN.toml``, ``--unit``, ``--range NAME=LO:HI``, ``--points``.

Every model command takes an optional design file; the flags override it and
what they leave out comes from the file (the merging is the library's:
[`resolve_design`][seapass.model.resolve.resolve_design]).  The one vocabulary
of ranges and grids:

* ``--range NAME=LO:HI``, repeatable: the search range of a parameter (``bound``,
  ``region``, ``sampled bound|region``; random ranges of ``sweep``); a parameter
  without one takes the file's ``[ranges]``, else ``[0, max(10·value, 1000)]``
  around the file's value, else ``0:1e5``;
* ``--points N``: the number of values on the gridded axis (``region`` columns,
  ``sampled region`` rows).

The old spellings (``--range LO:HI``, ``--x-range``, ``--y-range``, ``--nx``,
``--range2``, ``--rows``) still work for one release, with one ``warning:`` line.
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping, Sequence
from typing import Any

from ..errors import ParameterError
from .common import (
    check_period,
    parse_named,
    parse_range,
    refuse_delay_unless_allowed,
    values_from_args,
    warn,
)

__all__ = [
    "add_delay_time_option",
    "add_design_argument",
    "add_range_options",
    "add_unit_option",
    "declared",
    "deprecated_flag",
    "design_file_from_args",
    "design_from_args",
    "latency_message",
    "points_from_args",
    "ranges_from_args",
    "system_from_design_args",
    "unit_suffix",
    "units_from_args",
    "units_json",
]

_ELEMENTS = ("D1", "D2", "CA", "CL")


def add_design_argument(p: argparse.ArgumentParser) -> None:
    """The optional positional ``DESIGN.toml``, ``--unit NAME=UNIT`` and ``--delay-time``."""
    p.add_argument(
        "design",
        nargs="?",
        metavar="DESIGN.toml",
        help="design file (TOML, see 'seapass analyze --help'); the model flags override it",
    )
    add_unit_option(p)
    add_delay_time_option(p)


def add_delay_time_option(p: Any) -> None:
    """``--delay-time SECONDS``: the loop latency, replacing ``[control] delay_time``."""
    p.add_argument(
        "--delay-time",
        type=float,
        metavar="SECONDS",
        help="loop latency: C_A and C_L act SECONDS late (times exp(-delay_time*s)); "
        "replaces the design file's [control] delay_time, 0 for none (default: the file's, "
        "else none)",
    )


def add_unit_option(p: argparse.ArgumentParser) -> None:
    """``--unit NAME=UNIT``, repeatable."""
    p.add_argument(
        "--unit",
        action="append",
        default=[],
        metavar="NAME=UNIT",
        help="unit of a parameter for labels and JSON, repeatable, e.g. --unit ki=1/s "
        "(SI symbols with prefixes, '*', '/', '^N')",
    )


def add_range_options(p: Any, *, points: int | None = None, points_help: str = "") -> None:
    """``--range NAME=LO:HI`` (repeatable) and, with ``points``, ``--points N``."""
    p.add_argument(
        "--range",
        action="append",
        default=[],
        metavar="NAME=LO:HI",
        help="search range of a parameter, repeatable (default: the design file's [ranges], "
        "else [0, max(10*value, 1000)], else 0:1e5)",
    )
    if points is not None:
        p.add_argument("--points", type=int, metavar="N", help=f"{points_help} (default: {points})")


def deprecated_flag(old: str, new: str) -> None:
    """One ``warning:`` line for an old spelling."""
    warn(f"{old} is deprecated and will be removed in the next release; use {new}")


def ranges_from_args(
    args: argparse.Namespace,
    names: Sequence[str],
    old: Mapping[str, tuple[str, str | None]] | None = None,
    *,
    strict: bool = True,
) -> dict[str, tuple[float, float] | None]:
    """The ``--range`` of each of ``names`` (None: not given), old spellings included.

    ``old`` maps a name to its deprecated option and value (``("--x-range", "0:1")``);
    a bare ``--range LO:HI`` (old spelling) is the range of ``names[0]``.  ``strict``:
    ``LO < HI`` (else ``LO <= HI``).
    """
    out: dict[str, tuple[float, float] | None] = dict.fromkeys(names)
    named = [r for r in args.range if "=" in r]
    for r in args.range:
        if "=" not in r:
            if out[names[0]] is not None:
                raise ParameterError(f"--range {names[0]} is given twice; give each name once")
            deprecated_flag(f"--range {r}", f"--range {names[0]}={r}")
            out[names[0]] = parse_range(r, "--range", strict=strict)
    for name, (lo, hi) in parse_named(named, "--range", 2, "NAME=LO:HI, e.g. kd=0:5000"):
        if name not in out:
            raise ParameterError(
                f"--range {name}: not a free parameter here (the free ones: {', '.join(names)})"
            )
        if out[name] is not None:
            raise ParameterError(f"--range {name} is given twice; give each name once")
        out[name] = parse_range(f"{lo}:{hi}", f"--range {name}", strict=strict)
    for name, (flag, text) in (old or {}).items():
        if text is None:
            continue
        if out[name] is not None:
            raise ParameterError(f"give --range {name}=LO:HI only ({flag} is its old spelling)")
        deprecated_flag(f"{flag} {text}", f"--range {name}={text}")
        out[name] = parse_range(text, flag, strict=strict)
    return out


def points_from_args(args: argparse.Namespace, old: str, default: int) -> int:
    """``--points N``, or its old spelling (``--nx``, ``--rows``) with a warning, or ``default``."""
    flag = "--" + old.replace("_", "-")
    old_value = getattr(args, old)
    if old_value is not None:
        if args.points is not None:
            raise ParameterError(f"give --points only ({flag} is its old spelling)")
        deprecated_flag(f"{flag} {old_value}", f"--points {old_value}")
        return int(old_value)
    return default if args.points is None else int(args.points)


def units_from_args(args: argparse.Namespace) -> dict[str, str]:
    """``--unit NAME=UNIT`` items; a repeated name is an error."""
    out: dict[str, str] = {}
    for item in getattr(args, "unit", []):
        name, sep, unit = item.partition("=")
        name = name.strip()
        if not sep or not name or not unit.strip():
            raise ParameterError(f"--unit {item!r}: expected NAME=UNIT, e.g. --unit ki=1/s")
        if name in out:
            raise ParameterError(f"--unit {name} is given twice; give each name once")
        out[name] = unit.strip()
    return out


def design_file_from_args(args: argparse.Namespace) -> Any:
    """The command line's design file (``DESIGN.toml``), read and checked; None without one.

    A command reads its file once with this and passes the `Design` along
    (``file=`` of `design_from_args`, `system_from_design_args` and the robust
    paths): the file is read through the guarded reader exactly once.
    """
    from ..model.design_file import load_design

    path = getattr(args, "design", None)
    return None if path is None else load_design(path)


def design_from_args(
    args: argparse.Namespace,
    free: Mapping[str, str] | None = None,
    *,
    default_loop: Any = None,
    file: Any = None,
) -> Any:
    """The [`ResolvedDesign`][seapass.model.resolve.ResolvedDesign] of the command line.

    ``free`` maps each free parameter to how it was given (``{"kd": "bound kd"}``);
    it must not also be given with ``--set``.  The loop options (if the command has
    them) change the file's ``[control]``, else ``default_loop``.  ``file``: the
    design file already read (`design_file_from_args`); None reads ``args.design``.
    """
    from ..model.resolve import resolve_design
    from .controller_options import (
        controller_given,
        discrete_from_args,
        elements_from_args,
        plant_from_args,
    )

    labels = dict(free or {})
    values = values_from_args(args)
    for name, label in labels.items():
        if name in values:
            raise ParameterError(
                f"--set {name}: {name} is a free parameter here ({label}); do not also give "
                "it a value"
            )
    design = file if file is not None else design_file_from_args(args)
    plant = plant_from_args(args)
    if plant and design is not None:
        raise ParameterError("--plant: give hardware parameters in the design file's [plant]")
    for name in plant:
        if name in values:
            raise ParameterError(f"--plant {name}: also given with --set; give it once")
    values = {**values, **plant}
    elements = {e: getattr(args, e) for e in _ELEMENTS if getattr(args, e, None) is not None}
    if controller_given(args):  # the blocks, compiled into CA and CL
        names = {**(design.values if design is not None else {}), **values, **dict.fromkeys(labels)}
        elements["CA"], elements["CL"] = elements_from_args(args, names)
    loop: dict[str, Any] = {}
    if hasattr(args, "period"):
        check_period(args.period)
        loop = {k: getattr(args, k, None) for k in ("period", "delay", "velocity_filter", "method")}
    try:
        resolved = resolve_design(
            design,
            elements=elements,
            values=values,
            free=labels,
            units=units_from_args(args),
            loop=loop,
            default_loop=default_loop,
            load_mass=getattr(args, "load_mass", None),
            step=getattr(args, "step", None),
            horizon=getattr(args, "horizon", None),
            plant=tuple(plant),
            delay_time=getattr(args, "delay_time", None),
            discrete=discrete_from_args(args, design),
        )
    except ParameterError as exc:
        if exc.argument == "delay_time":
            raise ParameterError(latency_message(str(exc))) from None
        where = {f"values[{n!r}]": label for n, label in labels.items()}
        where.update({f"values[{n!r}]": f"--plant {n}" for n in plant})
        if exc.argument in where:  # a free (or --plant) name the model does not use
            msg = str(exc)[len(exc.argument) + 2 :]
            raise ParameterError(f"{where[exc.argument]}: {msg}") from None
        raise
    sampled = getattr(getattr(args, "func", None), "__module__", "").endswith("cmd_sampled")
    if resolved.delay_time and not getattr(args, "allow_delay", False) and sampled:
        raise ParameterError(  # the sampled loop: its latency is whole samples (z^-d)
            f"the loop latency delay_time = {resolved.delay_time:g} s (the design file's "
            "[control] delay_time or --delay-time) is a continuous delay; the sampled commands "
            "(with or without --uncertain) model the latency as whole samples of the loop: give "
            "--delay N (or [control] delay = N) and --delay-time 0"
        )
    if resolved.delay_time and not getattr(args, "allow_delay", False):
        raise ParameterError(
            f"the loop latency delay_time = {resolved.delay_time:g} s (the design file's "
            "[control] delay_time or --delay-time) puts exp(-delay_time*s) on C_A and C_L; "
            "this command does not handle a delay yet: give --delay-time 0 to run it without "
            "the latency ('seapass check' and 'seapass delay-margin' decide the delayed design)"
        )
    refuse_delay_unless_allowed(args, resolved.sea)
    return resolved


def latency_message(text: str) -> str:
    """A library message about ``delay_time`` in the CLI's words (``--delay-time``)."""
    if text.startswith("delay_time: "):
        return "--delay-time" + text[len("delay_time") :]
    return text


def system_from_design_args(args: argparse.Namespace, *, file: Any = None) -> tuple[Any, Any]:
    """The raw ``--Z`` impedance (and None), or the SEA of the design and flags (and its
    resolution); ``file`` as in `design_from_args`."""
    from ..model.sea import Impedance

    if getattr(args, "Z", None) is None:
        resolved = design_from_args(args, file=file)
        return resolved.sea, resolved
    from .controller_options import model_given

    if args.design is not None or model_given(args):
        raise ParameterError(
            "give either --Z or a design (DESIGN.toml, --D1/--D2/--CA/--CL, --controller, "
            "--plant), not both"
        )
    if args.unit:
        raise ParameterError("--unit names a parameter of an SEA design, not of --Z")
    z = Impedance(expr=args.Z, values=values_from_args(args))
    return refuse_delay_unless_allowed(args, z), None


def declared(args: argparse.Namespace) -> bool:
    """True when the command ran from a design file or with ``--unit`` (units are shown)."""
    return getattr(args, "design", None) is not None or bool(getattr(args, "unit", []))


def unit_suffix(args: argparse.Namespace, resolved: Any, name: str) -> str:
    """``" N/m"`` after a value of ``name`` when units are shown and it has one, else ``""``."""
    unit = resolved.units.get(name, "") if resolved is not None and declared(args) else ""
    return f" {unit}" if unit else ""


def units_json(args: argparse.Namespace, resolved: Any) -> dict[str, Any]:
    """``{"units": {...}}`` when a design file or ``--unit`` was given, else ``{}``.

    Without either, the JSON of a command stays as it was (every unit is the default).
    """
    if resolved is None or not declared(args):
        return {}
    return {"units": dict(resolved.units)}
