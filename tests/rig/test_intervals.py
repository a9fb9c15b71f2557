"""A fit's intervals in the rig file (``[intervals]``): written by the fit, read back, recomputed."""

from __future__ import annotations

import tomllib
from importlib import resources

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from seapass.errors import FileFormatError, ParameterError
from seapass.rig import chirp_command, twin_log
from seapass.rig.identify import fit_rig
from seapass.rig.intervals import FitIntervals
from seapass.rig.rigfile import paper_rig, parse_rig

RIG = paper_rig()


@pytest.fixture(scope="module")
def fit():  # type: ignore[no-untyped-def]
    log = twin_log(RIG, chirp_command(RIG.control.rate, duration=2.0), load_mass=0.1, seed=7)
    return fit_rig(log, RIG)


def test_the_fit_writes_its_95_percent_intervals_into_the_rig_file_it_emits(fit) -> None:  # type: ignore[no-untyped-def]
    text = resources.files("seapass").joinpath("data/paper_rig.toml").read_text(encoding="utf-8")
    out = fit.updated_rig_text(text, relative_to="/tmp/out/fitted.toml")
    assert text.splitlines()[0] in out  # the file's own lines and comments are kept
    assert "# written by seapass rig fit; read by --robust\n[intervals]" in out
    rig = parse_rig(tomllib.loads(out))
    iv = rig.intervals
    assert iv is not None and iv.confidence == 0.95 and iv.dof == fit.windows_used - 6
    for name in ("m", "b", "b1"):
        p = fit[name]
        assert iv.intervals[name] == (p.low, p.high) and iv.stderr[name] == p.stderr
    assert set(iv.intervals) == {"m", "b", "b1"}  # Coulomb levels are not model parameters
    # the fitted values are inside (the twin's own values too: m 1.02032, b 10, b1 30)
    lo, hi = iv.intervals["m"]
    assert lo <= rig.actuator_mass <= hi
    assert parse_rig(tomllib.loads(RIG.to_toml())).intervals is None
    # refitting a fitted file updates the table in place
    again = fit.updated_rig_text(out)
    assert again.count("[intervals]") == 1 and parse_rig(tomllib.loads(again)) == rig


def test_a_level_is_recomputed_from_the_standard_errors_with_students_t(fit) -> None:  # type: ignore[no-untyped-def]
    iv = fit.intervals()
    at99 = iv.at(0.99)
    dof = fit.windows_used - 6
    for name in ("m", "b", "b1"):
        p = fit[name]
        q = stats.t.ppf(0.995, dof)
        assert at99.intervals[name] == pytest.approx(
            (p.value - q * p.stderr, p.value + q * p.stderr), rel=1e-12
        )
    lo95, hi95 = iv.intervals["m"]
    lo99, hi99 = at99.intervals["m"]
    assert lo99 < lo95 and hi95 < hi99
    assert iv.at(0.95) is iv
    with pytest.raises(ParameterError, match=r"confidence must lie in \(0, 1\)"):
        iv.at(1.0)


def test_without_standard_errors_another_level_is_refused() -> None:
    iv = FitIntervals(confidence=0.95, intervals={"m": (0.9, 1.1)})
    assert not iv.recomputable
    with pytest.raises(ParameterError, match="keep no standard errors"):
        iv.at(0.9)


def test_the_box_cuts_dampings_at_zero_and_refuses_a_mass_reaching_zero() -> None:
    iv = FitIntervals(confidence=0.95, intervals={"m": (0.9, 1.1), "b": (-0.5, 1.0), "b1": (2, 3)})
    assert iv.box() == {"m": (0.9, 1.1), "b": (0.0, 1.0), "b1": (2, 3)}
    assert iv.box(["m", "b"]) == {"m": (0.9, 1.1), "b": (0.0, 1.0)}
    with pytest.raises(ParameterError, match="does not bound the mass"):
        FitIntervals(confidence=0.95, intervals={"m": (-0.1, 1.1)}).box()


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"confidence": 0.95}, "gives no interval"),
        ({"confidence": 1.0, "m": [0.9, 1.1]}, r"intervals.confidence must lie in \(0, 1\)"),
        ({"confidence": 0.95, "m": [1.1, 0.9]}, "intervals.m"),
        ({"confidence": 0.95, "k1": [1.0, 2.0]}, "unknown key intervals.k1"),
        ({"confidence": 0.95, "m": [0.9, 1.1], "b_stderr": 0.1}, "no interval intervals.b"),
        ({"m": [0.9, 1.1]}, "intervals.confidence"),
    ],
)
def test_a_bad_intervals_table_names_the_key(table: dict, message: str) -> None:  # type: ignore[type-arg]
    data = {**RIG.to_dict(), "intervals": table}
    with pytest.raises(FileFormatError, match=message):
        parse_rig(data)


def test_the_frequency_response_fit_writes_intervals_too() -> None:
    from seapass.rig.frf import MeasuredResponse, fit_frf

    f = np.linspace(2.0, 40.0, 30)
    s = 2j * np.pi * f
    m, b, b1, k1 = 1.02, 10.0, 30.0, RIG.damper.k1
    T = RIG.period
    hold = np.exp(-s * RIG.control.delay * T) * (1 - np.exp(-s * T)) / (s * T)
    mL = 0.6
    # actuator and load with the damped spring between: solve the 2x2 system for F = hold
    za = m * s**2 + b * s + k1 + b1 * s
    zl = mL * s**2 + k1 + b1 * s
    c = k1 + b1 * s
    det = za * zl - c * c
    xa, xl = hold * zl / det, hold * c / det
    rows = np.stack([f, abs(xa), np.degrees(np.angle(xa)), abs(xl), np.degrees(np.angle(xl))], 1)
    fit = fit_frf(MeasuredResponse.from_polar(rows, source="frf.csv"), RIG)
    rig = fit.updated_rig()
    assert rig.intervals is not None and rig.intervals.dof == 2 * f.size - 3
    lo, hi = rig.intervals.intervals["m"]
    assert lo <= 1.02 + 1e-9 and hi >= 1.02 - 1e-9


@given(st.floats(0.05, 0.999), st.floats(0.05, 0.999))
def test_a_higher_level_gives_a_wider_interval_about_the_same_estimate(a: float, b: float) -> None:
    iv = FitIntervals(confidence=0.95, intervals={"m": (0.9, 1.1)}, stderr={"m": 0.05}, dof=40)
    low, high = sorted((a, b))
    inner, outer = iv.at(low).intervals["m"], iv.at(high).intervals["m"]
    assert outer[0] <= inner[0] and inner[1] <= outer[1]
    assert (inner[0] + inner[1]) / 2 == pytest.approx(1.0) == (outer[0] + outer[1]) / 2
