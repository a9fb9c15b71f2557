"""python-control interop, cross-checked against python-control; short reprs and notebook HTML."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import control
import numpy as np
import pytest

from seapass.analysis.freqresp import stiffness_response
from seapass.analysis.passivity import is_passive
from seapass.analysis.portresponse import impedance_response
from seapass.analysis.region import passive_intervals, passive_map
from seapass.errors import ExpressionError, ParameterError
from seapass.model.catalog import (
    PAPER_VALUES,
    REFERENCE_VALUES,
    SIMULATION_DESIGNS,
    TABLE_ROWS,
    design,
)
from seapass.model.design_file import load_design
from seapass.model.realization import INPUTS, OUTPUTS, closed_loop
from seapass.model.sea import SEA, Impedance
from seapass.sim.scenarios import Step
from seapass.sim.simulate import simulate

DESIGNS = [*SIMULATION_DESIGNS, *TABLE_ROWS]
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
W = np.logspace(-1, 4, 97)


def _sea(d: object) -> SEA:
    """The design at the reference values of the parameters it uses."""
    used = d.sea().parameters  # type: ignore[attr-defined]
    return d.sea({k: v for k, v in REFERENCE_VALUES.items() if k in used})  # type: ignore[attr-defined]


def _response(sys_: object, w: np.ndarray) -> np.ndarray:
    return np.asarray(control.frequency_response(sys_, w).complex).reshape(-1)


@pytest.mark.parametrize("d", DESIGNS, ids=lambda d: d.key)
def test_transfer_functions_match_our_frequency_responses(d: object) -> None:
    sea = _sea(d)
    k = sea.to_control("stiffness")
    z = sea.to_control("impedance")
    assert isinstance(k, control.TransferFunction) and k.isctime(strict=True)
    assert (k.input_labels, k.output_labels) == (["x_L"], ["F_L"])
    assert (z.input_labels, z.output_labels) == (["v_L"], ["F_L"])
    ours = stiffness_response(sea, W)
    theirs = _response(k, W)
    np.testing.assert_allclose(np.abs(theirs), ours.magnitude, rtol=1e-9)
    np.testing.assert_allclose(np.unwrap(np.angle(theirs)), np.radians(ours.phase), atol=1e-9)
    # Z = K/s, evaluated by python-control and by seapass's own impedance response
    np.testing.assert_allclose(_response(z, W), theirs / (1j * W), rtol=1e-9)
    zr = impedance_response(sea, W)  # W plus the exact band edges
    np.testing.assert_allclose(_response(z, zr.omega), zr.value, rtol=1e-9)


@pytest.mark.parametrize("d", DESIGNS, ids=lambda d: d.key)
def test_round_trip_through_python_control(d: object) -> None:
    sea = _sea(d)
    z = sea.to_control()
    back = Impedance.from_control(z)
    r0, r1 = is_passive(sea), is_passive(back)
    assert (r0.passive, r0.reason) == (r1.passive, r1.reason)
    np.testing.assert_allclose(
        np.array(r1.den) / r1.den[0], np.array(r0.den) / r0.den[0], rtol=1e-15
    )
    np.testing.assert_allclose(
        np.array(r1.num) / r1.den[0], np.array(r0.num) / r0.den[0], rtol=1e-15
    )
    again = back.to_control()
    np.testing.assert_allclose(_response(again, W), _response(z, W), rtol=1e-12)


def test_state_space_has_named_signals_and_matches_the_stiffness() -> None:
    sea = _sea(design("ours"))
    loop = closed_loop(sea, load_mass=0.5)
    ss = loop.to_control()
    assert isinstance(ss, control.StateSpace)
    assert ss.input_labels == list(INPUTS) and ss.output_labels == list(OUTPUTS)
    assert ss.state_labels == list(loop.states)
    np.testing.assert_allclose(np.sort_complex(ss.poles()), np.sort_complex(loop.poles), rtol=1e-9)
    # independent: the realization vs the symbolic stiffness, X_L/f_ext = 1/(m_L s^2 + K(s))
    k = stiffness_response(sea, W)
    kk = k.magnitude * np.exp(1j * np.radians(k.phase))
    expected = 1.0 / (0.5 * (1j * W) ** 2 + kk)
    np.testing.assert_allclose(_response(ss["x_L", "f_ext"], W), expected, rtol=1e-8)


def test_impedance_from_control_rejects_what_is_not_an_impedance() -> None:
    with pytest.raises(ParameterError, match="SISO"):
        Impedance.from_control(control.rss(2, 2, 1))
    with pytest.raises(ParameterError, match="discrete-time"):
        Impedance.from_control(control.tf([1], [1, -0.5], 0.01))
    with pytest.raises(ExpressionError, match=r"control\.TransferFunction"):
        Impedance.from_control([1, 2])  # type: ignore[arg-type]
    ss = control.ss([[-2.0]], [[1.0]], [[1.0]], [[1.0]])  # (s + 3)/(s + 2)
    assert is_passive(Impedance.from_control(ss)).passive


def test_to_control_names_missing_values_and_bad_kinds() -> None:
    sea = design("LP").sea(PAPER_VALUES)
    with pytest.raises(ParameterError, match=r"kd.*values=\{'kd'"):
        sea.to_control()
    with pytest.raises(ParameterError, match="impedance, stiffness"):
        _sea(design("LP")).to_control("admittance")
    assert sea.to_control(values={"kd": 200.0}).dcgain() == pytest.approx(np.inf)


def test_reprs_are_short_and_html_is_a_table() -> None:
    sea = _sea(design("ours"))
    r = is_passive(SEA(D1="k1", CL="kd + bd*s", values=dict(m=1, b=10, k1=1000, kd=500, bd=20)))
    free = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1, b=10, k1=1e3, b1=None, kd=None))
    objects = [
        sea,
        Impedance(expr="(s + 1)/(s + 2)"),
        r,
        stiffness_response(sea),
        impedance_response(sea),
        closed_loop(sea, load_mass=1.0),
        design("ours"),
        load_design(EXAMPLES / "ours.toml"),
        passive_intervals(free.with_values(b1=20.0), "kd", 0.0, 5000.0),
        passive_map(free, "kd", np.linspace(0.0, 2000.0, 3), "b1", (0.0, 100.0)),
        simulate(sea, load_mass=1.0, scenario=Step(0.1), horizon=0.5),
    ]
    for obj in objects:
        text = repr(obj)
        assert len(text) <= 250 and "mappingproxy" not in text and "array(" not in text, text
        html = obj._repr_html_()  # type: ignore[attr-defined]
        assert html.startswith("<div>") and "<table>" in html
    assert repr(r).startswith("PassivityResult(passive=False, reason='negative_real_part'")
    assert r.tolerance not in repr(r)
    assert repr(SEA(D1="k1 + b1*s", CA="kd", values=dict(m=1, b=10, k1=1e3, b1=20, kd=5))) == (
        "SEA(D1='b1*s + k1', CA='kd', values={'m': 1, 'b': 10, 'k1': 1000, 'b1': 20, 'kd': 5})"
    )
    assert repr(SEA(D1="k1", m=2, values={"b": 1.5, "k1": None})) == (
        "SEA(D1='k1', m='2', values={'b': 1.5, 'k1': None})"
    )


def test_control_is_imported_only_on_use() -> None:
    code = (
        "import sys, seapass as sp; "
        "sea = sp.SEA(D1='k1', CL='kd', values=dict(m=1, b=10, k1=1000, kd=500)); "
        "sp.is_passive(sea); repr(sea); print('control' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_results_plot_themselves_on_given_axes() -> None:
    from matplotlib.figure import Figure

    sea = _sea(design("ours"))
    fig = Figure()
    ax = fig.subplots()
    free = sea.with_values(kd=None)
    assert passive_intervals(free, "kd", 0.0, 5000.0).plot(ax=ax) is ax
    axes = Figure().subplots(2, 1)
    run = simulate(sea, load_mass=1.0, scenario=Step(0.1), horizon=0.5)
    assert list(run.plot(axes=axes)) == list(axes)


def test_docs_page_python_runs(capsys: pytest.CaptureFixture[str]) -> None:
    import re

    from seapass.plot.style import bare_figures

    page = EXAMPLES.parent / "docs" / "plots-and-control.md"
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), re.S)
    assert len(blocks) == 3
    with bare_figures():
        for i, block in enumerate(blocks):
            exec(compile(block, f"{page.name} python block {i}", "exec"), {})
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "((35.35533905932738, inf),)"
    assert out[1:5] == ["333.3333333333333", "['theta_A', 'theta_L', 'f_ext']", "True", "True"]
