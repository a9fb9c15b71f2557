"""The one rtol range (sampled bounds and regions, the C export, the command line)."""

from __future__ import annotations

from pathlib import Path

import pytest

from helpers import REPO
from seapass.errors import ParameterError
from seapass.files import limits
from seapass.files.limits import MAX_RTOL, MIN_RTOL, check_rtol
from seapass.model.design_file import load_design


@pytest.mark.parametrize("rtol", [MIN_RTOL, 1e-6, MAX_RTOL, 1])
def test_rtol_in_range(rtol: float) -> None:
    if rtol == 1:
        with pytest.raises(ParameterError):
            check_rtol(rtol)
    else:
        assert check_rtol(rtol) == rtol


@pytest.mark.parametrize("rtol", [0.0, -1.0, 1e-13, 0.5, float("nan"), float("inf"), True, "1e-6"])
def test_rtol_out_of_range_names_the_argument(rtol: object) -> None:
    with pytest.raises(ParameterError, match=r"rtol must be in \[1e-12, 0\.01\]") as info:
        check_rtol(rtol)  # type: ignore[arg-type]
    assert info.value.argument == "rtol"


def test_the_export_checks_rtol_before_certifying(monkeypatch: pytest.MonkeyPatch) -> None:
    from seapass.export import deployment

    def never(*args: object, **kwargs: object) -> None:
        raise AssertionError("certified before checking rtol")

    monkeypatch.setattr(deployment, "sampled_verdict", never)
    design = load_design(Path(__file__).parents[2] / "examples" / "ours.toml")
    with pytest.raises(ParameterError, match="rtol"):
        deployment.plan_deployment(design, rtol=0.5)


# ------------------------------------------ documented limits (moved from test_hardening, issue 12)


def test_every_limit_is_documented() -> None:
    doc = (REPO / "docs" / "verification.md").read_text()
    for name in limits.__all__:
        if name.isupper():
            assert f"`{name}`" in doc, name
