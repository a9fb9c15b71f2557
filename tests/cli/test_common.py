"""Issue 13, strict input and one convention across commands (items 3, 4, 5 and 9).

Unknown, unused and repeated names are errors with a did-you-mean; values
with a leading minus work with every option; likely unit slips warn; a
controller that needs more than one derivative is flagged; ``--version``;
``check`` exits 0/1/2 like ``cmp``; figures with ``--plot``, several files with
``--out DIR``, text by default and JSON with ``--json``, a ``wrote`` line for
every file, defaults in ``--help``; Python errors name Python arguments;
no internal tokens in what people read.
"""

from __future__ import annotations

import argparse
import ast
import contextlib
import importlib
import io
import json
import re
from pathlib import Path

import pytest

import seapass as sp
from helpers import LP_ARGV, design_argv
from seapass.cli import build_parser, main
from seapass.cli.common import HelpFormatter, check_period, check_step, error_text
from seapass.errors import ExpressionError, ParameterError
from seapass.model.catalog import PAPER_VALUES
from seapass.version import __version__

REPO = Path(__file__).resolve().parents[2]
LP = list(LP_ARGV)  # the paper's load-side P on its plant (tests/helpers.py)
OURS = design_argv("ours", PAPER_VALUES, b1=20, bd=25)


def cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:  # --help, --version
            code = int(exc.code or 0)
    return code, out.getvalue(), err.getvalue()


def one_error(argv: list[str], *needles: str) -> str:
    code, _, err = cli(argv)
    lines = err.splitlines()
    assert code == 2 and lines and lines[-1].startswith("error:"), (argv, err)
    assert all(line.startswith("warning:") for line in lines[:-1]), err
    for n in needles:
        assert n in lines[-1], (n, err)
    return lines[-1]


def forbid(monkeypatch: pytest.MonkeyPatch, target: str) -> None:
    def work(*a: object, **k: object) -> None:
        raise AssertionError(f"{target} ran although the input is invalid")

    module, _, name = target.rpartition(".")
    monkeypatch.setattr(importlib.import_module(module), name, work)


def parsers() -> dict[str, argparse.ArgumentParser]:
    out = {"seapass": build_parser()}
    todo = [("seapass", out["seapass"])]
    while todo:
        prefix, p = todo.pop()
        for a in p._actions:
            if isinstance(a, argparse._SubParsersAction):
                for name, sub in a.choices.items():
                    out[f"{prefix} {name}"] = sub
                    todo.append((f"{prefix} {name}", sub))
    return out


# ---------------------------------------------------------------- item 3: typos pass silently


def test_unknown_set_name_is_an_error_with_did_you_mean() -> None:
    one_error(["check", *LP, "--set", "kdd=5000"], "--set kdd", "did you mean 'kd'?")


def test_unused_set_name_is_an_error() -> None:
    one_error(["check", *LP, "--set", "kd=500", "--set", "bd=3"], "--set bd", "not a parameter")


def test_repeated_set_name_is_an_error() -> None:
    one_error(["check", *LP, "--set", "kd=1", "--set", "kd=2"], "--set kd is given twice")


def test_tune_bound_typo_is_an_error_before_tuning(monkeypatch: pytest.MonkeyPatch) -> None:
    forbid(monkeypatch, "seapass.tuning.search.differential_search")
    one_error(["tune", "APD", "--tune", "kx=0:5"], "--tune kx", "not a parameter of the design")
    one_error(["tune", "APD", "--tune", "bdd=0:5"], "did you mean 'bd'?")
    one_error(["tune", "APD", "--tune", "kd=0:5", "--tune", "kd=0:6"], "twice")
    one_error(["tune", "--design", "APD", "--bound", "kd=0:5", "--bound", "kd=0:6"], "twice")
    one_error(["tune", "LP", "--set", "kk1=5"], "--set kk1", "did you mean 'k1'?")


def test_sweep_grid_and_range_names_are_checked(tmp_path: Path) -> None:
    out = ["--out", str(tmp_path / "s.csv"), "--no-metrics"]
    one_error(["sweep", *LP, "--grid", "kdd=0:1:1", *out], "--grid kdd", "did you mean 'kd'?")
    one_error(["sweep", *LP, "--grid", "kd=0:1:1", "--grid", "kd=0:2:1", *out], "twice")
    one_error(["sweep", *LP, "--sample", "3", "--range", "kx=0:1", *out], "--range kx")
    one_error(["sweep", *LP, "--grid", "kd=0:1:1", "--set", "kd=1", *out], "--set kd", "free")


