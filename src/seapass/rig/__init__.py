"""The hardware rig: its file, the digital twin, the paper's experiment on it, and your own rig.

What lives here: [`rigfile`][seapass.rig.rigfile] (`Rig` and its strict TOML
loader and writer), [`schema`][seapass.rig.schema] (its sections, every key typed
and range-checked), [`packaged`][seapass.rig.packaged] (the template for your
rig; whether a rig is the paper's bench), [`plant`][seapass.rig.plant] (the
nonlinear plant: friction, saturation, encoders), [`twin`][seapass.rig.twin]
(batches of sampled closed loops on it), [`experiment`][seapass.rig.experiment],
[`impacts`][seapass.rig.impacts], [`predictions`][seapass.rig.predictions] and
[`findings`][seapass.rig.findings] (the paper's Section VI on the twin),
[`design_sweep`][seapass.rig.design_sweep] (any design file's controller swept on the
twin), [`design_runs`][seapass.rig.design_runs] (``rig sweep`` and ``rig impacts`` by
design name: LP, Ours or a design file),
[`log`][seapass.rig.log] (a logged run: the CSV loader, logs made on the twin),
[`chirp`][seapass.rig.chirp] (the command to play on a bench to log such a run),
[`moments`][seapass.rig.moments] and [`identify`][seapass.rig.identify] (fitting
``m, b, b1`` and Coulomb friction to a log, with confidence intervals),
[`frf`][seapass.rig.frf] (``m, b, b1`` from a measured frequency response),
[`intervals`][seapass.rig.intervals] (a fit's intervals in the rig file, ``[intervals]``),
[`robustbox`][seapass.rig.robustbox] (the box of a robust verdict: design file, fitted
rig, caller) and
[`mujoco_model`][seapass.rig.mujoco_model] (an optional MuJoCo cross-check; needs
the ``mujoco`` extra).

May import: [`seapass.errors`][seapass.errors], [`seapass.progress`][seapass.progress], [`seapass.files`][seapass.files], [`seapass.model`][seapass.model],
[`seapass.sim`][seapass.sim], [`seapass.sampled`][seapass.sampled] (the discrete controllers the twin
runs), [`seapass.robust`][seapass.robust] (`robustbox` checks a box).
"""

from .chirp import ChirpPlan, chirp_plan
from .experiment import ExperimentResult, RigSweepResult, run_experiment, run_rig_sweep
from .identify import FitParameter, RigFit, fit_rig
from .impacts import ImpactResult, run_impacts
from .log import RigLog, chirp_command, load_log, twin_log, twin_step_log
from .packaged import is_paper_hardware, rig_template
from .plant import TwinPlant
from .rigfile import Rig, load_rig, paper_rig
from .twin import LoopResult, simulate_loop

__all__ = [
    "ChirpPlan",
    "ExperimentResult",
    "FitParameter",
    "ImpactResult",
    "LoopResult",
    "Rig",
    "RigFit",
    "RigLog",
    "RigSweepResult",
    "TwinPlant",
    "chirp_command",
    "chirp_plan",
    "fit_rig",
    "is_paper_hardware",
    "load_log",
    "load_rig",
    "paper_rig",
    "rig_template",
    "run_experiment",
    "run_impacts",
    "run_rig_sweep",
    "simulate_loop",
    "twin_log",
    "twin_step_log",
]
