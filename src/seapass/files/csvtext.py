"""CSV text of result rows: one writer for the data files of results.

`rows_csv` writes a list of dicts (one per row, the keys of the first row as
header) with exact numbers (``repr`` of a float) and an empty cell for None.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["rows_csv"]


def rows_csv(rows: Sequence[Mapping[str, Any]]) -> str:
    """CSV text of ``rows`` (header: the keys of the first row); ``""`` for no rows.

    >>> print(rows_csv([{"kd": 100.0, "status": "settled", "t": None}]), end="")
    kd,status,t
    100.0,settled,
    """
    if not rows:
        return ""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(list(rows[0]))
    for r in rows:
        w.writerow(
            ["" if v is None else repr(v) if isinstance(v, float) else v for v in r.values()]
        )
    return buf.getvalue()
