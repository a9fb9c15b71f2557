"""The controller-block and plant options of every model command.

Wherever ``--CA``/``--CL`` are accepted, a controller may be given as blocks
instead (the ``[controller]`` table of a design file), compiled exactly into
``C_A`` and ``C_L`` by [`derive_controller`][seapass.model.controller.derive_controller]::

    --controller impedance --force-loop "kp + ki/s" --impedance "kv + bv*s" \\
        --damping-injection ba --feedforward

A controller that already runs on a microcontroller is given in ``z`` instead (the
``[discrete]`` table of a design file, run as is; see
[`ZController`][seapass.model.zcontroller.ZController])::

    --CA-z "(b0 + b1*z^-1)/(1 + a1*z^-1)" --CL-z "kl" --rate 1000

``--rate`` is the controller's rate in Hz (default: ``--period``'s, else the design
file's ``[control]``/``[discrete]`` rate).

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
    "discrete_from_args",
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
    z = p.add_argument_group("controller in z (instead of --CA/--CL; run as is at its rate)")
    z.add_argument(
        "--CA-z",
        metavar="EXPR",
        help="actuator-side controller K_A(z), e.g. "
        "'(b0 + b1*z^-1)/(1 + a1*z^-1)' (causal; z^-1 is one sample of delay)",
    )
    z.add_argument("--CL-z", metavar="EXPR", help="load-side controller K_L(z), e.g. 'kl'")
    z.add_argument("--rate", type=float, metavar="HZ", help="the z-controller's rate in Hz "
                   "(default: from --period, else the design file's)")  # fmt: skip
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
    zflags = any(getattr(args, e, None) is not None for e in ("CA_z", "CL_z"))
    return elements or controller_given(args) or zflags or bool(getattr(args, "plant", []))


def discrete_from_args(args: argparse.Namespace, design: Any = None) -> Any:
    """The [`ZController`][seapass.model.zcontroller.ZController] of ``--CA-z --CL-z
    --rate``, or None without ``--CA-z``/``--CL-z``.

    The rate: ``--rate``, else ``1/--period``, else ``design``'s controller in z or loop.

    Raises
    ------
    ParameterError
        ``--rate`` alone, a z-controller with ``--CA``/``--CL`` or controller blocks,
        no rate anywhere, or what the controller refuses, naming the flag.
    """
    from ..model.zcontroller import ZController

    ca, cl = getattr(args, "CA_z", None), getattr(args, "CL_z", None)
    rate = getattr(args, "rate", None)
    if ca is None and cl is None:
        if rate is not None:
            raise ParameterError("--rate is the rate of a controller in z: give --CA-z/--CL-z")
        return None
    if controller_given(args) or any(getattr(args, e) not in (None, "0") for e in ("CA", "CL")):
        raise ParameterError(
            "give the controller either in s (--CA/--CL or --controller) or in z "
            "(--CA-z/--CL-z), not both"
        )
    if rate is None and getattr(args, "period", None) is not None:
        rate = 1.0 / float(args.period)
    if rate is None and design is not None:
        rate = design.discrete.rate if design.discrete is not None else design.control_rate
    if rate is None:
        raise ParameterError("a controller in z needs its rate: give --rate HZ (e.g. --rate 1000)")
    try:
        return ZController(CA=ca or "0", CL=cl or "0", rate=rate)
    except SeapassError as exc:
        msg = str(exc)
        for side in ("CA", "CL"):
            msg = msg.replace(f"{side}_z: ", f"--{side}-z: ")
        raise ParameterError(msg.replace("rate: ", "--rate: ", 1)) from None


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
