"""Report directories: updated through links, the user's files kept, foreign files stop the run."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from helpers import (
    forbid,
    one_error,
    tiny_report,
)
from seapass.errors import OutputPathError
from seapass.files.owned import file_digest, read_manifest, write_manifest
from seapass.report.output import LEGACY_MARKER, check_output_dir, write_report

# ---------------------------------- output directories (moved from test_hardening, issue 12 item 8)


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
