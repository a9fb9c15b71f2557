"""The rig's data files come from its results: one CSV writer for the CLI and the report."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from seapass.cli import main
from seapass.files.csvtext import rows_csv
from seapass.rig.experiment import run_experiment
from seapass.rig.impacts import run_impacts
from seapass.rig.rigfile import paper_rig

RIG = paper_rig()


def test_rows_csv() -> None:
    assert rows_csv([]) == ""
    text = rows_csv([{"a": 0.1, "b": None, "c": "x,y"}, {"a": 2, "b": np.nan, "c": "z"}])
    assert text == 'a,b,c\n0.1,,"x,y"\n2,nan,z\n'


def test_experiment_and_impacts_csv(tmp_path: Path) -> None:
    quick = RIG.replace(impacts={"count": 3, "duration": 0.05})
    ex = run_experiment(quick, designs=["LP"], load_masses=[0.1], kd_max=200, kd_step=100)
    lines = ex.to_csv().splitlines()
    assert lines[0] == "design,load_mass,kd,bd,status,settling_time,steady_state_error"
    assert len(lines) == 1 + ex.sweeps[0].kd.size and lines[1].startswith("LP,0.1,0.0,0.0,")
    im = run_impacts(quick, windows=[0.01, 0.02])
    assert im.to_csv().splitlines()[0] == "impact,force,k_out"
    assert len(im.to_csv().splitlines()) == 1 + im.forces.size
    rig = tmp_path / "rig.toml"
    rig.write_text(quick.to_toml())
    out = tmp_path / "o"
    argv = ["rig", "sweep", "--rig", str(rig), "--design", "LP", "--load-mass", "0.1",
            "--kd-max", "200", "--kd-step", "100", "--no-progress", "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    assert (out / "sweep.csv").read_text() == ex.to_csv()
