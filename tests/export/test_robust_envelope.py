"""``export c --robust``: the guards' gain envelope is the robust one (issue 26, item 7).

The test of the brief: with a box whose robust gain intervals lie inside the sampled-data
ones, the envelope baked into the guards equals `robust_passive_intervals` rounded inward,
and every end it allows is passive for every plant of the box (checked by `robust_check`).
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.errors import NotPassiveError, ParameterError
from seapass.export import robust_envelope
from seapass.export.deployment import plan_deployment
from seapass.export.envelope import inward_interval
from seapass.model.design_file import load_design
from seapass.outcome import Outcome
from seapass.robust.box import uncertain_box
from seapass.robust.intervals import robust_passive_intervals
from seapass.robust.verdict import robust_check

DESIGN = """
name = "ours-box"
[model]
D1 = "k1 + b1*s"
CA = "kd + bd*s"
[parameters]
m = 1.02
b = 10.0
k1 = 1005.0
b1 = 30.0
kd = 500.0
bd = 25.0
[ranges]
kd = [0.0, 3000.0]
bd = [0.0, 100.0]
[control]
rate = 2000.0
[uncertainty]
m = [0.9, 1.1]
b1 = [20.0, 40.0]
"""


@pytest.fixture(scope="module")
def design_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    p = tmp_path_factory.mktemp("robust_export") / "ours_box.toml"
    p.write_text(DESIGN)
    return p


def test_the_guard_envelope_equals_the_robust_intervals_rounded_inward(design_file: Path) -> None:
    design = load_design(design_file)
    nominal = plan_deployment(design, force_limit=100.0, set_gains=True)
    robust = plan_deployment(design, force_limit=100.0, set_gains=True, robust=True)
    sea = design.sea()
    box = uncertain_box(sea, dict(design.uncertainty))
    for env, plain in zip(robust.gains, nominal.gains, strict=True):
        lo, hi = design.analysis_ranges()[env.name]
        res = robust_passive_intervals(
            sea.with_values(**{env.name: None}), env.name, lo, hi, box=box
        )
        ((a, b),) = [iv for iv in res.intervals if iv[0] <= env.nominal <= iv[1]]
        assert plain.low <= a and b <= plain.high  # the robust set lies in the sampled one here
        assert (env.low, env.high) == inward_interval(a, b)
        for end in (env.low, env.high):  # each end the guard allows: passive on the whole box
            assert robust_check(sea.with_values(**{env.name: end}), box=box).passive
    assert any(e.low > p.low for e, p in zip(robust.gains, nominal.gains, strict=True))
    assert any(
        "robust for every plant with b1 in [20, 40], m in [0.9, 1.1]" in n for n in robust.notes
    )


def test_the_cli_bakes_the_robust_envelope_into_the_guards(
    design_file: Path, tmp_path: Path
) -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["export", "c", str(design_file), "--out", str(tmp_path), "--set-gains",
                     "--force-limit", "100", "--robust", "--no-progress", "--json"])  # fmt: skip
    assert code == 0
    gains = json.loads(out.getvalue())["deployment"]["gains"]
    header = (tmp_path / "seapass_ctrl.h").read_text()
    assert "gain envelope robust for every plant" in header
    plan = plan_deployment(load_design(design_file), force_limit=100.0, set_gains=True, robust=True)
    for env in plan.gains:
        assert gains[env.name]["interval"] == [env.low, env.high]


def test_a_design_not_robustly_passive_or_without_a_box_is_refused(
    design_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    plain = tmp_path / "plain.toml"
    plain.write_text(DESIGN.split("[uncertainty]")[0])
    with pytest.raises(ParameterError, match="no \\[uncertainty\\] table"):
        plan_deployment(load_design(plain), force_limit=100.0, set_gains=True, robust=True)
    wide = tmp_path / "wide.toml"
    # a box down to b = 0 and b1 = 0 together: the degree of Re Z drops twice at that corner;
    # the corner blow-up proves it passive with its 35 boxes, so with a budget of 8 the
    # verdict is undecided, which a robust export must refuse as it refuses not_passive
    wide.write_text(DESIGN.replace("b1 = [20.0, 40.0]", "b1 = [0.0, 40.0]\nb = [0.0, 10.0]"))
    verdict = robust_check(
        load_design(wide).sea(), box=dict(load_design(wide).uncertainty), budget=8
    )
    if verdict.outcome is not Outcome.UNDECIDED:
        pytest.fail("the wide box was meant to be undecided with a budget of 8")
    monkeypatch.setattr(
        robust_envelope,
        "robust_check",
        lambda sea, *, box, budget: robust_check(sea, box=box, budget=8),
    )
    with pytest.raises(NotPassiveError, match="refusing a robust export"):
        plan_deployment(load_design(wide), force_limit=100.0, set_gains=True, robust=True)
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = main(["export", "c", str(plain), "--out", str(tmp_path / "o"), "--force-limit", "100",
                     "--robust", "--no-progress"])  # fmt: skip
    assert code == 2 and err.getvalue().count("\n") == 1 and err.getvalue().startswith("error: ")
