"""The paper's simulation experiment in one place: step, horizon, load masses, tolerance.

Every step response seapass judges (tuning, the simulation study, sweeps, the
explorer, the ``simulate`` command, design files without a ``[simulation]`` table)
takes what the user did not say from `PAPER_EXPERIMENT`: a 0.5 m reference step of both
references from rest, simulated for 10 s, a 10 kg tuning load among 1, 10 and 25 kg,
judged by the 2 % settling band, with a 1000 N actuator force limit while tuning.
Batch screens of many designs (sweeps, `batch_step_metrics`) simulate a shorter 5 s.

The rule everywhere: a value the caller gives wins, then the design file's, then the
experiment's (`Experiment.pick`).  The command line passes None for what the user did
not type, so a design file's ``[simulation] step`` is never overridden by a default.

Examples
--------
>>> PAPER_EXPERIMENT.step, PAPER_EXPERIMENT.horizon, PAPER_EXPERIMENT.load_masses
(0.5, 10.0, (1.0, 10.0, 25.0))
>>> PAPER_EXPERIMENT.pick("step", None, 0.1), PAPER_EXPERIMENT.pick("step", None, None)
(0.1, 0.5)

References
----------
.. [1] S. A. Mehta and D. P. Losey, "Combining Performance and Passivity in
   Linear Control of Series Elastic Actuators", Sec. V (simulation study).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

from ..errors import ParameterError
from .display import html_card, short_repr

__all__ = ["PAPER_EXPERIMENT", "Experiment"]


@dataclass(frozen=True, kw_only=True, repr=False)
class Experiment:
    """A step-response experiment: what is simulated and how it is judged.

    Parameters
    ----------
    step : float
        Reference step of both references from rest (m), nonzero.
    horizon : float
        Simulated time (s).
    load_mass : float
        Load mass the gains are tuned at (kg).
    load_masses : tuple of float
        Load masses every design is evaluated at (kg).
    tolerance : float
        Settling band, a fraction of the step.
    force_limit : float
        Largest peak actuator force while tuning (N): an average stiffness of
        2000 N/m over the 0.5 m step.
    screening_horizon : float
        Simulated time (s) of batch screens of many designs (sweeps).
    """

    step: float = 0.5
    horizon: float = 10.0
    load_mass: float = 10.0
    load_masses: tuple[float, ...] = (1.0, 10.0, 25.0)
    tolerance: float = 0.02
    force_limit: float = 1000.0
    screening_horizon: float = 5.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "load_masses", tuple(float(m) for m in self.load_masses))
        if not (math.isfinite(self.step) and self.step != 0):
            raise ParameterError(f"step: must be nonzero, got {self.step!r}", argument="step")
        for name in ("horizon", "load_mass", "force_limit", "screening_horizon"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ParameterError(f"{name}: must be positive, got {value!r}", argument=name)
        if not (self.load_masses and all(math.isfinite(m) and m > 0 for m in self.load_masses)):
            raise ParameterError(
                f"load_masses: every mass must be positive, got {self.load_masses}",
                argument="load_masses",
            )
        if not 0 < self.tolerance < 1:
            raise ParameterError(
                f"tolerance: must be in (0, 1), got {self.tolerance!r}", argument="tolerance"
            )

    def pick(self, name: str, given: Any, from_file: Any = None) -> Any:
        """``given``, else ``from_file``, else this experiment's ``name`` (None means not said)."""
        if given is not None:
            return given
        if from_file is not None:
            return from_file
        return getattr(self, name)

    def to_dict(self) -> dict[str, Any]:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def __repr__(self) -> str:
        return short_repr("Experiment", self.to_dict())

    def _repr_html_(self) -> str:
        rows = [(f.name.replace("_", " "), getattr(self, f.name)) for f in fields(self)]
        return html_card("Step-response experiment", rows)


PAPER_EXPERIMENT = Experiment()
"""The paper's simulation study (Sec. V): 0.5 m step, 10 s, tuned at 10 kg of 1/10/25 kg."""