def test_positional_parameter_names_are_checked() -> None:
    one_error(["bound", "kdd", *LP], "bound kdd", "did you mean 'kd'?")
    one_error(["region", "kd", "bdd", *OURS, "--range", "kd=0:1", "--range", "bdd=0:1"], "bdd")


def test_python_values_are_strict_and_name_the_python_argument() -> None:
    with pytest.raises(ParameterError, match=r"values\['kdd'\].*did you mean 'kd'") as info:
        sp.SEA(D1="k1", CL="kd", values={"m": 1, "b": 1, "k1": 1, "kdd": 5})
    assert "--" not in str(info.value) and info.value.argument == "values['kdd']"
    with pytest.raises(ParameterError, match=r"values\['k'\]"):
        sp.Impedance(expr="(s + 1)/(s + 2)", values={"k": 1.0})
    # a parameter that cancels out of Z was still used
    z = sp.Impedance(expr="k*s/(k*s + k)", values={"k": 2.0})
    assert sp.is_passive(z).passive


def test_python_api_errors_name_python_arguments_not_flags() -> None:
    with pytest.raises(ParameterError) as info:
        sp.is_passive(sp.SEA(D1="k1", CL="kd", values={"m": 1, "b": 1, "k1": 1}))
    assert "values={'kd'" in str(info.value) and "--set" not in str(info.value)
    with pytest.raises(ExpressionError) as info2:
        sp.SEA(D1="k1", CA="kd*x")
    assert "values={'x'" in str(info2.value) and "--set" not in str(info2.value)
    # the command line shows its own flags for the same errors
    assert "--set kd=VALUE" in error_text(info.value)
    assert "--CA" in error_text(info2.value) and "--set x=VALUE" in error_text(info2.value)


def _raise_messages(tree: ast.AST) -> list[str]:
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Raise) and node.exc is not None:
            for sub in ast.walk(node.exc):
                if isinstance(sub, ast.Constant) and isinstance(sub.value, str):
                    out.append(sub.value)
    return out


def test_no_cli_flag_in_errors_raised_below_the_cli() -> None:
    flag = re.compile(r"(?<![\w-])--[a-z]")
    found = []
    for f in sorted((REPO / "src" / "seapass").rglob("*.py")):
        if "cli" in f.relative_to(REPO / "src" / "seapass").parts:
            continue
        if f.name == "expr.py":  # parse_assignment parses the text of --set itself
            continue
        for msg in _raise_messages(ast.parse(f.read_text())):
            if flag.search(msg):
                found.append((f.name, msg))
    assert not found, found


# ---------------------------------------------------------------- item 4: negative numbers


@pytest.mark.parametrize(
    "argv",
    [
        ["bound", "kd", *LP, "--range", "-100:100"],
        ["check", "--D1", "k1", "--CL", "-kd", "--set", "m=1", "--set", "b=1", "--set", "k1=1",
         "--set", "kd=1"],
        ["check", "--D1", "k1", "--CL", "-k1*(kd/k1)", "--set", "m=1", "--set", "b=1",
         "--set", "k1=1", "--set", "kd=1"],
        ["simulate", *LP, "--set", "kd=500", "--load-mass", "1", "--horizon", "0.1",
         "--step", "-1e-3"],
        ["simulate", *LP, "--set", "kd=500", "--load-mass", "1", "--horizon", "0.1",
         "--load-displaced", "-0.02"],
        ["region", "kd", "b", "--D1", "k1", "--CL", "kd", "--set", "m=1", "--set", "k1=1000",
         "--range", "kd=-10:10", "--range", "b=0:1", "--points", "2"],
    ],
    ids=["range", "CL", "CL-expr", "step", "displaced", "x-range"],
)  # fmt: skip
def test_values_with_a_leading_minus_are_values(argv: list[str]) -> None:
    code, out, err = cli(argv)
    assert code in (0, 1), err
    assert "expected one argument" not in err and out


