"""Formulas in the report: plain text (Python syntax, as in ``data/``) shown as MathML.

The report keeps every formula as the plain text seapass prints and stores,
e.g. ``b*k1**2*(w - 1)*(w + 1)``; `formula_mathml` turns that text into
presentation MathML for ``report.html`` (rendered by the browser, offline:
no script, no font, no CDN).  The text is parsed with `ast` and every node is
checked against a whitelist, as in [`seapass.model.expr`][seapass.model.expr];
nothing is evaluated, so the formula is shown exactly as written (term order
and grouping kept) and user text never reaches code execution.  Text that is
not a formula of this grammar gives ``None``, and the report shows it as code.

Grammar: numbers, names, ``+ - * / **`` (``^`` also means power), unary signs,
comparisons ``<= >= < > == !=``, ``&`` (and), ``|`` (or), and the functions
``sqrt``, ``Abs``, ``exp``, ``log``, ``sin``, ``cos``, ``re``, ``im``, ``Max``, ``Min``.
Names are typeset as in the paper: ``k1`` as k₁, ``kd`` as k_d, ``x_L`` as x_L,
``w``/``omega`` as ω, Greek names as Greek letters.

`decimal_rational` prints a rational function with numeric coefficients at a
sensible precision (exact rationals such as ``1152921504606847*s**3`` are noise
to a reader).
"""

from __future__ import annotations

import ast
import html
import re
from functools import lru_cache
from typing import Any

__all__ = ["MAX_FORMULA_LENGTH", "decimal_rational", "formula_mathml"]

MAX_FORMULA_LENGTH = 4000
"""Longer text is shown as code, not parsed."""
_MAX_NODES = 3000

_GREEK = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ε", "zeta": "ζ",
    "eta": "η", "theta": "θ", "kappa": "κ", "lambda_": "λ", "mu": "μ", "nu": "ν", "xi": "ξ",
    "rho": "ρ", "sigma": "σ", "tau": "τ", "phi": "φ", "chi": "χ", "psi": "ψ", "omega": "ω",
    "w": "ω", "pi": "π", "Omega": "Ω", "Delta": "Δ",
}  # fmt: skip
# two-letter gain names of the paper written with a subscript: k_d, b_d, k_i
_SUBSCRIPTED = re.compile(r"^([kb])([dpi])$")
_TRAILING_DIGITS = re.compile(r"^([A-Za-z]+?)(\d+)$")
_FUNCS = {"sqrt", "Abs", "exp", "log", "sin", "cos", "re", "im", "Max", "Min"}
_CMP = {ast.LtE: "≤", ast.GtE: "≥", ast.Lt: "&lt;", ast.Gt: "&gt;", ast.Eq: "=", ast.NotEq: "≠"}

# display precedence: logical operators bind looser than comparisons (unlike Python's & and |)
_OR, _AND, _CMP_P, _ADD, _MUL, _NEG, _POW, _ATOM = range(1, 9)


class _NotAFormula(Exception):
    pass


def _mi(text: str) -> str:
    return f"<mi>{html.escape(text)}</mi>"


def _name(name: str) -> str:
    if name in _GREEK:
        return _mi(_GREEK[name])
    if name == "oo":
        return "<mi>∞</mi>"
    if "_" in name.strip("_"):
        base, sub = name.split("_", 1)
        return f"<msub>{_name(base)}{_name(sub) if not sub.isdigit() else f'<mn>{sub}</mn>'}</msub>"
    m = _SUBSCRIPTED.match(name) or _TRAILING_DIGITS.match(name)
    if m:
        base, sub = m.groups()
        sub_ml = f"<mn>{sub}</mn>" if sub.isdigit() else _mi(sub)
        return f"<msub>{_name(base)}{sub_ml}</msub>"
    if len(name) > 1:
        return f'<mi mathvariant="normal">{html.escape(name)}</mi>'
    return _mi(name)


def _number(value: Any) -> str:
    if isinstance(value, bool):
        return f"<mtext>{'true' if value else 'false'}</mtext>"
    if not isinstance(value, int | float):
        raise _NotAFormula
    text = repr(value) if isinstance(value, int) else f"{value:.15g}"
    if "e" in text:
        mant, exp = text.split("e")
        e = str(int(exp)).replace("-", "−")
        power = f"<msup><mn>10</mn><mn>{e}</mn></msup>"
        return power if mant in ("1", "1.0") else f"<mrow><mn>{mant}</mn><mo>·</mo>{power}</mrow>"
    return f"<mn>{text}</mn>"


