"""The issue-22 flow end to end: the rotary SEA with a PI force loop inside an impedance loop.

m = 0.4, b = 3, k1 = 2500, b1 = 2; C_f = kp + ki/s (kp = 2, ki = 20) with feed-forward,
Z_v = kv + bv s (kv = 1000, bv = 5), motor damping ba = 20, from the design file's
``[controller]`` block (``examples/cascaded_impedance.toml``).  The blocks compile into
C_A, C_L that share the integrator; the one minimal realization of ``[C_A  C_L]`` (one
integrator, not two) is what simulate, sampled, the twin and the exported C run.  Before
issue 22 the force step was "marginal, did not settle", ``sampled check`` found a spurious
z = 1 mode, ``sampled bound`` ran for minutes, ``tune`` retuned k1 and ``analyze`` did not
finish.  Commands taking model flags get the file's blocks as the equivalent flags
(``tests/cli/test_controller_options.py`` shows both compile alike); work is counted
(classified boxes), never timed.
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

import seapass.sampled.boxes as boxes_module
from seapass.cli import main
from seapass.model.design_file import load_design
from seapass.model.minimal import controller_realization
from seapass.sampled.passivity import sampled_passivity

CASCADE = Path(__file__).resolve().parents[2] / "examples" / "cascaded_impedance.toml"
VELOCITY = CASCADE.with_name("velocity_sourced.toml")
MODEL = ["--D1", "k1 + b1*s", "--controller", "impedance", "--force-loop", "kp + ki/s",
         "--impedance", "kv + bv*s", "--damping-injection", "ba", "--feedforward",
         "--set", "m=0.4", "--set", "b=3", "--set", "k1=2500", "--set", "b1=2",
         "--set", "kp=2", "--set", "bv=5", "--set", "ba=20"]  # fmt: skip
GAINS = ["--set", "ki=20", "--set", "kv=1000"]


def cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


@pytest.fixture
def boxes(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Counts the boxes the sampled bounds classify."""
    calls: list[int] = []
    original = boxes_module._classify

    def counted(*args, **kwargs):  # type: ignore[no-untyped-def]
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(boxes_module, "_classify", counted)
    return calls


def test_the_file_is_the_issues_design_with_one_integrator() -> None:
    design = load_design(CASCADE)
    assert {k: design.values[k] for k in ("m", "b", "k1", "b1")} == dict(
        m=0.4, b=3.0, k1=2500.0, b1=2.0
    )
    assert "k1" in design.plant_parameters and "k1" not in design.gains
    k = controller_realization(design.sea())
    assert k.order == 1 and k.is_minimal()  # the shared ki/s realized once


def test_check_and_the_passive_range() -> None:
    code, out, err = cli(["check", *MODEL, *GAINS])
    assert code == 0 and out.startswith("passive"), err
    code, out, err = cli(["bound", "kv", *MODEL, "--set", "ki=20", "--range", "0:5000", "--json"])
    assert code == 0, err
    (lo, hi), = json.loads(out)["intervals"]  # fmt: skip
    assert lo == 0 and hi == pytest.approx(2145.190916, rel=1e-9)


def test_force_step_settles_at_the_spring_ratio() -> None:
    """20 N on a 2 kg load against the rendered 1000 N/m: 0.02 m, stable, not marginal."""
    code, out, err = cli(["simulate", *MODEL, *GAINS, "--load-mass", "2", "--force-step", "20",
                          "--json"])  # fmt: skip
    assert code == 0, err
    data = json.loads(out)
    assert data["stable"] is True and data["marginal"] is False and data["diverged"] is False
    assert data["target"] == pytest.approx(0.02, rel=1e-12)
    assert data["status"] == "settled" and abs(data["final_error"]) < 1e-6


def test_sampled_check_decides_without_a_mode_at_one() -> None:
    code, out, err = cli(["sampled", "check", *MODEL, *GAINS, "--period", "0.001", "--json"])
    assert code == 0, err
    data = json.loads(out)
    assert data["status"] == "passive" and data["precision_bits"] == 128
    assert data["marginal"] is False and data["spectral_radius"] < 1 - 1e-3


