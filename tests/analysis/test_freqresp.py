"""One frequency-grid rule for `seapass response`, `seapass plot` and impedance_response."""

from __future__ import annotations

import contextlib
import io

import numpy as np
import pytest

from seapass.analysis.freqresp import check_points, log_frequencies
from seapass.analysis.portresponse import impedance_response
from seapass.cli import main
from seapass.errors import ParameterError
from seapass.files.limits import MAX_FREQUENCY_POINTS
from seapass.model.sea import Impedance

RESPONSE = ["response", "--D1", "k1", "--set", "m=1", "--set", "b=1", "--set", "k1=1"]

RESPONSE = ["response", "--D1", "k1", "--set", "m=1", "--set", "b=1", "--set", "k1=1"]


def test_log_frequencies() -> None:
    w = log_frequencies(0.1, 1e4, 6)
    assert np.allclose(w, [0.1, 1, 10, 100, 1e3, 1e4])
    for lo, hi in ((0, 10), (-1, 10), (10, 10), (10, 1), (1, float("inf"))):
        with pytest.raises(ParameterError, match="0 < lo < hi"):
            log_frequencies(lo, hi, 10)
    for n in (1, MAX_FREQUENCY_POINTS + 1, 2.5, True):
        with pytest.raises(ParameterError, match="points must be between 2 and 100000"):
            check_points(n)  # type: ignore[arg-type]


def test_the_library_default_grid_has_the_same_limit() -> None:
    with pytest.raises(ParameterError, match="points must be between"):
        impedance_response(Impedance(expr="1/(s + 1)"), points=MAX_FREQUENCY_POINTS + 1)


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["plot", "real", "--Z", "1/(s+1)", "--omega", "1:x"], "--omega end"),  # was "--range end"
        (["plot", "real", "--Z", "1/(s+1)", "--points", "1"], "got --points 1"),
        ([*RESPONSE, "--omega", "10:10"], "--omega must be positive frequencies 0 < lo < hi"),
    ],
)
def test_the_cli_words(argv: list[str], says: str) -> None:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        assert main(argv) == 2
    assert err.getvalue().count("\n") == 1 and says in err.getvalue(), err.getvalue()