def _paren(ml: str) -> str:
    return f"<mrow><mo>(</mo>{ml}<mo>)</mo></mrow>"


class _Printer:
    def __init__(self) -> None:
        self.nodes = 0

    def wrap(self, node: ast.AST, need: int) -> str:
        ml, prec = self.emit(node)
        return _paren(ml) if prec < need else ml

    def emit(self, node: ast.AST) -> tuple[str, int]:
        self.nodes += 1
        if self.nodes > _MAX_NODES:
            raise _NotAFormula
        if isinstance(node, ast.Constant):
            return _number(node.value), _ATOM
        if isinstance(node, ast.Name):
            return _name(node.id), _ATOM
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
            sign = "−" if isinstance(node.op, ast.USub) else "+"
            return f"<mrow><mo>{sign}</mo>{self.wrap(node.operand, _MUL)}</mrow>", _NEG
        if isinstance(node, ast.BinOp):
            return self.binop(node)
        if isinstance(node, ast.Compare):
            parts = [self.wrap(node.left, _ADD)]
            for op, right in zip(node.ops, node.comparators, strict=True):
                sym = _CMP.get(type(op))
                if sym is None:
                    raise _NotAFormula
                parts += [f"<mo>{sym}</mo>", self.wrap(right, _ADD)]
            return f"<mrow>{''.join(parts)}</mrow>", _CMP_P
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            return self.call(node.func.id, node.args, node.keywords), _ATOM
        raise _NotAFormula

    def binop(self, node: ast.BinOp) -> tuple[str, int]:
        op = node.op
        if isinstance(op, ast.Pow | ast.BitXor):
            base = self.wrap(node.left, _ATOM)
            exp, _p = self.emit(node.right)
            return f"<msup>{base}{exp}</msup>", _POW
        if isinstance(op, ast.Div):
            num, _p = self.emit(node.left)
            den, _q = self.emit(node.right)
            return f"<mfrac><mrow>{num}</mrow><mrow>{den}</mrow></mfrac>", _ATOM
        if isinstance(op, ast.Add | ast.Sub):
            left = self.wrap(node.left, _ADD)
            # a - (b + c) and a + (-b) keep their parentheses
            right_ml, rp = self.emit(node.right)
            if rp < _ADD or (isinstance(op, ast.Sub) and rp == _ADD) or rp == _NEG:
                right_ml = _paren(right_ml)
            sym = "+" if isinstance(op, ast.Add) else "−"
            return f"<mrow>{left}<mo>{sym}</mo>{right_ml}</mrow>", _ADD
        if isinstance(op, ast.Mult):
            left_ml, lp = self.emit(node.left)
            if lp < _MUL:
                left_ml = _paren(left_ml)
            right_ml, rp = self.emit(node.right)
            if rp <= _NEG:
                right_ml = _paren(right_ml)
            # a visible dot before a number (2·3, x·10), else invisible times
            number_next = isinstance(node.right, ast.Constant) or (
                isinstance(node.right, ast.BinOp)
                and isinstance(node.right.op, ast.Pow | ast.BitXor)
                and isinstance(node.right.left, ast.Constant)
            )
            times = "<mo>·</mo>" if number_next else "<mo>&#x2062;</mo>"
            return f"<mrow>{left_ml}{times}{right_ml}</mrow>", _MUL
        if isinstance(op, ast.BitAnd | ast.BitOr):
            prec = _AND if isinstance(op, ast.BitAnd) else _OR
            sym = "∧" if prec == _AND else "∨"
            left = self.wrap(node.left, prec)
            right = self.wrap(node.right, prec + 1 if prec == _AND else prec)
            return f"<mrow>{left}<mo>{sym}</mo>{right}</mrow>", prec
        raise _NotAFormula

    def call(self, name: str, args: list[ast.expr], keywords: list[ast.keyword]) -> str:
        if name not in _FUNCS or keywords or not args:
            raise _NotAFormula
        if name == "sqrt" and len(args) == 1:
            return f"<msqrt>{self.emit(args[0])[0]}</msqrt>"
        if name == "Abs" and len(args) == 1:
            return f"<mrow><mo>|</mo>{self.emit(args[0])[0]}<mo>|</mo></mrow>"
        inner = "<mo>,</mo>".join(self.emit(a)[0] for a in args)
        label = {"re": "Re", "im": "Im"}.get(name, name.lower() if name in ("Max", "Min") else name)
        return f'<mrow><mi mathvariant="normal">{label}</mi><mo>&#x2061;</mo>{_paren(inner)}</mrow>'


