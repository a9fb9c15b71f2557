"""What the explorer's sliders show: which parameters are gains, their default ranges, scales.

Controller gains (the parameters of ``C_A`` and ``C_L`` that are not plant parameters,
as [`SEA.gains`][seapass.model.sea.SEA.gains]) get a slider from 0; plant parameters
(``m b k1 k2 b1 b2``, those of ``D1``/``D2`` and the declared ones) a range of four
decades around their value.  Expression text is read with `ast`, never evaluated.
"""

from __future__ import annotations

import ast
from collections.abc import Mapping

from ..model.sea import PLANT_SYMBOLS

__all__ = ["default_range", "names_in", "slider_gains", "slider_scale"]


def slider_scale(lo: float, hi: float) -> str:
    """``"log"`` for a non-negative range spanning two decades or more (0 is its own stop).

    Examples
    --------
    >>> slider_scale(0.0, 5000.0), slider_scale(10.0, 1e5), slider_scale(1.0, 50.0)
    ('log', 'log', 'lin')
    """
    if lo >= 0 and hi > 0 and (lo == 0 or hi / lo >= 100):
        return "log"
    return "lin"


def default_range(name: str, value: float, *, gain: bool) -> tuple[float, float]:
    """Slider range for a parameter without one: gains from 0, plant values over four decades."""
    if gain or value == 0:
        return 0.0, max(10.0 * abs(value), 1000.0) if gain else max(10.0 * abs(value), 1.0)
    if value > 0:
        return value / 100.0, value * 100.0
    return 10.0 * value, -10.0 * value


def slider_gains(
    model: Mapping[str, str], values: Mapping[str, float], plant: tuple[str, ...] = ()
) -> tuple[str, ...]:
    """Controller parameters with a value that are not plant parameters (`SEA.gains`)."""
    hardware = {*PLANT_SYMBOLS, *plant}
    for key in ("D1", "D2"):
        hardware.update(names_in(model.get(key, "0")))
    out = []
    for key in ("CA", "CL"):
        for name in names_in(model.get(key, "0")):
            if name in values and name not in out and name not in hardware:
                out.append(name)
    return tuple(sorted(out))


def names_in(text: str) -> list[str]:
    """Identifiers in ``text`` (parsed by `ast`, never evaluated), in order of appearance."""
    try:
        tree = ast.parse(text.replace("^", "**"), mode="eval")
    except (SyntaxError, ValueError):
        return []
    names = sorted((n.col_offset, n.id) for n in ast.walk(tree) if isinstance(n, ast.Name))
    return list(dict.fromkeys(name for _, name in names if name != "s"))
