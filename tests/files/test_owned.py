"""One rule for every command that writes (issue 20, item 4): never replace a file seapass
did not write, unless the user passes ``--force``.

``seapass sweep --out victim.csv`` used to replace a user's file silently. The rule and the
record of what seapass wrote (``.seapass-written``, with the digest of each file) live in
`seapass.files.owned`; every writer goes through it (a source scan below keeps it so), and
every command that writes is run here against a file of the user's at its output path.
"""

from __future__ import annotations

import ast
import contextlib
import importlib
import io
import json
import os
from pathlib import Path

import pytest

from helpers import LP_ARGV, CallScan, scan_source, scan_text
from seapass.cli import build_parser, main
from seapass.errors import OutputPathError
from seapass.files.owned import (
    MANIFEST,
    check_replaceable,
    read_manifest,
    save_output,
    seapass_wrote,
    write_output_bytes,
    write_output_text,
)
from seapass.rig.log import chirp_command, twin_log
from seapass.rig.rigfile import paper_rig

REPO = Path(__file__).resolve().parents[2]
LP = list(LP_ARGV)  # the paper's load-side P on its plant (tests/helpers.py)
MINE = b"the user's own file\n"

# ------------------------------------------------------------------ the library rule


def test_new_files_are_written_and_recorded(tmp_path: Path) -> None:
    f = tmp_path / "a.csv"
    write_output_text(f, "x\n")
    assert f.read_text() == "x\n" and seapass_wrote(f)
    listed = read_manifest(tmp_path)
    assert listed is not None and listed["a.csv"].startswith("sha256:")
    write_output_text(f, "y\n")  # seapass's own, unchanged: replaced
    assert f.read_text() == "y\n"


def test_a_users_file_is_never_replaced_without_force(tmp_path: Path) -> None:
    f = tmp_path / "a.csv"
    f.write_bytes(MINE)
    with pytest.raises(OutputPathError, match=r"not written by seapass.*force=True"):
        write_output_text(f, "x\n")
    assert f.read_bytes() == MINE
    write_output_text(f, "x\n", force=True)
    assert f.read_text() == "x\n" and seapass_wrote(f)


def test_a_file_seapass_wrote_and_the_user_changed_is_the_users(tmp_path: Path) -> None:
    f = tmp_path / "a.csv"
    write_output_text(f, "x\n")
    f.write_text("x, edited\n")
    assert not seapass_wrote(f)
    with pytest.raises(OutputPathError, match="or was changed since"):
        write_output_bytes(f, b"y\n")
    assert f.read_text() == "x, edited\n"


def test_a_copied_manifest_entry_does_not_make_another_file_seapass(tmp_path: Path) -> None:
    write_output_text(tmp_path / "a.csv", "x\n")
    (tmp_path / "b.csv").write_text("mine\n")
    listed = read_manifest(tmp_path)
    assert listed is not None
    doc = json.loads((tmp_path / MANIFEST).read_text())
    doc["files"]["b.csv"] = listed["a.csv"]  # a forged entry: the digest does not match
    (tmp_path / MANIFEST).write_text(json.dumps(doc))
    with pytest.raises(OutputPathError):
        check_replaceable(tmp_path / "b.csv")


@pytest.mark.parametrize("kind", ["dir", "symlink", "fifo", "device"])
def test_special_files_are_never_replaced_even_with_force(tmp_path: Path, kind: str) -> None:
    f = tmp_path / "x.csv"
    if kind == "dir":
        f.mkdir()
    elif kind == "symlink":
        (tmp_path / "target").write_bytes(MINE)
        f.symlink_to(tmp_path / "target")
    elif kind == "fifo":
        os.mkfifo(f)
    else:
        f = Path("/dev/null")
    for force in (False, True):
        with pytest.raises(OutputPathError, match="seapass replaces only regular files"):
            check_replaceable(f, force=force)
    if kind == "symlink":
        assert (tmp_path / "target").read_bytes() == MINE


def test_a_foreign_file_in_the_manifest_slot_stops_the_write(tmp_path: Path) -> None:
    (tmp_path / MANIFEST).write_bytes(MINE)
    with pytest.raises(OutputPathError, match="not a seapass manifest"):
        write_output_text(tmp_path / "a.csv", "x\n")
    assert not (tmp_path / "a.csv").exists()
    write_output_text(tmp_path / "a.csv", "x\n", force=True)
    assert seapass_wrote(tmp_path / "a.csv")