@lru_cache(maxsize=4096)
def formula_mathml(text: str, *, display: bool = False) -> str | None:
    """Presentation MathML of the plain-text formula ``text``, or None if it is not one.

    Parameters
    ----------
    text : str
        A formula in Python syntax as seapass prints it (see the module docstring).
    display : bool
        Block (``display="block"``) instead of inline math.

    Returns
    -------
    str or None
        One ``<math>`` element (its ``alttext`` is ``text``), or None when
        ``text`` is not a formula of the grammar or is too long.

    Examples
    --------
    >>> formula_mathml("kd <= k1")
    '<math alttext="kd &lt;= k1"><mrow><msub><mi>k</mi><mi>d</mi></msub><mo>≤</mo><msub><mi>k</mi><mn>1</mn></msub></mrow></math>'
    >>> formula_mathml("import os") is None
    True
    """
    src = text.strip()
    if not src or len(src) > MAX_FORMULA_LENGTH:
        return None
    try:
        tree = ast.parse(src, mode="eval")
        body, _prec = _Printer().emit(tree.body)
    except (SyntaxError, ValueError, RecursionError, MemoryError, _NotAFormula):
        return None
    mode = ' display="block"' if display else ""
    alt = html.escape(src, quote=True)
    return f'<math alttext="{alt}"{mode}>{body}</math>'


def decimal_rational(expr: Any, var: Any = None, *, digits: int = 6) -> str:
    """A rational function of ``var`` with numeric coefficients, as text at ``digits`` digits.

    The denominator is made monic, so ``(2*s + 4)/(2*s**2 + 2)`` reads
    ``(s + 2)/(s**2 + 1)``; coefficients print with ``digits`` significant
    digits.  Returns ``str(expr)`` for an expression with free symbols other
    than ``var``.

    Examples
    --------
    >>> import sympy as sp
    >>> s = sp.Symbol("s")
    >>> decimal_rational((sp.Rational(1152921504606847, 10**15) * s**2 + 3) / (2 * s + 4), s)
    '(0.576461*s**2 + 1.5)/(s + 2)'
    """
    import sympy as sp

    from ..model.expr import S

    x = S if var is None else var
    num, den = sp.fraction(sp.cancel(sp.together(sp.sympify(expr))))
    if (num.free_symbols | den.free_symbols) - {x}:
        return str(expr)
    pn, pd = sp.Poly(num, x), sp.Poly(den, x)
    lead = pd.LC()
    n_text = _poly_text([c / lead for c in pn.all_coeffs()], str(x), digits)
    d_text = _poly_text([c / lead for c in pd.all_coeffs()], str(x), digits)
    if d_text == "1":
        return n_text
    n_text = f"({n_text})" if ("+" in n_text or " - " in n_text) else n_text
    d_text = f"({d_text})" if ("+" in d_text or " - " in d_text or "*" in d_text) else d_text
    return f"{n_text}/{d_text}"


def _poly_text(coeffs: list[Any], x: str, digits: int) -> str:
    """``c0*x**n + ... + cn`` from descending coefficients, zero terms dropped."""
    n = len(coeffs) - 1
    terms: list[tuple[bool, str]] = []
    for i, c in enumerate(coeffs):
        v = float(c)
        if v == 0:
            continue
        k = n - i
        mag = f"{abs(v):.{digits}g}"
        power = "" if k == 0 else (x if k == 1 else f"{x}**{k}")
        if power:
            body = power if mag == "1" else f"{mag}*{power}"
        else:
            body = mag
        terms.append((v < 0, body))
    if not terms:
        return "0"
    out = ("-" if terms[0][0] else "") + terms[0][1]
    for neg, body in terms[1:]:
        out += f" - {body}" if neg else f" + {body}"
    return out
