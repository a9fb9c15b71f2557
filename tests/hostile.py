"""Shared by the hostile-input tests: payloads, the stderr contract, a CLI runner, TOML mutation.

Every CLI run goes through :func:`seapass.cli.main` under a CPU budget
(``CPU_BUDGET_S`` seconds of CPU time per example, not wall-clock time: a busy
machine does not fail it, see ``cpu_budget``); the contract checked is: exit code 0 or
2, at most one line on stderr, no ``Traceback``.  Injection payloads try to
create a marker file (`MARKER`); it must never appear (the `no_marker` fixture).

Used by ``tests/cli/test_fuzz.py``, ``tests/model/test_expr_hostile.py``,
``tests/model/test_design_file_hostile.py``, ``tests/rig/test_rigfile_paper.py``,
``tests/files/test_hostile_files.py`` and ``tests/files/test_atomic.py``.
"""

from __future__ import annotations

import contextlib
import io
import os
import tomllib
from pathlib import Path

import pytest
from hypothesis import strategies as st

from cpu_budget import cpu_budget
from seapass.cli import main

CPU_BUDGET_S = 20.0


REPO = Path(__file__).resolve().parents[1]


MARKER = Path(os.environ.get("TMPDIR", "/tmp")) / f"seapass-fuzz-marker-{os.getpid()}"


def check_stderr(e: str, context: object = None) -> None:
    """The stderr contract: no traceback; ``warning:`` and ``wrote`` lines; at most one
    ``error:`` line, and it comes last."""
    assert "Traceback" not in e and "internal error" not in e, (context, e[-2000:])
    lines = e.splitlines()
    errors = [i for i, line in enumerate(lines) if line.startswith("error:")]
    assert len(errors) <= 1 and (not errors or errors[0] == len(lines) - 1), (context, e[-2000:])
    others = [line for line in lines if not line.startswith("error:")]
    assert all(line.startswith(("warning: ", "wrote ")) for line in others), (context, e[-2000:])


def is_check(argv: list[str]) -> bool:
    """Commands whose exit code 1 is a verdict (not passive), like cmp."""
    return argv[:1] == ["check"] or argv[:2] == ["sampled", "check"]


def run_cli(argv: list[str], codes: tuple[int, ...] | None = None) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with cpu_budget(CPU_BUDGET_S), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse --help / --version
            code = int(exc.code or 0)
    e = err.getvalue()
    if codes is None:
        codes = (0, 1, 2) if is_check(argv) else (0, 2)
    assert code in codes, (argv, code, e[-2000:])
    check_stderr(e, argv)
    assert not MARKER.exists(), argv
    return code, out.getvalue(), e


PAYLOADS = [
    "__import__('os').system('touch {m}')",
    "open('{m}', 'w')",
    "eval(\"open('{m}','w')\")",
    "exec(\"open('{m}','w')\")",
    "(lambda: open('{m}', 'w'))()",
    "().__class__.__bases__[0].__subclasses__()",
    "s.__class__.__init__.__globals__",
    "k1.__reduce__()",
    "[open('{m}','w') for _ in (1,)]",
    'f\'{{open("{m}","w")}}\'',
    "(x := open('{m}', 'w'))",
    "s if open('{m}','w') else 1",
    "__builtins__",
    "Symbol('x')",
    'sympify(\'open("{m}","w")\')',
    "s[0]",
    "*s",
    "s @ s",
    "s ** s",
    "s ** 1.5",
    "s ** (1/2)",
    "2 ** 99999999",
    "9" * 5000,
    "1" + "*s" * 500,
    "(" * 200 + "s" + ")" * 200,
    "import os",
    "k1;open('{m}','w')",
    "k1\nopen('{m}','w')",
    "\x00",
    "s\u200b+1",
    "ﬁ + s",
    "𝑠 + 1",
    "True",
    "None",
    "...",
    "b'1'",
    "'s'",
    "1j*s",
    "0x10*s",
    "1_000*s",
    "nan*s",
    "1e999*s",
    "1/(s-s)",
    "k1/(kd-kd)",
]


def payloads() -> list[str]:
    return [p.format(m=MARKER) for p in PAYLOADS]


def payload_id(text: str) -> str:
    """The test id without the process id (each pytest-xdist worker collects the same ids)."""
    return text.replace(str(MARKER), "MARKER")


@pytest.fixture
def no_marker():
    MARKER.unlink(missing_ok=True)
    yield
    assert not MARKER.exists()


_atoms = st.sampled_from(["s", "k1", "kd", "bd", "m", "0", "1", "2.5", "1e-6", "1e8", "0.0"])


@st.composite
def grammar(draw: st.DrawFn, depth: int = 4) -> str:
    if depth == 0:
        return draw(_atoms)
    kind = draw(st.sampled_from(["atom", "add", "sub", "mul", "div", "pow", "neg", "paren"]))
    if kind == "atom":
        return draw(_atoms)
    a = draw(grammar(depth - 1))
    if kind == "neg":
        return f"-{a}"
    if kind == "paren":
        return f"({a})"
    if kind == "pow":
        return f"({a})**{draw(st.integers(-14, 14))}"
    b = draw(grammar(depth - 1))
    op = {"add": "+", "sub": "-", "mul": "*", "div": "/"}[kind]
    return f"({a}){op}({b})"


TOML_VALUES = st.one_of(
    st.integers(-(10**20), 10**20),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20),
    st.booleans(),
    st.lists(st.floats(allow_nan=True), max_size=4),
    st.dictionaries(st.text(max_size=5), st.integers(), max_size=2),
    st.sampled_from(payloads()),
)


def mutate(draw: st.DrawFn, doc: dict) -> dict:
    doc = {k: (dict(v) if isinstance(v, dict) else v) for k, v in doc.items()}
    for _ in range(draw(st.integers(1, 4))):
        section = draw(st.sampled_from([*doc, "bogus_section"]))
        action = draw(st.sampled_from(["set", "delete", "add", "replace_section"]))
        if action == "replace_section" or section not in doc:
            doc[section] = draw(TOML_VALUES)
            continue
        if not isinstance(doc[section], dict):
            doc[section] = draw(TOML_VALUES)
            continue
        keys = list(doc[section]) or ["x"]
        key = draw(st.sampled_from(keys))
        if action == "delete":
            doc[section].pop(key, None)
        elif action == "add":
            doc[section][draw(st.text(min_size=1, max_size=8))] = draw(TOML_VALUES)
        else:
            doc[section][key] = draw(TOML_VALUES)
    return doc


def design_doc() -> dict:
    return tomllib.loads((REPO / "examples" / "ours.toml").read_text())
