"""``seapass response``: frequency response of the rendered stiffness ``|F_L/X_L(jω)|``."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from ..analysis.freqresp import stiffness_response
from ..errors import ParameterError
from .cmd_bound import parse_range
from .common import add_model_options, model_from_args, print_json, save_plot

EXAMPLE = """example:
  seapass response --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1005 \\
      --set b1=20 --set bd=25 --set kd=1000 --out stiffness.png
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "response",
        help="rendered stiffness |F_L/X_L(jw)| of a design, with a plot",
        description="Evaluate the first-principles F_L/X_L on the imaginary axis.",
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_model_options(p)
    p.add_argument("--omega", default="0.1:1e4", help="frequency range LO:HI in rad/s (log-spaced)")
    p.add_argument("--points", type=int, default=400, help="number of frequencies (default 400)")
    p.add_argument("--out", help="write the figure (PNG/PDF/SVG by extension)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    lo, hi = parse_range(args.omega)
    if lo <= 0:
        raise ParameterError("--omega: the lower frequency must be positive for a log scale")
    if not 2 <= args.points <= 100_000:
        raise ParameterError(f"--points {args.points}: use between 2 and 100000")
    sea = model_from_args(args)
    resp = stiffness_response(sea, np.logspace(np.log10(lo), np.log10(hi), args.points))
    if args.out:
        from ..plot.response import plot_stiffness_response

        k1 = sea.values.get("k1")
        save_plot(
            lambda: plot_stiffness_response(resp, title="rendered stiffness", reference=k1),
            args.out if Path(args.out).suffix else f"{args.out}.png",
        )
    if args.json:
        print_json(resp.to_dict())
    elif not args.out:
        print(f"static stiffness F_L/X_L(0) = {resp.static:.6g} N/m")
        print(f"high-frequency stiffness    = {resp.high_frequency:.6g} N/m")
        i = int(np.argmax(resp.magnitude))
        print(f"peak |F_L/X_L| = {resp.magnitude[i]:.6g} N/m at w = {resp.omega[i]:.6g} rad/s")
    return 0
