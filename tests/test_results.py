"""Results that are really immutable (issue 21, item 7).

Every frozen dataclass of seapass that a function returns (a result) is
``kw_only`` (so adding a field can never shift a positional call silently) and
holds no ``list``, ``dict`` or ``set`` (tuples and read-only mappings instead).
Inputs and value types users build themselves are listed below with the reason;
a new result is checked by default.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import pkgutil
import typing
from collections.abc import Iterator
from types import MappingProxyType
from typing import Any

import numpy as np
import pytest

import seapass

#: Frozen dataclasses that are inputs or values a user builds (often positionally), not results.
INPUTS = {
    # models, catalog entries and loaded files
    "seapass.model.sea.SEA", "seapass.model.impedance.Impedance", "seapass.model.catalog.CatalogDesign",
    "seapass.model.design_file.Design", "seapass.model.realization._Element",
    "seapass.model.realization._Controller",
    "seapass.rig.rigfile.Rig", "seapass.rig.log.RigLog", "seapass.paper.tables.PaperRow",
    # the rig file's declarative schema
    "seapass.files.schema.Field", "seapass.rig.schema.MotorSpec",
    "seapass.rig.schema.TransmissionSpec", "seapass.rig.schema.DamperSpec",
    "seapass.rig.schema.LoadSpec", "seapass.rig.schema.EncoderSpec",
    "seapass.rig.schema.ControlSpec", "seapass.rig.schema.ExperimentSpec",
    "seapass.rig.schema.ImpactSpec",
    # experiment and option inputs
    "seapass.analysis.coupled.Environment", "seapass.analysis.environment_box.EnvironmentBounds",
    "seapass.sim.scenarios.Step", "seapass.sim.scenarios.LoadDisplaced",
    "seapass.sim.scenarios.ForceStep", "seapass.sim.scenarios.ForceImpulse",
    "seapass.sim.scenarios.Trajectory", "seapass.sweep.spec.GridAxis",
    "seapass.sweep.spec.RangeAxis", "seapass.sweep.spec.SweepSpec",
    "seapass.sweep.location.Location", "seapass.model.loop.SampledLoop",
    "seapass.tuning.problem.TuningOptions", "seapass.tuning.problem.ResolvedTuning",
    "seapass.tuning.problem.TuningProblem", "seapass.explore.state.ExploreState",
    "seapass.report.pipeline.Stage",
    # exact values and compiled kernels
    "seapass.exact.halfline.HalfLinePoint", "seapass.sampled.joint.DiscreteTF",
    "seapass.sampled.plant.Plant", "seapass.sampled.alias.Pole", "seapass.sampled.alias.AliasSums",
    "seapass.sampled.family.ControllerPolys", "seapass.sampled.family.ControllerFamily",
    "seapass.analysis.environment_box._Polys", "seapass.batch.kernel.PassivityKernel",
    "seapass.batch.step_kernel.SimKernel", "seapass.export.realization.FilterSpec",
    "seapass.export.c_code.CLiteral",
    # the report's document model (built by the stages, normalized in __post_init__)
    "seapass.report.document.Math", "seapass.report.document.Table",
    "seapass.report.document.FigureData", "seapass.report.document.Finding",
    "seapass.report.document.Section", "seapass.report.document.Summary",
    "seapass.report.document.Report",
}  # fmt: skip
#: Dataclasses that are mutable on purpose (state, caches, handles), never results.
MUTABLE = {
    "seapass.explore.reports.ReportJob", "seapass.delay.margin._Candidate", "seapass.sampled.boxes._Setup",
    "seapass.sampled.controllers.DiscreteController", "seapass.sampled.controllers.LPController",
    "seapass.sampled.controllers.APDController", "seapass.sampled.controllers.OursController",
    "seapass.tuning.cost.ConstraintChecks", "seapass.sampled.joint.JointDifferenceEquation",
}  # fmt: skip
MUTABLE_TYPES = {
    "list", "dict", "set", "List", "Dict", "Set", "MutableMapping", "MutableSequence",
    "MutableSet", "defaultdict", "deque", "OrderedDict", "Counter", "bytearray",
}  # fmt: skip


def _dataclasses() -> Iterator[tuple[str, type]]:
    seen: set[type] = set()
    for info in pkgutil.walk_packages(seapass.__path__, "seapass."):
        module = importlib.import_module(info.name)
        for obj in vars(module).values():
            if (
                isinstance(obj, type)
                and dataclasses.is_dataclass(obj)
                and obj.__module__ == module.__name__
                and obj not in seen
            ):
                seen.add(obj)
                yield f"{obj.__module__}.{obj.__qualname__}", obj


ALL = sorted(_dataclasses())
RESULTS = [
    (name, cls)
    for name, cls in ALL
    if cls.__dataclass_params__.frozen and name not in INPUTS  # type: ignore[attr-defined]
]


def mutable_parts(annotation: Any) -> set[str]:
    """Names of mutable containers in a type hint (a string or a typing object)."""
    if isinstance(annotation, str):
        tree = ast.parse(annotation, mode="eval")
        names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
        names |= {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
        return names & MUTABLE_TYPES
    found = set()
    origin = typing.get_origin(annotation) or annotation
    if getattr(origin, "__name__", "") in MUTABLE_TYPES:
        found.add(origin.__name__)
    for arg in typing.get_args(annotation):
        found |= mutable_parts(arg)
    return found


def test_the_checks_see_a_list_and_a_dict() -> None:
    assert mutable_parts("tuple[tuple[float, float], ...]") == set()
    assert mutable_parts("Mapping[str, tuple[int, ...]] | None") == set()
    assert mutable_parts("list[tuple[float, float]]") == {"list"}
    assert mutable_parts("dict[str, float] | None") == {"dict"}
    assert mutable_parts(typing.Optional[dict[str, list[int]]]) == {"dict", "list"}  # noqa: UP045


def test_the_lists_name_existing_classes() -> None:
    names = {name for name, _cls in ALL}
    assert not (INPUTS | MUTABLE) - names
    assert len(RESULTS) > 50  # every result of the package, e.g. PassivityResult


@pytest.mark.parametrize(("name", "cls"), RESULTS, ids=[n for n, _c in RESULTS])
def test_frozen_results_are_keyword_only_and_hold_no_mutable_containers(
    name: str, cls: type
) -> None:
    fields = dataclasses.fields(cls)
    positional = [f.name for f in fields if f.init and not f.kw_only]
    assert not positional, f"{name}: add kw_only=True to the dataclass ({positional})"
    mutable = {f.name: sorted(mutable_parts(f.type)) for f in fields if mutable_parts(f.type)}
    assert not mutable, f"{name}: tuples or a read-only mapping instead of {mutable}"
    factories = [f.name for f in fields if f.default_factory in (list, dict, set)]
    assert not factories, f"{name}: a mutable default for {factories}"


def test_every_mutable_dataclass_is_known() -> None:
    """A result is frozen; only state, caches and handles are not."""
    mutable = {name for name, cls in ALL if not cls.__dataclass_params__.frozen}  # type: ignore[attr-defined]
    assert mutable == MUTABLE


def _containers(value: Any, depth: int = 0) -> Iterator[str]:
    if isinstance(value, list | dict | set):
        yield type(value).__name__
    elif isinstance(value, tuple) and depth < 3:
        for v in value:
            yield from _containers(v, depth + 1)
    elif isinstance(value, MappingProxyType) and depth < 3:
        for v in value.values():
            yield from _containers(v, depth + 1)


def test_built_results_hold_tuples_at_run_time() -> None:
    """The type hints are kept at run time too (a list typed as a tuple would slip by)."""
    from seapass.analysis.indices import passivity_indices
    from seapass.analysis.passivity import is_passive
    from seapass.analysis.region import passive_intervals, passive_map
    from seapass.explore.validation import check_state
    from seapass.model.loop import SampledLoop
    from seapass.model.sea import SEA
    from seapass.sampled.bound import sampled_passive_bound
    from seapass.sampled.passivity import sampled_passivity

    lp = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1, b=10, k1=1000, b1=20, kd=None))
    built = [
        is_passive("(s + 1)/(s + 2)"),
        passivity_indices("s/(s**2 + 0.2*s + 1)"),
        passive_intervals(lp, "kd", 0.0, 2000.0),
        passive_map(lp, "b1", np.array([10.0, 20.0]), "kd", (0.0, 2000.0), y_points=3),
        sampled_passivity(lp.with_values(kd=500.0), loop=SampledLoop(period=0.002)),
        sampled_passive_bound(lp, "kd", loop=SampledLoop(period=0.002), lo=0.0, hi=2e4, rtol=1e-3),
        check_state({"model": {"D1": "k1 +"}}),
    ]
    for result in built:
        for f in dataclasses.fields(result):
            found = list(_containers(getattr(result, f.name)))
            assert not found, f"{type(result).__name__}.{f.name} holds a {found[0]}"
