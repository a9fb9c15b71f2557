"""Vectorized engines for many designs of one configuration: verdicts and step metrics.

What lives here: [`verdicts`][seapass.batch.verdicts] (exact passivity of a batch:
certified float64 bounds, [`certificates`][seapass.batch.certificates], with the exact
test as fallback), [`kernel`][seapass.batch.kernel] (the configuration's symbolic
data, compiled once), [`step_metrics`][seapass.batch.step_metrics] (settling time,
final error and overshoot from the exact modal solution) and their helpers.
Every batch function documents its axes and broadcasts length-1 axes.

May import: [`seapass.errors`][seapass.errors], ``seapass.outcome``, [`seapass.exact`][seapass.exact], [`seapass.model`][seapass.model],
[`seapass.analysis`][seapass.analysis], [`seapass.sim`][seapass.sim].
"""

from .kernel import PassivityKernel, compile_passivity
from .step_metrics import BatchMetrics, batch_step_metrics
from .verdicts import BatchPassivity, batch_is_passive

__all__ = [
    "BatchMetrics",
    "BatchPassivity",
    "PassivityKernel",
    "batch_is_passive",
    "batch_step_metrics",
    "compile_passivity",
]
