"""``seapass plot bode|real|nyquist``: passivity in the frequency domain, as a figure.

``bode`` is the rendered stiffness ``F_L/X_L(jω)`` with its phase, ``real`` is
``Re Z(jω)`` with the bands where it is negative shaded, ``nyquist`` is the
Nyquist plot of ``Z``.  The bands are decided exactly (real roots of the
real-part polynomial), never read off the plotted grid.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from ..errors import ParameterError
from .common import (
    add_force_option,
    add_model_options,
    parse_range,
    plot_path,
    print_json,
    write_figure,
)
from .design_options import add_design_argument, system_from_design_args

if TYPE_CHECKING:  # the CLI starts fast: heavy modules load when a command runs
    import numpy as np

    from ..analysis.portresponse import ImpedanceResponse

EXAMPLE = """examples:
  seapass plot bode examples/ours.toml --plot bode.png
  seapass plot real --D1 k1 --CL "kd + bd*s" --set m=1 --set b=10 --set k1=1000 \\
      --set kd=500 --set bd=20 --plot real.png
  seapass plot nyquist --Z "(s - 1)/(s + 2)" --plot nyquist.svg
  seapass plot bode --D1 "k1 + b1*s" --CA "kd + bd*s" --set m=1 --set b=10 --set k1=1005 \\
      --set b1=30 --set kd=1000 --set bd=25 --omega 1:1e4 --plot bode.pdf
  seapass plot real --D1 "k1 + b1*s" --CA "(kd + bd*s)*exp(-tau*s)" --set m=1 --set b=10 \\
      --set k1=1000 --set b1=20 --set kd=3500 --set bd=25 --set tau=0.01 --plot real.png

With a delay exp(-NAME*s) (NAME given with --set, seconds): real and nyquist at that
delay; the shaded bands are proven Re Z < 0 by ball arithmetic (undecided ones grey),
never read off the curve.
"""

KINDS = {
    "bode": "rendered stiffness F_L/X_L(jw): magnitude and phase",
    "real": "Re Z(jw) against w, the bands where it is negative shaded (exact)",
    "nyquist": "Nyquist plot of the port impedance Z(jw)",
}


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg,unused-ignore]
    p = sub.add_parser(
        "plot",
        help="passivity plots: Bode of F_L/X_L, Re Z(jw) with failing bands, Nyquist of Z",
        description="Draw a design's port in the frequency domain. The bands where "
        "Re Z(jw) < 0 come from the exact analysis (the real roots of the real-part "
        "polynomial, isolated exactly), never from the plotted grid. Prints a summary; "
        "--plot FILE writes the figure (.png, .svg or .pdf).",
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "kind", choices=list(KINDS), help="; ".join(f"{k}: {v}" for k, v in KINDS.items())
    )
    add_design_argument(p)
    add_model_options(p)
    p.add_argument("--Z", help="raw impedance Z(s) instead of an SEA model, e.g. '(s + 1)/(s + 2)'")
    p.add_argument(
        "--omega",
        metavar="LO:HI",
        help="frequency range in rad/s, log-spaced (default: two decades around the poles, "
        "zeros and bands)",
    )
    p.add_argument("--points", type=int, default=600, help="number of frequencies (default: 600)")
    p.add_argument("--title", default="", help="figure title (default: the verdict)")
    p.add_argument(
        "--plot", metavar="FILE", help="write the figure; .png, .svg or .pdf (default .png)"
    )
    p.add_argument("--json", action="store_true", help="print the curve and the bands as JSON")
    add_force_option(p)
    p.set_defaults(func=run, allow_delay=True)


def _frequencies(text: str | None, points: int) -> np.ndarray | None:
    from ..analysis.freqresp import check_points, log_frequencies

    if text is None:
        check_points(points)
        return None
    return log_frequencies(*parse_range(text, "--omega"), points)


def run(args: argparse.Namespace) -> int:
    from ..analysis.freqresp import stiffness_response
    from ..analysis.portresponse import impedance_response
    from ..model.sea import SEA

    plot_path(args.plot, force=args.force)  # before the work
    system, _ = system_from_design_args(args)
    grid = _frequencies(args.omega, args.points)
    from ..delay.structure import has_model_delay

    if has_model_delay(system):  # certified bands at the delay: seapass.delay.response
        return _run_delayed(args, system, grid)
    label = "Z" if args.Z is not None else "Z_L"
    resp = impedance_response(system, grid, points=args.points)
    if args.kind == "bode":
        fr = stiffness_response(system, resp.omega, label="")
        if args.plot:
            k1 = system.values.get("k1") if isinstance(system, SEA) else None
            write_figure(
                lambda: fr.plot(title=args.title, reference=k1, bands=resp.negative_bands),
                args.plot,
                force=args.force,
            )
        if args.json:
            print_json({**fr.to_dict(), "negative_real_bands": _bands(resp)})
        else:
            _print_bode(fr, resp)
        return 0
    if args.plot:
        write_figure(lambda: resp.plot(args.kind, title=args.title), args.plot, force=args.force)
    if args.json:
        print_json(resp.to_dict())
    else:
        _print_bands(resp, label)
    return 0


def _run_delayed(args: argparse.Namespace, system: Any, grid: Any) -> int:
    from ..delay.passivity import delayed_passivity

    if args.kind == "bode":
        raise ParameterError("plot bode: not for a design with a delay; use real or nyquist")
    resp = delayed_passivity(system).response(grid)
    if args.plot:
        write_figure(lambda: resp.plot(args.kind, title=args.title), args.plot, force=args.force)
    if args.json:
        print_json(resp.to_dict())
        return 0
    text = ", ".join(f"({a:.6g}, {b:.6g})" for a, b in resp.negative_bands)
    print(f"Re Z(jw) < 0 for w in {text} rad/s (proven)" if text else
          "no band with Re Z(jw) < 0 proven on the curve's range")  # fmt: skip
    for a, b in resp.undecided_bands:  # a band end is known to 2^-40 (relative) or better
        if b - a > 1e-9 * b:
            print(f"undecided for w in ({a:.6g}, {b:.6g}) rad/s")
    return 0


def _bands(resp: ImpedanceResponse) -> list[list[float]]:
    return [[a, b] for a, b in resp.negative_bands]


def _print_bands(resp: ImpedanceResponse, label: str) -> None:
    if resp.negative_bands:
        text = ", ".join(f"({a:.6g}, {b:.6g})" for a, b in resp.negative_bands)
        print(f"Re {label}(jw) < 0 for w in {text} rad/s (exact)")
    else:
        print(f"Re {label}(jw) >= 0 at every frequency (exact; `seapass check` tests the rest)")
    w = resp.omega
    print(f"curve: {w.size} frequencies from {w[0]:.4g} to {w[-1]:.4g} rad/s")


def _print_bode(fr: Any, resp: ImpedanceResponse) -> None:
    print(f"static stiffness F_L/X_L(0) = {fr.static:.6g} N/m")
    print(f"high-frequency stiffness    = {fr.high_frequency:.6g} N/m")
    print(fr.peak().describe())
    phase = fr.wrapped_phase
    print(f"phase from {phase.min():.4g} to {phase.max():.4g} deg, whole turns removed "
          "(passive: within 0..180)")  # fmt: skip
    _print_bands(resp, "Z")
