"""Shared by many tests: the table of configurations, an argv builder, source scans.

* `CONFIGS`: the standard SEA structures under the short names the tests use
  (``"LP"``, ``"APD"``, ``"ours"``, ``"LPD"``, ...), each *derived from*
  `seapass.model.catalog` (never a copy of its expressions), so a test and the
  package cannot drift apart.  `configs` picks a sub-table.
* `design_argv`: the command-line words of a catalog design with values
  (``["--D1", "k1", "--CL", "kd", "--set", "m=1", ...]``).
* `CallScan` and `scan_source`: walk seapass's source for calls (the file-read
  and file-write guards of ``tests/files``).

Imported as ``helpers`` (``tests/`` is on ``sys.path`` under pytest's default
import mode, as for ``cpu_budget`` and ``long_jobs``).
"""

from __future__ import annotations

import ast
import contextlib
import importlib
import io
from collections.abc import Callable, Mapping
from pathlib import Path
from types import MappingProxyType
from typing import Any

import pytest

from seapass.model.catalog import PAPER_VALUES, design

REPO = Path(__file__).resolve().parents[1]
SRC = REPO / "src" / "seapass"
EXAMPLES = REPO / "examples"

# ------------------------------------------------------------------ the table of configurations

#: short test name -> catalog key
CATALOG_KEYS: Mapping[str, str] = MappingProxyType(
    {
        "LP": "LP",  # spring, load-side P
        "LP-damped": "mech/parallel-spring-damper",  # spring-damper, load-side P
        "LPD": "ctrl/load-PD",
        "LPI": "ctrl/load-PI",
        "APD": "APD",  # spring, actuator-side PD
        "API": "ctrl/act-PI",
        "ours": "ours",  # spring-damper, actuator-side PD
        "disjoint-damper": "mech/disjoint-spring-damper",
        "spring-spring": "mech/spring-spring",
    }
)


def elements(key: str) -> dict[str, str]:
    """The non-zero elements of catalog design ``key`` as `SEA` keywords (``D1=``, ``CL=``...)."""
    return {k: v for k, v in design(key).elements().items() if v != "0"}


CONFIGS: Mapping[str, Mapping[str, str]] = MappingProxyType(
    {name: MappingProxyType(elements(key)) for name, key in CATALOG_KEYS.items()}
)
"""Short name -> ``{"D1": ..., "CL": ...}`` (``SEA(**CONFIGS["LP"])``), from the catalog."""


def configs(*names: str) -> dict[str, dict[str, str]]:
    """A sub-table of `CONFIGS`, in the order given (each entry a fresh ``dict``)."""
    return {name: dict(CONFIGS[name]) for name in names}


# ------------------------------------------------------------------ command lines


def value_text(value: float | str) -> str:
    """A value as the command line takes it: ``1`` for 1.0, ``repr`` otherwise (no rounding)."""
    if isinstance(value, str):
        return value
    v = float(value)
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


def design_argv(
    key: str, values: Mapping[str, float | str] | None = None, **more: float | str
) -> list[str]:
    """The model words of catalog design ``key`` (or a `CONFIGS` name), then ``--set`` values.

    ``design_argv("LP", PAPER_VALUES)`` is
    ``["--D1", "k1", "--CL", "kd", "--set", "m=1", "--set", "b=10", "--set", "k1=1000"]``.
    """
    parts = dict(CONFIGS[key]) if key in CONFIGS else elements(key)
    argv = [word for name, text in parts.items() for word in (f"--{name}", text)]
    for name, v in {**(values or {}), **more}.items():
        argv += ["--set", f"{name}={value_text(v)}"]
    return argv


#: the paper's load-side P on its plant (m = 1, b = 10, k1 = 1000), kd free
LP_ARGV: tuple[str, ...] = tuple(design_argv("LP", PAPER_VALUES))

# ------------------------------------------------------------------ scans of seapass's source


