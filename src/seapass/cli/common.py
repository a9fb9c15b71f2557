"""Conventions shared by every subcommand: options, strict names, messages.

Every command, old or new, uses these helpers (see ``notes/cli-conventions.md``
in the project notes and the README's command-line section):

* model options: `add_model_options`, then `model_from_args` / `system_from_args`
  (strict ``--set``: unknown, unused or repeated names are errors with a
  did-you-mean);
* other named options (``--grid``, ``--range NAME=LO:HI``, ``--bound``, ``--tune``):
  `parse_named` + `check_names`; a plain range ``LO:HI``: `parse_range`;
* output: `add_json_option`, `add_plot_option` / `plot_path`,
  `add_out_dir_option` / `check_out_dir`; files are written and announced
  (``wrote PATH`` on stderr) by `save_plot`, `write_text`, `write_bytes` in
  [`seapass.cli.output`][seapass.cli.output];
* a design file on every command, ``--unit``, ``--range NAME=LO:HI`` and ``--points``:
  [`seapass.cli.design_options`][seapass.cli.design_options];
* the sampled loop: `add_loop_options` and `loop_from_args` (one
  [`SampledLoop`][seapass.model.loop.SampledLoop] from ``--period --delay
  --velocity-filter --method`` and a design file's ``[control]``);
* messages: `warn` (``warning: ...`` on stderr), the unit-slip checks
  `check_period` and `check_step`, and `error_text` (one line, CLI flags in place
  of Python argument names).
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ..errors import ParameterError, SeapassError, did_you_mean
from .output import (
    add_force_option,
    add_json_option,
    add_out_dir_option,
    add_plot_option,
    announce,
    atomic_save,
    atomic_write,
    atomic_write_text,
    check_out_dir,
    check_out_file,
    json_text,
    plot_path,
    print_json,
    save_plot,
    write_bytes,
    write_text,
)

__all__ = [
    "EXIT_CODES",
    "HelpFormatter",
    "Terminated",
    "add_force_option",
    "add_jobs_argument",
    "add_json_option",
    "add_model_options",
    "add_out_dir_option",
    "add_plot_option",
    "announce",
    "atomic_save",
    "atomic_write",
    "atomic_write_text",
    "check_names",
    "check_out_dir",
    "check_out_file",
    "check_period",
    "check_step",
    "cli_flag",
    "cli_words",
    "deprecated_alias",
    "error_text",
    "interrupted_code",
    "json_text",
    "model_from_args",
    "parse_named",
    "parse_range",
    "plot_path",
    "print_json",
    "save_plot",
    "system_from_args",
    "values_from_args",
    "warn",
    "warn_unrealizable",
    "write_bytes",
    "write_figure",
    "write_text",
]

EXIT_CODES = """exit codes:
  0    success (check: passive)
  1    a negative verdict of a check (check: not passive), like cmp
  2    bad input or another error: one 'error:' line on stderr
  130  interrupted (Ctrl-C); 143 terminated (SIGTERM)"""


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where Ctrl-C raises ``KeyboardInterrupt``: long jobs stop the same way."""


def interrupted_code(exc: BaseException) -> int:
    """The exit code of an interrupted command: 143 after SIGTERM, else 130 (Ctrl-C)."""
    return 143 if isinstance(exc, Terminated) else 130


class HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """Keeps the epilog's layout and shows every meaningful default in ``--help``."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help or ""
        default = action.default
        if (
            "default" in text.lower()
            or not action.option_strings
            or default in (None, False, [], argparse.SUPPRESS)
        ):
            return text
        return f"{text} (default: %(default)s)"


# --------------------------------------------------------------------------- messages


def warn(message: str) -> None:
    """One ``warning: ...`` line on stderr (stdout stays clean for ``--json``)."""
    print(f"warning: {' '.join(message.split())}", file=sys.stderr)


PERIOD_SLIP = 0.1
"""Control periods from this many seconds up look like a rate in Hz typed as seconds."""

STEP_SLIP = 0.2
"""Steps from this many metres up look like millimetres typed as metres."""


def check_period(period: float | None, flag: str = "--period") -> None:
    """Warn when a control period looks like a rate in Hz (``--period 500``)."""
    if period is not None and period >= PERIOD_SLIP:
        warn(
            f"{flag} {period:g} s is a very slow controller ({1 / period:.3g} Hz); if you meant "
            f"{period:g} Hz, give {flag} {1 / period:.6g}"
        )


def check_step(step: float | None, flag: str = "--step") -> None:
    """Warn when a reference step looks like millimetres typed as metres (``--step 500``)."""
    if step is not None and abs(step) >= STEP_SLIP:
        warn(
            f"{flag} {step:g} m is a large step for an SEA; if you meant {step:g} mm, "
            f"give {flag} {step / 1000:g}"
        )


_FLAGS = {
    "values": "--set",
    "Z": "--Z",
    "D1": "--D1",
    "D2": "--D2",
    "CA": "--CA",
    "CL": "--CL",
    "ranges": "--range",
    "samples": "--sample",
    "grid": "--grid",
    "budgets": "--budget",
}


_KEYED = {
    "values": "--set",
    "bounds": "--bound",
    "tune": "--tune",
    "units": "--unit",
    "budgets": "--budget",
}


def cli_flag(argument: str) -> str:
    """The command-line spelling of a Python argument: ``values['kd']`` → ``--set kd``.

    >>> cli_flag("values['kd']"), cli_flag("tune['kd']"), cli_flag("load_mass"), cli_flag("CA")
    ('--set kd', '--tune kd', '--load-mass', '--CA')
    """
    m = re.fullmatch(r"(values|bounds|tune|units|budgets)\['([^']*)'\]", argument)
    if m:
        return f"{_KEYED[m.group(1)]} {m.group(2)}"
    if argument in _FLAGS:
        return _FLAGS[argument]
    if argument.startswith("bounds."):  # an environment box: --mass, --damping, --stiffness
        return "--" + argument[len("bounds.") :]
    if re.fullmatch(r"[a-z][a-z0-9_]*", argument):
        return "--" + argument.replace("_", "-")
    return argument


def error_text(exc: BaseException) -> str:
    """One line for ``exc``, in the words of the command line.

    An `OSError` shows the path and the reason (no ``[Errno 2]``); a
    [`SeapassError`][seapass.errors.SeapassError] naming a Python argument
    (``values['kd']``) names the flag instead (``--set kd``).
    """
    if isinstance(exc, OSError) and not isinstance(exc, SeapassError) and exc.strerror:
        where = f"{exc.filename}: " if exc.filename is not None else ""
        msg = f"{where}{exc.strerror}"
    else:
        msg = str(exc)
        if isinstance(exc, KeyError) and exc.args:
            msg = str(exc.args[0])
        msg = cli_words(msg, getattr(exc, "argument", None))
    return " ".join(msg.split()) or type(exc).__name__


def cli_words(text: str, argument: str | None = None) -> str:
    """A library message or warning in the words of the command line.

    The library names Python arguments (``values['kd']``, ``tune={'kd': (lo, hi)}``,
    ``rtol``); the command line shows its flags instead.  ``argument`` is the
    argument an error names (its ``argument`` attribute).

    >>> cli_words("widen the box (tune={'kd': (lo, hi)})")
    'widen the box (--tune kd=LO:HI)'
    >>> cli_words("tune['bd']: no default box; give it as tune={'bd': (lo, hi)}", "tune")
    '--tune bd: no default box; give it as --tune bd=LO:HI'
    >>> cli_words("rtol must be in [1e-12, 0.01]; got rtol=0", "rtol")
    '--rtol must be in [1e-12, 0.01]; got --rtol 0'
    """
    # the spelled-out Python forms first: the generic "argument=" rewrite below would
    # otherwise turn "tune={'kd': (lo, hi)}" into "--tune {'kd': (lo, hi)}"
    msg = re.sub(r"e\.g\. values=\{'(\w+)': [^}]*\}", r"e.g. --set \1=VALUE", text)
    msg = re.sub(r"tune=\{'(\w+)': \([^)]*\)\}", r"--tune \1=LO:HI", msg)
    if argument and msg.startswith(f"{argument}: "):
        msg = f"{cli_flag(argument)}: {msg[len(argument) + 2 :]}"
    elif argument and re.fullmatch(r"[a-z][a-z0-9_]*", argument):  # "rtol must ...; rtol=0"
        flag = cli_flag(argument)
        msg = re.sub(rf"(?<![\w.'\[-]){argument}(=| )", lambda m: f"{flag} ", msg)
    msg = re.sub(r"^(CA|CL)_z: ", r"--\1-z: ", msg)  # a controller in z (ZController)
    msg = re.sub(
        r"(values|tune|units|budgets)\['(\w+)'\]",
        lambda m: f"{_KEYED[m.group(1)]} {m.group(2)}",
        msg,
    )
    return re.sub(r"\b([a-z][a-z_]*)=True\b", lambda m: "--" + m.group(1).replace("_", "-"), msg)


def deprecated_alias(args: argparse.Namespace, old: str, new: str) -> Any:
    """The value of option ``new``, or of its deprecated spelling ``old`` with a warning.

    Register the old spelling with ``help=argparse.SUPPRESS``; giving both is an error.
    """
    old_value, new_value = getattr(args, old), getattr(args, new)
    flag_old, flag_new = "--" + old.replace("_", "-"), "--" + new.replace("_", "-")
    if old_value is None:
        return new_value
    if new_value is not None:
        raise ParameterError(f"give {flag_new} only ({flag_old} is its old spelling)")
    warn(f"{flag_old} is deprecated here; use {flag_new} {old_value}")
    return old_value


# --------------------------------------------------------------------------- names


def parse_named(
    items: Sequence[str], flag: str, fields: int, example: str
) -> list[tuple[str, list[str]]]:
    """Split repeatable ``NAME=A:B[:C]`` options; a repeated NAME is an error.

    Values may start with a minus (``kd=-100:100``).  Returns ``[(name, [A, B, ...])]``
    in the order given; the parts are raw text (parse them with
    [`parse_value`][seapass.model.expr.parse_value]).
    """
    out: list[tuple[str, list[str]]] = []
    seen: set[str] = set()
    for item in items:
        name, sep, rest = item.partition("=")
        name = name.strip()
        parts = rest.split(":")
        if not sep or not name or len(parts) != fields or not all(p.strip() for p in parts):
            raise ParameterError(f"{flag} {item!r}: expected {example}")
        if name in seen:
            raise ParameterError(f"{flag} {name} is given twice; give each name once")
        seen.add(name)
        out.append((name, [p.strip() for p in parts]))
    return out


def check_names(
    names: Iterable[str], known: Iterable[str], flag: str, what: str = "the model"
) -> None:
    """Raise for a name that is not in ``known``, with the closest known name.

    >>> check_names(["kdd"], ["kd", "bd"], "--bound")
    Traceback (most recent call last):
    ...
    seapass.errors.ParameterError: --bound kdd: not a parameter of the model (did you mean 'kd'?); known: bd, kd
    """
    known = sorted(set(known))
    for name in names:
        if name not in known:
            raise ParameterError(
                f"{flag} {name}: not a parameter of {what}{did_you_mean(name, known)}; "
                f"known: {', '.join(known) or 'none'}"
            )


def parse_range(text: str, flag: str = "--range", *, strict: bool = False) -> tuple[float, float]:
    """``LO:HI`` as two finite numbers with ``LO <= HI`` (``LO < HI`` if ``strict``)."""
    from ..model.expr import parse_value

    parts = text.split(":")
    if len(parts) != 2:
        raise ParameterError(f"{flag} {text!r}: expected LO:HI, e.g. {flag} 0:1e5")
    lo = parse_value(parts[0].strip(), f"{flag} start")
    hi = parse_value(parts[1].strip(), f"{flag} end")
    if lo > hi or (strict and lo == hi):
        raise ParameterError(
            f"{flag} {text!r}: LO must {'be below' if strict else 'not exceed'} HI"
        )
    return lo, hi


# --------------------------------------------------------------------------- models


def add_jobs_argument(p: argparse.ArgumentParser) -> None:
    """``--jobs N``: worker processes for a report's independent stages."""
    p.add_argument(
        "--jobs",
        type=int,
        default=2,
        metavar="N",
        help="worker processes for the independent stages (1 = sequential)",
    )


