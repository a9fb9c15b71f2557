"""The one progress protocol (issue 21 item 6): implementations, old spellings, interrupts."""

from __future__ import annotations

import io
import re
from collections.abc import Callable
from pathlib import Path

import pytest

from long_jobs import Recorder
from seapass.errors import ParameterError, SeapassDeprecationWarning
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.progress import NoProgress, Progress, TextProgress, as_progress, task

SRC = Path(__file__).resolve().parents[1] / "src" / "seapass"


def test_implementations_follow_the_protocol() -> None:
    for p in (NoProgress(), TextProgress(io.StringIO()), Recorder()):
        assert isinstance(p, Progress)
    assert not isinstance(object(), Progress)


def test_text_progress_writes_one_line_per_task_two_levels_deep() -> None:
    out = io.StringIO()
    p = TextProgress(out)
    with task(p, "analyze x: 2 stages", 2):
        with task(p, "[1/2] sampled:  Sampled-data\npassivity"):
            with task(p, "sampled bound of kd", 100):  # a third level: no line
                p.advance(50, note="half")
        p.advance()
    assert out.getvalue() == "analyze x: 2 stages\n  [1/2] sampled: Sampled-data passivity\n"
    assert p.open == 0
    p.close()  # more closes than starts never go negative
    assert p.open == 0
    with pytest.raises(ParameterError, match="depth"):
        TextProgress(depth=0)


def test_task_closes_when_the_job_is_interrupted() -> None:
    rec = Recorder()
    with pytest.raises(KeyboardInterrupt), task(rec, "job", 3):
        raise KeyboardInterrupt
    assert rec.calls == [("start", "job", 3), ("close",)]


def test_old_spellings_warn_and_still_work(capsys: pytest.CaptureFixture[str]) -> None:
    assert isinstance(as_progress(None, where="f"), NoProgress)
    rec = Recorder()
    assert as_progress(rec, where="f") is rec
    with pytest.warns(SeapassDeprecationWarning, match=r"f\(progress=False\)"):
        assert isinstance(as_progress(False, where="f"), NoProgress)
    with pytest.warns(SeapassDeprecationWarning, match=r"f\(progress=True\)"):
        shown = as_progress(True, where="f")
    shown.start("on stderr")
    shown.close()
    assert capsys.readouterr().err == "on stderr\n"
    seen: list[tuple[int, int | None]] = []
    with pytest.warns(SeapassDeprecationWarning, match="callable"):
        old = as_progress(
            lambda d, t: seen.append((d, t)),
            where="f",
            call=lambda f: lambda done, total, note: f(done, total),
        )
    with task(old, "outer", 2):
        with task(old, "inner", 9):
            old.advance(5)  # inner steps are not the old callable's rows
        old.advance()
        old.advance()
    assert seen == [(1, 2), (2, 2)]
    with pytest.raises(ParameterError, match="progress must be"):
        as_progress(lambda d, t: None, where="f")  # f never took a callable
    with pytest.raises(ParameterError, match="progress must be"):
        as_progress("yes", where="f")


def test_no_isatty_in_the_library() -> None:
    """Only the command line asks whether a terminal is attached."""
    found = [
        str(p.relative_to(SRC))
        for p in SRC.rglob("*.py")
        if "cli" not in p.relative_to(SRC).parts[:1] and "isatty" in p.read_text(encoding="utf-8")
    ]
    assert found == []


def test_every_long_job_takes_a_progress() -> None:
    """The long jobs' ``progress`` is a Progress (None by default), not a bool or callable."""
    import inspect

    from seapass.export.c_code import export_c
    from seapass.export.deployment import plan_deployment
    from seapass.paper.simstudy import run_simulation_study
    from seapass.paper.tables import build_tables
    from seapass.report.analyze import analyze
    from seapass.report.pipeline import run_stages
    from seapass.report.reproduce import reproduce
    from seapass.rig.experiment import run_experiment
    from seapass.robust.sampled_intervals import robust_sampled_intervals
    from seapass.sampled.bound import sampled_passive_bound
    from seapass.sampled.region import sampled_region
    from seapass.sweep.runner import run_design_sweep
    from seapass.tuning.optimize import tune

    jobs = (export_c, plan_deployment, run_simulation_study, build_tables, analyze, run_stages,
            reproduce, run_experiment, sampled_passive_bound, sampled_region, run_design_sweep,
            tune, robust_sampled_intervals)  # fmt: skip
    for job in jobs:
        p = inspect.signature(job).parameters["progress"]
        assert p.default is None, job.__name__
        assert re.search(r"Progress", str(p.annotation)), (job.__name__, p.annotation)


# ------------------------------------------------------------------ interrupts


def test_interrupted_tuning_leaves_the_library_usable() -> None:
    from seapass.tuning.optimize import tune
    from seapass.tuning.problem import QUICK_OPTIONS

    rec = Recorder(stop_at=2)
    with pytest.raises(KeyboardInterrupt):
        tune("APD", options=QUICK_OPTIONS, progress=rec)
    assert rec.balanced and rec.calls[0] == ("start", "tuning APD: 12 generations", 12)
    assert [c[0] for c in rec.calls] == ["start", "advance", "advance", "close"]
    again = Recorder()
    a = tune("APD", options=QUICK_OPTIONS, progress=again)
    b = tune("APD", options=QUICK_OPTIONS)
    assert dict(a.gains) == dict(b.gains) and a.generations == b.generations == 12
    assert again.balanced and sum(c[1] for c in again.calls if c[0] == "advance") == 12


