"""The friction certificate: the two-port around the friction, and what passes or not."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from seapass.errors import ParameterError
from seapass.model.sea import SEA
from seapass.model.stiffness import load_impedance
from seapass.ports.friction import friction_certificate, friction_two_port

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0, kd=500.0, bd=25.0)


@pytest.mark.parametrize("at", ["actuator", "transmission"])
def test_no_friction_gives_back_the_one_port(at: str) -> None:
    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 300.0})
    z11, z12, z21, z22 = friction_two_port(sea, at).entries
    # a free port 2 (zero friction force) leaves the SEA as it is
    assert sp.cancel(z11 - z12 * z21 / z22 - load_impedance(sea)) == 0


@pytest.mark.parametrize("at", ["actuator", "transmission"])
def test_certified_for_a_mechanical_coupling_and_not_for_load_feedback(at: str) -> None:
    good = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG)
    assert friction_certificate(good, at=at).certified
    bad = SEA(D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kl": 300.0})
    cert = friction_certificate(bad, at=at)
    assert not cert.certified and "no proof" in cert.detail
    assert cert.to_dict()["certified"] is False


def test_viscous_friction_keeps_a_certified_design_passive() -> None:
    """Close the friction port with dampers (a passive friction law): the SEA stays passive."""
    from seapass.analysis.passivity import is_passive

    sea = SEA(D1="k1 + b1*s", CA="kd + bd*s", values=RIG)
    assert friction_certificate(sea).certified
    for c in np.geomspace(0.1, 1e4, 7):
        # viscous friction c on the actuator: the same as raising b by c
        assert is_passive(sea.with_values(b=RIG["b"] + float(c))).passive


def test_bad_site() -> None:
    with pytest.raises(ParameterError, match="at"):
        friction_certificate(SEA(D1="k1", values={"m": 1, "b": 1, "k1": 1}), at="gearbox")