def test_saver_output_is_recorded_and_the_manifest_drops_gone_files(tmp_path: Path) -> None:
    save_output(tmp_path / "f.bin", lambda p: Path(p).write_bytes(b"\x00\x01"))
    write_output_text(tmp_path / "g.txt", "g")
    (tmp_path / "f.bin").unlink()
    write_output_text(tmp_path / "h.txt", "h")
    assert sorted(read_manifest(tmp_path) or {}) == ["g.txt", "h.txt"]


# ------------------------------------------------------------------ one mechanism

WRITER_ATTRIBUTES = frozenset(
    "atomic_write atomic_save atomic_write_text write_text write_bytes savefig to_parquet".split()
)
WRITER_CALLS = frozenset(
    "os.replace os.rename os.link os.symlink shutil.copy shutil.copy2 shutil.copyfile "
    "shutil.move shutil.copytree np.save np.savez np.savetxt pq.write_table pacsv.write_csv".split()
)

#: (module, enclosing function, call) -> why it needs no ownership check
RAW_WRITES_ALLOWED = {
    ("report/output.py", "write_report", "atomic_write"): "into a new temporary directory; "
    "the report directory is checked as a whole by check_output_dir",
    ("report/output.py", "write_report", "os.replace"): "swapping the complete report in",
    ("report/output.py", "_carry_over", "os.link"): "the user's files into the new report",
    ("report/output.py", "_link_same", "os.link"): "an unchanged file seapass wrote, into the "
    "new temporary directory (analyze rewrites the report as stages finish)",
    ("report/output.py", "_carry_over", "os.symlink"): "the user's links into the new report",
    ("report/output.py", "_carry_over", "shutil.copy2"): "the user's files into the new report",
    ("export/compiled.py", "compile_c", "write_text"): "a shim in a TemporaryDirectory",
    ("explore/reports.py", "ReportJobs.start", "atomic_write_text"): "design.toml in the "
    "report directory the explorer has just created (mkdir exist_ok=False)",
    ("sweep/location.py", "Location.put_bytes", "atomic_write"): "parts and the journal in "
    "the sweep's own directory; a consolidated output is checked by "
    "sweep.runner.check_consolidated_target",
    ("sweep/location.py", "Location.save_via", "atomic_save"): "as put_bytes",
    ("sweep/store.py", "write_part", "pq.write_table"): "a part, into put_bytes's buffer",
    ("plot/style.py", "_render", "savefig"): "into a BytesIO",
    ("explore/reports.py", "ReportJobs.start", "open"): "the analyze log in the new directory",
    ("sweep/location.py", "Location.save_via.save", "open"): "atomic_save's temporary file",
}


class _Writes(CallScan):
    def __init__(self, module: str) -> None:
        super().__init__(module)
        self.helpers: set[str] = set()  # names imported from seapass's own cli writers

    def visit_ImportFrom(self, node: ast.ImportFrom) -> None:
        if node.module in ("common", "output") and node.level == 1:
            self.helpers |= {a.asname or a.name for a in node.names}

    def call_name(self, node: ast.Call) -> str | None:
        f = node.func
        text = ast.unparse(f)
        if text in WRITER_CALLS:
            return text
        if isinstance(f, ast.Attribute) and f.attr in WRITER_ATTRIBUTES:
            return f.attr
        if isinstance(f, ast.Name) and f.id in WRITER_ATTRIBUTES and f.id not in self.helpers:
            # cli.output.write_text / write_bytes (imported via .common) call files.owned
            return f.id
        if isinstance(f, ast.Name) and f.id == "open" and len(node.args) > 1:
            mode = node.args[1]
            if isinstance(mode, ast.Constant) and set(str(mode.value)) & set("wax+"):
                return "open"
        return None


def raw_writes() -> list[tuple[tuple[str, str, str], int, str]]:
    return scan_source(_Writes)


def test_every_output_goes_through_files_owned() -> None:
    found = raw_writes()
    assert found, "the scan finds nothing: it is broken"
    stray = [
        f"{m}:{line} {s} calls {n}"
        for (m, s, n), line, _ in found
        if (m, s, n) not in RAW_WRITES_ALLOWED
    ]
    assert not stray, (
        "write outputs with seapass.files.owned (write_output_text, write_output_bytes, "
        "save_output) or add the call to RAW_WRITES_ALLOWED with the reason:\n" + "\n".join(stray)
    )
    stale = sorted(set(RAW_WRITES_ALLOWED) - {key for key, _, _ in found})
    assert not stale, f"RAW_WRITES_ALLOWED lists calls that are gone: {stale}"


