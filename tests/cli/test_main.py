"""`seapass` main: a closed standard output exits quietly, one examples header per --help,
one witness line in `check`, overshoot in percent (issue 23 item 6)."""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from seapass.cli import EXIT_STDOUT_CLOSED, build_parser, main

BIN = Path(sys.executable).parent / "seapass"
NOT_PASSIVE = ["check", "--D1", "k1", "--CL", "kd"] + [
    a for kv in ("m=1", "b=10", "k1=1000", "kd=1500") for a in ("--set", kv)
]


class _ClosedPipe(io.StringIO):
    """Standard output whose reader has gone: every write fails as a pipe does."""

    def write(self, text: str) -> int:
        raise BrokenPipeError(32, "Broken pipe")


def test_a_closed_pipe_is_quiet_in_a_real_process() -> None:
    # the read end is closed before the command starts: its first write gets EPIPE
    read, write = os.pipe()
    os.close(read)
    try:
        proc = subprocess.run(
            [str(BIN), *NOT_PASSIVE], stdout=write, stderr=subprocess.PIPE, check=False
        )
    finally:
        os.close(write)
    assert proc.stderr == b"" and proc.returncode == EXIT_STDOUT_CLOSED


def test_head_of_check_has_no_error(tmp_path: Path) -> None:
    out = subprocess.run(
        f"'{BIN}' {' '.join(NOT_PASSIVE)} | head -1",
        shell=True, capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert out.stderr == "" and out.stdout.startswith("not passive")


def test_a_broken_pipe_elsewhere_is_still_an_error(monkeypatch: pytest.MonkeyPatch) -> None:
    # stdout fine (a StringIO: no descriptor to poll), the failing write is another file's
    err = io.StringIO()
    monkeypatch.setattr(sys, "stdout", _ClosedPipe())
    with contextlib.redirect_stderr(err):
        code = main(NOT_PASSIVE)
    assert code == 2 and err.getvalue().startswith("error:")


def _parsers(p: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    out = [p]
    for action in p._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in dict.fromkeys(action.choices.values()):
                out += _parsers(sub)
    return out


def test_every_help_has_at_most_one_examples_header() -> None:
    for p in _parsers(build_parser()):
        text = p.format_help()
        assert text.count("examples:") + text.count("example:") <= 1, p.prog
    rig = next(p for p in _parsers(build_parser()) if p.prog.endswith("seapass rig"))
    text = rig.format_help()
    assert text.count("examples:") == 1 and "seapass rig fit" in text and "rig sweep" in text


def test_check_prints_the_witness_frequency_once() -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(NOT_PASSIVE) == 1
    text = out.getvalue()
    assert text.count("at w = 1 rad/s") == 1 and "witness:" not in text
    assert text.startswith("not passive: Re Z(jw) < 0 at w = 1 rad/s")
