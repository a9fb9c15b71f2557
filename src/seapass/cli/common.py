"""Helpers shared by the subcommands: model options, ``--set`` parsing, JSON and atomic output."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from ..files.atomic import atomic_save, atomic_write, atomic_write_text
from ..model.expr import parse_assignment
from ..model.sea import SEA, Impedance

__all__ = [
    "add_model_options",
    "atomic_save",
    "atomic_write",
    "atomic_write_text",
    "json_text",
    "model_from_args",
    "print_json",
    "print_section_problems",
    "save_plot",
    "system_from_args",
    "values_from_args",
]


def add_model_options(p: argparse.ArgumentParser) -> None:
    """``--D1 --D2 --CA --CL --set`` as used by every model command."""
    g = p.add_argument_group("model (elements not given are 0)")
    g.add_argument("--D1", default="0", help="transmission, e.g. 'k1 + b1*s'")
    g.add_argument("--D2", default="0", help="load-to-ground element, e.g. 'k2'")
    g.add_argument("--CA", default="0", help="actuator-side controller, e.g. 'kd + bd*s'")
    g.add_argument("--CL", default="0", help="load-side controller, e.g. 'kd'")
    g.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="parameter value, repeatable, e.g. --set m=1 --set kd=5000",
    )


def values_from_args(args: argparse.Namespace) -> dict[str, float]:
    out: dict[str, float] = {}
    for item in args.set:
        name, val = parse_assignment(item)
        out[name] = val
    return out


def model_from_args(args: argparse.Namespace, extra_free: tuple[str, ...] = ()) -> SEA:
    values: dict[str, float | None] = dict(values_from_args(args))
    for name in extra_free:
        values.setdefault(name, None)
    return SEA(D1=args.D1, D2=args.D2, CA=args.CA, CL=args.CL, values=values)


def system_from_args(args: argparse.Namespace) -> SEA | Impedance:
    """The raw impedance given with ``--Z``, or else the SEA model of the element options."""
    if getattr(args, "Z", None) is None:
        return model_from_args(args)
    if any(getattr(args, e) != "0" for e in ("D1", "D2", "CA", "CL")):
        raise ValueError("give either --Z or the model elements --D1/--D2/--CA/--CL, not both")
    return Impedance(expr=args.Z, values=values_from_args(args))


def json_text(obj: Any) -> str:
    """Strict JSON text (non-finite floats become null), with a final newline."""
    return json.dumps(_clean(obj), indent=2, allow_nan=False) + "\n"


def _clean(obj: Any) -> Any:
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_clean(v) for v in obj]
    return obj


def print_json(obj: Any) -> None:
    """Print strict JSON (non-finite floats become null)."""
    sys.stdout.write(json_text(obj))


def save_plot(
    draw: Callable[[], Any], path: str | os.PathLike[str], *, formats: Sequence[str] | None = None
) -> list[Path]:
    """Draw a figure in the seapass style on a bare figure and save it atomically.

    ``draw()`` calls a [`seapass.plot`][seapass.plot] function without Axes and returns
    its Axes.  ``path`` with a suffix writes that format; without one, every
    format in ``formats`` (default PNG, SVG and PDF).
    """
    from ..plot.style import bare_figures, figure_style, save_figure

    with figure_style(), bare_figures():
        axes = draw()
        return save_figure(axes, path, formats=formats)


def print_section_problems(report: Any) -> None:
    """One stderr line naming the skipped sections of a report, one per failed section."""
    from ..report.document import SectionStatus

    skipped = [s.key for s in report.sections if s.status == SectionStatus.SKIPPED]
    if skipped:
        print(f"  skipped (reason in the report): {', '.join(skipped)}", file=sys.stderr)
    for s in report.sections:
        if s.status == SectionStatus.FAILED:
            print(f"  {s.key} FAILED: {s.text}", file=sys.stderr)