def test_the_write_scan_sees_the_writes_it_forbids() -> None:
    code = (
        "def f(p, df):\n"
        "    p.write_text('x'); atomic_write_text(p, 'x'); os.replace(p, p)\n"
        "    open(p, 'w'); open(p); shutil.copy2(p, p); df.to_parquet(p)\n"
    )
    assert sorted(scan_text(_Writes, code)) == sorted(
        ["write_text", "atomic_write_text", "os.replace", "open", "shutil.copy2", "to_parquet"]
    )


# ------------------------------------------------------------------ every command that writes

OUTPUT_OPTIONS = ("--out", "--plot", "--rig-out")
#: commands with an output option but nothing to replace
NO_FORCE = {"explore": "--reports: each report goes to a new directory (mkdir exist_ok=False)"}


def _subcommands(parser, prefix=()):
    import argparse

    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _subcommands(sub, (*prefix, name))
            return
    yield prefix, parser


def test_every_command_with_an_output_has_force() -> None:
    missing, seen = [], 0
    for path, parser in _subcommands(build_parser()):
        flags = {s for a in parser._actions for s in a.option_strings}
        if flags & set(OUTPUT_OPTIONS) and path[0] not in NO_FORCE:
            seen += 1
            if "--force" not in flags:
                missing.append(" ".join(path))
    assert seen == 22 and not missing, (seen, missing)  # 22: every command listed in COMMANDS


def cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def forbid(monkeypatch: pytest.MonkeyPatch, target: str) -> None:
    def work(*a: object, **k: object) -> None:
        raise AssertionError(f"{target} ran although its output would be refused")

    module, _, name = target.rpartition(".")
    monkeypatch.setattr(importlib.import_module(module), name, work)


