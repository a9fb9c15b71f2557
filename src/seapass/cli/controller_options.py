"""The controller-block and plant options of every model command.

Wherever ``--CA``/``--CL`` are accepted, a controller may be given as blocks
instead (the ``[controller]`` table of a design file), compiled exactly into
``C_A`` and ``C_L`` by [`derive_controller`][seapass.model.controller.derive_controller]::

    --controller impedance --force-loop "kp + ki/s" --impedance "kv + bv*s" \\
        --damping-injection ba --feedforward

``--plant NAME=VALUE`` gives a hardware parameter (fixed, never a default tuning
gain), like ``--set`` otherwise.  The flags ``--force-loop``, ``--velocity-loop``
and ``--damping-injection`` are the file's ``force``, ``velocity`` and ``damping``
(``--force`` and ``--damping`` mean other things on some commands).
"""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import ParameterError, SeapassError

__all__ = [
    "CONVENTION",
    "FLAGS",
    "add_controller_options",
    "controller_from_args",
    "controller_given",
    "derivation_from_args",
    "elements_from_args",
    "flag_words",
    "model_given",
    "plant_from_args",
]

CONVENTION = (
    "sign convention: f_A = CA*(theta - x_A) + CL*(theta - x_L); positions and the actuator "
    "force positive in one direction, theta the reference, positive gains restoring"
)
"""The C_A/C_L convention, said in ``--help`` of the model options."""

FLAGS = {
    "kind": "--controller",
    "force": "--force-loop",
    "impedance": "--impedance",
    "velocity": "--velocity-loop",
    "damping": "--damping-injection",
    "sensor": "--sensor",
    "feedforward": "--feedforward",
}
"""The flag of each argument of [`Controller`][seapass.model.controller.Controller]."""

_KINDS = ("force", "impedance", "velocity-sourced")


def add_controller_options(p: argparse.ArgumentParser) -> None:
    """``--controller KIND`` and its blocks, and ``--plant NAME=VALUE``, in their own group."""
    g = p.add_argument_group("controller as blocks (instead of --CA/--CL; see docs/controllers.md)")
    g.add_argument(
        "--controller",
        choices=_KINDS,
        metavar="KIND",
        help="force | impedance | velocity-sourced: compile the blocks below into CA and CL",
    )
    g.add_argument(
        "--force-loop",
        metavar="EXPR",
        help="force-loop compensator C_f on the measured force, e.g. 'kp + ki/s' "
        "(proper: filter a derivative)",
    )
    g.add_argument(
        "--impedance", metavar="EXPR", help="target impedance of the outer loop, e.g. 'kv + bv*s'"
    )
    g.add_argument(
        "--velocity-loop",
        metavar="EXPR",
        help="motor-velocity loop (velocity-sourced), e.g. 'kvp + kvi/s'",
    )
    g.add_argument(
        "--damping-injection",
        metavar="EXPR",
        help="damping injected on the actuator velocity, e.g. 'ba'",
    )
    g.add_argument(
        "--feedforward",
        action="store_true",
        help="force feed-forward: also apply the force reference directly",
    )
    g.add_argument(
        "--sensor",
        metavar="EXPR",
        help="measured force per unit deflection x_A - x_L (default: k1; a load "
        "cell: the transmission, e.g. 'k1 + b1*s')",
    )
    g.add_argument(
        "--plant",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a hardware parameter and its value, repeatable: fixed, never a "
        "default tuning gain (m b k1 k2 b1 b2 and the parameters of D1, D2 are "
        "plant parameters already)",
    )


def controller_given(args: argparse.Namespace) -> bool:
    """Whether any controller-block flag was given."""
    names = ("controller", "force_loop", "impedance", "velocity_loop", "damping_injection",
             "sensor", "feedforward")  # fmt: skip
    return any(getattr(args, n, None) not in (None, False) for n in names)


def model_given(args: argparse.Namespace) -> bool:
    """Whether a model was given on the command line (elements, controller blocks, plant)."""
    elements = any(getattr(args, e) not in (None, "0") for e in ("D1", "D2", "CA", "CL"))
    return elements or controller_given(args) or bool(getattr(args, "plant", []))


def controller_from_args(args: argparse.Namespace) -> Any:
    """The [`Controller`][seapass.model.controller.Controller] of the flags, or None.

    Raises
    ------
    ParameterError
        A block flag without ``--controller``, ``--controller`` together with
        ``--CA``/``--CL``, or what the controller itself refuses, naming the flag.
    """
    from ..model.controller import Controller

    if not controller_given(args):
        return None
    if args.controller is None:
        raise ParameterError(
            "the controller blocks need --controller KIND (force, impedance or velocity-sourced)"
        )
    raw = [f"--{e}" for e in ("CA", "CL") if getattr(args, e) not in (None, "0")]
    if raw:
        raise ParameterError(
            f"give either --controller with its blocks or {' and '.join(raw)}, not both: the "
            "blocks are compiled into CA and CL"
        )
    blocks = {
        "force": args.force_loop,
        "impedance": args.impedance,
        "velocity": args.velocity_loop,
        "damping": args.damping_injection,
    }
    kw: dict[str, Any] = {k: v for k, v in blocks.items() if v is not None}
    if args.sensor is not None:
        kw["sensor"] = args.sensor
    try:
        return Controller(kind=args.controller, feedforward=args.feedforward, **kw)
    except SeapassError as exc:
        raise ParameterError(flag_words(exc)) from None


def flag_words(exc: SeapassError) -> str:
    """A `Controller` error naming its flag: ``--force-loop: ...`` for ``force: ...``."""
    msg, arg = str(exc), exc.argument or ""
    if arg in FLAGS and msg.startswith(f"{arg}: "):
        msg = f"{FLAGS[arg]}: {msg[len(arg) + 2 :]}"
    return msg


def plant_from_args(args: argparse.Namespace) -> dict[str, float]:
    """The ``--plant NAME=VALUE`` values; a name given twice is an error."""
    from ..model.expr import parse_assignment

    out: dict[str, float] = {}
    for item in getattr(args, "plant", []):
        name, val = parse_assignment(item)
        if name in out:
            raise ParameterError(f"--plant {name} is given twice; give each name once")
        out[name] = val
    return out


def elements_from_args(args: argparse.Namespace, names: Any) -> tuple[str, str]:
    """``(CA, CL)``: the raw flags, or the controller blocks compiled with ``names`` allowed."""
    d = derivation_from_args(args, names)
    return (args.CA, args.CL) if d is None else (d.CA, d.CL)


def derivation_from_args(args: argparse.Namespace, names: Any) -> Any:
    """The [`ControllerDerivation`][seapass.model.controller.ControllerDerivation] of the
    flags, or None without controller blocks."""
    from ..model.controller import derive_controller

    controller = controller_from_args(args)
    if controller is None:
        return None
    try:
        return derive_controller(controller, parameters=names)
    except SeapassError as exc:
        raise ParameterError(flag_words(exc)) from None
