"""Whether the compiled C follows the Python controller is the library's call (VerifyResult.ok)."""

from __future__ import annotations

from seapass.export.compiled import VERIFY_RTOL, VerifyResult


def test_ok_is_max_rel_within_rtol() -> None:
    good = VerifyResult(steps=10, max_abs=1e-15, max_rel=1e-13, identical=False, saturated=0)
    bad = VerifyResult(steps=10, max_abs=1e-9, max_rel=1e-10, identical=False, saturated=0)
    assert good.ok and not bad.ok and good.rtol == VERIFY_RTOL == 1e-12
    assert good.to_dict() == {
        "steps": 10, "max_abs": 1e-15, "max_rel": 1e-13, "identical": False,
        "saturated": 0, "rtol": 1e-12, "ok": True,
    }  # fmt: skip
    assert not VerifyResult(steps=1, max_abs=0, max_rel=0.5, identical=False, saturated=0,
                            rtol=0.1).ok  # fmt: skip
