"""One verdict vocabulary (issue 21, item 3): every passivity result speaks `Outcome`.

* every public passivity result exposes ``outcome`` of type `Outcome`, and its
  ``passive`` (when it has one) is ``outcome.passive``;
* ``marginal`` has one meaning: decided, but near the boundary (never "undecided");
* no source compares a verdict, status, reason or kind to a string literal: the
  enums are compared (an AST scan of ``src/seapass``).
"""

from __future__ import annotations

import ast
import dataclasses
import itertools
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from seapass.analysis.coupled import CoupledResult, Environment, Stability, coupled_stability
from seapass.analysis.environment_box import (
    HUMAN_LIMB,
    BoxCertificate,
    EnvironmentBounds,
    certify_box,
)
from seapass.analysis.indices import PassivityIndex, PassivityIndices, passivity_indices
from seapass.analysis.passivity import PassivityResult, Reason, is_passive
from seapass.analysis.witness import WitnessResult, WitnessStatus, find_destabilizing_environment
from seapass.analysis.witness_search import Growth
from seapass.batch.verdicts import BatchPassivity, batch_is_passive
from seapass.explore.reports import JobStatus
from seapass.model.loop import SampledLoop
from seapass.model.sea import SEA
from seapass.outcome import Outcome
from seapass.paper.tables import BoundStatus
from seapass.report.document import Discrepancy, SectionStatus, Verdict
from seapass.sampled.bound import EdgeKind, SampledBoundResult, sampled_passive_bound
from seapass.sampled.boxes import BoxVerdict
from seapass.sampled.passivity import SampledPassivityResult, SampledReason, sampled_passivity
from seapass.sampled.verdict import Decision
from seapass.sim.metrics import Settling
from seapass.tuning.optimize import TuningResult, verify
from seapass.tuning.problem import TuningOptions, resolve_problem

SRC = Path(__file__).resolve().parents[1] / "src" / "seapass"
LP = dict(m=1, b=10, k1=1005, b1=30, kd=500)


def _lp(**values: Any) -> SEA:
    return SEA(D1="k1 + b1*s", CL="kd", values={**LP, **values})


def _results() -> dict[type, list[Any]]:
    """Cheap instances of every public passivity result, passive and not."""
    sea = _lp()
    problem = resolve_problem(sea, {"kd": (0.0, 1000.0)}, TuningOptions(horizon=1.0))
    z = ([1.0, -1.0], [1.0, 1.0])  # (s - 1)/(s + 1), descending
    return {
        PassivityResult: [is_passive("(s + 1)/(s + 2)"), is_passive("(s - 1)/(s + 2)")],
        SampledPassivityResult: [
            sampled_passivity(sea, loop=SampledLoop(period=0.002)),
            sampled_passivity(_lp(b1=1e6, k1=1000, kd=950), loop=SampledLoop(period=0.002)),
            sampled_passivity(
                _lp(b1=1e6, k1=1000, kd=950), loop=SampledLoop(period=0.002), max_precision=64
            ),
        ],
        CoupledResult: [
            coupled_stability("(s - 1)/(s + 1)", Environment(damping=0.5)),
            coupled_stability("(s + 1)/(s + 2)", Environment(mass=1.0)),
        ],
        WitnessResult: [
            find_destabilizing_environment("(s + 1)/(s + 2)"),
            find_destabilizing_environment(sea.with_values(k1=1000, b1=0, kd=2000), simulate=False),
        ],
        BoxCertificate: [
            certify_box([2, 1], [1, 1], HUMAN_LIMB),  # (s + 2)/(s + 1)
            certify_box(*(list(reversed(c)) for c in z), HUMAN_LIMB),
        ],
        PassivityIndices: [passivity_indices("s/(s**2 + 0.2*s + 1)"), passivity_indices(z)],
        PassivityIndex: [passivity_indices(z).input, passivity_indices(z).output],
        BatchPassivity: [batch_is_passive(_lp(kd=None), {"kd": np.array([500.0, 2000.0])})],
        TuningResult: [verify(problem, [500.0], bounds=problem.box)],
        Decision: [],
        BoxVerdict: [],
    }


