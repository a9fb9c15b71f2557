"""``[uncertainty]`` in design files and ``--robust [RIGFILE]`` on the commands, end to end (issue 26)."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.model.design_file import load_design
from seapass.rig import chirp_command, twin_log
from seapass.rig.rigfile import paper_rig
from seapass.robust.box import uncertain_box
from seapass.robust.intervals import robust_passive_intervals

BOXED = """
name = "lpbox"
[model]
D1 = "k1"
CL = "kd"
[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
kd = 500.0
[uncertainty]
m = [0.9, 1.1]
b = [8.0, 12.0]
"""

OURS = """
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
[control]
rate = 500.0
"""


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def _error(argv: list[str], needle: str) -> None:
    code, out, err = _cli(argv)
    assert code == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and needle in lines[0], err
    assert "Traceback" not in err


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("robust")
    (d / "boxed.toml").write_text(BOXED)
    (d / "ours.toml").write_text(OURS)
    rig = paper_rig()
    (d / "rig.toml").write_text(rig.to_toml())
    log = twin_log(rig, chirp_command(rig.control.rate, duration=2.0), load_mass=0.1, seed=7)
    (d / "chirp.csv").write_text(log.to_csv())
    code, _out, err = _cli(["rig", "fit", str(d / "chirp.csv"), "--rig", str(d / "rig.toml"),
                            "--rig-out", str(d / "fitted.toml")])  # fmt: skip
    assert code == 0, err
    return {p.stem: p for p in d.iterdir()}


def test_check_file_uses_its_uncertainty_table_as_uncertain_would(files: dict[str, Path]) -> None:
    code, out, _err = _cli(["check", str(files["boxed"]), "--json"])
    by_file = json.loads(out)
    code2, out2, _ = _cli(["check", "--D1", "k1", "--CL", "kd", "--set", "k1=1000", "--set",
                           "kd=500", "--uncertain", "m=0.9:1.1", "--uncertain", "b=8:12", "--json"])  # fmt: skip
    assert code == code2 == 0 and by_file == json.loads(out2)
    assert by_file["robust"] is True and by_file["box"] == {"b": [8.0, 12.0], "m": [0.9, 1.1]}


def test_flags_override_the_file(files: dict[str, Path]) -> None:
    d = json.loads(_cli(["check", str(files["boxed"]), "--uncertain", "m=0.95:1.05", "--json"])[1])
    assert d["box"] == {"b": [8.0, 12.0], "m": [0.95, 1.05]}
    d = json.loads(_cli(["check", str(files["boxed"]), "--set", "m=1", "--json"])[1])
    assert d["box"] == {"b": [8.0, 12.0]} and d["method"] == "exact"
    # the file's box makes kd 5e4 not passive for some plant: a verified worst case
    code, out, _ = _cli(["check", str(files["boxed"]), "--set", "kd=50000", "--json"])
    d = json.loads(out)
    assert code == 1 and d["status"] == "not_passive" and d["worst"] is not None


def test_bound_file_gives_the_robust_set_of_the_library(files: dict[str, Path]) -> None:
    code, out, _ = _cli(["bound", "kd", str(files["boxed"]), "--range", "kd=0:2000", "--json"])
    assert code == 0
    d = json.loads(out)
    design = load_design(files["boxed"])
    sea = design.sea().with_values(kd=None)
    lib = robust_passive_intervals(
        sea, "kd", 0, 2000, box=uncertain_box(sea, dict(design.uncertainty))
    )
    assert d["intervals"] == [list(iv) for iv in lib.intervals] and d["box"] == lib.box.to_dict()


def test_robust_with_a_fitted_rig_uses_its_95_percent_box(files: dict[str, Path]) -> None:
    text = files["fitted"].read_text()
    assert "[intervals]" in text and "confidence = 0.95" in text
    code, out, _ = _cli(["check", str(files["ours"]), "--robust", str(files["fitted"]), "--json"])
    d = json.loads(out)
    assert code == 0 and d["status"] == "passive" and set(d["box"]) == {"m", "b", "b1"}
    code, out99, _ = _cli(["check", str(files["ours"]), "--robust", str(files["fitted"]),
                           "--confidence", "0.999", "--json"])  # fmt: skip
    wide = json.loads(out99)["box"]
    assert wide["m"][0] < d["box"]["m"][0] and wide["m"][1] > d["box"]["m"][1]
    code, text_out, _ = _cli(["check", str(files["ours"]), "--robust", str(files["fitted"])])
    assert code == 0 and text_out.startswith("passive for every plant with b in [")


def test_robust_without_argument_takes_the_file_box(files: dict[str, Path]) -> None:
    code, out, _ = _cli(["check", str(files["boxed"]), "--robust", "--json"])
    assert code == 0 and json.loads(out)["box"] == {"b": [8.0, 12.0], "m": [0.9, 1.1]}


def test_bad_input_is_one_error_line(files: dict[str, Path], tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text(BOXED.replace("m = [0.9, 1.1]", "m = [0.0, 1.1]"))
    _error(["check", str(bad)], "uncertainty.m: [0, 1.1] includes non-physical values")
    bad.write_text(BOXED.replace("m = [0.9, 1.1]", "mm = [0.9, 1.1]"))
    _error(["check", str(bad)], "uncertainty.mm: not a parameter of the model")
    _error(["check", str(files["ours"]), "--robust", str(files["rig"])], "has no [intervals] table")
    for level in ("1.5", "0", "-0.1", "1"):
        _error(["check", str(files["ours"]), "--robust", str(files["fitted"]), "--confidence", level],
               "--confidence must lie in (0, 1)")  # fmt: skip
    _error(
        ["check", str(files["boxed"]), "--confidence", "0.9"],
        "--confidence LEVEL applies to --robust RIGFILE",
    )
    _error(["check", str(files["ours"]), "--robust"], "the design has no [uncertainty] table")
    _error(["bound", "m", str(files["boxed"])], "m is uncertain")
    _error(["check", str(files["boxed"]), "--set", "m=1", "--uncertain", "m=0.9:1.1"], "--set m")


def test_sampled_check_decides_the_fitted_box_with_the_robust_sampled_verdict(
    files: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    from seapass.robust import sampled_verdict

    monkeypatch.setattr(sampled_verdict, "PIECES", 150)  # less work per sub-box: counted
    code, out, err = _cli(
        [
            "sampled",
            "check",
            str(files["ours"]),
            "--robust",
            str(files["fitted"]),
            "--budget",
            "1",
            "--json",
        ]
    )
    d = json.loads(out)
    assert d["robust"] is True and d["sampled"] is True and set(d["box"]) == {"m", "b", "b1"}
    # the second-order enclosures certify the fitted 95 % box in one sub-box; the plain
    # sampled verdict agrees at its corners (an independent check, not a proof)
    assert d["status"] == "passive" and d["boxes"] == 1 and code == 0, err
    from itertools import product

    from seapass.model.design_file import load_design
    from seapass.sampled.passivity import sampled_passivity

    design = load_design(files["ours"])
    names = sorted(d["box"])
    for corner in product(*(d["box"][n] for n in names)):
        plain = sampled_passivity(
            design.sea(), loop=design.loop, values=dict(zip(names, corner, strict=True))
        )
        assert plain.passive, corner
    # without --robust the file's [uncertainty] does not switch it to a robust run
    boxed_ours = files["ours"].parent / "ours_boxed.toml"
    boxed_ours.write_text(OURS + "[uncertainty]\nm = [1.0, 1.04]\n")
    assert _cli(["sampled", "check", str(boxed_ours)])[0] == 0


def test_sampled_bound_takes_the_fitted_box(files: dict[str, Path]) -> None:
    argv = ["sampled", "bound", "kd", str(files["ours"]), "--range", "kd=0:2000", "--no-progress"]
    code, out, err = _cli([*argv, "--robust", str(files["fitted"]), "--budget", "1", "--json"])
    assert code == 0, err
    d = json.loads(out)
    assert set(d["box"]) == {"m", "b", "b1"} and d["kind"] == "gain"
    # a gain over a box that is not a point: the outer set only, the rest undecided
    assert d["intervals"] == [] and d["undecided"] == d["outer"] and d["budget_used"] == 1


def test_tune_passes_the_fitted_box_on_as_uncertain(
    files: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    import seapass.tuning.optimize as optimize

    seen: dict[str, object] = {}

    def fake_tune(*args: object, **kwargs: object) -> object:
        seen.update(kwargs)
        raise KeyboardInterrupt  # stop before any work; the CLI exits cleanly

    monkeypatch.setattr(optimize, "tune", fake_tune)
    code, _out, _err = _cli(
        ["tune", str(files["ours"]), "--quick", "--robust", str(files["fitted"])]
    )
    assert code == 130
    box = seen["uncertain"]
    assert isinstance(box, dict) and set(box) == {"m", "b", "b1"}
    lo, hi = box["m"]
    assert lo < 1.02 < hi  # the fit's interval around the twin's own mass


def test_the_robust_options_are_in_the_help() -> None:
    for argv in (["check"], ["bound"], ["sampled", "check"], ["sampled", "bound"], ["tune"],
                 ["analyze"], ["export", "c"]):  # fmt: skip
        out = io.StringIO()
        with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
            main([*argv, "--help"])
        assert "--robust [RIGFILE]" in out.getvalue() and "--confidence LEVEL" in out.getvalue()


def test_analyze_robust_takes_the_box_of_a_fitted_rig(
    files: dict[str, Path], tmp_path: Path
) -> None:
    code, _out, err = _cli(["analyze", str(files["ours"]), "--out", str(tmp_path / "r"), "--stages",
                            "robust", "--quick", "--no-progress", "--robust", str(files["fitted"])])  # fmt: skip
    assert code == 0, err
    data = json.loads((tmp_path / "r" / "data" / "robust.json").read_text())
    assert set(data["box"]) == {"m", "b", "b1"} and data["verdict"]["status"] == "passive"
    twin_mass = paper_rig().actuator_mass  # the fitted box holds the twin's own plant
    assert data["box"]["m"][0] <= twin_mass <= data["box"]["m"][1]


def test_the_robust_options_register_once() -> None:
    import argparse

    from seapass.cli.uncertain_options import add_robust_options, add_uncertain_options

    p = argparse.ArgumentParser()
    add_uncertain_options(p)  # brings --robust and --confidence
    add_robust_options(p.add_argument_group("again"))  # a command adding them too: no clash
    args = p.parse_args(["--robust", "fitted.toml", "--confidence", "0.9"])
    assert args.robust == "fitted.toml" and args.confidence == 0.9
    assert p.parse_args(["--robust"]).robust == "" and p.parse_args([]).robust is None


def test_twoport_check_takes_the_box_of_a_fitted_rig(files: dict[str, Path]) -> None:
    """``twoport check DESIGN --robust RIGFILE``: the rig's intervals as the box, as
    ``check`` takes them (issue 26)."""
    code, out, err = _cli(["twoport", "check", str(files["ours"]), "--robust",
                           str(files["fitted"]), "--json"])  # fmt: skip
    d = json.loads(out)
    box = json.loads(_cli(["check", str(files["ours"]), "--robust", str(files["fitted"]),
                           "--json"])[1])["box"]  # fmt: skip
    assert d["robust"] is True and d["box"] == box and set(box) >= {"m"}
    assert code == (0 if d["status"] == "passive" else 1), err
    assert (d["worst"] is None) == (d["status"] != "not_passive")
    _error(["twoport", "check", str(files["ours"]), "--robust", str(files["rig"])],
           "has no [intervals] table")  # fmt: skip
