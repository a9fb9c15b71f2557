"""The rig files seapass ships: the paper's bench, a template for yours, and telling them apart.

`rig_template` is the commented starting point of ``seapass rig template``;
`is_paper_hardware` decides whether results may be set beside the paper's
measurements (only for the paper's own bench).
"""

from __future__ import annotations

from importlib import resources
from typing import Any

from .rigfile import Rig, paper_rig

__all__ = ["HARDWARE_SECTIONS", "is_paper_hardware", "rig_template"]


def rig_template() -> str:
    """A commented rig file to start from (``seapass rig template``); it loads as is."""
    return resources.files("seapass").joinpath("data/rig_template.toml").read_text(encoding="utf-8")


HARDWARE_SECTIONS = ("motor", "transmission", "damper", "load", "encoders", "control")
"""The sections that describe the bench itself (the others describe protocols run on it)."""


def is_paper_hardware(rig: Rig) -> bool:
    """Whether ``rig`` is the packaged reconstruction of the paper's bench.

    Compares the numbers of the `HARDWARE_SECTIONS` with `paper_rig`'s; names,
    the description and the protocols may differ.  Only then do reports set
    the twin's results beside the paper's measured numbers.
    """

    def numbers(r: Rig) -> list[dict[str, Any]]:
        d = r.to_dict()
        return [{k: v for k, v in d[sec].items() if k != "name"} for sec in HARDWARE_SECTIONS]

    return numbers(rig) == numbers(paper_rig())
