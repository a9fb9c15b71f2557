"""``export c --robust``: the guards hold for every plant of the box at the real rate (issue 26).

The guard of a tunable gain is the certified inner robust *sampled* set containing its value
(``robust_sampled_intervals``, the loop's delay and velocity filter included) intersected
with the nominal sampled interval and the continuous robust interval, rounded inward.
Independent checks: the plain certified ``sampled_passivity`` at the corners and the centre
of the box for the gains the guard allows; a gain just outside the certified outer set fails
at a plant of the box; the compiled C refuses gains outside the envelope at runtime.  The box
is narrow (m ± 0.01 %) so that the certification takes a few seconds.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.errors import NotPassiveError, ParameterError
from seapass.export import compile_c, find_c_compiler, render_c, robust_envelope
from seapass.export.c_code import HEADER, SOURCE, ExportResult
from seapass.export.deployment import Deployment, plan_deployment
from seapass.export.envelope import inward_interval
from seapass.export.robust_envelope import DEFAULT_ENVELOPE_BUDGET, GainStatus
from seapass.model.design_file import load_design
from seapass.outcome import Outcome
from seapass.rig.rigfile import paper_rig
from seapass.robust.verdict import robust_check
from seapass.sampled.passivity import sampled_passivity

NARROW = """
name = "ours-narrow"
[model]
D1 = "k1 + b1*s"
CA = "kd + bd*s"
[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
b1 = 300.0
kd = 3050.0
bd = 300.0
[ranges]
kd = [3000.0, 3200.0]
bd = [250.0, 350.0]
[control]
rate = 500.0
delay = 1
velocity_filter = 50.0
"""
BOX = "[uncertainty]\nm = [0.9999, 1.0001]\n"
PLANTS = (0.9999, 1.0, 1.0001)  # the corners and the centre of the box
BUDGET = 8

# a wide box for the refusals before any sampled work (continuous verdict not certified)
WIDE = """
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
"""

needs_cc = pytest.mark.skipif(find_c_compiler() is None, reason="no C compiler on PATH")


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def _one_error(code: int, err: str, needle: str) -> None:
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("error: "), err
    assert needle in lines[0], err


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("robust_export")
    (d / "boxed.toml").write_text(NARROW + BOX)
    (d / "plain.toml").write_text(NARROW)
    rig = paper_rig().to_toml() + "\n[intervals]\nconfidence = 0.95\nm = [0.9999, 1.0001]\n"
    (d / "fitted.toml").write_text(rig)
    return {p.stem: p for p in d.iterdir()}


@pytest.fixture(scope="module")
def plan(files: dict[str, Path]) -> Deployment:
    return plan_deployment(
        load_design(files["boxed"]), force_limit=100.0, set_gains=True, tunable=["kd"],
        robust=True, robust_budget=BUDGET,
    )  # fmt: skip


def test_the_guard_is_the_certified_inner_piece_rounded_inward(
    files: dict[str, Path], plan: Deployment
) -> None:
    nominal = plan_deployment(
        load_design(files["boxed"]), force_limit=100.0, set_gains=True, tunable=["kd"]
    )
    kd = next(g for g in plan.gains if g.name == "kd")
    plain = next(g for g in nominal.gains if g.name == "kd")
    assert plan.robust is not None and plan.robust.certified and not plan.robust.warnings
    (ev,) = plan.robust.gains
    assert ev.status is GainStatus.CERTIFIED and ev.budget_used <= BUDGET
    (piece,) = [iv for iv in ev.inner if iv[0] <= 3050.0 <= iv[1]]
    assert (kd.low, kd.high) == inward_interval(*kd.exact)  # rounded inward
    assert piece[0] <= kd.low and kd.high <= piece[1]  # inside the certified inner set
    assert plain.low <= kd.low and kd.high <= plain.high  # and the nominal sampled one
    assert kd.high < plain.high  # the box narrows the guard here
    assert ev.undecided and ev.outer[-1][1] < plain.high  # an outer cut inside the range


def test_gains_the_guard_allows_are_passive_at_the_corners_and_centre(plan: Deployment) -> None:
    """Independent: the plain certified verdict at each plant, for gains across the guard."""
    kd = next(g for g in plan.gains if g.name == "kd")
    sea = plan.design.sea()
    for gain in (
        kd.low,
        (kd.low + kd.nominal) / 2,
        kd.nominal,
        (kd.nominal + kd.high) / 2,
        kd.high,
    ):
        for m in PLANTS:
            r = sampled_passivity(sea.with_values(m=m, kd=gain), loop=plan.loop)
            assert r.outcome is Outcome.PASSIVE, (gain, m, r.detail)
    assert robust_check(sea.with_values(kd=kd.high), box=plan.robust.box).passive  # type: ignore[union-attr]


def test_a_gain_just_outside_the_outer_set_fails_at_a_plant(plan: Deployment) -> None:
    assert plan.robust is not None
    (ev,) = plan.robust.gains
    outside = ev.outer[-1][1] * (1 + 1e-6)
    sea = plan.design.sea()
    verdicts = [
        sampled_passivity(sea.with_values(m=m, kd=outside), loop=plan.loop).outcome for m in PLANTS
    ]
    assert Outcome.NOT_PASSIVE in verdicts
    assert ev.failing  # and every failing plant reported is verified by the plain verdict
    for w in ev.failing:
        r = sampled_passivity(sea.with_values(**w.values), loop=plan.loop)
        assert r.outcome is Outcome.NOT_PASSIVE and not plan.in_certified_set(
            {"kd": w.values["kd"]}
        )


@needs_cc
def test_the_compiled_guard_refuses_gains_outside_the_robust_envelope(
    plan: Deployment, tmp_path: Path
) -> None:
    texts = render_c(plan)
    for name, body in texts.items():
        (tmp_path / name).write_text(body)
    res = ExportResult(header=tmp_path / HEADER, source=tmp_path / SOURCE, deployment=plan)
    assert "#define SEAPASS_CTRL_ROBUST_CERTIFIED 1" in texts[HEADER]
    assert "Robust envelope (certified) for every plant with m in [0.9999, 1.0001]" in texts[HEADER]
    c = compile_c(res)
    kd = next(g for g in plan.gains if g.name == "kd")
    assert c.set_gains(kd=kd.high) == 0 and c.set_gains(kd=kd.low) == 0
    # passive at the nominal plant, outside the robust guard: refused
    for bad in (math.nextafter(kd.high, math.inf), (kd.high + 3108.0) / 2, 3105.0):
        assert c.set_gains(kd=bad) == 2
        assert c.gains["kd"] == kd.low  # unchanged


def test_without_tunable_gains_the_design_itself_is_certified_for_the_box(
    files: dict[str, Path],
) -> None:
    dep = plan_deployment(
        load_design(files["boxed"]), force_limit=100.0, robust=True, robust_budget=4
    )
    assert dep.robust is not None and dep.robust.certified and not dep.robust.gains
    assert dep.robust.sampled.startswith("passive at the design's gains")
    assert dep.to_dict()["robust"]["box"] == {"m": [0.9999, 1.0001]}


def test_undecided_near_the_value_is_refused_unless_a_fallback_accepts_less(
    files: dict[str, Path],
) -> None:
    design = load_design(files["boxed"])
    kw = dict(force_limit=100.0, set_gains=True, tunable=["kd"], robust=True, robust_budget=1)
    with pytest.raises(NotPassiveError, match="kd = 3050 is undecided"):
        plan_deployment(design, **kw)  # type: ignore[arg-type]
    pinned = plan_deployment(design, robust_fallback="pin", **kw)  # type: ignore[arg-type]
    kd = next(g for g in pinned.gains if g.name == "kd")
    assert (kd.low, kd.high) == (3050.0, 3050.0) and pinned.robust is not None
    assert pinned.robust.certified and pinned.robust.gains[0].status is GainStatus.PINNED
    loud = plan_deployment(design, robust_fallback="nominal", **kw)  # type: ignore[arg-type]
    assert loud.robust is not None and not loud.robust.certified
    assert loud.robust.gains[0].status is GainStatus.NOMINAL
    assert any("nominal plant only" in w for w in loud.robust.warnings)
    banner = render_c(loud)[HEADER]
    assert "*** WARNING: NOT CERTIFIED FOR EVERY PLANT OF THE BOX" in banner
    assert "#define SEAPASS_CTRL_ROBUST_CERTIFIED 0" in banner
    assert loud.to_dict()["robust"]["certified"] is False


def test_the_cli_bakes_the_robust_sampled_envelope_into_the_guards(
    files: dict[str, Path], plan: Deployment, tmp_path: Path
) -> None:
    code, out, err = _cli(["export", "c", str(files["boxed"]), "--out", str(tmp_path),
                           "--set-gains", "--tunable", "kd", "--force-limit", "100", "--robust",
                           "--budget", str(BUDGET), "--json"])  # fmt: skip
    assert code == 0, err
    dep = json.loads(out)["deployment"]
    assert dep["gains"]["kd"]["interval"] == [g.low for g in plan.gains if g.name == "kd"] + [
        g.high for g in plan.gains if g.name == "kd"
    ]
    assert dep["robust"] == plan.robust.to_dict()  # type: ignore[union-attr]
    assert "robust envelope over the box" in err  # the progress
    assert "SEAPASS_CTRL_ROBUST_CERTIFIED 1" in (tmp_path / HEADER).read_text()


def test_the_cli_takes_the_box_of_a_fitted_rig(
    files: dict[str, Path], plan: Deployment, tmp_path: Path
) -> None:
    code, out, err = _cli(["export", "c", str(files["plain"]), "--out", str(tmp_path),
                           "--set-gains", "--tunable", "kd", "--force-limit", "100", "--robust",
                           str(files["fitted"]), "--budget", str(BUDGET), "--no-progress"])  # fmt: skip
    assert code == 0, err
    assert "Robust envelope (certified) for every plant with m in [0.9999, 1.0001]" in out
    kd = next(g for g in plan.gains if g.name == "kd")
    assert f"kd = 3050, tunable in [{kd.low:.10g}" in out  # the same envelope as the table's


def test_the_cli_refuses_an_undecided_envelope_and_warns_on_the_nominal_fallback(
    files: dict[str, Path], tmp_path: Path
) -> None:
    argv = ["export", "c", str(files["boxed"]), "--set-gains", "--tunable", "kd",
            "--force-limit", "100", "--robust", "--budget", "1", "--no-progress"]  # fmt: skip
    code, _out, err = _cli([*argv, "--out", str(tmp_path / "a")])
    _one_error(code, err, "--robust-fallback pin")
    assert "robust_" not in err and not (tmp_path / "a").exists()
    code, out, err = _cli([*argv, "--out", str(tmp_path / "b"), "--robust-fallback", "nominal",
                           "--json"])  # fmt: skip
    assert code == 0 and "warning: NOT CERTIFIED FOR EVERY PLANT OF THE BOX" in err
    assert json.loads(out)["deployment"]["robust"]["warnings"]


def test_bad_robust_options_are_one_error_line(files: dict[str, Path], tmp_path: Path) -> None:
    base = ["export", "c", str(files["boxed"]), "--out", str(tmp_path), "--force-limit", "100"]
    _one_error(*_cli([*base, "--budget", "4"])[::2], "apply to --robust")
    _one_error(*_cli([*base, "--robust-fallback", "pin"])[::2], "apply to --robust")
    _one_error(*_cli([*base, "--robust", "--budget", "0"])[::2], "--budget must be")
    _one_error(*_cli([*base[:2], str(files["plain"]), *base[3:], "--robust"])[::2],
               "no [uncertainty] table")  # fmt: skip
    with pytest.raises(ParameterError, match="robust_fallback must be"):
        plan_deployment(load_design(files["boxed"]), force_limit=1.0, robust=True,
                        robust_fallback="maybe")  # fmt: skip
    with pytest.raises(ParameterError, match="need robust=True"):
        plan_deployment(load_design(files["boxed"]), force_limit=1.0, robust_budget=3)
    assert not any(tmp_path.iterdir())


def test_ctrl_c_during_the_certification_writes_nothing(
    files: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import seapass.robust.sampled_intervals as si

    def interrupted(*args: object, **kwargs: object) -> object:
        raise KeyboardInterrupt

    monkeypatch.setattr(si, "robust_sampled_intervals", interrupted)
    code, _out, err = _cli(["export", "c", str(files["boxed"]), "--out", str(tmp_path / "o"),
                            "--set-gains", "--tunable", "kd", "--force-limit", "100",
                            "--robust", "--no-progress"])  # fmt: skip
    assert code == 130 and "interrupted" in err and not (tmp_path / "o").exists()


def test_a_design_not_robustly_passive_in_continuous_time_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    wide = tmp_path / "wide.toml"
    # a box down to b = 0 and b1 = 0 together: the degree of Re Z drops twice at that corner;
    # the corner blow-up proves it passive with its 35 boxes, so with a budget of 8 the
    # verdict is undecided, which a robust export must refuse as it refuses not_passive
    wide.write_text(WIDE + "[uncertainty]\nb1 = [0.0, 40.0]\nb = [0.0, 10.0]\nm = [0.9, 1.1]\n")
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


def test_the_cli_default_budget_is_the_library_default() -> None:
    from seapass.cli import cmd_export

    assert cmd_export.DEFAULT_ENVELOPE_BUDGET == DEFAULT_ENVELOPE_BUDGET