def add_model_options(p: argparse.ArgumentParser) -> None:
    """``--D1 --D2 --CA --CL --set`` as used by every model command, and the controller blocks
    and ``--plant`` of [`controller_options`][seapass.cli.controller_options]."""
    from .controller_options import CONVENTION, add_controller_options

    g = p.add_argument_group(
        "model (elements not given: the design file's, else 0)", f"{CONVENTION}."
    )
    g.add_argument("--D1", help="transmission, e.g. 'k1 + b1*s'")
    g.add_argument("--D2", help="load-to-ground element, e.g. 'k2'")
    g.add_argument("--CA", help="actuator-side controller, e.g. 'kd + bd*s'")
    g.add_argument("--CL", help="load-side controller, e.g. 'kd'")
    g.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="parameter value, repeatable, e.g. --set m=1 --set kd=5000; every name must be "
        "used by the model and given once",
    )
    add_controller_options(p)


def values_from_args(args: argparse.Namespace) -> dict[str, float]:
    """The ``--set`` values; a name given twice is an error."""
    from ..model.expr import parse_assignment

    out: dict[str, float] = {}
    for item in args.set:
        name, val = parse_assignment(item)
        if name in out:
            raise ParameterError(
                f"--set {name} is given twice ({out[name]:g} and {val:g}); give each name once"
            )
        out[name] = val
    return out