def test_tune_callback_is_deprecated_but_still_stops_the_run() -> None:
    from seapass.tuning.optimize import tune
    from seapass.tuning.problem import QUICK_OPTIONS

    seen: list[int] = []

    def stop(generation: int, best: float) -> None:
        seen.append(generation)
        if generation == 3:
            raise KeyboardInterrupt

    with (
        pytest.warns(SeapassDeprecationWarning, match="callback"),
        pytest.raises(KeyboardInterrupt),
    ):
        tune("ours", options=QUICK_OPTIONS, callback=stop)
    assert seen == [1, 2, 3]


def _wall(**values: float) -> SEA:
    return SEA(D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1005, b1=30, **values))


def test_interrupted_sampled_bound_leaves_the_library_usable() -> None:
    from seapass.sampled.bound import sampled_passive_bound

    loop = SampledLoop(period=0.002, delay=1)
    sea = _wall(bd=25)
    rec = Recorder(stop_at=1)
    with pytest.raises(KeyboardInterrupt):
        sampled_passive_bound(sea, "kd", loop=loop, lo=0, hi=2e4, rtol=1e-6, progress=rec)
    assert rec.balanced
    again = Recorder()
    r = sampled_passive_bound(sea, "kd", loop=loop, lo=0, hi=2e4, rtol=1e-6, progress=again)
    fresh = sampled_passive_bound(sea, "kd", loop=loop, lo=0, hi=2e4, rtol=1e-6)
    assert r.to_dict() == fresh.to_dict() and not r.budget_exhausted
    assert again.balanced and sum(c[1] for c in again.calls if c[0] == "advance") == 100


def test_sampled_region_reports_rows_and_their_bounds() -> None:
    from seapass.sampled.region import sampled_region

    ideal = SampledLoop(period=0.002)
    rec = Recorder()
    z = sampled_region(
        _wall().with_values(kd=None, bd=None), "kd", "bd", loop=ideal, p1_range=(0, 1e5),
        p2_range=(0, 50), n=2, setups=[ideal], progress=rec,
    )  # fmt: skip
    starts = [c[1] for c in rec.calls if c[0] == "start"]
    assert starts[0] == "Z-width map of kd against bd: 2 rows"
    assert sum(s.startswith("sampled bound of kd") for s in starts) == 2
    assert rec.balanced and not z.budget_exhausted
    rows: list[tuple[int, int]] = []
    with pytest.warns(SeapassDeprecationWarning):
        sampled_region(
            _wall().with_values(kd=None, bd=None), "kd", "bd", loop=ideal, p1_range=(0, 1e5),
            p2_range=(0, 50), n=2, setups=[ideal], progress=lambda d, t: rows.append((d, t)),
        )  # fmt: skip
    assert rows == [(1, 2), (2, 2)]


def _jobs(tmp: Path, sweep: object) -> dict[str, Callable[[Progress], object]]:
    """Every long job outside analyze, each on a small input, taking the progress."""
    from seapass.export.c_code import export_c
    from seapass.paper.simstudy import run_simulation_study
    from seapass.paper.tables import build_tables
    from seapass.report.reproduce import reproduce
    from seapass.rig.experiment import run_experiment
    from seapass.rig.rigfile import paper_rig
    from seapass.sweep.runner import run_design_sweep

    ours = SRC.parents[1] / "examples" / "ours.toml"
    return {
        "sweep": lambda p: run_design_sweep(sweep, tmp / "s.parquet", progress=p),  # type: ignore[arg-type]
        "rig sweep": lambda p: run_experiment(
            paper_rig(), designs=("LP",), load_masses=[10.0], kd=[0.0, 100.0], progress=p
        ),
        "paper study": lambda p: run_simulation_study(
            designs=("LP",), quick=True, horizon=1.0, dt=2e-3, progress=p
        ),
        "paper tables": lambda p: build_tables(progress=p),
        "export c": lambda p: export_c(ours, tmp / "c", set_gains=True, tunable=["kd"], progress=p),
        "reproduce": lambda p: reproduce(stages=["stiffness"], quick=True, progress=p),
    }


@pytest.mark.parametrize(
    "job", ["sweep", "rig sweep", "paper study", "paper tables", "export c", "reproduce"]
)
def test_every_long_job_stops_cleanly_at_an_interrupt(
    job: str, tmp_path: Path, small_sweep: object
) -> None:
    """KeyboardInterrupt from the progress's first advance: it propagates, every task is
    closed, no output is left half-written, and the same call then completes (the
    library keeps no state from the interrupted run)."""
    run = _jobs(tmp_path, small_sweep)[job]
    rec = Recorder(stop_at=1)
    with pytest.raises(KeyboardInterrupt):
        run(rec)
    assert rec.balanced and rec.calls[0][0] == "start" and rec.advances == 1
    left = sorted(p.name for p in tmp_path.iterdir())
    # a sweep keeps its finished parts to resume from (each written atomically)
    assert left == (["s.parquet.parts"] if job == "sweep" else [])
    if job in ("paper tables", "reproduce"):
        return  # complete runs of these are tested elsewhere (tens of seconds each)
    again = Recorder()
    if job == "sweep":
        from seapass.sweep.runner import run_design_sweep

        run_design_sweep(small_sweep, tmp_path / "s.parquet", resume=True, progress=again)  # type: ignore[arg-type]
    else:
        run(again)
    assert again.balanced and again.advances >= 1
