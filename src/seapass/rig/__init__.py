"""The hardware rig: its file, the digital twin, and the paper's experiment on it.

What lives here: [`rigfile`][seapass.rig.rigfile] (`Rig` and its strict TOML
loader), [`plant`][seapass.rig.plant] (the nonlinear plant: friction, saturation,
encoders), [`twin`][seapass.rig.twin] (batches of sampled closed loops on it),
[`experiment`][seapass.rig.experiment], [`impacts`][seapass.rig.impacts],
[`predictions`][seapass.rig.predictions] and [`findings`][seapass.rig.findings] (the paper's
Section VI on the twin) and [`mujoco_model`][seapass.rig.mujoco_model] (an optional
MuJoCo cross-check; needs the ``mujoco`` extra).

May import: everything in [`seapass.sampled`][seapass.sampled] and below.
"""

from .experiment import ExperimentResult, RigSweepResult, run_experiment, run_rig_sweep
from .impacts import ImpactResult, run_impacts
from .plant import TwinPlant
from .rigfile import Rig, load_rig, paper_rig
from .twin import LoopResult, simulate_loop

__all__ = [
    "ExperimentResult",
    "ImpactResult",
    "LoopResult",
    "Rig",
    "RigSweepResult",
    "TwinPlant",
    "load_rig",
    "paper_rig",
    "run_experiment",
    "run_impacts",
    "run_rig_sweep",
    "simulate_loop",
]