@pytest.fixture(scope="module")
def results() -> dict[type, list[Any]]:
    return _results()


def _outcome_declared(cls: type) -> bool:
    names = {f.name for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else set()
    return "outcome" in names or isinstance(getattr(cls, "outcome", None), property)


def test_every_passivity_result_declares_an_outcome(results: dict[type, list[Any]]) -> None:
    for cls in results:
        assert _outcome_declared(cls), f"{cls.__name__} has no outcome"


def test_every_passivity_result_has_an_outcome_of_type_outcome(
    results: dict[type, list[Any]],
) -> None:
    for cls, instances in results.items():
        for r in instances:
            assert isinstance(r, cls)
            if isinstance(r, BatchPassivity):
                assert all(isinstance(o, Outcome) for o in r.outcome.flat)
                assert (np.vectorize(lambda o: o.passive)(r.outcome) == r.passive).all()
                continue
            assert isinstance(r.outcome, Outcome), cls.__name__
            if hasattr(r, "passive"):
                assert r.passive is r.outcome.passive, cls.__name__


def test_outcomes_are_the_expected_ones(results: dict[type, list[Any]]) -> None:
    """Each result says what it proves, and never passive without a proof."""
    P, N, U = Outcome.PASSIVE, Outcome.NOT_PASSIVE, Outcome.UNDECIDED
    assert [r.outcome for r in results[PassivityResult]] == [P, N]
    assert [r.outcome for r in results[SampledPassivityResult]] == [P, N, U]
    # one environment proves only "not passive" (passivity theorem), never passive
    assert [r.outcome for r in results[CoupledResult]] == [N, U]
    assert [r.outcome for r in results[WitnessResult]] == [P, N]
    assert [r.outcome for r in results[BoxCertificate]] == [P, U]
    assert [r.outcome for r in results[PassivityIndices]] == [P, N]
    assert results[TuningResult][0].outcome is P


def test_outcome_of_a_coupling_needs_a_passive_environment() -> None:
    """An unstable coupling with an active environment proves nothing about the design."""
    passive_z = coupled_stability("(s + 1)/(s + 2)", "(s - 1)/(s + 1)")
    assert passive_z.status is Stability.UNSTABLE and passive_z.outcome is Outcome.UNDECIDED
    active_z = coupled_stability("(s - 1)/(s + 1)", "(s + 3)/(s + 4)")
    assert active_z.status is Stability.UNSTABLE and active_z.outcome is Outcome.NOT_PASSIVE


@pytest.mark.parametrize(
    "z",
    ["(s + 1)/(s + 2)", "(s - 1)/(s + 2)", "1/s", "s", "1/(s**2 + 1)", "(s**2 + 1)/s",
     "1/(s + 1) - 1e-9", "s/(s**2 + 0.2*s + 1)", "(s + 2)/((s + 1)*(s - 1))", "1/(s + 1)**2",
     "(s**2 + 2*s + 5)/(s**2 + 0.1*s + 1)"],
)  # fmt: skip
def test_index_outcome_agrees_with_the_positive_real_test(z: str) -> None:
    """Independent methods: the sign of ν (an infimum on the half-line) and the PR test."""
    assert passivity_indices(z).outcome is is_passive(z).outcome


def test_marginal_means_decided_near_the_boundary() -> None:
    """The one meaning of ``marginal`` (seapass.outcome): decided, within the stated margin."""
    # Re Z(jw) ~ (1 - w^2)^2 + a w^2 touches zero at w = 1 when a = 0
    near = is_passive("(s**2 + 1e-13*s + 1)/(s**2 + s + 1)")
    assert near.marginal and near.outcome is Outcome.PASSIVE
    assert near.status == "passive (marginal)"
    assert not is_passive("(s + 1)/(s + 2)").marginal
    undecided = sampled_passivity(
        _lp(b1=1e6, k1=1000, kd=950), loop=SampledLoop(period=0.002), max_precision=64
    )
    assert undecided.outcome is Outcome.UNDECIDED and not undecided.marginal
    assert undecided.to_dict()["marginal"] is False and undecided.to_dict()["status"] == "undecided"


@pytest.fixture(scope="module")
def bound() -> SampledBoundResult:
    return sampled_passive_bound(
        _lp(kd=None),
        "kd",
        loop=SampledLoop(period=0.002),
        lo=0.0,
        hi=2e4,
        rtol=1e-3,
        design_value=500.0,
    )


def test_json_values_stay_the_strings(
    results: dict[type, list[Any]], bound: SampledBoundResult
) -> None:
    r = results[SampledPassivityResult][1].to_dict()
    assert r["status"] == "not_passive" and r["reason"] == "low_frequency"
    assert type(r["status"]) is str
    assert bound.design_outcome is Outcome.PASSIVE
    edges = bound.to_dict()["edges"]
    assert edges and all(e["kind"] in {k.value for k in EdgeKind} for e in edges)
    assert results[PassivityResult][1].to_dict()["status"] == "not passive"


def test_the_dead_nyquist_edge_kind_is_gone() -> None:
    assert "nyquist" not in {k.value for k in EdgeKind}


def test_undecided_design_value_is_not_called_not_passive(bound: SampledBoundResult) -> None:
    b = bound
    edge = b.edges[0]
    inside = dataclasses.replace(b, design_value=(edge.lo + edge.hi) / 2, design_passive=False)
    assert inside.design_outcome is Outcome.UNDECIDED
    beyond = dataclasses.replace(b, design_value=b.hi, design_passive=False)
    assert beyond.design_outcome is Outcome.NOT_PASSIVE


def test_bounds_outside_the_box_are_undecided_not_safe() -> None:
    light = EnvironmentBounds(mass=(0.0, 1.0))
    cert = certify_box([2, 1], [1, 1], light)
    assert cert.outcome is Outcome.UNDECIDED and not cert.certified
    witness = find_destabilizing_environment("(s - 1)/(s + 2)", simulate=False)
    assert witness.status in set(WitnessStatus)


# --------------------------------------------------------------------- the AST scan

#: Attributes whose value is a verdict, status, reason or kind.
VERDICT_NAMES = {"status", "outcome", "reason", "verdict", "bound_status", "growth"}
#: Every string value of a verdict-like enum (the empty ``NONE`` reasons aside).
VERDICT_ENUMS = (
    Outcome, Reason, SampledReason, EdgeKind, WitnessStatus, BoundStatus, Stability, Growth,
    Verdict, Discrepancy, SectionStatus, Settling, JobStatus,
)  # fmt: skip
VERDICT_VALUES = {m.value for e in VERDICT_ENUMS for m in e if m.value} | {"not passive"}


def _strings(node: ast.AST) -> list[str]:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.Tuple | ast.List | ast.Set) and node.elts:
        found = [_strings(e) for e in node.elts]
        return [s for f in found for s in f] if all(found) else []
    return []


