"""Issue 12: bounded time and memory on every input, one clear error line, safe output directories.

One test (at least) per item of the issue.  Commands run in-process through
`seapass.cli.main` (the stderr contract is `check_stderr` of the fuzz tests);
the memory bounds are measured in a subprocess under ``resource`` limits in
``tests/files/test_hostile_files.py``.
"""

from __future__ import annotations

import contextlib
import importlib
import io
import os
import socket
import struct
import subprocess
import threading
import warnings
from pathlib import Path

import msgpack
import pytest

from cpu_budget import BLOCKED_S
from helpers import LP_ARGV
from seapass.cli import main
from seapass.errors import FileFormatError, OutputPathError, ParameterError
from seapass.files import limits
from seapass.files.owned import file_digest, read_manifest, write_manifest
from seapass.files.textfile import read_text_file
from seapass.files.toml import loads_strict
from seapass.model.design_file import load_design
from seapass.report.document import Report, Section
from seapass.report.output import LEGACY_MARKER, check_output_dir, write_report
from seapass.report.render import render_markdown
from seapass.rig.rigfile import load_rig, paper_rig
from seapass.sweep.cluster import probe_scheduler

REPO = Path(__file__).resolve().parents[2]
OURS = (REPO / "examples" / "ours.toml").read_text()
PAPER_RIG = (REPO / "src" / "seapass" / "data" / "paper_rig.toml").read_text()
LP = list(LP_ARGV)  # the paper's load-side P on its plant (tests/helpers.py)


def cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def one_error(argv: list[str], *needles: str) -> str:
    """Run ``argv``: exit 2, exactly one ``error:`` line naming every needle."""
    code, _, err = cli(argv)
    assert code == 2, (argv, err)
    assert err.startswith("error:") and err.count("\n") == 1, err
    for n in needles:
        assert n in err, (n, err)
    return err


def design(tmp_path: Path, text: str, name: str = "d.toml") -> Path:
    f = tmp_path / name
    f.write_text(text, encoding="utf-8")
    return f


def forbid(monkeypatch: pytest.MonkeyPatch, target: str) -> None:
    """Make ``target`` fail the test if called: validation must happen before the work."""

    def work(*a: object, **k: object) -> None:
        raise AssertionError(f"{target} ran although the input is invalid")

    module, _, name = target.rpartition(".")
    monkeypatch.setattr(importlib.import_module(module), name, work)


# ---------------------------------------------------------------- 1. memory grows without limit


def test_design_delay_is_capped_at_load_time(tmp_path: Path) -> None:
    f = design(tmp_path, OURS.replace("delay = 1 ", "delay = 1000000000 "))
    with pytest.raises(FileFormatError, match=r"control\.delay"):
        load_design(f)
    one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "control.delay", "100")


def test_design_load_masses_list_is_capped(tmp_path: Path) -> None:
    masses = ", ".join(["1.0"] * 200_000)
    f = design(
        tmp_path, OURS.replace("load_masses = [1.0, 10.0, 25.0]", f"load_masses = [{masses}]")
    )
    one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "load_masses", "200,000")


def test_sampled_bound_samples_are_capped(monkeypatch: pytest.MonkeyPatch) -> None:
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    one_error(
        ["sampled", "bound", "kd", *LP, "--range", "kd=0:5000", "--samples", "100000000"],
        "--samples",
    )


@pytest.mark.parametrize("device", ["/dev/zero", "fifo", "dir"])
def test_device_fifo_and_directory_are_refused_before_reading(tmp_path: Path, device: str) -> None:
    path = {"/dev/zero": "/dev/zero", "fifo": str(tmp_path / "p"), "dir": str(tmp_path)}[device]
    if device == "fifo":
        os.mkfifo(path)  # opening it for reading without a writer must not wait
    one_error(["rig", "show", "--rig", path], path, "not a rig file")
    one_error(["simulate", *LP, "--set", "kd=500", "--load-mass", "1", "--trajectory", path], path)


