"""The python-control note of docs/plots-and-control.md, checked: `control.ispassive` on
`sea.to_control()` says a passive design is not passive, `get_input_ff_index` raises, and
seapass's exact verdict is right (cross-checked on a dense grid and by the poles)."""

from __future__ import annotations

import warnings
from pathlib import Path

import control
import numpy as np
import pytest

from seapass.analysis.indices import passivity_indices
from seapass.analysis.passivity import is_passive
from seapass.model.sea import SEA

DOCS = Path(__file__).resolve().parents[2] / "docs" / "plots-and-control.md"
STIFF_SPRING = SEA(D1="k1", D2="k2", CA="kd", values=dict(m=1, b=10, k1=1000, k2=1e5, kd=500))
OURS_STIFF = SEA(
    D1="k1 + b1*s", CA="kd + bd*s", values=dict(m=1, b=10, k1=1005, b1=30, kd=5000, bd=25)
)


def _passive_on_a_grid(sea: SEA) -> bool:
    """Independent check: poles in the closed left half-plane, Re Z(jω) >= 0 on a dense grid."""
    z = sea.to_control()
    num, den = np.ravel(z.num[0][0]), np.ravel(z.den[0][0])
    w = np.logspace(-3, 6, 20001)
    re = (np.polyval(num, 1j * w) / np.polyval(den, 1j * w)).real
    return bool(np.all(np.roots(den).real <= 1e-9) and np.all(re >= -1e-9 * np.abs(re).max()))


def test_control_ispassive_says_a_passive_design_is_not() -> None:
    assert is_passive(STIFF_SPRING).passive and _passive_on_a_grid(STIFF_SPRING)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert control.ispassive(STIFF_SPRING.to_control()) is False


def test_control_input_ff_index_raises_where_seapass_has_the_exact_index() -> None:
    assert is_passive(OURS_STIFF).passive and _passive_on_a_grid(OURS_STIFF)
    nu = passivity_indices(OURS_STIFF).nu
    assert nu == pytest.approx(16.1538, rel=1e-4)
    with warnings.catch_warnings(), pytest.raises(RuntimeError, match="infeasible"):
        warnings.simplefilter("ignore")
        control.get_input_ff_index(OURS_STIFF.to_control())


def test_the_docs_say_so_with_the_reason() -> None:
    text = DOCS.read_text()
    assert "control.ispassive" in text and "get_input_ff_index" in text
    assert "k2=1e5" in text and "kd = 5000" in text and "16.15" in text
    assert "no\ninterior" in text or "no interior" in text
