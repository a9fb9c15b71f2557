"""Atomic output: an interrupted write leaves the old file and no leftovers."""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
from pathlib import Path

import pytest

from helpers import LP_ARGV, forbid, one_error
from hostile import no_marker  # noqa: F401 (a fixture)
from seapass.cli import main
from seapass.files.atomic import atomic_save, atomic_write, atomic_write_text

# -------------------------------------------------------- interrupted writes (moved from test_fuzz)


class Boom(Exception):
    pass


@pytest.mark.usefixtures("no_marker")
@pytest.mark.parametrize("exc", [Boom, KeyboardInterrupt])
def test_interrupted_atomic_write_keeps_the_old_file(tmp_path, exc):
    target = tmp_path / "result.json"
    target.write_text("old")
    with pytest.raises(exc):
        with atomic_write(target) as fh:
            fh.write("new, half written")
            raise exc()
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.json"]


@pytest.mark.usefixtures("no_marker")
@pytest.mark.parametrize("exc", [Boom, KeyboardInterrupt])
def test_interrupted_atomic_save_keeps_the_old_file(tmp_path, exc):
    target = tmp_path / "figure.png"
    target.write_bytes(b"old")

    def save(path: str) -> None:
        Path(path).write_bytes(b"partial")
        raise exc()

    with pytest.raises(exc):
        atomic_save(target, save)
    assert target.read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figure.png"]


@pytest.mark.usefixtures("no_marker")
def test_atomic_write_replaces_and_cleans_up(tmp_path):
    target = tmp_path / "sub" / "a.txt"
    atomic_write_text(target, "one")
    atomic_write_text(target, "two")
    assert target.read_text() == "two"
    assert [p.name for p in target.parent.iterdir()] == ["a.txt"]


@pytest.mark.usefixtures("no_marker")
def test_interrupted_cli_output_leaves_previous_files(tmp_path, monkeypatch):
    """A KeyboardInterrupt while the witness figure is saved: old files stay, no leftovers."""
    from seapass.files.owned import MANIFEST, write_output_bytes

    out = tmp_path / "w"
    out.mkdir()
    write_output_bytes(out / "witness.png", b"old png")  # seapass's: it may be replaced
    import matplotlib.figure

    def interrupted(self, *a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", interrupted)
    argv = ["witness", "--Z", "(s - 1)/(s + 1)", "--out", str(out)]
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(argv)
    assert code == 130 and "interrupted" in err.getvalue()
    assert (out / "witness.png").read_bytes() == b"old png"
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "witness.png"]


# ------------------ an unwritable --out is found first (moved from test_hardening, issue 12 item 6)


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
        sim = [
            "simulate",
            *LP_ARGV,
            "--set",
            "kd=5",
            "--load-mass",
            "1",
            "--plot",
            str(ro / "f.png"),
        ]
        one_error(sim, "--plot", "cannot write in")
        assert list(ro.iterdir()) == []
