"""The gain envelope `export c` certifies: every number it writes or prints for a tunable
gain's interval is proven passive (issue 20, item 2).  Independent check: the point
verdict `sampled_passivity` at those very doubles."""

from __future__ import annotations

import contextlib
import io
import re
from fractions import Fraction
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.export import c_literal
from seapass.export.envelope import certify_gains
from seapass.model.design_file import load_design
from seapass.outcome import Outcome
from seapass.sampled.passivity import sampled_passivity

LP = """
name = "lp"
[model]
D1 = "k1 + b1*s"
CL = "kd"
[parameters]
m = 1.02
b = 10.0
k1 = 1005.0
b1 = 30.0
kd = 500.0
[ranges]
kd = [0.0, 2000.0]
[control]
rate = 500.0
delay = 1
velocity_filter = 50.0
"""


def passive_at(dsg, gain: str, value: float) -> bool:
    r = sampled_passivity(
        dsg.sea(), loop=dsg.loop, values={gain: float(value)}, continuous_gate=False
    )
    return r.outcome is Outcome.PASSIVE


@pytest.mark.parametrize("rtol", [1e-2, 1e-6])
def test_envelope_ends_and_printed_numbers_are_passive(tmp_path: Path, rtol: float) -> None:
    path = tmp_path / "lp.toml"
    path.write_text(LP)
    dsg = load_design(path)
    (env,), _notes = certify_gains(dsg, ["kd"], rtol=rtol)
    assert Fraction(env.low) >= env.exact[0] and Fraction(env.high) <= env.exact[1]
    assert passive_at(dsg, "kd", env.low) and passive_at(dsg, "kd", env.high)
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["export", "c", str(path), "--out", str(tmp_path / "c"), "--force-limit",
                     "100", "--set-gains", "--rtol", str(rtol)])  # fmt: skip
    assert code == 0
    ((lo, hi),) = re.findall(r"kd = 500, tunable in \[(\S+), (\S+)\]", out.getvalue())
    assert env.low <= Fraction(lo) <= Fraction(hi) <= env.high  # rounded inward
    assert passive_at(dsg, "kd", float(lo)) and passive_at(dsg, "kd", float(hi))
    # the C source enforces exactly these doubles
    source = (tmp_path / "c" / "seapass_ctrl.c").read_text()
    assert f".kd = {c_literal(env.high).literal}," in source
    assert f".kd = {c_literal(env.low).literal}," in source
