"""Rig files speak the loop's one spelling; the old ``[control]`` keys warn and load the same."""

from __future__ import annotations

import io
import tomllib
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.errors import FileFormatError, SeapassDeprecationWarning
from seapass.model.loop import SampledLoop
from seapass.rig.packaged import rig_template
from seapass.rig.rigfile import load_rig, paper_rig, parse_rig

PAPER = Path(__file__).resolve().parents[2] / "src" / "seapass" / "data" / "paper_rig.toml"
NEW = "delay = 1\n"
NEW_FILTER = "velocity_filter = 50.0\n"


def _paper_text() -> str:
    text = PAPER.read_text(encoding="utf-8")
    assert NEW in text and NEW_FILTER in text  # the packaged rig speaks the one spelling
    return text


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("delay_samples = 1\n", NEW, "control.delay_samples is deprecated; write control.delay"),
        (
            "velocity_filter_hz = 50.0\n",
            NEW_FILTER,
            "control.velocity_filter_hz is deprecated; write control.velocity_filter",
        ),
    ],
)
def test_each_old_key_warns_and_loads_identically(old: str, new: str, message: str) -> None:
    text = _paper_text().replace(new, old)
    with pytest.warns(SeapassDeprecationWarning, match=message):
        rig = parse_rig(tomllib.loads(text))
    assert rig == paper_rig() and rig.loop == SampledLoop(rate=500.0, delay=1, velocity_filter=50.0)


def test_both_old_keys_together_and_zero_meaning_no_filter(tmp_path: Path) -> None:
    text = _paper_text().replace(NEW, "delay_samples = 1\n")
    with pytest.warns(SeapassDeprecationWarning) as caught:
        old = parse_rig(tomllib.loads(text.replace(NEW_FILTER, "velocity_filter_hz = 0.0\n")))
    assert len(caught) == 2
    unfiltered = parse_rig(tomllib.loads(_paper_text().replace(NEW_FILTER, "")))
    assert old == unfiltered and old.loop.velocity_filter is None
    assert old.control.velocity_filter is None and "velocity_filter" not in old.to_dict()["control"]
    assert parse_rig(tomllib.loads(old.to_toml())) == old  # written back in the one spelling


def test_a_key_in_both_spellings_or_a_filter_above_nyquist_is_refused() -> None:
    both = _paper_text().replace(NEW, NEW + "delay_samples = 1\n")
    with pytest.raises(FileFormatError, match=r"give control\.delay only"):
        parse_rig(tomllib.loads(both))
    fast = _paper_text().replace(NEW_FILTER, "velocity_filter = 250.0\n")
    with pytest.raises(FileFormatError, match=r"control\.velocity_filter: .*Nyquist"):
        parse_rig(tomllib.loads(fast))


def test_the_template_loads_without_a_warning(
    tmp_path: Path, recwarn: pytest.WarningsRecorder
) -> None:
    path = tmp_path / "rig.toml"
    path.write_text(rig_template(), encoding="utf-8")
    assert load_rig(path).loop.delay == 1
    assert not [w for w in recwarn if issubclass(w.category, SeapassDeprecationWarning)]


def test_the_cli_shows_an_old_key_as_one_warning_line(tmp_path: Path) -> None:
    path = tmp_path / "old.toml"
    path.write_text(_paper_text().replace(NEW, "delay_samples = 1\n"), encoding="utf-8")
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(["rig", "show", "--rig", str(path), "--json"])
    assert code == 0
    assert err.getvalue() == (
        "warning: control.delay_samples is deprecated; write control.delay\n"
    ), err.getvalue()
    assert '"delay": 1' in out.getvalue() and "delay_samples" not in out.getvalue()
