"""Witnesses within physical bounds: found inside the box, or proven (or plainly not) absent."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from seapass.analysis.coupled import Environment, coupled_stability
from seapass.analysis.environment_box import (
    HUMAN_LIMB,
    EnvironmentBounds,
    certify_box,
    crossing_cells,
)
from seapass.analysis.impedance import exact_rational_function
from seapass.analysis.witness import find_destabilizing_environment
from seapass.cli import main
from seapass.errors import FileFormatError, ParameterError
from seapass.model.design_file import load_design, parse_design
from seapass.model.sea import SEA, Impedance
from seapass.report.analyze import analyze

PLANT = {"m": 1.0, "b": 10.0, "k1": 1000.0}
LOAD_PD = SEA(D1="k1", CL="kd + bd*s", values={**PLANT, "kd": 500.0, "bd": 25.0})
# the same with a tiny derivative (a power of two, so the exact arithmetic stays small):
# not passive, but only environments far lighter than a hand can exploit it
LOAD_PD_TINY = SEA(D1="k1", CL="kd + bd*s", values={**PLANT, "kd": 500.0, "bd": 2.0**-6})


def _float_poles(system, env: Environment) -> np.ndarray:
    """Roots of the numerator of Z + Z_e, from float coefficients (independent of seapass)."""
    num, den = exact_rational_function(system)
    n = np.array([float(c) for c in reversed(num)])
    d = np.array([float(c) for c in reversed(den)])
    ne, de = np.array([env.mass, env.damping, env.stiffness]), np.array([1.0, 0.0])
    chi = np.polyadd(np.polymul(n, de), np.polymul(ne, d))
    return np.roots(np.trim_zeros(chi, "f"))


def _sample(bounds: EnvironmentBounds, n: int, seed: int) -> list[Environment]:
    """Corners and log-uniform draws of the box (zero lower bounds kept as values)."""
    rng = np.random.default_rng(seed)
    out = [
        Environment(m, b, k) for m in bounds.mass for b in bounds.damping for k in bounds.stiffness
    ]
    for _ in range(n):
        vals = []
        for lo, hi in (bounds.mass, bounds.damping, bounds.stiffness):
            start = lo if lo > 0 else hi * 1e-4
            vals.append(float(np.exp(rng.uniform(np.log(start), np.log(hi)))) if hi > 0 else 0.0)
        out.append(Environment(*vals))
    return out


def test_the_issue_load_pd_witness_is_a_plausible_hand_not_milligrams():
    free = find_destabilizing_environment(LOAD_PD, bounds=None, simulate=False)
    assert free.found and free.environment.mass < 1e-3  # the old, meaningless witness
    w = find_destabilizing_environment(LOAD_PD)
    assert w.found and HUMAN_LIMB.contains(w.environment) and w.bounds == HUMAN_LIMB
    assert coupled_stability(LOAD_PD, w.environment).rhp
    assert np.max(_float_poles(LOAD_PD, w.environment).real) > 0
    assert w.simulation is not None and w.simulation.growth_factor > 2
    assert "within m in [0.1, 10] kg" in w.detail


def test_no_destabilizing_hand_is_proven_and_checked_by_sampling():
    w = find_destabilizing_environment(LOAD_PD_TINY, simulate=False)
    assert not w.passive and not w.found and w.certified
    assert "proven exactly" in w.detail and "Outside the bounds" in w.detail
    assert w.outside is not None and not HUMAN_LIMB.contains(w.outside)
    assert coupled_stability(LOAD_PD_TINY, w.outside).rhp  # the design is truly not passive
    for env in _sample(HUMAN_LIMB, 120, seed=1):  # the certificate, refuted by no sample
        assert coupled_stability(LOAD_PD_TINY, env).bounded, env
        assert np.max(_float_poles(LOAD_PD_TINY, env).real) < 1e-6


@pytest.mark.parametrize(
    ("system", "bounds"),
    [
        (LOAD_PD, EnvironmentBounds(mass=(0.5, 5.0), damping=(0.0, 50.0), stiffness=(0.0, 2000.0))),
        (
            LOAD_PD,
            EnvironmentBounds(mass=(2.0, 10.0), damping=(40.0, 100.0), stiffness=(0.0, 10.0)),
        ),
        (
            LOAD_PD_TINY,
            EnvironmentBounds(mass=(1e-6, 1e-4), damping=(0.0, 1.0), stiffness=(0.0, 10.0)),
        ),
        (Impedance(expr="1/(s + 1) - 1/1024"), HUMAN_LIMB),
        (Impedance(expr="(s - 1)/(s + 2)"), EnvironmentBounds((0.1, 1.0), (1.0, 2.0), (0.0, 5.0))),
        (Impedance(expr="(s - 1)/(s + 2)"), EnvironmentBounds((0.1, 1.0), (0.0, 0.25), (0.0, 5.0))),
    ],
)
def test_bounded_search_is_consistent_with_sampling(system, bounds):
    """Found: inside the box and unstable.  Certified: no sample of the box is unstable."""
    w = find_destabilizing_environment(system, bounds=bounds, simulate=False)
    assert not w.passive
    if w.found:
        assert bounds.contains(w.environment) and coupled_stability(system, w.environment).rhp
        assert not w.certified
    samples = _sample(bounds, 60, seed=2)
    unstable = [e for e in samples if not coupled_stability(system, e).bounded]
    if w.certified:
        assert not unstable
    if unstable:  # a sample destabilizes it: then the search must have found one too
        assert w.found


def test_crossing_cells_and_the_certificate_agree_on_a_pinned_case():
    num, den = exact_rational_function("(s - 1)/(s + 2)")
    lossy = EnvironmentBounds((0.1, 1.0), (1.0, 2.0), (0.0, 5.0))  # b > -Re Z everywhere
    assert not crossing_cells(num, den, lossy)
    assert certify_box(num, den, lossy).certified
    light = EnvironmentBounds((0.1, 1.0), (0.0, 0.25), (0.0, 5.0))  # Re Z(0) = -1/2 < -b
    assert not certify_box(num, den, light).certified
    zero_mass = EnvironmentBounds((0.0, 1.0), (1.0, 2.0), (0.0, 5.0))
    assert "mass bound includes 0" in certify_box(num, den, zero_mass).reason


def test_bounds_validation():
    with pytest.raises(ParameterError, match="mass"):
        EnvironmentBounds(mass=(2.0, 1.0))
    with pytest.raises(ParameterError, match="passive"):
        EnvironmentBounds(damping=(-1.0, 1.0))
    assert HUMAN_LIMB.clip(100.0, -1.0, 1e9) == Environment(10.0, 0.0, 5000.0)


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


PD_ARGS = ["--D1", "k1", "--CL", "kd + bd*s", "--set", "m=1", "--set", "b=10",
           "--set", "k1=1000", "--set", "kd=500"]  # fmt: skip


def test_cli_witness_bounds():
    code, out, _ = _cli(["witness", *PD_ARGS, "--set", "bd=25", "--mass", "0.5:5",
                         "--stiffness", "0:2000", "--json"])  # fmt: skip
    data = json.loads(out)
    assert code == 0 and data["found"] and data["bounds"]["mass"] == [0.5, 5.0]
    assert 0.5 <= data["environment"]["mass"] <= 5.0
    code, out, _ = _cli(["witness", *PD_ARGS, "--set", "bd=0.015625"])
    assert code == 0 and "no destabilizing environment (proven exactly)" in out
    code, _, err = _cli(["witness", *PD_ARGS, "--set", "bd=25", "--mass", "1", "--json"])
    assert code == 2 and "LO:HI" in err and err.count("\n") == 1
    code, _, err = _cli(["witness", *PD_ARGS, "--set", "bd=25", "--unbounded", "--mass", "1:2"])
    assert code == 2 and "one or the other" in err


DESIGN = """
name = "load-PD"
[model]
D1 = "k1"
CL = "kd + bd*s"
[parameters]
m = 1.0
b = 10.0
k1 = 1000.0
kd = 500.0
bd = 0.015625
[environment]
mass = [0.2, 4.0]
"""


def test_design_file_environment_and_the_analyze_stage(tmp_path: Path):
    path = tmp_path / "pd.toml"
    path.write_text(DESIGN)
    design = load_design(path)
    assert dict(design.environment) == {"mass": (0.2, 4.0)}
    sec = analyze(design, stages=["witness"]).sections[0]
    assert sec.key == "witness" and sec.status == "ok"
    assert "proven exactly" in sec.text and "m in [0.2, 4] kg" in sec.text
    assert sec.findings[0].verdict == "agrees"
    assert json.loads(sec.files["witness.json"])["certified"] is True
    for bad, fragment in (("mass = [4.0, 0.2]", "lo <= hi"), ("weight = [1, 2]", "unknown key"),
                          ("mass = [-1.0, 2.0]", ">= 0")):  # fmt: skip
        text = DESIGN.replace("mass = [0.2, 4.0]", bad)
        import tomllib

        with pytest.raises(FileFormatError, match=fragment):
            parse_design(tomllib.loads(text))
