"""Generated C controller (issue 16): equivalence with the Python controller, guards, files.

The C code is compiled with the system compiler under
``-std=c99 -Wall -Wextra -Werror -pedantic`` and driven through ctypes.  The
Python side is independent of the generator: seapass's ``DiscreteController``
run by the runtime's ``ControlLoop`` (which saturates) on ``SimulatedHardware``
(which delays), replaying scripted measurements.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import shutil
import subprocess
import tomllib
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import seapass
from seapass.errors import NotPassiveError, OutputPathError, ParameterError
from seapass.export import (
    c_literal,
    compile_c,
    equivalence_inputs,
    export_c,
    find_c_compiler,
    inward_interval,
    verify_c,
)
from seapass.model.catalog import PAPER_VALUES
from seapass.model.catalog import design as catalog_design
from seapass.model.design_file import load_design, parse_design
from seapass.rig.plant import TwinPlant
from seapass.rig.rigfile import paper_rig
from seapass.sampled.controllers import DiscreteController
from seapass.sampled.runtime import ControlLoop, SimulatedHardware

ROOT = Path(__file__).resolve().parents[2]
CC = find_c_compiler()
needs_cc = pytest.mark.skipif(
    CC is None,
    reason="no C compiler (cc, gcc or clang) on PATH and CC unset: the generated-C "
    "equivalence tests need one; install gcc to run them",
)

BENCH = paper_rig().model_values()  # m, b, k1, b1 of the paper's bench
SAMPLED = {"rate": 500.0, "delay": 1, "velocity_filter": 50.0}  # the bench's loop

# a custom design: lead compensator plus derivative on the actuator, on the bench's spring
LEAD = f"""
name = "lead"
title = "Damped spring, actuator-side lead compensator"
[model]
D1 = "k1 + b1*s"
CA = "kd*(1 + s/wz)/(1 + s/wp) + bd*s"
[parameters]
m = {BENCH["m"]!r}
b = {BENCH["b"]!r}
k1 = {BENCH["k1"]!r}
b1 = {BENCH["b1"]!r}
kd = 800.0
wz = 30.0
wp = 300.0
bd = 5.0
[control]
rate = 500.0
delay = 1
velocity_filter = 50.0
"""
DESIGNS = ("APD", "LP", "Ours", "lead")
FORCE_LIMIT = 100.0
# limits that clip roughly the largest 1-10 % of each design's commands on the test inputs
LIMITS = {"LP": 20.0, "APD": 18.0, "Ours": 100.0, "lead": 40.0}


def catalog(key: str, values: dict, control: dict, ranges: dict, **model: str):
    """A design of the catalog entry ``key`` (elements overridable, e.g. ``D1``)."""
    return parse_design(
        {
            "name": key,
            "model": {**catalog_design(key).elements(), **model},
            "parameters": values,
            "ranges": ranges,
            "control": control,
        }
    )


def design(name: str, **control: object):
    if name == "LP":  # the paper's LP controller on the bench's damped spring, as on the rig
        ranges = {"kd": [0.0, 2000.0]}
        dsg = catalog("LP", {**BENCH, "kd": 500.0}, SAMPLED, ranges, D1="k1 + b1*s")
    elif name == "APD":  # the paper's APD on its pure spring; no delay, raw velocity
        values = {**PAPER_VALUES, "kd": 385.0, "bd": 5.0}
        dsg = catalog("APD", values, {"rate": 500.0}, {"kd": [0.0, 2000.0], "bd": [0.0, 10.0]})
    elif name == "Ours":  # the repository's example
        dsg = load_design(ROOT / "examples" / "ours.toml")
    else:
        dsg = parse_design(tomllib.loads(LEAD))
    if "delay" in control:
        dsg = dataclasses.replace(dsg, loop=dsg.loop.replace(delay=control["delay"]))
    return dsg


class ScriptedPlant:
    """Stands in for a TwinPlant: replays measured positions, ignores the force."""

    def __init__(self, x_A: np.ndarray, x_L: np.ndarray) -> None:
        self.x_A, self.x_L, self.k, self.time = x_A, x_L, 0, 0.0

    def read_encoders(self) -> tuple[float, float]:
        return float(self.x_A[self.k]), float(self.x_L[self.k])

    def counts_to_positions(self, a: float, b: float) -> tuple[float, float]:
        return a, b

    def apply(self, force: float, dt: float, *, external_force: float = 0.0) -> None:
        self.k += 1
        self.time += dt


def python_applied(
    controller, dsg, inputs: np.ndarray, delay: int, limit: float = FORCE_LIMIT
) -> np.ndarray:
    """Commands the Python runtime applies: ControlLoop saturates, SimulatedHardware delays."""
    steps = inputs.shape[1]
    period = float(dsg.period)
    hw = SimulatedHardware(ScriptedPlant(inputs[0], inputs[1]), delay=delay)
    loop = ControlLoop(hw, controller, period=period, force_limit=limit)
    refs = inputs[2:]

    def reference(t: float) -> tuple[float, float]:
        k = round(t / period)
        return float(refs[0, k]), float(refs[1, k])

    rec = loop.run(steps * period, reference=reference)
    assert rec.stop_reason == "" and len(rec.command) == steps
    return np.concatenate([np.zeros(delay), rec.command[: steps - delay]])


def rel_error(got: np.ndarray, want: np.ndarray) -> float:
    return float(np.max(np.abs(got - want)) / np.max(np.abs(want)))


# ------------------------------------------------------------------ literals


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_c_literal_is_the_exact_double(x: float) -> None:
    lit = c_literal(x)
    assert float.fromhex(lit.literal) == x and float(lit.decimal) == x
    assert str(Fraction(x)) in lit.comment


@given(st.fractions(max_denominator=10**30))
def test_c_literal_comment_carries_the_exact_rational(q: Fraction) -> None:
    lit = c_literal(q)
    assert float.fromhex(lit.literal) == float(q)
    assert lit.comment.startswith(str(q))
    assert ("exactly" in lit.comment) == (Fraction(float(q)) == q)


@given(st.fractions(), st.fractions())
def test_inward_interval_is_the_widest_inside(a: Fraction, b: Fraction) -> None:
    lo, hi = min(a, b), max(a, b)
    x, y = inward_interval(lo, hi)
    assert lo <= Fraction(x) and Fraction(y) <= hi
    assert Fraction(math.nextafter(x, -math.inf)) < lo
    assert Fraction(math.nextafter(y, math.inf)) > hi


# ------------------------------------------------------------------ equivalence


@needs_cc
@pytest.mark.parametrize("name", DESIGNS)
def test_c_matches_python_controller_for_10000_steps(name: str, tmp_path: Path) -> None:
    dsg = design(name)
    res = export_c(dsg, tmp_path, force_limit=LIMITS[name])
    ctrl = compile_c(res)
    assert ctrl.init_status == 0 and ctrl.messages == []
    inputs = equivalence_inputs(10_000, seed=7)
    got = ctrl.run(*inputs)
    py = DiscreteController.from_sea(dsg.sea(), dsg.period, velocity_filter=dsg.velocity_filter)
    want = python_applied(py, dsg, inputs, dsg.control_delay, LIMITS[name])
    assert rel_error(got, want) <= 1e-12
    # fixed gains run the Python coefficients in the Python order: bit for bit
    assert np.array_equal(got, want)
    assert 10 < ctrl.saturated < 1000  # the inputs exercise the saturation, not only it


@needs_cc
@pytest.mark.parametrize("hardware_delay", [0, 1])
def test_twin_closed_loop_with_c_matches_python(hardware_delay: int, tmp_path: Path) -> None:
    rig = paper_rig()
    # Ours on the bench at its loop: 500 Hz, one sample of delay, 50 Hz velocity filter
    dsg = catalog("ours", {**BENCH, "kd": 1000.0, "bd": 25.0}, SAMPLED, {})
    dsg = dataclasses.replace(dsg, rig_file="paper")
    res = export_c(dsg, tmp_path, hardware_delay=hardware_delay)
    assert res.deployment.force_limit == rig.force_limit
    assert res.deployment.code_delay == 1 - hardware_delay

    def run(controller, delay: int):
        plant = TwinPlant(rig, load_mass=0.1)
        plant.reset(x_A=0.02, x_L=0.02)
        push = lambda t: 8.0 if 0.5 <= t < 0.6 else 0.0  # noqa: E731
        hw = SimulatedHardware(plant, delay=delay, external_force=push)
        loop = ControlLoop(
            hw, controller, period=rig.period, force_limit=rig.force_limit,
            position_limits=(-0.15, 0.15),
        )  # fmt: skip
        rec = loop.run(1.5, reference=lambda t: (0.0, 0.0) if t < 1.0 else (0.01, 0.01))
        return rec, plant.state

    py = DiscreteController.from_sea(dsg.sea(), rig.period, velocity_filter=50.0)
    want, want_state = run(py, 1)
    got, got_state = run(compile_c(res), hardware_delay)
    assert want.stop_reason == got.stop_reason == ""
    assert np.array_equal(got.x_A, want.x_A) and np.array_equal(got.x_L, want.x_L)
    assert got_state == want_state
    assert abs(want.x_L[-1] - 0.01) < 0.005  # the loop did track the step


@needs_cc
def test_verify_reports_identical_commands(tmp_path: Path) -> None:
    res = export_c(design("lead"), tmp_path, force_limit=FORCE_LIMIT)
    v = verify_c(res, steps=2000)
    assert v.identical and v.max_rel == 0.0 and v.steps == 2000


# ------------------------------------------------------------------ guards


@needs_cc
def test_init_refuses_another_period_and_calls_the_hook(tmp_path: Path) -> None:
    res = export_c(design("LP"), tmp_path, force_limit=FORCE_LIMIT)
    bad = compile_c(res, period=0.001)
    assert bad.init_status == 1
    assert [code for code, _ in bad.messages] == [1]
    assert "period" in bad.messages[0][1]
    assert bad.step((0.01, 0.0)) == 0.0 and bad.fault == 4  # refused: never runs
    near = compile_c(res, period=math.nextafter(0.002, 1.0))
    assert near.init_status == 1  # one ulp off is another period
    ok = compile_c(res, period=1.0 / 500.0)
    assert ok.init_status == 0 and ok.messages == []


@needs_cc
def test_nonfinite_measurement_stops_safely_until_reset(tmp_path: Path) -> None:
    res = export_c(design("Ours", delay=0), tmp_path, force_limit=FORCE_LIMIT)
    c = compile_c(res)
    assert c.step((0.01, 0.0)) != 0.0
    assert c.step((math.nan, 0.0)) == 0.0
    assert c.step((0.01, math.inf)) == 0.0 and c.step((0.01, 0.0)) == 0.0
    assert c.fault == 3 and [m[0] for m in c.messages] == [3]  # hook called once
    c.reset()
    assert c.fault == 0 and c.step((0.01, 0.0)) != 0.0


@needs_cc
def test_set_gains_accepts_the_certified_interval_only(tmp_path: Path) -> None:
    dsg = design("LP")
    res = export_c(dsg, tmp_path, force_limit=FORCE_LIMIT, set_gains=True, rtol=1e-2)
    (kd,) = res.deployment.gains
    assert kd.tunable and kd.low <= 500.0 <= kd.high < 2000.0
    text = res.header.read_text()
    assert "seapass_ctrl_set_gains" in text and "SEAPASS_CTRL_SET_GAINS 1" in text
    c = compile_c(res)
    inside = (kd.low + 500.0) / 2
    assert c.set_gains(kd=inside) == 0 and c.gains == {"kd": inside}
    for bad in (math.nextafter(kd.high, math.inf), -1.0, math.nan, math.inf):
        assert c.set_gains(kd=bad) == 2
        assert c.gains == {"kd": inside}  # refused: unchanged
    assert all(code == 2 and "kd" in msg for code, msg in c.messages)
    # the C controller at the new gain is the Python controller at that gain
    c.reset()
    inputs = equivalence_inputs(10_000, seed=3)
    got = c.run(*inputs)
    py = DiscreteController.from_sea(
        dsg.sea().with_values(kd=inside), dsg.period, velocity_filter=dsg.velocity_filter
    )
    assert rel_error(got, python_applied(py, dsg, inputs, 1)) <= 1e-12


@needs_cc
def test_set_gains_moves_one_gain_at_a_time(tmp_path: Path) -> None:
    dsg = design("APD")
    res = export_c(dsg, tmp_path, force_limit=FORCE_LIMIT, set_gains=True, rtol=1e-2)
    env = {g.name: g for g in res.deployment.gains}
    c = compile_c(res)
    kd2 = (env["kd"].low + 385.0) / 2
    bd2 = (env["bd"].low + 5.0) / 2
    assert c.set_gains(kd=kd2) == 0
    assert c.set_gains(bd=bd2) == 2  # kd already moved: two gains off is not certified
    assert "more than one gain" in c.messages[-1][1]
    assert c.set_gains(kd=385.0, bd=bd2) == 0
    assert c.gains == {"bd": bd2, "kd": 385.0}
    assert res.deployment.in_certified_set({"bd": bd2}) is True
    assert res.deployment.in_certified_set({"bd": bd2, "kd": kd2}) is False
    inputs = equivalence_inputs(10_000, seed=5)
    c.reset()
    got = c.run(*inputs)
    py = DiscreteController.from_sea(dsg.sea().with_values(bd=bd2), dsg.period)
    assert rel_error(got, python_applied(py, dsg, inputs, 0)) <= 1e-12


@needs_cc
def test_set_gains_keeps_fixed_gains_fixed(tmp_path: Path) -> None:
    res = export_c(
        design("APD"), tmp_path, force_limit=FORCE_LIMIT, set_gains=True,
        tunable=["bd"], rtol=1e-2,
    )  # fmt: skip
    assert res.deployment.tunable == ("bd",)
    c = compile_c(res)
    assert c.set_gains(kd=386.0) == 2
    assert "kd is not tunable" in c.messages[-1][1]
    assert c.set_gains(bd=4.0) == 0


@needs_cc
def test_set_gains_on_a_rational_controller(tmp_path: Path) -> None:
    # kd scales the lead filter: C_A = kd*F(s) + bd*s, F discretized by Tustin on its own
    data = tomllib.loads(LEAD)
    data["ranges"] = {"kd": [0.0, 1600.0]}
    dsg = parse_design(data)
    res = export_c(dsg, tmp_path, force_limit=40.0, set_gains=True, tunable=["kd"],
                   rtol=1e-2)  # fmt: skip
    assert [f.gain for f in res.deployment.filters] == [None, "kd"]
    (kd,) = (g for g in res.deployment.gains if g.tunable)
    c = compile_c(res)
    new = (kd.low + 800.0) / 2
    assert c.set_gains(kd=new) == 0
    inputs = equivalence_inputs(10_000, seed=11)
    got = c.run(*inputs)
    py = DiscreteController.from_sea(
        dsg.sea().with_values(kd=new), dsg.period, velocity_filter=dsg.velocity_filter
    )
    assert rel_error(got, python_applied(py, dsg, inputs, 1, 40.0)) <= 1e-12


def test_nonaffine_gain_cannot_be_tunable(tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match=r"wz does not enter C_A .* linearly"):
        export_c(design("lead"), tmp_path, force_limit=1.0, set_gains=True, tunable=["wz"])
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ refusals


def test_not_passive_design_is_refused_unless_allowed(tmp_path: Path) -> None:
    # the catalog's LP on its undamped spring: sampled load feedback is never passive
    dsg = catalog("LP", {**PAPER_VALUES, "kd": 500.0}, {"rate": 500.0}, {})
    with pytest.raises(NotPassiveError, match="refusing to export"):
        export_c(dsg, tmp_path, force_limit=10.0)
    assert list(tmp_path.iterdir()) == []
    res = export_c(dsg, tmp_path, force_limit=10.0, allow_nonpassive=True)
    header = res.header.read_text()
    assert "SEAPASS_CTRL_CERTIFIED 0" in header and "NOT CERTIFIED" in header
    with pytest.raises(ParameterError, match="certified design"):
        export_c(dsg, tmp_path, force_limit=10.0, allow_nonpassive=True, set_gains=True)


@pytest.mark.parametrize(
    ("change", "kwargs", "match"),
    [
        ({"control"}, {"force_limit": 1.0}, r"no \[control\] rate"),
        ((), {}, "no \\[rig\\] to take the force limit"),
        ((), {"force_limit": -1.0}, "positive finite force"),
        ((), {"force_limit": math.inf}, "positive finite force"),
        ((), {"force_limit": 1.0, "hardware_delay": 2}, "exceeds the certified delay"),
        ((), {"force_limit": 1.0, "tunable": ["kd"]}, "need set_gains"),
        (
            (),
            {"force_limit": 1.0, "set_gains": True, "tunable": ["k1"]},
            "k1' is a plant parameter",
        ),
        ((), {"force_limit": 1.0, "set_gains": True, "tunable": ["kq"]}, "not a controller gain"),
        ((), {"force_limit": 1.0, "set_gains": True, "tunable": []}, "at least one gain"),
    ],
)
def test_bad_options_fail_before_any_work(change, kwargs, match, tmp_path: Path) -> None:
    dsg = design("LP")
    if "control" in change:
        dsg = dataclasses.replace(dsg, loop=None)
    with pytest.raises(ParameterError, match=match):
        export_c(dsg, tmp_path / "out", **kwargs)
    assert not (tmp_path / "out").exists()


def test_files_not_written_by_seapass_are_never_replaced(tmp_path: Path) -> None:
    mine = tmp_path / "seapass_ctrl.c"
    mine.write_text("int main(void) { return 0; }\n")
    with pytest.raises(OutputPathError, match="not written by seapass"):
        export_c(design("LP"), tmp_path, force_limit=FORCE_LIMIT)
    assert mine.read_text() == "int main(void) { return 0; }\n"
    assert not (tmp_path / "seapass_ctrl.h").exists()
    # a file seapass wrote and the user then edited is the user's too
    export_c(design("LP"), tmp_path, force_limit=FORCE_LIMIT, force=True)
    assert mine.read_text().startswith("/* seapass_ctrl.c")
    (tmp_path / "seapass_ctrl.h").write_text("/* edited */\n")
    with pytest.raises(OutputPathError, match=r"seapass_ctrl\.h exists and was not written"):
        export_c(design("LP"), tmp_path, force_limit=FORCE_LIMIT)
    assert (tmp_path / "seapass_ctrl.h").read_text() == "/* edited */\n"


def test_export_is_deterministic_and_replaces_its_own_files(tmp_path: Path) -> None:
    first = export_c(design("APD"), tmp_path, force_limit=FORCE_LIMIT)
    texts = (first.header.read_text(), first.source.read_text())
    again = export_c(design("APD"), tmp_path, force_limit=FORCE_LIMIT)
    assert (again.header.read_text(), again.source.read_text()) == texts
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        ".seapass-written",  # the manifest of what seapass wrote here
        "seapass_ctrl.c",
        "seapass_ctrl.h",
    ]


def test_generated_files_carry_the_envelope(tmp_path: Path) -> None:
    res = export_c(design("Ours"), tmp_path, force_limit=FORCE_LIMIT, hardware_delay=1)
    h, c = res.header.read_text(), res.source.read_text()
    assert (
        "#define SEAPASS_CTRL_PERIOD 0.002 /* 1/500 rounded to 0.002; 0x1.0624dd2f1a9fcp-9 */" in h
    )
    assert "seapass_ctrl_period = 0x1.0624dd2f1a9fcp-9; /* 1/500 rounded to 0.002 */" in c
    assert "SEAPASS_CTRL_DELAY_SAMPLES 1" in h and "SEAPASS_CTRL_CODE_DELAY_SAMPLES 0" in h
    assert "SEAPASS_CTRL_VELOCITY_FILTER_HZ 50.0 /* 50 exactly; 0x1.9p+5 */" in h
    assert ".kd = 0x1.abp+10, /* 1708 exactly */" in c
    assert "line[" not in h  # the platform supplies the delay
    assert "#include <math.h>" not in c and "stdio" not in c  # dependency-free
    # every coefficient literal is commented with the exact rational it comes from
    (joint,) = res.deployment.filters  # C_A's two paths: one difference equation
    real = joint.realization
    assert joint.order == 1  # the velocity filter, once
    for coeff in (*(c for num in real.numerators for c in num), *real.denominator):
        assert f"{c_literal(coeff).literal}, /* " in c and str(coeff) in c


@needs_cc
@pytest.mark.skipif(shutil.which("c++") is None, reason="no C++ compiler for the header check")
def test_header_is_valid_cpp_for_arduino_sketches(tmp_path: Path) -> None:
    export_c(design("APD"), tmp_path, force_limit=FORCE_LIMIT, set_gains=True,
               tunable=["bd"], rtol=1e-2)  # fmt: skip
    sketch = tmp_path / "sketch.cpp"
    sketch.write_text(
        '#include "seapass_ctrl.h"\n'
        "static seapass_ctrl_state ctrl;\n"
        "int main() {\n"
        "  seapass_ctrl_gains g = seapass_ctrl_certified_gains;\n"
        "  seapass_ctrl_init(&ctrl, SEAPASS_CTRL_PERIOD, 0, 0);\n"
        "  return seapass_ctrl_set_gains(&ctrl, &g);\n"
        "}\n"
    )
    flags = ["-std=c++11", "-Wall", "-Wextra", "-Werror", "-pedantic", "-fsyntax-only"]
    proc = subprocess.run(
        ["c++", *flags, f"-I{tmp_path}", str(sketch)], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr


# ------------------------------------------------------------------ CLI


def test_cli_export_writes_and_summarises(tmp_path: Path, capsys) -> None:
    from seapass.cli import main

    ours = str(ROOT / "examples" / "ours.toml")
    out = tmp_path / "fw"
    assert main(["export", "c", ours, "--out", str(out)]) == 0
    cap = capsys.readouterr()
    assert "certified" in cap.out and "±129.6 N" in cap.out  # the paper rig's peak force
    assert cap.err == f"wrote {out / 'seapass_ctrl.h'}\nwrote {out / 'seapass_ctrl.c'}\n"
    assert main(["export", "c", ours, "--out", str(out), "--force-limit", "50", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["deployment"]["period_exact"] == "1/500"
    assert data["deployment"]["gains"]["kd"]["value"] == 1708.0
    assert data["deployment"]["force_limit"] == 50.0


@needs_cc
def test_cli_verify(tmp_path: Path, capsys) -> None:
    from seapass.cli import main

    path = tmp_path / "lead.toml"
    path.write_text(LEAD)
    argv = ["export", "c", str(path), "--out", str(tmp_path), "--force-limit", "50"]
    assert main([*argv, "--verify"]) == 0
    assert "identical to the Python controller" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["--force-limit", "0"], "positive finite force"),
        ([], r"no \[rig\].*--force-limit N"),
        (["--force-limit", "5", "--tunable", "kd"], "need --set-gains"),
        (["--force-limit", "5", "--set-gains", "--tunable", ","], "--tunable needs gain names"),
        (["--force-limit", "5", "--rtol", "0"], "--rtol must be in"),
    ],
)
def test_cli_errors_are_one_line(args, match, tmp_path: Path, capsys) -> None:
    from seapass.cli import main

    path = tmp_path / "lead.toml"
    path.write_text(LEAD)
    assert main(["export", "c", str(path), "--out", str(tmp_path / "o"), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1
    assert re.search(match, err)
    assert not (tmp_path / "o").exists()


def test_top_level_entry_point() -> None:
    assert seapass.export_c is export_c


@needs_cc
def test_docs_loop_example_compiles_against_generated_code(tmp_path: Path) -> None:
    docs = ROOT / "docs" / "deploy.md"
    text = docs.read_text(encoding="utf-8")
    marker = "<!-- compiled-example: loop_posix.c -->\n```c\n"
    start = text.index(marker) + len(marker)
    (tmp_path / "loop_posix.c").write_text(text[start : text.index("```", start)])
    export_c(design("Ours"), tmp_path, force_limit=FORCE_LIMIT)
    flags = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-c"]
    for name in ("loop_posix.c", "seapass_ctrl.c"):
        proc = subprocess.run(
            [CC, *flags, f"-I{tmp_path}", "-o", str(tmp_path / f"{name}.o"), str(tmp_path / name)],
            capture_output=True, text=True,
        )  # fmt: skip
        assert proc.returncode == 0, proc.stderr