@pytest.fixture(scope="module")
def rig_files(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    d = tmp_path_factory.mktemp("rig")
    rig = paper_rig()
    (d / "rig.toml").write_text(rig.to_toml())
    log = twin_log(rig, chirp_command(rig.control.rate, duration=4.0), load_mass=0.1, seed=1)
    (d / "log.csv").write_text(log.to_csv())
    return d / "rig.toml", d / "log.csv"


SWEEP = ["sweep", *LP[:-2], "--sample", "20", "--range", "k1=100:5000", "--range", "kd=0:5000"]
SWEEP += ["--no-metrics", "--no-progress"]

# name: (argv with {d} for a directory and {f} for a file, the output to occupy, the work
# that must not start when it is refused, or None: cheap enough to run with --force too)
COMMANDS = {
    "sweep csv": ([*SWEEP, "--out", "{d}/victim.csv"], "victim.csv", None),
    "sweep parquet": ([*SWEEP, "--out", "{d}/victim.parquet"], "victim.parquet", None),
    "sweep plot": (
        [*SWEEP, "--out", "{d}/s.csv", "--heatmap", "k1,kd", "--plot", "{d}/map.png"],
        "map.png",
        None,
    ),
    "export c": (
        ["export", "c", str(REPO / "examples/ours.toml"), "--out", "{d}", "--force-limit", "50"],
        "seapass_ctrl.h",
        None,
    ),
    "analyze": (
        ["analyze", str(REPO / "examples/lp.toml"), "--out", "{d}", "--stages", "passivity"],
        "report.md",
        None,
    ),
    "reproduce": (
        ["reproduce", "--out", "{d}", "--stages", "tables"],
        "report.html",
        "seapass.report.reproduce.reproduce",
    ),
    "plot": (["plot", "real", *LP, "--set", "kd=500", "--plot", "{d}/f.svg"], "f.svg", None),
    "simulate": (
        [
            "simulate",
            *LP,
            "--set",
            "kd=500",
            "--load-mass",
            "1",
            "--horizon",
            "1",
            "--plot",
            "{d}/s.png",
        ],
        "s.png",
        None,
    ),
    "response": (["response", *LP, "--set", "kd=500", "--plot", "{d}/r.pdf"], "r.pdf", None),
    "region": (
        [
            "region",
            "kd",
            "b",
            *LP[:-4],
            "--set",
            "k1=1000",
            "--range",
            "kd=0:2000",
            "--range",
            "b=1:20",
            "--points",
            "20",
            "--plot",
            "{d}/m.png",
        ],
        "m.png",
        "seapass.analysis.region.passive_map",
    ),
    "witness": (
        ["witness", "--Z", "(s - 1)/(s + 1)", "--out", "{d}"],
        "witness.json",
        "seapass.analysis.witness.find_destabilizing_environment",
    ),
    "tables": (
        ["tables", "--out", "{d}"],
        "mech_pure-spring.png",
        "seapass.paper.tables.build_tables",
    ),
    "figure": (["figure", "sims", "--out", "{d}"], "sims.csv", None),
    "sampled check": (
        ["sampled", "check", "--period", "0.002", *LP, "--set", "kd=500", "--out", "{d}"],
        "sampled_check.json",
        None,
    ),
    "sampled bound": (
        [
            "sampled",
            "bound",
            "kd",
            "--period",
            "0.002",
            *LP,
            "--range",
            "kd=0:2000",
            "--out",
            "{d}",
        ],
        "sampled_bound_kd.json",
        "seapass.sampled.bound.sampled_passive_bound",
    ),
    "sampled region": (
        [
            "sampled",
            "region",
            "kd",
            "b",
            "--period",
            "0.002",
            *LP[:-4],
            "--set",
            "k1=1000",
            "--range",
            "kd=0:2000",
            "--range",
            "b=1:20",
            "--out",
            "{d}",
        ],
        "sampled_region_kd_b.csv",
        "seapass.sampled.region.sampled_region",
    ),
    "rig sweep": (
        ["rig", "sweep", "--out", "{d}"],
        "sweep.csv",
        "seapass.rig.experiment.run_experiment",
    ),
    "rig impacts": (
        ["rig", "impacts", "--out", "{d}"],
        "impacts.png",
        "seapass.rig.impacts.run_impacts",
    ),
    "rig fit --rig-out": (
        ["rig", "fit", "{log}", "--rig", "{rig}", "--rig-out", "{d}/fitted.toml"],
        "fitted.toml",
        "seapass.rig.log.load_log",
    ),
    "rig fit --plot": (
        ["rig", "fit", "{log}", "--rig", "{rig}", "--plot", "{d}/fit.png"],
        "fit.png",
        None,
    ),
    "rig chirp": (
        ["rig", "chirp", "--rig", "{rig}", "--duration", "1", "--out", "{d}/command.csv"],
        "command.csv",
        None,
    ),
}
EXPENSIVE_WITHOUT_FORBID = {"figure": "seapass.paper.simstudy.run_simulation_study"}


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_writing_command_refuses_a_users_file(
    name: str, tmp_path: Path, rig_files: tuple[Path, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    argv_t, occupied, work = COMMANDS[name]
    rig, log = rig_files
    d = tmp_path / "out"
    d.mkdir()
    argv = [a.format(d=d, rig=rig, log=log) for a in argv_t]
    victim = d / occupied
    victim.write_bytes(MINE)
    heavy = work or EXPENSIVE_WITHOUT_FORBID.get(name)
    with monkeypatch.context() as m:
        if heavy is not None:
            forbid(m, heavy)  # the refusal comes before the work
        code, _, err = cli(argv)
    assert code == 2, (name, err)
    assert err.startswith("error: ") and err.count("\n") == 1, err
    assert victim.name in err or f"{d} is a non-empty directory" in err, err  # report dirs
    assert "not written by seapass" in err or "that seapass did not write" in err, err
    assert "--force" in err, err
    assert victim.read_bytes() == MINE
    if heavy is not None:
        return
    # with --force the file is replaced, and then it is seapass's: the next run needs no --force
    code, _, err = cli([*argv, "--force"])
    assert code in (0, 1), (name, err)
    assert victim.read_bytes() != MINE
    code, _, err = cli(argv)
    assert code in (0, 1), (name, err)
    assert "error" not in err, err


def test_sweep_attack_commands(tmp_path: Path) -> None:
    """The issue's attack: ``sweep --out victim.csv`` and ``.parquet``."""
    for suffix in ("csv", "parquet"):
        victim = tmp_path / f"victim.{suffix}"
        victim.write_bytes(MINE)
        code, _, err = cli([*SWEEP, "--out", str(victim)])
        assert code == 2 and err.count("\n") == 1 and "pass --force to replace it" in err
        assert victim.read_bytes() == MINE
        assert not (tmp_path / f"victim.{suffix}.parts").exists()  # no work started


def test_a_report_directory_keeps_other_commands_files(tmp_path: Path) -> None:
    out = tmp_path / "r"
    argv = ["analyze", str(REPO / "examples/lp.toml"), "--out", str(out), "--stages", "passivity"]
    assert cli(argv)[0] == 0
    assert cli(["witness", "--Z", "(s + 1)/(s + 2)", "--out", str(out)])[0] == 0
    (out / "notes.txt").write_text("mine")
    assert cli(argv)[0] == 0
    assert (out / "notes.txt").read_text() == "mine"
    assert seapass_wrote(out / "witness.json")  # carried over, still seapass's
    assert cli(["witness", "--Z", "(s + 1)/(s + 2)", "--out", str(out)])[0] == 0