class CallScan(ast.NodeVisitor):
    """Calls in one module of seapass with their enclosing function or class.

    Subclasses say which calls count in `call_name`; `found` collects
    ``((module, scope, name), line, call text)``; ``scope`` is the dotted chain of
    enclosing functions and classes (``"<module>"`` at module level).
    """

    def __init__(self, module: str) -> None:
        self.module = module
        self.scope: list[str] = []
        self.found: list[tuple[tuple[str, str, str], int, str]] = []

    def call_name(self, node: ast.Call) -> str | None:  # pragma: no cover - overridden
        """The name under which ``node`` counts, None when it does not."""
        raise NotImplementedError

    def _enter(self, node: ast.AST, name: str) -> None:
        self.scope.append(name)
        self.generic_visit(node)
        self.scope.pop()

    def visit_FunctionDef(self, node: ast.FunctionDef) -> None:
        self._enter(node, node.name)

    def visit_AsyncFunctionDef(self, node: ast.AsyncFunctionDef) -> None:
        self._enter(node, node.name)

    def visit_ClassDef(self, node: ast.ClassDef) -> None:
        self._enter(node, node.name)

    def visit_Call(self, node: ast.Call) -> None:
        name = self.call_name(node)
        if name is not None:
            scope = ".".join(self.scope) or "<module>"
            self.found.append(((self.module, scope, name), node.lineno, ast.unparse(node.func)))
        self.generic_visit(node)


def scan_source(
    scan: Callable[[str], CallScan], *, skip: tuple[str, ...] = ("files/",)
) -> list[tuple[tuple[str, str, str], int, str]]:
    """Run ``scan(module)`` over every module of seapass except those under ``skip``."""
    found: list[tuple[tuple[str, str, str], int, str]] = []
    for path in sorted(SRC.rglob("*.py")):
        module = path.relative_to(SRC).as_posix()
        if module.startswith(skip):
            continue
        v = scan(module)
        v.visit(ast.parse(path.read_text(encoding="utf-8")))
        found += v.found
    return found


def scan_text(scan: Callable[[str], CallScan], code: str) -> list[str]:
    """The names ``scan`` finds in ``code`` (to check that a scan sees what it forbids)."""
    v = scan("x.py")
    v.visit(ast.parse(code))
    return [name for (_, _, name), _, _ in v.found]


# ------------------------------------------------------------------ the command line in-process

OURS_TEXT = (EXAMPLES / "ours.toml").read_text(encoding="utf-8")
"""``examples/ours.toml``, the repository's example design file."""
PAPER_RIG_TEXT = (SRC / "data" / "paper_rig.toml").read_text(encoding="utf-8")
"""The packaged paper rig file."""


def run_main(argv: list[str]) -> tuple[int, str, str]:
    """``seapass.cli.main(argv)`` in-process: exit code, standard output, standard error."""
    from seapass.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def one_error(argv: list[str], *needles: str) -> str:
    """Run ``argv``: exit 2, exactly one ``error:`` line naming every needle."""
    code, _, err = run_main(argv)
    assert code == 2, (argv, err)
    assert err.startswith("error:") and err.count("\n") == 1, err
    for n in needles:
        assert n in err, (n, err)
    return err


def design_text(name: str, **tables: Mapping[str, Any]) -> str:
    """A design file's TOML text: ``name`` and each table (``model={"D1": "k1"}``,
    ``parameters={"m": 1.0}``, ``uncertainty={"m": [0.9, 1.1]}``, ...), in the given order.

    >>> print(design_text("t", model={"D1": "k1"}, uncertainty={"m": [0.9, 1.1]}), end="")
    name = "t"
    [model]
    D1 = "k1"
    [uncertainty]
    m = [0.9, 1.1]
    """

    def value(v: Any) -> str:
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, list | tuple):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    lines = [f"name = {value(name)}"]
    for table, items in tables.items():
        lines += [f"[{table}]", *(f"{k} = {value(v)}" for k, v in items.items())]
    return "\n".join(lines) + "\n"


def write_file(folder: Path, text: str, name: str = "d.toml") -> Path:
    """``text`` written as ``folder/name`` (a design or rig file for a test)."""
    f = folder / name
    f.write_text(text, encoding="utf-8")
    return f


def forbid(monkeypatch: pytest.MonkeyPatch, target: str) -> None:
    """Make ``target`` ("package.module.function") fail the test if called: validation must
    happen before the work."""

    def work(*a: object, **k: object) -> None:
        raise AssertionError(f"{target} ran although the input is invalid")

    module, _, name = target.rpartition(".")
    monkeypatch.setattr(importlib.import_module(module), name, work)


def tiny_report(title: str = "t", text: str = "hello") -> Any:
    """A one-section `seapass.report.document.Report`."""
    from seapass.report.document import Report, Section

    return Report(title=title, intro="intro", sections=(Section(key="a", title="A", text=text),))
