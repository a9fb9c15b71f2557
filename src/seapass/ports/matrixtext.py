"""A matrix of expressions written as text: ``"[[E11, E12], [E21, E22]]"``.

Only the nesting is read by ``ast`` (a list of equally long lists); every entry
is handed on as text to the safe expression parser of
[`seapass.model.expr`][seapass.model.expr], never evaluated.  The length of the
text and the number of rows are bounded first.
"""

from __future__ import annotations

import ast

from ..errors import ExpressionError
from ..files.limits import MAX_EXPRESSION_LENGTH, MAX_PORTS

__all__ = ["parse_matrix_text"]

MAX_MATRIX_TEXT = MAX_PORTS * MAX_PORTS * MAX_EXPRESSION_LENGTH
"""Longest matrix text accepted (characters)."""


def parse_matrix_text(text: str, what: str = "Z") -> list[list[str]]:
    """The rows of ``text`` as lists of entry texts.

    Examples
    --------
    >>> parse_matrix_text("[[b + k/s, c/s], [-c/s, b + k/s]]")
    [['b + k/s', 'c/s'], ['-c/s', 'b + k/s']]
    """
    if not isinstance(text, str) or not text.strip():
        raise ExpressionError(f'{what}: give a matrix such as "[[E11, E12], [E21, E22]]"')
    if len(text) > MAX_MATRIX_TEXT:
        raise ExpressionError(
            f"{what}: the matrix text is {len(text)} characters; the limit is {MAX_MATRIX_TEXT}"
        )
    src = text.strip().replace("^", "**")
    try:
        tree = ast.parse(src, mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(
            f"{what}: cannot parse the matrix {text.strip()!r}: {exc.msg}"
        ) from None
    rows = tree.body
    if not isinstance(rows, ast.List | ast.Tuple) or not all(
        isinstance(r, ast.List | ast.Tuple) for r in rows.elts
    ):
        raise ExpressionError(f'{what}: expected a matrix of rows, e.g. "[[E11, E12], [E21, E22]]"')
    if len(rows.elts) > MAX_PORTS:
        raise ExpressionError(f"{what}: {len(rows.elts)} rows; the limit is {MAX_PORTS} ports")
    out = []
    for i, row in enumerate(rows.elts):
        assert isinstance(row, ast.List | ast.Tuple)
        entries = []
        for j, node in enumerate(row.elts):
            seg = ast.get_source_segment(src, node)
            if seg is None or isinstance(node, ast.List | ast.Tuple):
                raise ExpressionError(f"{what}[{i}][{j}]: expected an expression")
            entries.append(seg.strip())
        out.append(entries)
    n = len(out)
    if n == 0 or any(len(r) != n for r in out):
        shape = [len(r) for r in out]
        raise ExpressionError(f"{what}: the matrix must be square; got {n} rows of lengths {shape}")
    return out