def test_unknown_double_dash_options_are_still_errors() -> None:
    one_error(["check", *LP, "--set", "kd=1", "--rnage", "1"], "unrecognized arguments")


# ---------------------------------------------------------------- unit slips, realizability


def test_unit_slips_warn(capsys: pytest.CaptureFixture[str]) -> None:
    check_period(500.0)
    check_period(0.002)
    check_step(500.0)
    check_step(0.05)
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2
    assert err[0].startswith("warning: --period 500 s") and "--period 0.002" in err[0]
    assert err[1].startswith("warning: --step 500 m") and "--step 0.5" in err[1]


def test_unit_slip_warnings_in_commands(monkeypatch: pytest.MonkeyPatch) -> None:
    code, _, err = cli(["simulate", *LP, "--set", "kd=500", "--load-mass", "1", "--horizon", "0.2",
                        "--step", "500", "--json"])  # fmt: skip
    assert code == 0 and err.startswith("warning: --step 500 m")
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    argv = ["sampled", "bound", "kd", *LP, "--range", "kd=0:5000", "--period", "500", "--rtol", "0"]
    code, _, err = cli(argv)
    assert code == 2 and err.startswith("warning: --period 500 s"), err


def test_improper_controller_is_flagged_not_realizable() -> None:
    code, out, err = cli(["check", *LP[:2], "--CA", "kd*s**3", *LP[4:], "--set", "kd=5", "--json"])
    assert code in (0, 1)
    assert err.startswith("warning: --CA 'kd*s**3' has 3 more zeros than poles: not realizable")
    assert json.loads(out)["realizable"] is False
    code, out, err = cli(["check", *OURS, "--set", "kd=5", "--json"])  # kd + bd*s: one derivative
    assert code == 0 and err == "" and json.loads(out)["realizable"] is True


# ---------------------------------------------------------------- item 5: conventions


def test_version() -> None:
    code, out, _ = cli(["--version"])
    assert code == 0 and out.strip() == f"seapass {__version__}"


def test_check_exit_codes_like_cmp() -> None:
    assert cli(["check", *LP, "--set", "kd=500"])[0] == 0
    assert cli(["check", *LP, "--set", "kd=2000"])[0] == 1
    assert cli(["check", *LP, "--set", "kd=2000", "--json"])[0] == 1
    assert cli(["check", *LP])[0] == 2
    readme = (REPO / "README.md").read_text()
    assert re.search(r"0.*passive.*1.*not passive.*2.*bad input", readme, re.S | re.I)


def test_every_parser_shows_defaults_in_help() -> None:
    for name, p in parsers().items():
        assert issubclass(p.formatter_class, HelpFormatter), name
        fmt = p.formatter_class(prog=name)
        for a in p._actions:
            meaningful = a.option_strings and a.default not in (None, False, [], argparse.SUPPRESS)
            if meaningful and a.help is not argparse.SUPPRESS:
                shown = (fmt._get_help_string(a) or "") % {"default": a.default}
                assert "default" in shown, (name, a.option_strings)


def test_figure_and_directory_flags_are_uniform() -> None:
    for name, p in parsers().items():
        visible = {
            s: a for a in p._actions if a.help is not argparse.SUPPRESS for s in a.option_strings
        }
        assert "--out-fig" not in visible and "--plots" not in visible, name
        if "--plot" in visible:
            assert visible["--plot"].metavar == "FILE", name
        # sweep --out: the results file; rig chirp --out: the command file (issue 23)
        if "--out" in visible and name not in ("seapass sweep", "seapass rig chirp"):
            assert visible["--out"].metavar == "DIR", name
    for name in ("region", "response", "simulate", "sweep"):
        assert any("--plot" in a.option_strings for a in parsers()[f"seapass {name}"]._actions)


def test_region_announces_its_figure_and_prints_text(tmp_path: Path) -> None:
    fig = tmp_path / "r"
    argv = ["region", "kd", "b1", *OURS[:2], "--CL", "kd", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--range", "kd=0:1200", "--range", "b1=0:100", "--points", "2",
            "--plot", str(fig)]  # fmt: skip
    code, out, err = cli(argv)
    assert code == 0 and err == f"wrote {fig}.png\n" and (tmp_path / "r.png").stat().st_size > 0
    assert out.startswith("kd = 0: passive b1 in")


