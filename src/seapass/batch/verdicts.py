"""Vectorized exact passivity verdicts for many parameter sets of one configuration.

`batch_is_passive` compiles the configuration once
([`compile_passivity`][seapass.batch.kernel.compile_passivity]), decides each chunk of designs
with certified float64 bounds ([`seapass.batch.certificates`][seapass.batch.certificates]) and sends
every design the bounds leave undecided to the exact rational test
[`seapass.analysis.passivity.positive_real_test`][seapass.analysis.passivity.positive_real_test].  The verdicts are
therefore identical to [`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive].
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from ..analysis.passivity import positive_real_test
from ..errors import ParameterError
from ..exact import poly as ep
from ..model.sea import SEA
from ..outcome import Outcome
from .certificates import decide_chunk
from .inputs import broadcast_values
from .kernel import PassivityKernel, compile_passivity

__all__ = ["BatchPassivity", "batch_is_passive"]


# --------------------------------------------------------------------------- inputs


# --------------------------------------------------------------------------- polynomial bank


# --------------------------------------------------------------------------- derivation


# --------------------------------------------------------------------------- result


@dataclass(frozen=True, kw_only=True)
class BatchPassivity:
    """Verdicts for a batch of designs.

    Every array has the broadcast shape of the inputs (the design axes).

    Attributes
    ----------
    params : tuple of str
        Parameters given per design.
    passive : ndarray of bool
        Exact verdicts (identical to [`is_passive`][seapass.analysis.passivity.is_passive]).
    margin : ndarray of float
        ``min_{x≥0} P(x)/A(x)`` in [-1, 1] (see the module notes); NaN when
        not computed.
    certified : ndarray of bool
        True where the float64 decision was certified; False where the exact
        rational fallback decided.
    undefined : ndarray of bool
        True where the impedance is undefined for the values (its denominator
        vanishes identically; [`is_passive`][seapass.analysis.passivity.is_passive] raises
        there); such designs are reported not passive with a NaN margin.
    """

    params: tuple[str, ...]
    passive: np.ndarray
    margin: np.ndarray
    certified: np.ndarray
    undefined: np.ndarray

    def __post_init__(self) -> None:
        for name in ("passive", "margin", "certified", "undefined"):
            getattr(self, name).flags.writeable = False

    @property
    def outcome(self) -> np.ndarray:
        """`Outcome` of every design (object array): exact, so never ``UNDECIDED``."""
        out = np.empty(self.passive.shape, dtype=object)
        out[...] = Outcome.NOT_PASSIVE  # (np.full would store plain strings)
        out[self.passive] = Outcome.PASSIVE
        return out

    @property
    def n_exact(self) -> int:
        """Number of designs decided by the exact fallback."""
        return int(self.certified.size - np.count_nonzero(self.certified))

    @property
    def fraction_passive(self) -> float:
        return float(np.mean(self.passive)) if self.passive.size else math.nan


# --------------------------------------------------------------------------- decision


def _exact_one(kernel: PassivityKernel, point: Sequence[float]) -> tuple[bool, float]:
    vals = [Fraction(float(v)) for v in point]
    bank = kernel.bank
    num = ep.as_poly([bank.exact(nm, vals) for nm in kernel.n_exact])
    den = ep.as_poly([bank.exact(nm, vals) for nm in kernel.d_exact])
    if den.is_zero():
        raise ParameterError(
            "the impedance has a zero denominator for "
            + ", ".join(f"{p}={float(v):g}" for p, v in zip(kernel.params, point, strict=True))
        )
    # unreduced, as is_passive passes it: a value-specific common factor is a hidden mode
    res = positive_real_test(num, den, support=kernel.support)
    return res.passive, res.margin


def batch_is_passive(
    sea: SEA,
    values: Mapping[str, Any],
    *,
    margin: bool = True,
    chunk_size: int = 1 << 16,
    throw: bool = False,
) -> BatchPassivity:
    """Exact passivity verdicts for many parameter sets of one configuration.

    Parameters
    ----------
    sea : SEA
        The configuration.  Parameters not in ``values`` keep their value in ``sea``.
    values : mapping of str to array_like
        One array per parameter, broadcast together (length-1 axes broadcast);
        the broadcast shape is the design shape.  Must cover every free parameter.
    margin : bool, default True
        Also compute the passivity margin (a batched eigenvalue problem per
        design; about 3x the cost of the verdict alone).
    chunk_size : int
        Designs evaluated per vectorized block (bounds the memory).
    throw : bool, default False
        Raise `ParameterError` for a design whose impedance is undefined
        (zero denominator) instead of marking it in ``undefined``.

    Returns
    -------
    BatchPassivity
        Arrays of the broadcast shape.  Verdicts equal those of
        [`seapass.analysis.passivity.is_passive`][seapass.analysis.passivity.is_passive] for every design.

    Raises
    ------
    ParameterError
        For unknown or missing parameters, non-finite values or shapes that do
        not broadcast (the message names the argument and its shape).

    Examples
    --------
    Load-side P on a pure spring is passive exactly up to ``kd = k1``:

    >>> import numpy as np
    >>> from seapass.model.sea import SEA
    >>> lp = SEA(D1="k1", CL="kd", values=dict(m=1, b=10, k1=1000, kd=None))
    >>> batch_is_passive(lp, {"kd": np.array([500.0, 1000.0, 1500.0])}).passive.tolist()
    [True, True, False]

    The proposed design (damped spring, actuator-side PD) is passive for every gain:

    >>> ours = SEA(D1="k1 + b1*s", CA="kd + bd*s",
    ...            values=dict(m=1, b=10, k1=1000, b1=20, kd=None, bd=None))
    >>> batch_is_passive(ours, {"kd": np.array([5000.0, 1e6]), "bd": 25.0}).passive.tolist()
    [True, True]
    """
    if chunk_size < 1:
        raise ParameterError(f"chunk_size must be positive, got {chunk_size}")
    names = tuple(values)
    kernel = compile_passivity(sea, names)
    flat, shape = broadcast_values(values, names)
    n = int(np.prod(shape, dtype=np.int64))
    passive = np.zeros(n, dtype=bool)
    marg = np.full(n, np.nan)
    cert = np.zeros(n, dtype=bool)
    undefined = np.zeros(n, dtype=bool)
    cols_all = [flat[p] for p in names]
    for start in range(0, n, chunk_size):
        stop = min(n, start + chunk_size)
        cols = [c[start:stop] for c in cols_all]
        status, m = decide_chunk(kernel, cols, margin)
        passive[start:stop] = status == 1
        cert[start:stop] = status >= 0
        marg[start:stop] = m
        for i in np.nonzero(status < 0)[0]:
            try:
                verdict, mm = _exact_one(kernel, [c[i] for c in cols])
            except ParameterError:
                if throw:
                    raise
                undefined[start + i] = True
                verdict, mm = False, math.nan
            passive[start + i] = verdict
            if margin:
                marg[start + i] = mm
    if not margin:
        marg[:] = np.nan
    return BatchPassivity(
        params=names,
        passive=passive.reshape(shape),
        margin=marg.reshape(shape),
        certified=cert.reshape(shape),
        undefined=undefined.reshape(shape),
    )
