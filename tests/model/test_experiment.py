"""The paper's experiment in one place: every default step, horizon and load mass comes from it,
and a design file's ``[simulation]`` wins over it (``seapass tune FILE`` tunes at the file's step)."""

from __future__ import annotations

import inspect
import io
import json
import tokenize
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from seapass.batch.step_metrics import batch_step_metrics
from seapass.cli import main
from seapass.errors import ParameterError
from seapass.explore.state import ExploreState
from seapass.model.design_file import Design, load_design
from seapass.model.experiment import PAPER_EXPERIMENT, Experiment
from seapass.model.sea import SEA
from seapass.sim.scenarios import Step
from seapass.sim.simulate import simulate
from seapass.sweep.spec import GridAxis, SweepSpec
from seapass.tuning.problem import TuningOptions, resolve_problem

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src" / "seapass"

# where the paper's step, horizon and load masses used to be written out
EXPERIMENT_USERS = (
    "cli/cmd_simulate.py",
    "cli/cmd_sweep.py",
    "cli/cmd_tune.py",
    "tuning/problem.py",
    "sweep/spec.py",
    "model/design_file.py",
    "explore/state.py",
    "batch/step_metrics.py",
    "sim/scenarios.py",
    "sim/simulate.py",
    "paper/simstudy.py",
    "report/stages/simulation.py",
)


def _copy_of_ours(tmp_path: Path, step: str | None) -> Path:
    text = (ROOT / "examples" / "ours.toml").read_text(encoding="utf-8")
    assert "\nstep = 0.5\n" in text
    path = tmp_path / "ours.toml"
    path.write_text(text.replace("\nstep = 0.5\n", "\n" if step is None else f"\nstep = {step}\n"))
    return path


def _tune_json(argv: list[str]) -> dict:
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(["tune", *argv, "--tune", "kd=0:5000", "--maxiter", "1", "--popsize", "2",
                     "--no-progress", "--json"])  # fmt: skip
    assert code in (0, 1), err.getvalue()
    return json.loads(out.getvalue())


def test_tune_takes_the_step_of_the_design_file(tmp_path: Path) -> None:
    assert _tune_json([str(_copy_of_ours(tmp_path, "0.1"))])["step"] == 0.1
    assert _tune_json([str(_copy_of_ours(tmp_path, "0.1")), "--step", "0.2"])["step"] == 0.2
    assert _tune_json([str(_copy_of_ours(tmp_path, None))])["step"] == PAPER_EXPERIMENT.step


def test_the_library_resolves_given_then_file_then_experiment(tmp_path: Path) -> None:
    design = load_design(_copy_of_ours(tmp_path, "0.1"))
    assert resolve_problem(design).options.step == 0.1
    assert resolve_problem(design, options=TuningOptions(step=0.2)).options.step == 0.2
    opts = resolve_problem("ours").options
    assert (opts.step, opts.horizon, opts.load_mass) == (
        PAPER_EXPERIMENT.step,
        PAPER_EXPERIMENT.horizon,
        PAPER_EXPERIMENT.load_mass,
    )


def test_every_default_is_the_experiments() -> None:
    e = PAPER_EXPERIMENT
    sea = SEA(D1="k1", CL="kd", values={"m": 1.0, "b": 10.0, "k1": 1000.0, "kd": None})
    assert Step().size == Step(None).size == e.step  # type: ignore[arg-type]
    spec = SweepSpec(sea=sea, grid=(GridAxis("kd", 0.0, 10.0, 5.0),), step=None, load_mass=None)  # type: ignore[arg-type]
    assert (spec.step, spec.load_mass, spec.horizon) == (e.step, e.load_mass, e.screening_horizon)
    design = Design(name="d", D1="k1", CA="kd", values={"m": 1.0, "b": 10.0, "k1": 1.0, "kd": 1.0})
    assert (design.step, design.horizon, design.load_masses) == (e.step, e.horizon, e.load_masses)
    state = ExploreState(
        name="x", model={"D1": "k1", "CL": "kd"}, values={"m": 1.0, "b": 10.0, "k1": 1.0, "kd": 1.0},
        ranges={"k1": (0.0, 10.0), "kd": (0.0, 10.0)}, gain="kd", region=("kd", "k1"),
    )  # fmt: skip
    assert (state.step, state.horizon, state.load_mass) == (e.step, e.horizon, e.load_mass)
    batch = inspect.signature(batch_step_metrics).parameters
    assert (batch["step"].default, batch["horizon"].default) == (e.step, e.screening_horizon)
    assert TuningOptions().force_limit == e.force_limit
    r = simulate(sea.with_values(kd=500.0), load_mass=e.load_mass, dt=0.01)
    assert r.time[-1] == e.horizon and r.target == e.step


def test_no_literal_step_is_left_where_the_experiment_is_used() -> None:
    """No number 0.5 in the code of the modules that take the experiment (prose may say it;
    ``0.5 * x`` is arithmetic, not a step)."""
    found = []
    for rel in EXPERIMENT_USERS:
        path = SRC / rel
        with path.open("rb") as f:
            toks = [t for t in tokenize.tokenize(f.readline) if t.type not in (
                tokenize.NL, tokenize.NEWLINE, tokenize.COMMENT, tokenize.INDENT, tokenize.DEDENT)]  # fmt: skip
        for i, tok in enumerate(toks):
            if tok.type == tokenize.NUMBER and complex(tok.string) == 0.5:
                around = {toks[i - 1].string, toks[i + 1].string}
                if not around & {"*", "/"}:
                    found.append(f"{rel}:{tok.start[0]}")
    assert not found, found


@pytest.mark.parametrize(
    ("kw", "argument"),
    [
        ({"step": 0.0}, "step"),
        ({"horizon": -1.0}, "horizon"),
        ({"load_mass": float("nan")}, "load_mass"),
        ({"load_masses": ()}, "load_masses"),
        ({"load_masses": (1.0, -2.0)}, "load_masses"),
        ({"tolerance": 1.0}, "tolerance"),
        ({"force_limit": 0.0}, "force_limit"),
    ],
)
def test_an_experiment_is_checked_at_construction(kw: dict, argument: str) -> None:
    with pytest.raises(ParameterError) as info:
        Experiment(**kw)
    assert info.value.argument == argument and str(info.value).startswith(f"{argument}: ")


def test_pick_and_to_dict() -> None:
    e = Experiment(step=0.25)
    assert e.pick("step", None, None) == 0.25 and e.pick("step", None, 0.1) == 0.1
    assert e.pick("step", 0.3, 0.1) == 0.3
    assert e.to_dict()["step"] == 0.25 and "Experiment(step=0.25" in repr(e)
    assert "load masses" in e._repr_html_()