def test_old_figure_flags_still_work_with_a_warning(tmp_path: Path) -> None:
    code, _, err = cli(["response", *OURS, "--set", "kd=5", "--points", "5", "--out",
                        str(tmp_path / "f.svg")])  # fmt: skip
    assert code == 0 and err.splitlines() == [
        f"warning: --out is deprecated here; use --plot {tmp_path / 'f.svg'}",
        f"wrote {tmp_path / 'f.svg'}",
    ]


def test_sweep_prints_text_by_default_and_json_on_request(tmp_path: Path) -> None:
    base = ["sweep", *LP, "--grid", "kd=0:1500:500", "--no-metrics", "--no-progress"]
    code, out, err = cli([*base, "--out", str(tmp_path / "a.csv")])
    assert code == 0 and out.startswith("4 designs") and err == f"wrote {tmp_path / 'a.csv'}\n"
    code, out, _ = cli([*base, "--out", str(tmp_path / "b.csv"), "--json"])
    assert code == 0 and json.loads(out)["n_designs"] == 4


def test_bound_documents_the_free_parameter_rule() -> None:
    code, out, _ = cli(["bound", "--help"])
    assert code == 0 and "PARAM itself" in out
    one_error(["bound", "kd", *LP, "--set", "kd=3"], "--set kd", "free parameter")


# ---------------------------------------------------------------- item 9: internal tokens


def test_no_internal_tokens_in_check_and_witness_text() -> None:
    code, out, _ = cli(["check", *LP, "--set", "kd=2000"])
    assert code == 1 and "negative_real_part" not in out and "None" not in out
    code, out, _ = cli(["witness", *LP, "--set", "kd=2000"])
    assert code == 0 and "negative_real_part" not in out and "Re Z(jw) < 0" in out


def test_witness_figure_title_uses_the_description() -> None:
    from seapass.analysis.witness import find_destabilizing_environment
    from seapass.plot.style import bare_figures
    from seapass.plot.witness import plot_witness

    res = find_destabilizing_environment(
        sp.SEA(D1="k1", CL="kd", values={"m": 1, "b": 10, "k1": 1000, "kd": 2000}), simulate=True
    )
    with bare_figures():
        axes = plot_witness(res)
        title = axes[0].figure.get_suptitle()
    assert "negative_real_part" not in title and "Re Z(jw) < 0" in title


def test_rig_gains_text_has_no_none_token() -> None:
    from seapass.cli.cmd_rig import _gain

    assert _gain(None, "twin") == "no kd (twin)" and _gain(1200.0, "twin") == "kd = 1200 (twin)"


def test_overshoot_has_the_same_unit_in_text_and_json() -> None:
    argv = ["simulate", *OURS, "--set", "kd=2000", "--load-mass", "10", "--horizon", "2"]
    _, text, _ = cli(argv)
    _, js, _ = cli([*argv, "--json"])
    # text: percent (the one format of an overshoot shown to a person); JSON: the fraction
    shown = float(re.search(r"overshoot: (\S+) % of the step", text).group(1))
    assert shown == pytest.approx(100 * json.loads(js)["overshoot"], rel=1e-3)


def test_missing_file_is_path_and_reason() -> None:
    err = one_error(["analyze", "/nonexistent/design.toml", "--out", "x"], "No such file")
    assert "Errno" not in err and "/nonexistent/design.toml" in err


def test_no_help_text_joins_two_lines_with_a_lone_backslash() -> None:
    """A ``\\`` at a line's end in a plain string joins the lines: help examples need ``\\\\``."""
    import io as _io
    import tokenize
    from pathlib import Path as _Path

    bad = []
    for path in sorted((_Path(__file__).parents[2] / "src" / "seapass" / "cli").glob("*.py")):
        text = path.read_text(encoding="utf-8")
        for tok in tokenize.generate_tokens(_io.StringIO(text).readline):
            if tok.type != tokenize.STRING:
                continue
            body = tok.string.lstrip("rRbBuUfF")
            prefix = tok.string[: len(tok.string) - len(body)]
            body = body.lstrip("\"'").removeprefix("\\\n")  # '"""\' opens without a newline
            if "r" not in prefix.lower() and "\\\n" in body.replace("\\\\", ""):
                bad.append(f"{path.name}:{tok.start[0]}")
    assert bad == []
