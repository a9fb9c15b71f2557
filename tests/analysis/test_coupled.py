"""Text of coupled-stability results whose floating-point evidence overflows.

The verdict (``rhp``) is exact; the pole locations and the simulated growth are
floating-point evidence and may be ``nan`` for extreme values (e.g. m = 1e-300,
b = 1e300).  No ``nan`` is printed as if it were a number.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from seapass.analysis.coupled import CoupledResult, Stability
from seapass.analysis.coupled_response import CoupledSimulation


def _result(poles: list[complex], *, rhp: bool) -> CoupledResult:
    return CoupledResult(
        status=Stability.UNSTABLE if rhp else Stability.STABLE,
        rhp=rhp,
        repeated_axis=False,
        characteristic=(1.0, 1.0),
        common=(1.0,),
        poles=np.array(poles, dtype=complex),
    )


@pytest.mark.parametrize(
    ("poles", "rhp", "expected"),
    [
        ([complex(2.5, 1.0)], True, "2.5 1/s"),
        ([complex(-1.0, 0.0)], False, "-1 1/s"),
        ([], False, "-inf 1/s"),
        ([complex(math.nan, 0.0)], True, "beyond double precision (a right-half-plane pole"),
        ([complex(math.nan, 0.0)], False, "beyond double precision"),
    ],
)
def test_max_real_part_text(poles, rhp, expected):
    text = _result(poles, rhp=rhp).max_real_part_text
    assert text.startswith(expected)
    assert "nan" not in text


@pytest.mark.parametrize(
    ("growth", "expected"), [(12.5, "grows x12.5"), (math.nan, "not representable")]
)
def test_growth_text(growth, expected):
    sim = CoupledSimulation(
        t=np.linspace(0, 1, 3), y=np.zeros(3), output="port displacement", growth_rate=1.0,
        growth_factor=growth,
    )  # fmt: skip
    assert sim.growth_text.startswith(expected) and "nan" not in sim.growth_text
