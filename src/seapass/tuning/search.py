"""The global search: differential evolution with a fixed seed, progress and clean Ctrl-C,
then `snap_to_edges` for an optimum that the search approaches on the edge of its box.

References
----------
.. [1] R. Storn and K. Price, "Differential evolution -- a simple and efficient
   heuristic for global optimization over continuous spaces", J. Global
   Optimization 11, 1997.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any

import numpy as np
from scipy.optimize import differential_evolution

from ..progress import Progress, task
from .problem import TuningOptions, TuningProblem

__all__ = ["SNAP_FRACTION", "differential_search", "single_threaded_blas", "snap_to_edges"]

SNAP_FRACTION = 0.05
"""Gains this close to an edge of the searched box (a fraction of its width) are tried on it."""


def differential_search(
    cost: Callable[[np.ndarray], float],
    bounds: Sequence[tuple[float, float]],
    options: TuningOptions,
    *,
    label: str,
    progress: Progress,
    callback: Callable[[int, float], None] | None = None,
) -> Any:
    """Minimize ``cost`` over the box ``bounds`` (one ``(lo, hi)`` per gain).

    ``options.maxiter`` generations of ``options.popsize × len(bounds)``
    members, Latin-hypercube start, seeded by ``options.seed`` (reproducible),
    no gradient polish (the cost is piecewise smooth at best).  The search is one
    task of ``progress`` (``options.maxiter`` steps), advanced after every
    generation with the best cost as its note.  A ``KeyboardInterrupt`` (also from
    ``progress.advance``) propagates after the task is closed.

    Returns
    -------
    scipy.optimize.OptimizeResult
        ``nit`` is the number of generations run.
    """

    generation = [0]

    def on_generation(intermediate_result: Any) -> bool:
        generation[0] += 1
        best = float(intermediate_result.fun)
        progress.advance(1, note=f"best {best:.4g}")
        if callback is not None:  # the deprecated callback(generation, best) of tune
            callback(generation[0], best)
        return False

    with (
        single_threaded_blas(),
        task(progress, f"tuning {label}: {options.maxiter} generations", options.maxiter),
    ):
        return differential_evolution(
            cost,
            list(bounds),
            seed=options.seed,
            maxiter=options.maxiter,
            popsize=options.popsize,
            tol=1e-8,
            atol=0.0,
            mutation=(0.5, 1.0),
            recombination=0.7,
            polish=False,
            init="latinhypercube",
            callback=on_generation,
            updating="immediate",
        )


@contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Small matrices: threaded BLAS only adds contention (20-40x slower on a busy machine)."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # optional speed-up
        yield
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def snap_to_edges(
    problem: TuningProblem,
    bounds: Mapping[str, tuple[float, float]],
    x: list[float],
    best: float,
    cost: Callable[[Any], float],
) -> tuple[list[float], float]:
    """Move gains within `SNAP_FRACTION` of an edge of the searched box onto it, when better.

    Differential evolution approaches an optimum on the boundary of its box only
    slowly (a trial point beyond the box is resampled inside it), so a gain the
    objective pushes against an edge ends a little inside it.  Each such gain is
    tried at the edge with the full cost, exact passivity included; the move is
    kept only when it lowers the cost.
    """
    x = list(x)
    for i, gain in enumerate(problem.gains):
        lo, hi = bounds[gain]
        near = [e for e in (lo, hi) if 0 < abs(x[i] - e) <= SNAP_FRACTION * (hi - lo)]
        for edge in near:
            trial = [*x[:i], edge, *x[i + 1 :]]
            value = float(cost(np.array(trial)))
            if value < best:
                x, best = trial, value
    return x, best
