"""Hostile and malformed input: never a traceback, never a hang, never code execution.

Every CLI run goes through :func:`seapass.cli.main` under a CPU budget
(``CPU_BUDGET_S`` seconds of CPU time per example, not wall-clock time: a busy
machine does not fail it, see ``cpu_budget``); the contract checked is: exit code 0 or
2, at most one line on stderr, no ``Traceback``.  Injection payloads try to
create a marker file; it must never appear.  The harness lives in ``tests/hostile.py``.

This file attacks the command line (`seapass.cli`); the hostile-input tests of other
targets sit with their module's tests: the parser in ``tests/model/test_expr_hostile.py``,
design and rig documents in ``tests/model/test_design_file_hostile.py`` and
``tests/rig/test_rigfile_paper.py``, garbage files in ``tests/files/test_hostile_files.py``,
interrupted writes in ``tests/files/test_atomic.py``.  Mutated design files through
``seapass analyze`` stay here (the command is the target).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cpu_budget import cpu_budget
from helpers import LP_ARGV, design_argv
from hostile import (  # noqa: F401 (no_marker)
    CPU_BUDGET_S,
    MARKER,
    design_doc,
    grammar,
    mutate,
    no_marker,
    payload_id,
    payloads,
    run_cli,
)
from seapass.cli import build_parser, main
from seapass.errors import SeapassError
from seapass.model.catalog import PAPER_VALUES
from seapass.model.sea import SEA, Impedance

pytestmark = pytest.mark.usefixtures("no_marker")  # no payload may create the marker file


def run_cli_fuzz(argv: list[str]) -> None:
    run_cli(argv)


# ---------------------------------------------------------------- injection


@pytest.mark.parametrize("text", payloads(), ids=payload_id)
def test_injection_through_models_and_cli_does_nothing(text):
    for build in (lambda: SEA(D1="k1", CA=text), lambda: Impedance(expr=text)):
        with contextlib.suppress(SeapassError):
            build()
    run_cli(["check", "--D1", "k1", "--CL", text, "--set", "m=1", "--set", "b=1"])
    run_cli(["check", "--Z", text])
    run_cli(["witness", "--Z", text])
    run_cli(["check", "--D1", "k1", "--set", f"{text}=1"])
    run_cli(["check", "--D1", "k1", "--set", f"k1={text}"])


# ---------------------------------------------------------------- CLI fuzz

ELEMENTS = [
    "0",
    "k1",
    "k1 + b1*s",
    "kd + bd*s",
    "kd + ki/s",
    "kd",
    "b2*s",
    "k2",
    "1/s",
    "s**12",
    "kd*s/(s + 1)",
    "",
    " ",
    "k1 +",
    "x",
    "s^2",
    "1/0",
    "-k1",
    "1e308*s",
    "k1*1e-300",
    "(k1 + b1*s)**-3",
]
NAMES = ["m", "b", "k1", "b1", "kd", "bd", "ki", "k2", "b2", "k", "s", "_x", "1a", "", "a b"]
NUMBERS = [
    "1",
    "0",
    "-1",
    "1e-6",
    "1e8",
    "2000",
    "nan",
    "inf",
    "-inf",
    "1e309",
    "abc",
    "",
    "4.9e-324",
]
GENERIC = [
    *NUMBERS,
    "0:1",
    "1:0",
    "0:0",
    "-1:5",
    "1:1e12",
    "1:nan",
    "a:b",
    "1:2:3",
    "k1",
    "kd",
    "/nonexistent/dir/f.png",
    "out.png",
    "out.xyz",
    "5",
    "100",
    "0.002",
]
MODEL_OPTS = {"--D1", "--D2", "--CA", "--CL", "--Z"}


def _subparsers(p: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for a in p._actions:
        if isinstance(a, argparse._SubParsersAction):
            return dict(a.choices)
    return {}


def _commands() -> dict[tuple[str, ...], argparse.ArgumentParser]:
    out: dict[tuple[str, ...], argparse.ArgumentParser] = {}
    for name, sp_ in _subparsers(build_parser()).items():
        inner = _subparsers(sp_)
        if inner:
            for n2, p2 in inner.items():
                out[(name, n2)] = p2
        else:
            out[(name,)] = sp_
    return out


COMMANDS = _commands()
# analysis commands are fast on any input; the others run long jobs on valid input
FAST = sorted(
    k
    for k in COMMANDS
    if k[0] in {"check", "bound", "region", "response", "plot", "witness"} or k[0] == "sampled"
)


@st.composite
def argvs(draw: st.DrawFn, commands: list[tuple[str, ...]]) -> list[str]:
    key = draw(st.sampled_from(commands))
    parser = COMMANDS[key]
    argv = list(key)
    for a in parser._actions:
        if a.dest == "help":
            continue
        if not a.option_strings:  # positional
            if a.choices:
                argv.append(draw(st.sampled_from([*map(str, a.choices), "bogus"])))
            else:
                argv.append(draw(st.sampled_from(NAMES + GENERIC)))
            continue
        if not draw(st.booleans()):
            continue
        opt = a.option_strings[-1]
        if a.nargs == 0:
            argv.append(opt)
        elif opt == "--set":
            for _ in range(draw(st.integers(1, 6))):
                argv += [opt, f"{draw(st.sampled_from(NAMES))}={draw(st.sampled_from(NUMBERS))}"]
        elif opt in MODEL_OPTS:
            argv += [opt, draw(st.one_of(st.sampled_from(ELEMENTS), grammar(2)))]
        elif a.choices:
            argv += [opt, draw(st.sampled_from([*map(str, a.choices), "bogus"]))]
        else:
            argv += [opt, draw(st.sampled_from(GENERIC))]
    if draw(st.booleans()):  # a plausible complete model makes deeper code paths reachable
        argv += ["--set", "m=1", "--set", "b=10", "--set", "k1=1000", "--set", "kd=500"]
    return argv


@settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(argv=argvs(FAST))
def test_cli_fuzz_analysis_commands(argv, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run_cli_fuzz(argv)


OURS = design_argv("ours", m=1, b=10, k1=1000, b1=20, bd=25, kd=5000)
LP = list(LP_ARGV)  # the paper's load-side P on its plant (tests/helpers.py)
UNIT_SETS = design_argv("LP", m=1, b=1, k1=1)[4:]  # --set m=1 --set b=1 --set k1=1
TEMPLATES = [
    ["check", *OURS, "--json"],
    ["check", "--Z", "(s + 1)/(s + 2)"],
    ["bound", "kd", *LP, "--range", "kd=0:5000", "--json"],
    [
        "region",
        "kd",
        "bd",
        *design_argv("APD", PAPER_VALUES),
        "--range",
        "kd=0:5000",
        "--range",
        "bd=0:50",
        "--points",
        "4",
        "--json",
    ],
    ["response", *OURS, "--omega", "0.1:1e4", "--points", "50", "--json"],
    ["witness", *LP, "--set", "kd=2000", "--json"],
    ["sampled", "check", "--period", "0.002", *OURS, "--json"],
    ["sampled", "bound", "kd", "--period", "0.002", *LP, "--range", "kd=0:5000", "--json"],
    ["simulate", *OURS, "--load-mass", "1", "--horizon", "0.5", "--json"],
]


@st.composite
def mutated_argvs(draw: st.DrawFn) -> list[str]:
    """A valid command line with one to three tokens replaced, dropped or added."""
    argv = list(draw(st.sampled_from(TEMPLATES)))
    for _ in range(draw(st.integers(1, 3))):
        values = [j for j in range(1, len(argv)) if not argv[j].startswith("--")]
        if not values:
            break
        i = draw(st.sampled_from(values))
        prev = argv[i - 1]
        action = draw(st.sampled_from(["replace"] * 6 + ["drop", "insert"]))
        if action == "drop":
            del argv[i]
        elif action == "insert":
            argv.insert(i, draw(st.sampled_from([*GENERIC, "--set", "--json", "--out", "-x"])))
        elif prev in MODEL_OPTS:
            argv[i] = draw(st.one_of(st.sampled_from(ELEMENTS + payloads()), grammar(2)))
        elif prev == "--set":
            name = draw(st.sampled_from([argv[i].split("=")[0], *NAMES]))
            argv[i] = f"{name}={draw(st.sampled_from(NUMBERS))}"
        else:
            argv[i] = draw(st.sampled_from(GENERIC + NAMES))
    return argv


@settings(
    max_examples=200,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(argv=mutated_argvs())
def test_cli_fuzz_mutated_valid_command_lines(argv, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run_cli_fuzz(argv)


SLOW_BAD = [
    ["figure", "bogus", "--out", "x"],
    ["figure", "sims", "--out", "x", "--horizon", "nan"],
    ["figure", "sims", "--out", "x", "--seed", "abc"],
    ["tables", "--format", "xml"],
    ["rig", "fit", "/nonexistent/log.csv", "--rig", "/nonexistent/rig.toml"],
    ["rig", "fit", "log.csv", "--rig", "rig.toml", "--window", "-3"],
    ["rig", "fit", "log.csv", "--rig", "rig.toml", "--confidence", "nan"],
    ["rig", "template", "--bogus"],
    ["reproduce", "--out", "x", "--stages", "bogus"],
    ["reproduce", "--out", "x", "--jobs", "-3", "--stages", "tables"],
    ["analyze", "/nonexistent/design.toml", "--out", "x"],
    ["export", "c", "/nonexistent/design.toml", "--out", "x"],
    ["export", "c", "/nonexistent/design.toml", "--out", "x", "--rtol", "-1"],
    ["export", "c", "/nonexistent/design.toml", "--out", "x", "--hardware-delay", "x"],
    ["export", "cpp", "design.toml", "--out", "x"],
    ["tune", "--design", "bogus"],
    ["tune", "--load-mass", "nan"],
    ["tune", "--set", "kd=1", "--bound", "kd=5:1"],
    ["tune", "--maxiter", "-5"],
    ["delay-margin", "tau", "ours", "--rtol", "nan"],
    ["delay-margin", "tau", "--Z", "exp(s)"],
    ["sweep", "--grid", "kd=abc"],
    ["sweep", "--range", "1:0"],
    ["sweep", "--sample", "-1"],
    ["simulate", *LP, "--set", "kd=500", "--horizon", "1e12", "--dt", "1e-9"],
    ["simulate", *LP, "--set", "kd=500", "--trajectory", "/nonexistent.csv"],
    ["simulate", *LP, "--set", "kd=500", "--dt", "0"],
    ["rig", "bogus"],
    ["rig", "show", "--rig", "/nonexistent.toml"],
    ["rig", "sweep", "--kd-step", "0"],
    ["rig", "sweep", "--kd-max", "nan"],
    ["rig", "impacts", "--rig", "/dev/null"],
    ["sampled", "check", "--period", "0", "--D1", "k1"],
    ["sampled", "check", "--period", "nan", "--D1", "k1"],
    ["region", "kd", "bd", *design_argv("APD", m=1, b=1, k1=1), "--points", "100000000"],
    ["response", "--D1", "k1", *UNIT_SETS, "--points", "10000000000"],
    ["twoport", "check", "--Z11", "1", "--Z12", "1/0", "--Z21", "0", "--Z22", "1"],
    ["twoport", "bound", "kl", "--D1", "k1", "--CL", "kl", *UNIT_SETS, "--range", "nan:1"],
    ["twoport", "friction", "--D1", "k1", "--set", "m=1", "--set", "b=1", "--set", "k1=inf"],
    ["mimo", "check", "--Z", "[[1, 2], [3, 4], [5, 6]]"],
    ["mimo", "bound", "c", "--Z", "[[c]]" * 1000, "--range", "0:1"],
    ["explore", "--port", "-1", "--no-browser"],
    ["explore", "--port", "abc"],
    ["explore", "/nonexistent/design.toml", "--no-browser"],
    ["explore", "--workers", "-2", "--no-browser"],
    ["nonexistent-command"],
    [],
]


@pytest.mark.parametrize("argv", SLOW_BAD, ids=lambda a: " ".join(a)[:60] or "empty")
def test_cli_hostile_options_of_every_command(argv, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = run_cli(argv)
    assert code == 2 and err.startswith("error:")


EXTREME_VALID = [
    # far outside the documented span: the verdicts stay exact, the evidence may be nan
    ["witness", *design_argv("LP", m="4.9e-324", b=10, k1=1000, kd=2000), "--json"],
    ["witness", *design_argv("LP", m="1e300", b="1e300", k1="1e300", kd="2e300"), "--out", "w"],
    ["witness", *design_argv("LP", m="1e-300", b="1e300", k1="4.9e-324", kd=1)],
    ["bound", "kd", *design_argv("LP", m=1, b=1, k1=1), "--range", "0:1e308"],
    ["check", "--D1", "k1", "--set", "m=1e-300", "--set", "b=1e300", "--set", "k1=4.9e-324"],
    ["witness", *design_argv("LP", m="1e-6", b="1e8", k1="1e8", kd="1.0000001e8")],
    ["check", "--D1", "k1", "--set", "m=1", "--set", "b=1", "--set", "k1=1", "--json", "--json"],
]


@pytest.mark.parametrize("argv", EXTREME_VALID, ids=lambda a: " ".join(a)[:60])
def test_cli_extreme_but_valid_values_answer(argv, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run_cli(argv)


# once ZeroDivisionError, mpmath NoConvergence and OverflowError tracebacks; now range errors
SAMPLED_CRASHES = [
    ["--set", "k1=4.9e-324", "--period", "0.002"],
    ["--set", "m=4.9e-324", "--set", "k1=1000", "--period", "0.002"],
    ["--set", "k1=1000", "--period", "4.9e-324"],
]


@pytest.mark.parametrize("extra", SAMPLED_CRASHES, ids=["k1-denormal", "m-denormal", "T-denormal"])
def test_sampled_check_extreme_values_answer_in_one_line(extra, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    base = ["sampled", "check", *design_argv("ours", m=1, b=10, b1=20, bd=25, kd=5000)]
    run_cli(base + extra)


def test_every_subcommand_is_covered_by_a_hostile_case():
    covered = {tuple(a[:1]) for a in SLOW_BAD if a} | {k[:1] for k in FAST}
    assert {k[:1] for k in COMMANDS} <= covered


# ---------------------------------------------------------------- design files through analyze


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return (
            "nan"
            if math.isnan(v)
            else ("inf" if v == math.inf else "-inf" if v == -math.inf else repr(v))
        )
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return _toml_key(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def _toml_key(k: str) -> str:
    """A TOML basic string: escapes for quote, backslash and every non-printable character."""
    out = []
    for ch in k:
        if 0xD800 <= ord(ch) <= 0xDFFF:
            raise TypeError("surrogates cannot be written to TOML")
        if ch in '"\\':
            out.append("\\" + ch)
        elif ch.isprintable() and ch != "\x7f":
            out.append(ch)
        else:
            out.append(f"\\u{ord(ch):04x}" if ord(ch) <= 0xFFFF else f"\\U{ord(ch):08x}")
    return '"' + "".join(out) + '"'


def _dump(doc: dict) -> str:
    top = [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in doc.items() if not isinstance(v, dict)]
    tables = [
        f"[{_toml_key(k)}]\n"
        + "\n".join(f"{_toml_key(a)} = {_toml_value(b)}" for a, b in v.items())
        for k, v in doc.items()
        if isinstance(v, dict)
    ]
    return "\n".join(top) + "\n" + "\n\n".join(tables) + "\n"


@settings(
    max_examples=20,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(data=st.data())
def test_mutated_design_files_through_analyze(data, tmp_path):
    """``seapass analyze FILE --stages core``: 0/1 on a loadable design, else one error line."""
    pytest.importorskip("seapass.model.design_file")
    doc = mutate(data.draw, design_doc())
    f = tmp_path / "design.toml"
    try:
        f.write_text(_dump(doc), encoding="utf-8", errors="surrogatepass")
    except (TypeError, UnicodeEncodeError):
        return
    out, err = io.StringIO(), io.StringIO()
    argv = ["analyze", str(f), "--out", str(tmp_path / "out"), "--stages", "core", "--no-progress"]
    with (
        cpu_budget(CPU_BUDGET_S),
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
    ):
        code = main(argv)
    e = err.getvalue()
    assert code in (0, 1, 2), (code, e[-2000:])
    assert "Traceback" not in e, e[-2000:]
    if code == 2:
        assert e.count("\n") == 1 and e.startswith("error:"), e[-2000:]
    assert not MARKER.exists()