def test_large_files_are_refused_by_size(tmp_path: Path) -> None:
    big = tmp_path / "big.toml"
    big.write_bytes(b"# " + b"x" * limits.MAX_TEXT_FILE_BYTES)
    with pytest.raises(FileFormatError, match="larger than the limit"):
        read_text_file(big)
    one_error(["rig", "show", "--rig", str(big)], "larger than the limit")


def test_design_rig_file_must_be_a_small_regular_file(tmp_path: Path) -> None:
    for target in ("/dev/zero", str(tmp_path / "missing.toml")):
        f = design(tmp_path, OURS.replace('preset = "paper"', f'file = "{target}"'))
        one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "rig.file", target)


def test_missing_file_message_has_no_errno(tmp_path: Path) -> None:
    err = one_error(["rig", "show", "--rig", str(tmp_path / "nope.toml")], "No such file")
    assert "Errno" not in err


# ---------------------------------------------------------------- 2. deeply nested TOML


@pytest.mark.parametrize(
    "nest", ["a = " + "[" * 500 + "]" * 500, "a = " + "{b = " * 500 + "1" + "}" * 500]
)
def test_deeply_nested_toml_is_one_line(tmp_path: Path, nest: str) -> None:
    f = design(tmp_path, nest + "\n")
    with pytest.raises(FileFormatError, match="nested too deeply"):
        loads_strict(f.read_text())
    one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "nested too deeply")
    one_error(["rig", "show", "--rig", str(f)], "nested too deeply")
    one_error(["rig", "sweep", "--rig", str(f)], "nested too deeply")


def test_moderate_nesting_beyond_the_limit_is_refused() -> None:
    with pytest.raises(FileFormatError, match="limit is 8"):
        loads_strict("a = " + "[" * 20 + "]" * 20)


# ---------------------------------------------------------------- 3. step counts