def _name(node: ast.AST) -> str | None:
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Name):
        return node.id
    return None


def string_comparisons(source: str) -> list[str]:
    """Comparisons of a verdict-like name, or with a verdict value, to string literals."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Compare):
            continue
        sides = [node.left, *node.comparators]
        for a, b in itertools.pairwise(sides):
            for x, y in ((a, b), (b, a)):
                texts = _strings(y)
                if texts and (_name(x) in VERDICT_NAMES or set(texts) & VERDICT_VALUES):
                    out.append(f"line {node.lineno}: {ast.unparse(node)}")
    return out


def test_the_scan_catches_string_verdicts() -> None:
    caught = string_comparisons(
        "a = r.status == 'passive'\n"
        "b = res.reason in ('negative_power', 'unstable')\n"
        "c = 'not_passive' != x\n"
        "d = verdict != 'matches'\n"
        "e = r.outcome is Outcome.PASSIVE\n"
        "f = kind == 'bode'\n"
    )
    assert [c.split(":")[0] for c in caught] == ["line 1", "line 2", "line 3", "line 4"]


def test_no_source_compares_a_verdict_to_a_string() -> None:
    bad = {
        str(path.relative_to(SRC)): found
        for path in sorted(SRC.rglob("*.py"))
        if (found := string_comparisons(path.read_text(encoding="utf-8")))
    }
    assert not bad, f"compare the enums, not their strings: {bad}"
