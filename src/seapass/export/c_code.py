"""Generate dependency-free C99 (``seapass_ctrl.h`` / ``seapass_ctrl.c``) for a deployment.

[`export_c`][seapass.export.c_code.export_c] plans the deployment ([`plan_deployment`][seapass.export.deployment.plan_deployment]:
exact coefficients, certified envelope) and renders two Jinja2 templates shipped
with the package.  The generated code is deterministic (same design, same
bytes), uses no library call, and prints every number as a C99 hexadecimal
double literal, exact by the standard on every compiler, commented with the
exact rational it was rounded from.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from importlib import resources
from pathlib import Path
from typing import Any

import jinja2

from ..delay.latency import LatencyCheck
from ..errors import ParameterError
from ..files.owned import check_replaceable, write_output_text
from ..model.design_file import Design, load_design
from ..progress import ProgressLike, as_progress
from ..version import __version__
from .ctext import C_KEYWORDS, c_code, c_comment, c_identifier, c_number, c_string, finalize
from .deployment import Deployment, plan_deployment
from .latency import latency_banner, latency_guard
from .realization import FilterSpec
from .robust_envelope import DEFAULT_ENVELOPE_BUDGET

__all__ = [
    "C_KEYWORDS",
    "CLiteral",
    "ExportResult",
    "c_literal",
    "check_c_names",
    "export_c",
    "render_c",
]

HEADER = "seapass_ctrl.h"
SOURCE = "seapass_ctrl.c"

_INPUTS = {
    "error_A": ("e_A", "theta_A - x_A", "C_A error input"),
    "measurement_A": ("m_A", "-x_A", "C_A measurement input (derivatives act on -x_A only)"),
    "error_L": ("e_L", "theta_L - x_L", "C_L error input"),
    "measurement_L": ("m_L", "-x_L", "C_L measurement input (derivatives act on -x_L only)"),
}


@dataclass(frozen=True)
class CLiteral:
    """A double as C source: exact hex and shortest round-trip decimal, and its exact origin.

    ``literal`` (C99 hexadecimal floating constant) is exact by the standard and is
    what the ``.c`` file uses; ``decimal`` (Python's shortest repr, valid C and
    C++) is what the header's macros use, so C++ (Arduino) code can include it.
    """

    literal: str
    decimal: str
    comment: str


def c_literal(value: Fraction | float | int) -> CLiteral:
    """The double nearest ``value`` as C literals, commented with the exact value.

    >>> c_literal(Fraction(1, 500))
    CLiteral(literal='0x1.0624dd2f1a9fcp-9', decimal='0.002', comment='1/500 rounded to 0.002')
    >>> c_literal(300).literal, c_literal(300).comment
    ('0x1.2cp+8', '300 exactly')
    """
    exact = Fraction(value)
    d = float(exact)
    mant, _, exp = d.hex().partition("p")
    if "." in mant:
        mant = mant.rstrip("0").rstrip(".")
    shown = str(exact)
    if Fraction(d) == exact:
        comment = f"{shown} exactly" if exact.denominator == 1 else f"{shown} = {d!r} exactly"
    else:
        comment = f"{shown} rounded to {d!r}"
    return CLiteral(f"{mant}p{exp}", repr(d), comment)


@dataclass(frozen=True, kw_only=True)
class ExportResult:
    """What [`export_c`][seapass.export.c_code.export_c] wrote.

    Attributes
    ----------
    header, source : Path
        ``seapass_ctrl.h`` and ``seapass_ctrl.c``.
    deployment : Deployment
        The controller and envelope they implement.
    latency : LatencyCheck or None
        ``τ*`` against the loop latency ([`latency_guard`][seapass.export.latency.latency_guard]);
        None without a stated latency.
    """

    header: Path
    source: Path
    deployment: Deployment
    latency: LatencyCheck | None = None


def _environment() -> jinja2.Environment:
    folder = resources.files(__package__).joinpath("templates")

    def load(name: str) -> str:
        return folder.joinpath(name).read_text(encoding="utf-8")

    env = jinja2.Environment(
        loader=jinja2.FunctionLoader(load),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,  # C source, not HTML: seapass.export.ctext escapes instead
        finalize=finalize,  # every printed value went through one of the filters below
    )
    env.filters.update(
        c_comment=c_comment, c_string=c_string, c_identifier=c_identifier, c_number=c_number
    )
    return env


def _formula(f: FilterSpec) -> list[str]:
    den = " + ".join(["1"] + [f"a{i} z^-{i}" for i in range(1, f.order + 1)])
    lines = []
    for j, sig in enumerate(f.inputs):
        terms = " + ".join(f"b{j},{i} z^-{i}" if i else f"b{j},0" for i in range(f.order + 1))
        lines.append(f"{_INPUTS[sig][0]}: ({terms}) / ({den})")
    return lines


def _filters(dep: Deployment) -> list[dict[str, Any]]:
    out, offset = [], 0
    for i, f in enumerate(dep.filters):
        n = f.order + 1
        paths = ", ".join(f"C_{s[-1]} {s[:-2]} ({_INPUTS[s][1]})" for s in f.inputs)
        title = f"one difference equation of {paths} over their common denominator"
        if f.gain is not None:
            title += f", output times gain {f.gain}"
        elif dep.set_gains:
            title += " (the part without tunable gains)"
        out.append(
            {
                "index": i,
                "title": title,
                "formula": _formula(f),
                "order": f.order,
                "offset": offset,
                "n": n,
                "k": len(f.inputs),
                "b": [[c_literal(c) for c in num] for num in f.realization.numerators],
                "a": [c_literal(c) for c in f.realization.denominator],
                "inputs": [_INPUTS[sig][0] for sig in f.inputs],
                "gain_expr": None
                if f.gain is None
                else c_code(f"s->gains.{c_identifier(f.gain, 'gain name')}"),
            }
        )
        offset += f.order
    return out


def _banner(dep: Deployment) -> list[str]:
    d = dep.design
    sea = d.sea()
    T = dep.period
    lines = [f"Design: {d.name}" + (f" -- {d.title}" if d.title else "")]
    lines += [
        f"  {k} = {text}"
        for k, text in (("D1", d.D1), ("D2", d.D2), ("CA", d.CA), ("CL", d.CL))
        if getattr(sea, k) != 0
    ]
    lines.append("  parameters: " + ", ".join(f"{k} = {v!r}" for k, v in sorted(d.values.items())))
    lines += [
        "",
        "Controller (seapass.sampled.controllers.DiscreteController, run exactly):",
        "  u = C_A(s)[theta_A - x_A] + C_L(s)[theta_L - x_L], with the constant and",
        f"  strictly proper parts on the error (strictly proper parts by {d.loop.method if d.loop else 'tustin'}) and",
        "  the derivative terms on the measurement only (backward difference",
        "  (1 - z^-1)/T through the low-pass (1 - a)/(1 - a z^-1)), all paths over one",
        "  common denominator (a pole C_A and C_L share is one state), then saturated",
        f"  to +-{dep.force_limit!r} N and delayed {dep.code_delay} sample(s) in this code.",
        f"  T = {T} s ({float(1 / T):g} Hz); a = {dep.velocity_pole}"
        + (
            f" (cutoff {dep.velocity_filter!r} Hz)"
            if dep.velocity_filter
            else " (no velocity filter)"
        ),
        "",
    ]
    if dep.certified:
        lines += [
            "Passivity envelope (certified by seapass at export time):",
            f"  sampled-data passive at T = {T} s, delay {dep.delay} sample(s)"
            f" ({dep.code_delay} in this code + {dep.hardware_delay} on the platform),",
            "  velocity filter "
            + (f"{dep.velocity_filter!r} Hz" if dep.velocity_filter else "none")
            + f": {dep.verdict}",
        ]
    else:
        lines += [
            "*** NOT CERTIFIED: this design FAILED seapass's sampled-data passivity check ***",
            f"  ({dep.verdict}); it was exported on explicit request (allow_nonpassive).",
        ]
    for g in dep.gains:
        if g.tunable and g.search is not None:
            lo, hi = g.exact
            lines.append(
                f"  {g.name} = {g.nominal!r}, tunable in [{lo}, {hi}]"
                f" (searched [{g.search[0]!r}, {g.search[1]!r}])"
            )
        else:
            lines.append(f"  {g.name} = {g.nominal!r}" + (" (fixed)" if dep.set_gains else ""))
    if dep.set_gains:
        lines += [
            "  Certified set for seapass_ctrl_set_gains: one tunable gain at a time inside",
            "  its interval, every other gain at its certified value (the per-gain",
            "  intervals prove nothing about moving two gains together).",
        ]
    lines += [f"  note: {n}" for n in dep.notes]
    if dep.robust is not None:
        lines += ["", *dep.robust.banner()]
    return lines


def check_c_names(design: Design) -> None:
    """Refuse gain names that cannot be C identifiers of the generated API.

    See [`c_identifier`][seapass.export.ctext.c_identifier]: C and C++ keywords,
    reserved names, macros of the included headers and the ``seapass_`` prefix.
    """
    for g in design.gains:
        c_identifier(g, "gain name")


def render_c(dep: Deployment, latency: LatencyCheck | None = None) -> dict[str, str]:
    """The two files for ``dep`` as ``{file name: text}`` (``latency``: `latency_guard`'s)."""
    check_c_names(dep.design)
    filters = _filters(dep)
    used = {sig for f in dep.filters for sig in f.inputs}
    signals = [
        {"var": _INPUTS[s][0], "expr": c_code(_INPUTS[s][1]), "comment": _INPUTS[s][2]}
        for s in ("error_A", "measurement_A", "error_L", "measurement_L")
        if s in used
    ]
    unused = [p for p, s in (("theta_A", "error_A"), ("theta_L", "error_L")) if s not in used]
    n_states = sum(f.order for f in dep.filters)
    vf = dep.velocity_filter
    ctx = {
        "name": dep.design.name,
        "version": __version__,
        "banner": _banner(dep) + latency_banner(latency),
        "period": c_literal(dep.period),
        "rate": c_literal(1 / dep.period),
        "delay": dep.delay,
        "code_delay": dep.code_delay,
        "velocity_filter": c_literal(Fraction(vf) if vf else 0),
        "force_limit": c_literal(dep.force_limit),
        "certified": dep.certified,
        "robust": None if dep.robust is None else dep.robust.certified,
        "set_gains": dep.set_gains,
        "gains": [
            {
                "name": g.name,
                "tunable": dep.set_gains and g.tunable,
                "nominal": c_literal(g.nominal),
                "low": c_literal(g.low),
                "high": c_literal(g.high),
            }
            for g in dep.gains
        ],
        "filters": filters,
        "signals": signals,
        "unused": unused,
        "n_states": n_states,
        "n_tunable": sum(1 for g in dep.gains if dep.set_gains and g.tunable),
        "n_states_alloc": max(n_states, 1),
    }
    env = _environment()
    return {
        HEADER: env.get_template(f"{HEADER}.j2").render(ctx),
        SOURCE: env.get_template(f"{SOURCE}.j2").render(ctx),
    }


def export_c(
    design: Design | str | os.PathLike[str],
    out: str | os.PathLike[str],
    *,
    force_limit: float | None = None,
    hardware_delay: int = 0,
    set_gains: bool = False,
    tunable: Sequence[str] | None = None,
    allow_nonpassive: bool = False,
    rtol: float = 1e-6,
    progress: ProgressLike = None,
    force: bool = False,
    latency: float | None = None,
    robust: bool = False,
    robust_budget: int = DEFAULT_ENVELOPE_BUDGET,
    robust_fallback: str | None = None,
) -> ExportResult:
    """Write ``seapass_ctrl.h`` and ``seapass_ctrl.c`` for the deployed controller of ``design``.

    The files hold the controller's difference equations (actuator and load
    side, velocity filter), the force saturation, the delay line and the
    passivity envelope: the certified period (``init`` refuses another), delay,
    filter and gains, and with ``set_gains=True`` a guarded
    ``seapass_ctrl_set_gains`` that refuses gains outside the certified set.
    See ``docs/deploy.md`` for the generated API.

    Parameters
    ----------
    design : Design or path-like
        The design (or its TOML file); it needs a ``[control] rate``.
    out : path-like
        Directory to write into (created if missing).  Existing files of these
        names are replaced only if seapass wrote them and they are unchanged
        ([`seapass.files.owned`][seapass.files.owned]), or with ``force``.
    force_limit, hardware_delay, set_gains, tunable, allow_nonpassive, rtol, progress
        See [`plan_deployment`][seapass.export.deployment.plan_deployment].
    robust, robust_budget, robust_fallback
        See [`plan_deployment`][seapass.export.deployment.plan_deployment].
    force : bool
        Replace existing files of these names even if seapass did not write them.
    latency : float, optional
        The loop latency [s], replacing ``[control] delay_time``: ``τ*`` must cover it
        ([`latency_guard`][seapass.export.latency.latency_guard]); the header records both.

    Returns
    -------
    ExportResult

    Raises
    ------
    ParameterError, FileFormatError
        For a design or option the export cannot honour.
    OutputPathError
        When ``out`` holds a file of these names that seapass did not write.
    NotPassiveError
        When the design is not passive at its sampled rate, or ``τ*`` does not cover the
        loop latency (unless ``allow_nonpassive``).
    """
    if not isinstance(design, Design):
        design = load_design(design)
    folder = Path(out)
    if folder.exists() and not folder.is_dir():
        raise ParameterError(f"out: {folder} is a file; give a directory")
    targets = [folder / HEADER, folder / SOURCE]
    check_c_names(design)
    for t in targets:  # before the (slow) certification
        check_replaceable(t, force=force)
    lag = latency_guard(design, latency, allow_nonpassive=allow_nonpassive)
    dep = plan_deployment(
        design,
        force_limit=force_limit,
        hardware_delay=hardware_delay,
        set_gains=set_gains,
        tunable=tunable,
        allow_nonpassive=allow_nonpassive,
        rtol=rtol,
        progress=as_progress(progress, where="export_c"),
        robust=robust,
        robust_budget=robust_budget,
        robust_fallback=robust_fallback,
    )
    files = render_c(dep, lag)
    for t in targets:
        check_replaceable(t, force=force)
    for t in targets:
        write_output_text(t, files[t.name], force=force)
    return ExportResult(header=targets[0], source=targets[1], deployment=dep, latency=lag)
