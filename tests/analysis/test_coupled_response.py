"""The impulse response behind a witness: poles far apart in magnitude are not "repeated"
(issue 20, item 7: the witness case of test_fuzz took 2-8 s through scipy's impulse
response, and said the unstable mode grows by a factor 0)."""

from __future__ import annotations

import contextlib
import io
import json

import mpmath
import pytest
import scipy.signal
from flint import fmpq_poly

from cpu_budget import cpu_budget
from seapass.analysis.coupled_response import _partial_fractions
from seapass.cli import main

EXTREME = ["witness", "--D1", "k1", "--CL", "kd", "--set", "m=1e-6", "--set", "b=1e8",
           "--set", "k1=1e8", "--set", "kd=1.0000001e8"]  # fmt: skip
# its coupled characteristic polynomial (with the environment m_e = 10, k_e = 5): poles at
# 5e-8 ± 3162.3j, -1.0000001 and -1e14
DEN = fmpq_poly(
    [10000001500000000, 10000000500000000,
     fmpq_poly([4722366955106317112492914348225])[0] / 4722366482869645213696,
     1000000000, fmpq_poly([23611832414348225])[0] / 2361183241434822606848]
)  # fmt: skip


def test_poles_far_apart_get_residues_that_reassemble_the_transfer():
    roots, res = _partial_fractions(fmpq_poly([1]), DEN)
    assert res is not None  # not mistaken for a repeated pole
    # independent check: sum r_i / (s - p_i) == 1/den(s) at a few points, 50 digits
    coeffs = [mpmath.mpf(int(c.p)) / int(c.q) for c in reversed(DEN.coeffs())]
    with mpmath.workdps(50):
        for s in (mpmath.mpc(0.3, 2), mpmath.mpc(-5, 4000), mpmath.mpc(1e3, -1e5)):
            exact = 1 / mpmath.polyval(coeffs, s)
            modal = sum(complex(r) / (s - complex(p)) for r, p in zip(res, roots, strict=True))
            assert abs(modal - exact) <= 1e-8 * abs(exact)


def test_extreme_witness_is_a_sum_of_modes_and_fast(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("scipy.signal.impulse is for repeated poles only")

    monkeypatch.setattr(scipy.signal, "impulse", refuse)
    out, err = io.StringIO(), io.StringIO()
    with cpu_budget(10.0), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        assert main([*EXTREME, "--json"]) == 0
    assert err.getvalue() == ""
    sim = json.loads(out.getvalue())["simulation"]
    assert sim["growth_rate"] == pytest.approx(5e-8, rel=1e-3)
    assert sim["growth_factor"] > 1  # the unstable mode grows (scipy's answer was 0)