def test_rig_step_counts_are_capped_at_load_time(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    text = (
        PAPER_RIG.replace("rate = 500.0", "rate = 1000000.0")
        .replace("substeps = 10", "substeps = 10000")
        .replace("horizon = 3.0", "horizon = 10000.0")
        .replace("settle_cap = 2.0", "settle_cap = 2.0")
    )
    f = design(tmp_path, text, "rig.toml")
    with pytest.raises(FileFormatError, match=r"experiment\.horizon"):
        load_rig(f)
    forbid(monkeypatch, "seapass.rig.experiment.run_experiment")
    one_error(["rig", "sweep", "--rig", str(f)], "control periods per run")


def test_twin_batch_is_capped_before_allocation() -> None:
    from seapass.rig.twin import simulate_loop

    rig = paper_rig()
    with pytest.raises(ParameterError, match="recorded samples"):
        simulate_loop(rig, load_mass=[0.1] * 5000, duration=10.0, kp_actuator=100.0)


def test_sampled_delay_is_capped(monkeypatch: pytest.MonkeyPatch) -> None:
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    forbid(monkeypatch, "seapass.sampled.passivity.sampled_passivity")
    one_error(
        ["sampled", "bound", "kd", *LP, "--range", "kd=0:5000", "--delay", "1000000"], "--delay"
    )
    one_error(["sampled", "check", *LP, "--set", "kd=5", "--delay", "1000000"], "--delay")


# ---------------------------------------------------------------- 4. a scheduler that is not Dask


@contextlib.contextmanager
def fake_server(reply: bytes | None):
    """A TCP server that sends ``reply`` (None: nothing) to every connection."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(4)
    conns: list[socket.socket] = []
    stop = threading.Event()

    def serve() -> None:
        srv.settimeout(0.1)
        while not stop.is_set():
            try:
                c, _ = srv.accept()
            except OSError:
                continue
            conns.append(c)
            if reply is not None:
                c.sendall(reply)

    t = threading.Thread(target=serve, daemon=True)
    t.start()
    try:
        yield f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    finally:
        stop.set()
        t.join()
        for c in conns:
            c.close()
        srv.close()


def dask_greeting() -> bytes:
    """What a Dask scheduler sends first: a length prefix, one frame, a msgpack map."""
    frame = msgpack.packb({"compression": None, "python": (3, 11, 7), "pickle-protocol": 5})
    body = struct.pack("<QQ", 1, len(frame)) + frame
    return struct.pack("<Q", len(body)) + body


@pytest.mark.parametrize(
    ("reply", "needle"),
    [(None, "within"), (b"HTTP/1.1 200 OK\r\n\r\n" * 50, "answers like a Dask scheduler")],
    ids=["silent", "http"],
)
def test_scheduler_probe_is_bounded_and_one_line(reply: bytes | None, needle: str) -> None:
    with fake_server(reply) as address:
        # silent: the probe's own deadline must end it (whatever the load, nothing comes);
        # http: the answer ends it, the deadline only guards against a fake that never runs
        with pytest.raises(ConnectionError, match=needle):
            probe_scheduler(address, timeout=0.5 if reply is None else BLOCKED_S)


def test_scheduler_probe_accepts_a_dask_greeting_and_refuses_closed_ports() -> None:
    with fake_server(dask_greeting()) as address:
        probe_scheduler(address, timeout=BLOCKED_S)  # the greeting ends it
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with pytest.raises(ConnectionError, match="refused"):
        probe_scheduler(f"tcp://127.0.0.1:{port}", timeout=BLOCKED_S)  # refused at once


def test_cli_sweep_with_a_fake_scheduler_is_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import seapass.sweep.cluster as cluster

    monkeypatch.setattr(cluster, "SCHEDULER_TIMEOUT", 0.5)
    with fake_server(b"\xff" * 64) as address:
        one_error(
            ["sweep", *LP, "--grid", "kd=0:10:5", "--no-metrics", "--out", str(tmp_path / "s.csv"),
             "--scheduler", address],
            "Dask scheduler",
        )  # fmt: skip


# ---------------------------------------------------------------- 5. rtol that never ends


@pytest.mark.parametrize("rtol", ["0", "1e-300", "1e-13", "nan", "-1"])
def test_sampled_bound_rtol_is_validated(rtol: str, monkeypatch: pytest.MonkeyPatch) -> None:
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    one_error(["sampled", "bound", "kd", *LP, "--range", "kd=0:5000", "--rtol", rtol], "--rtol")


def test_rtol_below_the_smallest_enclosure_width_is_refused(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the certified bound encloses each edge to rtol relative to the edge: any rtol from
    # MIN_RTOL up is reachable in doubles, even on a range far from 0
    forbid(monkeypatch, "seapass.sampled.bound.sampled_passive_bound")
    one_error(
        ["sampled", "bound", "kd", *LP, "--range", "kd=1e15:1.0000001e15", "--rtol", "1e-13"],
        "--rtol 1e-13",
    )


# ---------------------------------------------------------------- 6. unwritable --out, found first


def test_dangling_symlink_out_fails_before_work(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    link = tmp_path / "out"
    link.symlink_to(tmp_path / "nowhere" / "x")
    forbid(monkeypatch, "seapass.report.reproduce.reproduce")
    one_error(["reproduce", "--out", str(link), "--stages", "tables"], "--out", "does not exist")
    forbid(monkeypatch, "seapass.analysis.witness.find_destabilizing_environment")
    one_error(["witness", "--Z", "(s - 1)/(s + 1)", "--out", str(link / "w")], "symbolic link")
    forbid(monkeypatch, "seapass.analysis.region.passive_map")
    region = ["region", "kd", "b", "--D1", "k1", "--CL", "kd", "--set", "m=1", "--set", "k1=1000",
              "--range", "kd=0:1", "--range", "b=0:1", "--plot", str(link / "r.png")]  # fmt: skip
    one_error(region, "--plot", "does not exist")


def test_file_where_a_directory_is_needed_fails_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    f = tmp_path / "file"
    f.write_text("x")
    forbid(monkeypatch, "seapass.report.reproduce.reproduce")
    one_error(["reproduce", "--out", str(f), "--stages", "tables"], "not a directory")
    one_error(["tables", "--out", str(f / "sub")], "not a directory")


@contextlib.contextmanager
def read_only_dir(path: Path):
    """A directory nobody can write in: mode 0555, and for root the immutable attribute."""
    path.mkdir()
    path.chmod(0o555)
    immutable = False
    if os.geteuid() == 0:  # root ignores the mode bits
        proc = subprocess.run(["chattr", "+i", str(path)], capture_output=True, check=False)
        if proc.returncode != 0:
            path.chmod(0o755)
            pytest.skip("running as root without chattr +i: no read-only directory to test")
        immutable = True
    try:
        yield path
    finally:
        if immutable:
            subprocess.run(["chattr", "-i", str(path)], check=True)
        path.chmod(0o755)


def test_read_only_out_fails_before_work(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    with read_only_dir(tmp_path / "ro") as ro:
        forbid(monkeypatch, "seapass.report.reproduce.reproduce")
        one_error(
            ["reproduce", "--out", str(ro / "r"), "--stages", "tables"], "--out", "cannot write"
        )
        forbid(monkeypatch, "seapass.analysis.witness.find_destabilizing_environment")
        one_error(["witness", "--Z", "(s - 1)/(s + 1)", "--out", str(ro)], "cannot write in")
        forbid(monkeypatch, "seapass.sim.simulate.simulate")
        sim = ["simulate", *LP, "--set", "kd=5", "--load-mass", "1", "--plot", str(ro / "f.png")]
        one_error(sim, "--plot", "cannot write in")
        assert list(ro.iterdir()) == []


# ---------------------------------------------------------------- 7. design values too loose


@pytest.mark.parametrize(
    ("old", "new", "key"),
    [
        ("rate = 500.0", "rate = 1e-300", "control.rate"),
        ("horizon = 10.0", "horizon = 1e12", "simulation.horizon"),
        ("step = 0.5", "step = 1e9", "simulation.step"),
        ("velocity_filter = 50.0", "velocity_filter = 1e300", "control.velocity_filter"),
        ("tune_mass = 10.0", "tune_mass = 1e300", "simulation.tune_mass"),
        ("kd = 1708.0", "kd = 1e-400", "too small for a float"),
    ],
)
def test_design_values_out_of_range_are_refused(
    tmp_path: Path, old: str, new: str, key: str
) -> None:
    assert old in OURS
    f = design(tmp_path, OURS.replace(old, new))
    with pytest.raises(FileFormatError, match=key):
        load_design(f)


# ---------------------------------------------------------------- 8. output directories


def tiny_report(title: str = "t", text: str = "hello") -> Report:
    return Report(title=title, intro="intro", sections=(Section(key="a", title="A", text=text),))


def test_symlinked_out_is_updated_through_the_link(tmp_path: Path) -> None:
    real = tmp_path / "real"
    link = tmp_path / "link"
    write_report(tiny_report(text="first"), real)
    (real / "data" / "stale.csv").write_text("seapass wrote this once")  # listed below
    listed = read_manifest(real)
    assert listed is not None and "data/findings.json" in listed
    write_manifest(real, {**listed, "data/stale.csv": file_digest(real / "data" / "stale.csv")})
    link.symlink_to(real, target_is_directory=True)
    write_report(tiny_report(text="second"), link)
    assert link.is_symlink() and os.readlink(link) == str(real)
    assert "second" in (real / "report.md").read_text()
    assert not (real / "data" / "stale.csv").exists()  # seapass's own old file is gone
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "real"]  # no leftovers


def test_files_the_user_added_are_kept(tmp_path: Path) -> None:
    out = tmp_path / "r"
    write_report(tiny_report(text="first"), out)
    (out / "notes.txt").write_text("mine")
    (out / "mine").mkdir()
    (out / "mine" / "plot.png").write_bytes(b"png")
    (out / "empty").mkdir()
    write_report(tiny_report(text="second"), out)
    assert (out / "notes.txt").read_text() == "mine"
    assert (out / "mine" / "plot.png").read_bytes() == b"png"
    assert (out / "empty").is_dir()
    assert "second" in (out / "report.md").read_text()


def test_a_foreign_file_where_seapass_writes_stops_the_run_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "r"
    write_report(tiny_report(), out)
    (out / "figures").mkdir(exist_ok=True)
    (out / "figures" / "my.png").write_bytes(b"mine")
    with pytest.raises(OutputPathError, match=r"figures/my\.png"):
        check_output_dir(out)
    forbid(monkeypatch, "seapass.report.reproduce.reproduce")
    one_error(
        ["reproduce", "--out", str(out), "--stages", "tables"],
        "my.png",
        "was not written by seapass",
    )
    assert (out / "figures" / "my.png").read_bytes() == b"mine"


def test_old_marker_without_manifest_keeps_files_outside_the_report_names(tmp_path: Path) -> None:
    out = tmp_path / "r"
    (out / "data").mkdir(parents=True)
    (out / "data" / "old.csv").write_text("old")
    (out / "report.md").write_text("old")
    (out / LEGACY_MARKER).write_text("written by seapass; this directory is replaced as a whole\n")
    (out / "notes.txt").write_text("mine")
    write_report(tiny_report(), out)
    assert (out / "notes.txt").read_text() == "mine"
    assert not (out / "data" / "old.csv").exists()


# ---------------------------------------------------------------- 9. text fields


def test_title_length_is_capped(tmp_path: Path) -> None:
    f = design(tmp_path, OURS.replace('title = "', 'title = "' + "x" * 300))
    with pytest.raises(FileFormatError, match="title: 3"):
        load_design(f)
    rig = design(
        tmp_path, PAPER_RIG.replace('description = "', 'description = "' + "y" * 5000), "rig.toml"
    )
    with pytest.raises(FileFormatError, match="description"):
        load_rig(rig)


def test_huge_title_file_is_refused_by_size(tmp_path: Path) -> None:
    f = design(tmp_path, OURS.replace('title = "', 'title = "' + "x" * 20_000_000))
    one_error(["analyze", str(f), "--out", str(tmp_path / "o")], "larger than the limit")


def test_html_in_a_title_is_shown_not_run_in_markdown(tmp_path: Path) -> None:
    md = render_markdown(
        tiny_report(title="<script>alert(1)</script> ok", text="<img src=x onerror=y>")
    )
    assert "<script>" not in md and "<img" not in md
    assert "&lt;script>alert(1)&lt;/script> ok" in md
    f = design(tmp_path, OURS.replace('title = "', 'title = "<script>alert(1)</script>'))
    assert load_design(f).title.startswith("<script>")  # accepted as text, escaped on output


# ---------------------------------------------------------------- 10. input hygiene


def test_syntax_warning_does_not_add_a_line() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        err = one_error(["check", "--Z", "(40)**1inf"], "cannot parse")
    assert "SyntaxWarning" not in err


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("ｓ + 1", "write 's'"),
        ("𝑠 + 1", "write 's'"),
        ("٣*s + 1", "write '3'"),
        ("s\u200b+1", "U+200B"),
    ],
)
def test_unicode_lookalikes_are_refused_naming_the_character(text: str, shown: str) -> None:
    one_error(["check", "--Z", text], "non-ASCII", shown)


def test_arabic_indic_digits_in_values_are_refused() -> None:
    one_error(["check", *LP, "--set", "kd=٣"], "non-ASCII", "write '3'")


def test_values_that_underflow_are_refused() -> None:
    one_error(["check", *LP, "--set", "kd=1e-400"], "too small for a float")
    one_error(["check", "--Z", "1e-400*s + 1"], "too small for a float")
    code, _, _ = cli(["check", *LP, "--set", "kd=4.9e-324"])  # denormal, but not zero
    assert code == 0


def test_tiny_load_mass_is_an_error_not_an_unstable_verdict() -> None:
    ours = ["--D1", "k1 + b1*s", "--CA", "kd + bd*s", "--set", "m=1", "--set", "b=10",
            "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25", "--set", "kd=1000"]  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # scipy overflow warnings must not escape either
        for mass in ("1e-300", "1e-6"):
            err = one_error(["simulate", *ours, "--load-mass", mass], "too stiff")
            assert "unstable" not in err


def test_every_limit_is_documented() -> None:
    doc = (REPO / "docs" / "verification.md").read_text()
    for name in limits.__all__:
        if name.isupper():
            assert f"`{name}`" in doc, name
