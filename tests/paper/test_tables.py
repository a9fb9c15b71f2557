"""The wording of a bound's status in the reproduce report's findings."""

from __future__ import annotations

import pytest

from seapass.paper.tables import BoundStatus


@pytest.mark.parametrize("status", list(BoundStatus))
def test_the_phrase_reads_as_a_sentence(status: BoundStatus) -> None:
    text = f"transfer function, passivity polynomial and bound agree: {status.phrase}"
    assert "((" not in text and "agrees" not in status.phrase and ") agree" not in text


def test_the_report_says_agree_once(monkeypatch: pytest.MonkeyPatch, paper_tables: list) -> None:
    from seapass.report.pipeline import StageContext
    from seapass.report.stages import tables
    from seapass.report.stages.tables import stage_tables

    # the stage words the session's rows (derived once, tests/conftest.py)
    monkeypatch.setattr(tables, "build_tables", lambda **_: list(paper_tables))
    details = [f.detail for f in stage_tables(StageContext(quick=True)).findings]
    assert any("never passive" in d for d in details)
    assert not [d for d in details if "(agrees" in d or d.count("agree") > 1]
