"""The dangerous band: exactly where some delay makes Re Z negative (dense-grid cross-check)."""

from __future__ import annotations

import numpy as np
import pytest

from seapass.delay.balls import precision
from seapass.delay.bands import band_polynomials, dangerous_bands
from seapass.delay.structure import delayed_impedance
from seapass.delay.trig import real_part
from seapass.model.sea import SEA


def _min_over_theta(f, w):
    """min over θ of A + B cos θ + C sin θ on a grid of θ (independent of the exact test)."""
    theta = np.linspace(0, 2 * np.pi, 721)
    a, b, c = (np.polynomial.polynomial.polyval(w, [float(x) for x in p.coeffs()] or [0.0])
               for p in (f.cos[0], f.cos[1], f.sin[1]))  # fmt: skip
    return (a[:, None] + b[:, None] * np.cos(theta) + c[:, None] * np.sin(theta)).min(axis=1)


@pytest.mark.parametrize("values", [dict(kd=500, bd=25, b1=20), dict(kd=3000, bd=60, b1=5),
                                    dict(kd=100, bd=0, b1=40)])  # fmt: skip
def test_bands_match_the_minimum_over_the_delay(values):
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
              values=dict(m=1.0, b=10.0, k1=1000.0, tau=None, **values))  # fmt: skip
    f = real_part(delayed_impedance(sea, free_delay=True))
    bands = [(float(a), float(b)) for a, b in dangerous_bands(f)]
    w = np.geomspace(1e-2, 1e4, 4000)
    low = _min_over_theta(f, w)
    scale = np.abs(low).max()
    inside = np.zeros_like(w, dtype=bool)
    for a, b in bands:
        inside |= (w > a) & (w < b)
    # the grid agrees with the exact band away from its edges
    assert np.all(low[~inside] >= -1e-9 * scale)
    edge = np.zeros_like(inside)
    for a, b in bands:
        edge |= (np.abs(w - a) < 1e-3 * max(a, 1)) | (np.abs(w - b) < 1e-3 * b)
    assert np.all(low[inside & ~edge] < 0)


def test_delay_independent_design_has_no_band():
    # Z = m s + b + B e^{-sτ}: A = b, B = B, C = 0; A ≥ |B| when B ≤ b
    f = real_part(
        delayed_impedance("m*s + b + B*exp(-tau*s)", values=dict(m=1, b=2, B=1), free_delay=True)
    )
    assert dangerous_bands(f) == []
    bp = band_polynomials(f)
    with precision(64):
        assert bp.gap(1) > 0 and bp.a(1) > 0


def test_band_polynomials_need_first_order():
    f = real_part(
        delayed_impedance("m*s + b + B*exp(-2*tau*s)", values=dict(m=1, b=2, B=1), free_delay=True)
    )
    with pytest.raises(ValueError, match="first power"):
        band_polynomials(f)
