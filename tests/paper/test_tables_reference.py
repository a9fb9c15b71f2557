"""Tables I and II: reference values for every row, and JSON that sympify can read back."""

import json

import pytest
import sympy as sp

import seapass.paper.tables
from seapass.cli import main
from seapass.paper.tables import PAPER_ROWS, build_tables

NAMES = "m b k1 k2 b1 b2 kd bd ki s w"


@pytest.fixture(scope="module")
def rows(paper_tables):
    return {r.paper.name: r for r in paper_tables}


def test_the_shared_rows_are_what_build_tables_derives(paper_tables):
    assert [r.paper.name for r in paper_tables] == [r.name for r in PAPER_ROWS]
    assert build_tables is seapass.paper.tables.build_tables  # not a patched stand-in


@pytest.fixture
def built_once(monkeypatch, paper_tables):
    """``seapass tables`` here formats the session's rows instead of deriving them again (the
    command's own derivation runs end to end in ``tests/cli/test_golden.py``)."""
    monkeypatch.setattr(seapass.paper.tables, "build_tables", lambda **_: list(paper_tables))


# name: (stiffness_agrees, eq4_agrees, polynomial agrees, bound status, exact condition)
EXPECTED = {
    "mech/pure-spring": (True, True, True, "exact", "k1 - kd >= 0"),
    "mech/spring-spring": (False, False, False, "unsafe", "k1 - kd >= 0"),
    "mech/parallel-spring-damper": (True, True, False, "sufficient only", None),
    "mech/disjoint-spring-damper": (False, False, False, "sufficient only", None),
    "ctrl/load-P": (True, True, False, "exact", "k1 - kd >= 0"),
    "ctrl/load-PD": (True, True, True, "agrees (not passive)", "False"),
    "ctrl/load-PI": (True, True, True, "agrees (not passive)", "False"),
    "ctrl/act-P": (True, True, True, "exact", "True"),
    "ctrl/act-PD": (True, True, True, "exact", "True"),
    "ctrl/act-PI": (True, True, True, "agrees (not passive)", "False"),
    "proposed": (True, True, True, "sufficient only", "True"),
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_row_reference_values(rows, name):
    st, eq4, agrees, status, exact = EXPECTED[name]
    r = rows[name]
    assert r.stiffness_agrees is st
    assert r.eq4_agrees is eq4
    assert r.agrees is agrees
    assert r.bound_status == status
    if exact is not None:
        assert str(r.exact_condition) == exact


def test_unsafe_counterexample_is_certified(rows):
    """Table I row 2: kd <= k1 + k2 admits non-passive designs."""
    from seapass.analysis.passivity import is_passive
    from seapass.model.sea import SEA

    ce = rows["mech/spring-spring"].counterexample
    assert ce["kd"] <= ce["k1"] + ce["k2"]
    assert not is_passive(SEA(D1="k1", D2="k2", CL="kd", values=ce)).passive


def test_proposed_is_passive_beyond_the_papers_bound(rows):
    ce = rows["proposed"].counterexample
    b, bd, b1, m = ce["b"], ce["bd"], ce["b1"], ce["m"]
    assert ce["kd"] > ((b + bd) ** 2 + b * b1 + b1 * bd) / (2 * m)


def test_cli_json_rows_parse_with_sympify(capsys, built_once):
    assert main(["tables", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [d["name"] for d in data] == [
        "mech/pure-spring",
        "mech/spring-spring",
        "mech/parallel-spring-damper",
        "mech/disjoint-spring-damper",
        "ctrl/load-P",
        "ctrl/load-PD",
        "ctrl/load-PI",
        "ctrl/act-P",
        "ctrl/act-PD",
        "ctrl/act-PI",
        "proposed",
    ]
    syms = {n: sp.Symbol(n) for n in NAMES.split()}
    keys = {
        "table",
        "name",
        "D1",
        "D2",
        "CA",
        "CL",
        "stiffness",
        "paper_stiffness",
        "condition",
        "paper_condition",
        "agrees",
        "exact_condition",
    }
    for d in data:
        assert keys <= set(d)
        for k in (
            "D1",
            "D2",
            "CA",
            "CL",
            "stiffness",
            "paper_stiffness",
            "condition",
            "paper_condition",
            "exact_condition",
        ):
            sp.sympify(d[k], locals=syms)  # our own output, parsed as the issue requires
        assert isinstance(d["agrees"], bool)


@pytest.mark.parametrize("fmt", ["markdown", "latex", "text"])
def test_formats_and_plots(capsys, tmp_path, fmt, built_once):
    args = ["tables", "--format", fmt]
    if fmt == "markdown":
        args += ["--plots", str(tmp_path)]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "proposed" in out
    if fmt == "markdown":
        assert out.count("| mech/") == 4
        assert len(list(tmp_path.glob("*.png"))) == 11
    if fmt == "latex":
        assert "\\begin{tabular}" in out
