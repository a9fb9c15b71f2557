"""``rig sweep`` and ``rig impacts`` by design name: the paper's LP/Ours or any design file.

Independent check: a design file whose controller is the rig's own Ours PD
(``kd + bd*s`` at the rig's ``impacts.kd``, ``impacts.bd``), realized as a discrete
controller at the rig's loop, gives the twin's built-in PD impacts exactly, and the
same Eq. (10) response; a z controller runs too (without Eq. (10)).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from helpers import PAPER_RIG_TEXT, design_text, one_error, run_main
from seapass.errors import ParameterError
from seapass.model.design_file import Design
from seapass.rig.design_runs import named_design, rig_impacts, rig_sweep
from seapass.rig.rigfile import load_rig, paper_rig

PLANT = {"m": 1.0, "b": 10.0, "k1": 1005.0, "b1": 30.0}  # the paper rig's k1, b1
GAINS = {"kd": 1000.0, "bd": 25.0}  # its impacts.kd, impacts.bd
OURS_AS_FILE = design_text(
    "ours-pd", model={"D1": "k1 + b1*s", "CA": "kd + bd*s"}, parameters={**PLANT, **GAINS}
)
Z_FILE = design_text(
    "zpd",
    model={"D1": "k1 + b1*s"},
    parameters={**PLANT, **GAINS},
    discrete={"rate": 500.0, "CA": "kd + bd*500*(1 - z^-1)"},
    control={"delay": 1},
)
NO_CONTROLLER = design_text("nc", model={"D1": "k1 + b1*s"}, parameters=PLANT)


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("designs")
    out = {"rig": d / "rig.toml", "ours": d / "ours.toml", "z": d / "z.toml", "none": d / "n.toml"}
    out["rig"].write_text(PAPER_RIG_TEXT.replace("count = 10", "count = 3"), encoding="utf-8")
    out["ours"].write_text(OURS_AS_FILE, encoding="utf-8")
    out["z"].write_text(Z_FILE, encoding="utf-8")
    out["none"].write_text(NO_CONTROLLER, encoding="utf-8")
    return out


def test_the_design_of_ours_gives_the_twins_own_pd_impacts(files: dict[str, Path]) -> None:
    rig = load_rig(files["rig"])
    assert (rig.impacts.kd, rig.impacts.bd, rig.damper.k1, rig.damper.b1) == (1000, 25, 1005, 30)
    own, file = rig_impacts(rig), rig_impacts(rig, design=files["ours"])
    assert own.design is None and file.design == "ours-pd"
    np.testing.assert_allclose(file.k_out, own.k_out, rtol=1e-9)
    np.testing.assert_allclose(file.k_out_vs_b1, own.k_out_vs_b1, rtol=1e-9)
    np.testing.assert_allclose(file.k_out_linear_vs_window, own.k_out_linear_vs_window, rtol=1e-9)
    np.testing.assert_allclose(file.eq10_magnitude, own.eq10_magnitude, rtol=1e-9)
    assert file.static_stiffness == pytest.approx(own.static_stiffness, rel=1e-12)
    assert own.findings and file.findings == () and file.paper_k_out is None  # the paper's: Ours


def test_a_z_controller_holds_the_output_without_eq10(files: dict[str, Path]) -> None:
    res = rig_impacts(load_rig(files["rig"]), design=files["z"])
    assert res.design == "zpd" and res.omega.size == res.eq10_magnitude.size == 0
    assert res.static_stiffness is None and np.all(np.isfinite(res.k_out)) and res.k_out_mean > 0
    json.dumps(res.to_dict(), allow_nan=False)  # strict JSON


def test_cli_impacts_with_a_design_file(files: dict[str, Path], tmp_path: Path) -> None:
    rig = str(files["rig"])
    code, out, err = run_main(
        ["rig", "impacts", "--rig", rig, "--design", str(files["ours"]), "--json"]
    )
    assert code == 0, err
    d = json.loads(out)
    own = json.loads(run_main(["rig", "impacts", "--rig", rig, "--json"])[1])
    assert d["design"] == "ours-pd" and own["design"] is None and d["findings"] == []
    assert d["k_out_mean"] == pytest.approx(own["k_out_mean"], rel=1e-9)
    code, out, err = run_main(["rig", "impacts", "--rig", rig, "--design", str(files["z"]),
                           "--out", str(tmp_path)])  # fmt: skip
    assert code == 0, err
    assert "design zpd: its controller holds the output" in out and "static none" in out
    assert (tmp_path / "impacts.png").stat().st_size > 0


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["rig", "impacts", "--design", "nosuch.toml"], "'nosuch.toml' is neither ours nor"),
        (["rig", "impacts", "--design", "LP"], "'LP' is neither ours nor a design file"),
        (["rig", "impacts", "--design", "{none}"], "has no controller (C_A = C_L = 0)"),
        (["rig", "sweep", "--gain", "kv"], "gain: give a design file"),
        (["rig", "sweep", "--design", "XX"], "'XX' is neither LP, ours, both nor a design"),
        (["rig", "sweep", "--kd-step", "0.001"], "gives more than 2000 gains"),
    ],
)
def test_bad_input_is_one_error_line(files: dict[str, Path], argv: list[str], says: str) -> None:
    one_error([a.replace("{none}", str(files["none"])) for a in argv], says)


def test_the_library_takes_names_paths_and_designs(files: dict[str, Path]) -> None:
    assert named_design("both") == "both" and named_design("ours", allowed=("ours",)) == "ours"
    design = named_design(files["ours"])
    assert isinstance(design, Design) and named_design(design) is design
    with pytest.raises(ParameterError, match="design: 'PD'") as info:
        rig_sweep(paper_rig(), design="PD")
    assert info.value.argument == "design"
    res = rig_sweep(load_rig(files["rig"]), design=design, gain="kd", load_masses=[0.1],
                    kd_max=2000.0, kd_step=1000.0)  # fmt: skip
    (sweep,) = res.sweeps
    assert sweep.design == "ours-pd" and list(sweep.kd) == [0.0, 1000.0, 2000.0]
