"""The one guarded reader of user files (issue 20, item 3).

`open_text_file` / `read_text_file` refuse FIFOs, devices, directories and
files over their cap before reading, and a source scan keeps every other read
of a file out of seapass: any ``read_text``, ``read_bytes``, ``open``,
``np.loadtxt``, ``pd.read_*``, ``pq.read_*``, ``tomllib.load`` ... outside
``seapass.files`` must be on the allow-list below, with the reason it does not
read a path a user gave (package data, seapass's own files, writes) or reads
one only after `check_input_file`.
"""

from __future__ import annotations

import ast
import os
import threading
from pathlib import Path

import pytest

from helpers import (
    LP_ARGV,
    CallScan,
    one_error,
    scan_source,
    scan_text,
)
from seapass.errors import FileFormatError
from seapass.files import limits
from seapass.files.textfile import check_input_file, open_text_file, read_text_file

READ_ATTRIBUTES = frozenset(
    "read_text read_bytes open load loads_file loadtxt genfromtxt fromfile read_csv read_table "
    "read_parquet read_json read_excel read_pickle read_feather read_schema read_metadata "
    "ParquetFile open_csv dataset".split()
)

#: (module, enclosing function, called attribute) -> why it is not a read of a user path
ALLOWED = {
    ("cli/__init__.py", "_stdout_closed", "open"): "os.open of os.devnull for writing, put "
    "over a standard output whose reader is gone",
    ("explore/reports.py", "ReportJob.log", "read_text"): "the log seapass's own analyze "
    "subprocess writes in the report directory the explorer created",
    ("explore/reports.py", "ReportJobs.start", "open"): "a write (wb) of that log",
    ("explore/server.py", "serve.announce", "open"): "webbrowser.open: a URL, not a file",
    ("export/c_code.py", "_environment.load", "read_text"): "package data (templates)",
    ("report/render.py", "_resource", "read_text"): "package data (templates)",
    ("report/output.py", "_link_same", "read_bytes"): "a file of a report seapass wrote "
    "itself, compared before hard-linking it into the new report",
    ("rig/packaged.py", "rig_template", "read_text"): "package data",
    ("rig/rigfile.py", "paper_rig", "read_text"): "package data",
    ("sweep/location.py", "Location.reader", "open"): "fsspec object (remote: no FIFO)",
    ("sweep/location.py", "Location.read_text", "open"): "fsspec object, read with a cap",
    ("sweep/location.py", "Location.save_via.save", "open"): "a write (wb) of a temporary file",
    ("sweep/location.py", "Location.save_via", "open"): "a write (wb) of a temporary object",
    ("sweep/runner.py", "run_design_sweep", "open"): "SweepStore.open: not a file",
    ("sweep/store.py", "SweepStore._count_from_disk", "read_table"): "Location.reader checked",
    ("sweep/store.py", "_read_existing_manifest", "read_text"): "Location.read_text (guarded)",
    ("sweep/store.py", "consolidate.tables", "read_table"): "Location.reader checked",
    ("sweep/store.py", "_part_schema", "read_schema"): "Location.reader checked",
    ("sweep/store.py", "iter_batches", "open_csv"): "Location.reader checked",
    ("sweep/store.py", "iter_batches", "ParquetFile"): "Location.reader checked",
    ("sweep/store.py", "schema_columns", "open_csv"): "Location.reader checked",
}


class _Reads(CallScan):
    def call_name(self, node: ast.Call) -> str | None:
        f = node.func
        if isinstance(f, ast.Attribute) and f.attr in READ_ATTRIBUTES:
            return f.attr
        if isinstance(f, ast.Name) and f.id == "open":
            return "open"
        return None


def file_reads() -> list[tuple[tuple[str, str, str], int, str]]:
    return scan_source(_Reads)


def test_every_file_read_goes_through_seapass_files() -> None:
    reads = file_reads()
    assert reads, "the scan finds nothing: it is broken"
    stray = [f"{m}:{line} {text}" for (m, s, n), line, text in reads if (m, s, n) not in ALLOWED]
    assert not stray, (
        "read user files with seapass.files.textfile (read_text_file, open_text_file, "
        "check_input_file), or add the call to ALLOWED with the reason:\n" + "\n".join(stray)
    )
    stale = sorted(set(ALLOWED) - {key for key, _, _ in reads})
    assert not stale, f"ALLOWED lists calls that are gone: {stale}"


