"""Issue 26, "Done means": a round trip on the digital twin.

Simulate the twin's log, fit it, take the 95 % box, certify a design robustly and run
the twin at plants drawn from the box against a passive termination (a hand:
mass, spring and damper in unilateral contact): the energy the hand puts into the
port, ``E(t) = ∫ F_ext dx_L``, never goes below 0 (the SEA never gives back more
than it was given).  Short logs and runs keep it cheap; the plants are counted.
"""

from __future__ import annotations

import numpy as np
import pytest

from seapass.analysis.passivity import is_passive
from seapass.model.sea import SEA
from seapass.rig import chirp_command, twin_log
from seapass.rig.identify import fit_rig
from seapass.rig.rigfile import paper_rig
from seapass.rig.robustbox import robust_box
from seapass.rig.twin import simulate_loop
from seapass.robust.verdict import robust_check
from seapass.sampled.passivity import sampled_passivity

RIG = paper_rig()
PLANTS = 5  # twin runs at plants drawn from the box
HAND = {"mass": 1.0, "stiffness": 5000.0, "damping": 10.0, "speed": 0.2}


def port_energy(force: np.ndarray, x_load: np.ndarray) -> np.ndarray:
    """Energy put into the SEA's port by the termination, ``∫ F dx_L`` (trapezoid, J)."""
    return np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(x_load))])


def test_port_energy_sees_energy_given_and_taken_back() -> None:
    x = np.linspace(0.0, 1.0, 11)
    assert port_energy(np.full(11, 2.0), x)[-1] == pytest.approx(2.0)
    assert port_energy(np.full(11, -2.0), x).min() == pytest.approx(-2.0)  # extracted


def test_fit_the_twin_take_the_95_percent_box_certify_and_stay_passive_on_the_twin() -> None:
    log = twin_log(RIG, chirp_command(RIG.control.rate, duration=2.0), load_mass=0.1, seed=7)
    fitted = fit_rig(log, RIG).updated_rig()
    design = SEA(D1="k1 + b1*s", CA="kd + bd*s",
                 values=dict(m=1.0, b=10.0, k1=RIG.damper.k1, b1=30.0, kd=500.0, bd=25.0))  # fmt: skip
    box = robust_box(design, rig=fitted)
    assert box is not None and set(box.intervals) == {"m", "b", "b1"}
    truth = RIG.model_values()
    for name, (lo, hi) in box.intervals.items():  # the twin's own plant is in its 95 % box
        assert lo <= truth[name] <= hi, name
    verdict = robust_check(design, box=box)
    assert verdict.passive and verdict.worst is None
    reflected = RIG.actuator_mass - RIG.transmission.carriage_mass
    rng = np.random.default_rng(26)
    runs = 0
    for i in range(PLANTS):
        plant = {k: float(rng.uniform(lo, hi)) for k, (lo, hi) in box.intervals.items()}
        assert is_passive(design.with_values(**plant)).passive  # the plain exact test agrees
        twin = RIG.replace(transmission={"carriage_mass": plant["m"] - reflected,
                                         "viscous": plant["b"]}, damper={"b1": plant["b1"]})  # fmt: skip
        assert sampled_passivity(design.with_values(**plant), loop=twin.loop).passive
        res = simulate_loop(twin, load_mass=0.1, kp_actuator=500.0, kv_actuator=25.0,
                            duration=0.5, hand=HAND, seed=i)  # fmt: skip
        runs += 1
        energy = port_energy(res.external_force[0], res.x_L[0])
        hand_energy = 0.5 * HAND["mass"] * HAND["speed"] ** 2
        assert not res.diverged[0]
        assert energy.min() >= -1e-6 * hand_energy  # never extracted against the hand
        assert energy.max() > 0.5 * hand_energy  # the hand did push: the check is not empty
    assert runs == PLANTS