def test_sampled_bounds_finish_with_few_boxes(boxes: list[int]) -> None:
    code, out, err = cli(["sampled", "bound", "kv", "--range", "0:5000", *MODEL, "--set",
                          "ki=20", "--period", "0.001", "--json"])  # fmt: skip
    assert code == 0, err
    data = json.loads(out)
    assert data["undecided"] == [] and data["intervals"][0][0] == 0
    assert data["max_passive"] == pytest.approx(1926.80069, rel=1e-7)
    assert len(boxes) < 400
    # ki from 0: at ki = 0 the integrator (and the power at ω = 0) vanishes; ki = 0 is
    # decided alone and only a sliver next to it stays undecided, with bounded work
    boxes.clear()
    code, out, err = cli(["sampled", "bound", "ki", "--range", "0:200", *MODEL, "--set",
                          "kv=1000", "--period", "0.001", "--json"])  # fmt: skip
    assert code == 0, err
    data = json.loads(out)
    assert len(boxes) < 400
    (u_lo, u_hi), = data["undecided"]  # fmt: skip
    assert u_lo == 0 and 0 < u_hi <= 200 * 2e-6
    assert data["intervals"][0] == [0, 0] and data["intervals"][1][0] == u_hi
    assert data["max_passive"] == pytest.approx(104.8776271, rel=1e-7)
    # the point verdicts (one realization per value, no family) agree on both sides
    design = load_design(CASCADE)
    for ki, passive in ((0.0, True), (1e-3, True), (104.8, True), (105.0, False)):
        got = sampled_passivity(design.sea().with_values(ki=ki), loop=design.loop,
                                continuous_gate=False)  # fmt: skip
        assert got.passive is passive, ki


def test_tune_keeps_the_spring() -> None:
    code, out, err = cli(["tune", str(CASCADE), "--quick", "--maxiter", "1", "--popsize", "2",
                          "--no-progress", "--json"])  # fmt: skip
    assert code in (0, 1), err
    assert set(json.loads(out)["gains"]) == {"ba", "bv", "ki", "kp", "kv"}


def test_analyze_reports_with_the_rig_section(tmp_path: Path) -> None:
    """The file with a ``[rig]``: the report's rig section runs the design's controller."""
    design = tmp_path / "cascaded.toml"
    design.write_text(CASCADE.read_text(encoding="utf-8") + '\n[rig]\npreset = "paper"\n',
                      encoding="utf-8")  # fmt: skip
    out_dir = tmp_path / "r"
    code, out, err = cli(["analyze", str(design), "--out", str(out_dir), "--quick",
                          "--stages", "passivity,rig", "--no-progress", "--json",
                          "--jobs", "1"])  # fmt: skip
    assert code == 0, err
    summary = json.loads(out)
    assert summary["failed"] == []
    status = {s["key"]: s["status"] for s in summary["sections"]}
    assert status.get("rig") == "ok", summary["sections"]
    html = (out_dir / "report.html").read_text(encoding="utf-8")
    assert "kp is swept from 0 to 20" in html  # the first gain of the file's [ranges]


@pytest.mark.parametrize("path", [CASCADE, VELOCITY])
def test_rig_sweep_runs_the_design(path: Path) -> None:
    gain = load_design(path).gains[0] if path == VELOCITY else "kv"
    lo, hi = load_design(path).analysis_ranges()[gain]
    code, out, err = cli(["rig", "sweep", "--design", str(path), "--gain", gain, "--load-mass",
                          "2", "--kd-step", str((hi - lo) / 5), "--no-progress", "--json"])  # fmt: skip
    assert code == 0, err
    (sweep,) = json.loads(out)["sweeps"]
    assert sweep["gain"] == gain and len(sweep["runs"]) == 6
    if path == CASCADE:  # kv = 1000 (the file's design) settles on the twin
        run = next(r for r in sweep["runs"] if r["kv"] == 1000)
        assert run["status"] == "settled"
    code, _, err = cli(["rig", "sweep", "--design", str(path), "--gain", "k1", "--load-mass", "2"])
    assert code == 2 and "not a controller gain" in err


@pytest.mark.parametrize("path", [CASCADE, VELOCITY])
def test_export_c_compiles_and_matches_python(path: Path, tmp_path: Path) -> None:
    code, out, err = cli(["export", "c", str(path), "--out", str(tmp_path), "--force-limit",
                          "100", "--verify", "--json"])  # fmt: skip
    assert code == 0, err
    data = json.loads(out)
    assert data["verify"]["ok"] is True and data["deployment"]["certified"] is True
    assert "k1" not in data["deployment"]["gains"]
