"""`rig fit --frf`: m, b, b1 from a measured frequency response, checked against an
independent two-mass model solved with sympy (the load's mass and damping unknown to the fit)."""

from __future__ import annotations

import contextlib
import io
import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from seapass.cli import main
from seapass.errors import FileFormatError, ParameterError
from seapass.rig.frf import fit_frf, load_frf
from seapass.rig.packaged import rig_template
from seapass.rig.rigfile import paper_rig, parse_rig

RIG = paper_rig()
TRUE = {"m": 1.3, "b": 12.0, "b1": 25.0}


def _two_mass_response(freq: np.ndarray, *, m_load: float = 0.4, b_load: float = 0.7) -> tuple:
    """x_A/F, x_L/F of actuator and load joined by k1 + b1 s, force through hold and delay."""
    s, m, b, b1, k1, mL, bL, G = sp.symbols("s m b b1 k1 mL bL G")
    xa, xl = sp.symbols("xa xl")
    sol = sp.solve(
        [
            sp.Eq((m * s**2 + b * s + k1 + b1 * s) * xa - (k1 + b1 * s) * xl, G),
            sp.Eq((mL * s**2 + bL * s + k1 + b1 * s) * xl - (k1 + b1 * s) * xa, 0),
        ],
        [xa, xl],
    )
    T, d = RIG.period, RIG.control.delay
    out = []
    for expr in (sol[xa], sol[xl]):
        f = sp.lambdify((s, G), expr.subs({m: TRUE["m"], b: TRUE["b"], b1: TRUE["b1"],
                                           k1: RIG.damper.k1, mL: m_load, bL: b_load}))  # fmt: skip
        sv = 2j * np.pi * freq
        hold = np.exp(-sv * d * T) * (1 - np.exp(-sv * T)) / (sv * T)
        out.append(np.array([complex(f(x, g)) for x, g in zip(sv, hold, strict=True)]))
    return out[0], out[1]


def _csv(freq: np.ndarray, ha: np.ndarray, hl: np.ndarray) -> str:
    rows = ["frequency,xa_mag,xa_phase,xl_mag,xl_phase"] + [
        ",".join(
            repr(float(x))
            for x in (f, abs(a), np.degrees(np.angle(a)), abs(c), np.degrees(np.angle(c)))
        )
        for f, a, c in zip(freq, ha, hl, strict=True)
    ]
    return "# measured on the bench\n" + "\n".join(rows) + "\n"


def test_exact_response_gives_the_parameters(tmp_path: Path) -> None:
    freq = np.geomspace(2.0, 60.0, 40)
    (tmp_path / "r.csv").write_text(_csv(freq, *_two_mass_response(freq)))
    fit = fit_frf(load_frf(tmp_path / "r.csv"), RIG)
    for name, value in TRUE.items():
        assert fit[name].value == pytest.approx(value, rel=1e-6)
    assert fit.residual_std < 1e-8


def test_noisy_response_gives_close_estimates(tmp_path: Path) -> None:
    freq = np.geomspace(2.0, 60.0, 80)
    ha, hl = _two_mass_response(freq)
    rng = np.random.default_rng(4)

    def noise(h):
        return h * (1 + 0.01 * (rng.standard_normal(h.size) + 1j * rng.standard_normal(h.size)))

    (tmp_path / "r.csv").write_text(_csv(freq, noise(ha), noise(hl)))
    fit = fit_frf(load_frf(tmp_path / "r.csv"), RIG)
    # 1 % noise on the measured response: the estimates stay within 5 % (the intervals treat
    # the noise as an error of the force equation, so they are not claimed to cover it)
    for name, value in TRUE.items():
        assert fit[name].value == pytest.approx(value, rel=0.05), (name, fit[name])
        assert fit[name].low < fit[name].value < fit[name].high


def test_cli_fit_frf_json_text_and_rig_out(tmp_path: Path) -> None:
    freq = np.geomspace(2.0, 60.0, 30)
    (tmp_path / "r.csv").write_text(_csv(freq, *_two_mass_response(freq)))
    rig = tmp_path / "rig.toml"
    rig.write_text(rig_template())
    out, err = io.StringIO(), io.StringIO()
    argv = ["rig", "fit", str(tmp_path / "r.csv"), "--frf", "--rig", str(rig)]
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        assert main([*argv, "--json", "--rig-out", str(tmp_path / "fitted.toml")]) == 0
    data = json.loads(out.getvalue())
    assert data["kind"] == "frequency_response"
    assert data["parameters"]["b1"]["value"] == pytest.approx(TRUE["b1"], rel=1e-6)
    text = (tmp_path / "fitted.toml").read_text()
    fitted = parse_rig(tomllib.loads(text))
    assert fitted.damper.b1 == pytest.approx(TRUE["b1"], rel=1e-6)
    assert fitted.actuator_mass == pytest.approx(TRUE["m"], rel=1e-6)
    assert text.count("#") == rig_template().count("#") + 1  # comments kept; [intervals] noted
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(argv) == 0
    assert "Coulomb friction is not seen" in out.getvalue() and "b1" in out.getvalue()


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("1,2,3\n", "expected 5 numbers"),
        ("1,1,0,1,0\n2,1,0,1,0\n", "at least 3"),
        ("2,1,0,1,0\n1,1,0,1,0\n3,1,0,1,0\n", "increase"),
        ("1,-1,0,1,0\n2,1,0,1,0\n3,1,0,1,0\n", "positive"),
        ("1,nan,0,1,0\n", "expected 5 numbers"),
    ],
)
def test_bad_files_name_the_line(tmp_path: Path, text: str, says: str) -> None:
    (tmp_path / "r.csv").write_text(text)
    with pytest.raises(FileFormatError, match=says):
        load_frf(tmp_path / "r.csv")
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(
            ["rig", "fit", str(tmp_path / "r.csv"), "--frf", "--rig", str(_rig_file(tmp_path))]
        )
    assert code == 2 and err.getvalue().startswith("error:") and err.getvalue().count("\n") == 1


def _rig_file(tmp_path: Path) -> Path:
    p = tmp_path / "rig.toml"
    p.write_text(RIG.to_toml())
    return p


def test_beyond_nyquist_and_plot_are_refused(tmp_path: Path) -> None:
    freq = np.array([10.0, 100.0, 300.0])
    ha, hl = np.ones(3, complex), np.ones(3, complex)
    (tmp_path / "r.csv").write_text(_csv(freq, ha, hl))
    with pytest.raises(ParameterError, match="Nyquist"):
        fit_frf(load_frf(tmp_path / "r.csv"), RIG)
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["rig", "fit", str(tmp_path / "r.csv"), "--frf", "--rig", str(_rig_file(tmp_path)),
                     "--plot", str(tmp_path / "p.png")])  # fmt: skip
    assert code == 2 and "--plot" in err.getvalue()