def test_the_scan_sees_the_reads_it_forbids(tmp_path: Path) -> None:
    code = (
        "import numpy as np, pandas as pd, tomllib\n"
        "def f(p):\n"
        "    p.read_text(); p.read_bytes(); open(p); np.loadtxt(p); pd.read_csv(p)\n"
        "    tomllib.load(p)\n"
    )
    assert sorted(scan_text(_Reads, code)) == sorted(
        ["read_text", "read_bytes", "open", "loadtxt", "read_csv", "load"]
    )


# ------------------------------------------------------------------ the guarded readers


@pytest.fixture
def fifo(tmp_path: Path):
    """A FIFO, and a thread that opens and closes its write end until the test ends.

    A reader that waited for a writer (the bug) is released and reads an empty
    file, so a regression fails on the message instead of hanging the suite.
    """
    path = tmp_path / "fifo"
    os.mkfifo(path)
    done = threading.Event()

    def release() -> None:
        while not done.wait(0.05):
            try:
                os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
            except OSError:  # no reader yet
                pass

    thread = threading.Thread(target=release, daemon=True)
    thread.start()
    yield path
    done.set()
    thread.join()


@pytest.mark.parametrize("reader", ["read_text_file", "open_text_file", "check_input_file"])
def test_fifos_devices_and_directories_are_refused_at_once(fifo: Path, reader: str) -> None:
    def read(path: Path) -> object:
        if reader == "read_text_file":
            return read_text_file(path)
        if reader == "check_input_file":
            return check_input_file(path)
        with open_text_file(path) as fh:
            return fh.read()

    for path, kind in ((fifo, r"a pipe \(FIFO\)"), (Path("/dev/zero"), "a character device")):
        with pytest.raises(FileFormatError, match=f"is {kind}, not a file"):
            read(path)
    with pytest.raises(FileFormatError, match="is a directory"):
        read(fifo.parent)


def test_stream_reads_lines_and_refuses_a_file_that_grows(tmp_path: Path) -> None:
    f = tmp_path / "t.csv"
    f.write_text("a,b\nc,é\r\n")
    with open_text_file(f) as fh:
        assert list(fh) == ["a,b\n", "c,é\r\n"]  # newline="" keeps \r\n for csv
    f.write_text("x" * 100)
    with pytest.raises(FileFormatError, match="larger than the limit of 99 bytes"):
        with open_text_file(f, max_bytes=99):
            pass
    with open_text_file(f, max_bytes=100) as fh:
        with f.open("a") as grow:
            grow.write("more")
        with pytest.raises(FileFormatError, match="larger than the limit"):
            fh.read()


def test_stream_refuses_text_that_is_not_utf8(tmp_path: Path) -> None:
    f = tmp_path / "t.csv"
    f.write_bytes(b"ok\n\xff\xfe\n")
    with pytest.raises(FileFormatError, match="not a UTF-8 text file"):
        with open_text_file(f) as fh:
            fh.read()


def test_kind_only_check(tmp_path: Path) -> None:
    f = tmp_path / "big"
    with f.open("wb") as fh:
        fh.truncate(10 << 30)  # sparse: 10 GiB, nothing written
    assert check_input_file(f, max_bytes=None) == f
    with pytest.raises(FileFormatError, match="larger than the limit"):
        check_input_file(f)


# ------------- devices, FIFOs, large and missing files (moved from test_hardening, issue 12 item 1)


@pytest.mark.parametrize("device", ["/dev/zero", "fifo", "dir"])
def test_device_fifo_and_directory_are_refused_before_reading(tmp_path: Path, device: str) -> None:
    path = {"/dev/zero": "/dev/zero", "fifo": str(tmp_path / "p"), "dir": str(tmp_path)}[device]
    if device == "fifo":
        os.mkfifo(path)  # opening it for reading without a writer must not wait
    one_error(["rig", "show", "--rig", path], path, "not a rig file")
    one_error(
        ["simulate", *LP_ARGV, "--set", "kd=500", "--load-mass", "1", "--trajectory", path], path
    )


def test_large_files_are_refused_by_size(tmp_path: Path) -> None:
    big = tmp_path / "big.toml"
    big.write_bytes(b"# " + b"x" * limits.MAX_TEXT_FILE_BYTES)
    with pytest.raises(FileFormatError, match="larger than the limit"):
        read_text_file(big)
    one_error(["rig", "show", "--rig", str(big)], "larger than the limit")


def test_missing_file_message_has_no_errno(tmp_path: Path) -> None:
    err = one_error(["rig", "show", "--rig", str(tmp_path / "nope.toml")], "No such file")
    assert "Errno" not in err