def model_from_args(
    args: argparse.Namespace, extra_free: Sequence[str] | Mapping[str, str] = ()
) -> Any:
    """The [`SEA`][seapass.model.sea.SEA] of ``--D1 --D2 --CA --CL --set`` (or the controller
    blocks, ``--plant``).

    ``extra_free`` names parameters left free (the swept or bounded ones), as
    names or as ``{name: how it was given}`` (``{"kd": "--grid kd"}``); each must
    appear in the model and must not also be given with ``--set``.
    """
    from ..model.sea import SEA
    from .controller_options import discrete_from_args, elements_from_args, plant_from_args

    labels = dict(extra_free) if isinstance(extra_free, Mapping) else {n: n for n in extra_free}
    values: dict[str, float | None] = dict(values_from_args(args))
    plant = plant_from_args(args)
    for name in plant:
        if name in values:
            raise ParameterError(f"--plant {name}: also given with --set; give it once")
    values.update(plant)
    for name, label in labels.items():
        if name in values:
            raise ParameterError(
                f"--set {name}: {name} is a free parameter here ({label}); do not also give "
                "it a value"
            )
        values[name] = None
    CA, CL = elements_from_args(args, values)
    try:
        return refuse_delay_unless_allowed(
            args,
            SEA(
                D1=args.D1 or "0",
                D2=args.D2 or "0",
                CA=CA or "0",
                CL=CL or "0",
                values=values,
                plant=tuple(plant),
                discrete=discrete_from_args(args),
            ),
        )
    except ParameterError as exc:
        free = {f"values[{n!r}]": label for n, label in labels.items()}
        free.update({f"values[{n!r}]": f"--plant {n}" for n in plant})
        if exc.argument in free:  # a free (or --plant) name the model does not use
            msg = str(exc)[len(exc.argument) + 2 :]
            raise ParameterError(f"{free[exc.argument]}: {msg}") from None
        raise


def warn_unrealizable(system: Any) -> bool:
    """Warn for each controller that needs more than one derivative; True if realizable."""
    from ..model.sea import SEA, unrealizable_controllers

    if not isinstance(system, SEA):
        return True
    bad = unrealizable_controllers(system)
    for name, excess in bad.items():
        warn(
            f"--{name} '{getattr(system, name)}' has {excess} more zeros than poles: not "
            "realizable (the controller measures positions and velocities, so at most one "
            "derivative); the answer is for the ideal model only. Add filter poles, e.g. "
            "'kd*s**2/(1 + s/500)**2'"
        )
    return not bad


def system_from_args(args: argparse.Namespace) -> Any:
    """The raw impedance given with ``--Z``, or else the SEA model of the element options."""
    from ..model.sea import Impedance
    from .controller_options import model_given

    if getattr(args, "Z", None) is None:
        return model_from_args(args)
    if model_given(args):
        raise ParameterError("give either --Z or the model elements --D1/--D2/--CA/--CL, not both")
    return refuse_delay_unless_allowed(args, Impedance(expr=args.Z, values=values_from_args(args)))


DELAY_COMMANDS = "'seapass check' and 'seapass delay-margin'"
"""The commands that decide a model with a delay factor ``exp(-NAME*s)``."""


def refuse_delay_unless_allowed(args: argparse.Namespace, system: Any) -> Any:
    """Refuse a delay factor in a command that does not handle one (``allow_delay`` unset)."""
    from ..delay.structure import has_model_delay

    if not getattr(args, "allow_delay", False) and has_model_delay(system):
        from ..errors import DelayError

        raise DelayError(
            f"this command does not handle a delay exp(-NAME*s) yet; {DELAY_COMMANDS} "
            "decide delayed designs"
        )
    return system


def write_figure(
    draw: Callable[[], Any], path: str | os.PathLike[str], *, force: bool = False
) -> Path:
    """`save_plot` for a ``--plot FILE`` option: one file, checked by `plot_path`, announced.

    The suffix picks the format (``.png``, ``.svg`` or ``.pdf``); a path without
    one gets ``.png``.  A file seapass did not write is replaced only with ``force``.
    """
    p = plot_path(os.fspath(path), force=force)
    assert p is not None
    (written,) = save_plot(draw, p, force=force, flag="--plot")
    return written
