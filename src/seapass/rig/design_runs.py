"""The twin's experiments by the name of a design: ``rig sweep`` and ``rig impacts``.

`rig_sweep` and `rig_impacts` are what the two commands call: a design is named the
way the command line names it, the paper's ``LP``, ``ours`` (``both`` for the sweep),
or a design file whose controller (continuous or in z) runs on the twin
([`run_design_sweeps`][seapass.rig.design_sweep.run_design_sweeps],
[`run_impacts`][seapass.rig.impacts.run_impacts] with ``design=``).  Every rule
between the options lives here: ``gain`` needs a design file, the gain grid is
bounded (`MAX_KD_GAINS_CLI`), a name that is neither is refused.

Examples
--------
>>> from seapass.rig.rigfile import paper_rig
>>> rig_sweep(paper_rig(), design="PD")
Traceback (most recent call last):
...
seapass.errors.ParameterError: design: 'PD' is neither LP, ours, both nor a design file
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from ..errors import ParameterError
from ..files.limits import MAX_KD_GAINS_CLI
from ..model.design_file import Design, load_design
from ..progress import ProgressLike
from .design_sweep import run_design_sweeps
from .experiment import ExperimentResult, run_experiment
from .impacts import ImpactResult, run_impacts
from .rigfile import Rig

__all__ = ["PAPER_NAMES", "named_design", "rig_impacts", "rig_sweep"]

PAPER_NAMES = ("LP", "ours", "both")
"""The names of the paper's designs the sweep knows by their gains (``both``: LP and Ours)."""

DesignName = str | os.PathLike[str] | Design


def named_design(design: DesignName, *, allowed: Sequence[str] = PAPER_NAMES) -> str | Design:
    """One of ``allowed`` as given, or the `Design` of a file (read once, checked).

    Raises
    ------
    ParameterError
        For a name that is neither one of ``allowed`` nor an existing file.
    FileFormatError, OSError
        For a design file that does not load (`load_design`).
    """
    if isinstance(design, Design):
        return design
    if str(design) in allowed:
        return str(design)
    if not Path(design).is_file():
        raise ParameterError(
            f"design: {str(design)!r} is neither {', '.join(allowed)} nor a design file",
            argument="design",
        )
    return load_design(design)


def rig_sweep(
    rig: Rig,
    *,
    design: DesignName = "both",
    gain: str | None = None,
    load_masses: Sequence[float] | None = None,
    kd_max: float | None = None,
    kd_step: float | None = None,
    progress: ProgressLike = None,
) -> ExperimentResult:
    """The settling experiment of ``rig sweep``: the paper's designs or any design file.

    Parameters
    ----------
    rig : Rig
    design : {"LP", "ours", "both"}, path or Design
        The paper's LP, Ours, both (their ``kd`` swept, with the paper's findings), or a
        design file whose controller runs on the twin (`run_design_sweeps`, no findings).
    gain : str, optional
        With a design file: the gain to sweep (default the first in its ``[ranges]``).
    load_masses : sequence of float, optional
        Default: the rig file's ``experiment.load_masses``.
    kd_max, kd_step : float, optional
        Largest gain and step (of the swept gain); default the rig's experiment for
        LP and Ours, the gain's range for a design file.
    progress : Progress, optional
        Progress of the paper's sweeps.

    Returns
    -------
    ExperimentResult

    Raises
    ------
    ParameterError
        For an unknown design, ``gain`` without a design file, or a grid of more than
        `MAX_KD_GAINS_CLI` gains.
    """
    chosen = named_design(design)
    if isinstance(chosen, Design):
        sweeps = run_design_sweeps(
            rig, chosen, gain=gain, load_masses=load_masses, gain_max=kd_max, gain_step=kd_step
        )
        return ExperimentResult(rig_name=rig.name, sweeps=sweeps, findings=())
    if gain is not None:
        raise ParameterError(
            "gain: give a design file to sweep another gain (LP and Ours sweep kd)",
            argument="gain",
        )
    kd_max = rig.experiment.kd_max if kd_max is None else kd_max
    kd_step = rig.experiment.kd_step if kd_step is None else kd_step
    if kd_max / kd_step > MAX_KD_GAINS_CLI:
        raise ParameterError(
            f"kd_step: {kd_step:g} gives more than {MAX_KD_GAINS_CLI} gains; use a larger step",
            argument="kd_step",
        )
    return run_experiment(
        rig,
        designs=["LP", "ours"] if chosen == "both" else [chosen],
        load_masses=load_masses,
        kd_max=kd_max,
        kd_step=kd_step,
        progress=progress,
    )


def rig_impacts(rig: Rig, *, design: DesignName = "ours") -> ImpactResult:
    """The impacts of ``rig impacts``: Ours (the rig's ``impacts.kd``, ``impacts.bd``) or
    the controller of a design file holding the output (`run_impacts`).

    Raises
    ------
    ParameterError
        For a name that is neither ``ours`` nor a design file, or a design without a
        controller.
    """
    chosen = named_design(design, allowed=("ours",))
    return run_impacts(rig, design=chosen if isinstance(chosen, Design) else None)
