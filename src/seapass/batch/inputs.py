"""Checking and broadcasting the per-design arrays of a batch (axis: design)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..model.sea import SEA

__all__ = [
    "broadcast_values",
    "check_batch_params",
]


def broadcast_values(
    values: Mapping[str, Any], names: Sequence[str], labels: Mapping[str, str] | None = None
) -> tuple[dict[str, np.ndarray], tuple[int, ...]]:
    """Broadcast the arrays ``values[name]`` to one common shape.

    Returns the flattened float64 arrays (design axis only) and the broadcast
    shape.  Raises `ParameterError` naming the argument and its shape
    when shapes do not broadcast or values are not finite; ``labels`` renames
    arguments in messages (default ``values['name']``).
    """
    labels = labels or {}

    def label(name: str) -> str:
        return labels.get(name, f"values[{name!r}]")

    arrays: dict[str, np.ndarray] = {}
    for name in names:
        try:
            arr = np.asarray(values[name], dtype=np.float64)
        except (TypeError, ValueError):
            raise ParameterError(f"{label(name)} must be numeric") from None
        if not np.all(np.isfinite(arr)):
            raise ParameterError(f"{label(name)} (shape {arr.shape}) contains non-finite numbers")
        arrays[name] = arr
    shape: tuple[int, ...] = ()
    for name, arr in arrays.items():
        try:
            shape = np.broadcast_shapes(shape, arr.shape)
        except ValueError:
            shapes = ", ".join(f"{k}: {a.shape}" for k, a in arrays.items())
            raise ParameterError(
                f"{label(name)} has shape {arr.shape}, which does not broadcast with the "
                f"shape {shape} of the arguments before it ({shapes}); give equal shapes or "
                "length-1 axes"
            ) from None
    flat = {k: np.broadcast_to(a, shape).reshape(-1) for k, a in arrays.items()}
    return flat, tuple(shape)


def check_batch_params(sea: SEA, params: Sequence[str]) -> tuple[str, ...]:
    """``params`` as a tuple, checked: each appears in ``sea`` and together they cover
    every free parameter of ``sea``; a controller given in z is refused (the batch kernels
    are continuous-time)."""
    from ..model.zcontroller import continuous_only

    continuous_only(sea, "the batch sweep (continuous-time kernels)")
    params = tuple(params)
    unknown = [p for p in params if p not in sea.parameters]
    if unknown:
        raise ParameterError(
            f"parameter(s) {', '.join(unknown)} do not appear in the model "
            f"(its parameters are {', '.join(sea.parameters) or 'none'})"
        )
    missing = [p for p in sea.free_parameters if p not in params]
    if missing:
        raise ParameterError(
            f"no values for free parameter(s) {', '.join(missing)}: give arrays for them"
        )
    return params
