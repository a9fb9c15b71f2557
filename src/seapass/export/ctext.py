"""The one place where text becomes C source: comments, string literals, identifiers, numbers.

Every value a C template prints goes through one of these filters (the
template environment's ``finalize`` refuses anything else, so a template
cannot print user text raw by mistake):

* [`c_comment`][seapass.export.ctext.c_comment]: text for inside ``/* ... */``
  (titles, names, formulas, notes);
* [`c_string`][seapass.export.ctext.c_string]: the content of a ``"..."`` literal;
* [`c_identifier`][seapass.export.ctext.c_identifier]: a name used as C code
  (a gain's struct field), refused unless it is a plain C99 and C++ identifier
  that no keyword, reserved name or macro of the included headers takes;
* [`c_number`][seapass.export.ctext.c_number]: a numeric literal seapass printed;
* [`c_code`][seapass.export.ctext.c_code]: a fragment seapass wrote itself
  (``theta_A - x_A``), never user text.

The escaped text is printable ASCII only and holds no ``*/``, ``/*``, ``??``
(trigraphs), backslash-newline or control character, so no title can end a
comment, start a directive, splice a line or trip ``-Wall -Wextra -pedantic``.

References
----------
ISO/IEC 9899:1999 (C99), 5.1.1.2 (translation phases: trigraphs, line splicing,
comments), 6.4.1 (keywords), 6.4.4.4 and 6.4.5 (escape sequences), 7.1.3
(reserved identifiers).
"""

from __future__ import annotations

import re
from typing import Any

from ..errors import ParameterError

__all__ = [
    "CPP_KEYWORDS",
    "C_KEYWORDS",
    "HEADER_MACROS",
    "CText",
    "c_code",
    "c_comment",
    "c_identifier",
    "c_number",
    "c_string",
    "finalize",
]

#: C99 keywords (and the C11/C23 ones, so that a newer compiler agrees).
C_KEYWORDS = frozenset(
    "auto break case char const continue default do double else enum extern float for goto if "
    "inline int long register restrict return short signed sizeof static struct switch typedef "
    "union unsigned void volatile while _Bool _Complex _Imaginary _Alignas _Alignof _Atomic "
    "_Generic _Noreturn _Static_assert _Thread_local alignas alignof bool constexpr false "
    "nullptr static_assert thread_local true typeof typeof_unqual".split()
)

#: C++ keywords and alternative tokens: the header is also C++ (Arduino sketches).
CPP_KEYWORDS = frozenset(
    "and and_eq asm bitand bitor catch char8_t char16_t char32_t class co_await co_return "
    "co_yield compl concept const_cast consteval constinit decltype delete dynamic_cast "
    "explicit export friend mutable namespace new noexcept not not_eq operator or or_eq "
    "private protected public reinterpret_cast requires static_cast template this throw try "
    "typeid typename using virtual wchar_t xor xor_eq".split()
)

#: Names the headers the generated code includes (float.h, stddef.h) define.
HEADER_MACROS = frozenset(
    "NULL offsetof size_t ptrdiff_t max_align_t wchar_t FLT_RADIX FLT_ROUNDS FLT_EVAL_METHOD "
    "DECIMAL_DIG FLT_MANT_DIG DBL_MANT_DIG LDBL_MANT_DIG FLT_DIG DBL_DIG LDBL_DIG FLT_MIN_EXP "
    "DBL_MIN_EXP LDBL_MIN_EXP FLT_MIN_10_EXP DBL_MIN_10_EXP LDBL_MIN_10_EXP FLT_MAX_EXP "
    "DBL_MAX_EXP LDBL_MAX_EXP FLT_MAX_10_EXP DBL_MAX_10_EXP LDBL_MAX_10_EXP FLT_MAX DBL_MAX "
    "LDBL_MAX FLT_EPSILON DBL_EPSILON LDBL_EPSILON FLT_MIN DBL_MIN LDBL_MIN FLT_TRUE_MIN "
    "DBL_TRUE_MIN LDBL_TRUE_MIN FLT_DECIMAL_DIG DBL_DECIMAL_DIG LDBL_DECIMAL_DIG "
    "FLT_HAS_SUBNORM DBL_HAS_SUBNORM LDBL_HAS_SUBNORM".split()
)

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,62}")
_NUMBER = re.compile(
    r"-?(?:0x[0-9a-f]+(?:\.[0-9a-f]+)?p[+-][0-9]+|[0-9]+(?:\.[0-9]+)?(?:e[+-]?[0-9]+)?)"
)


class CText(str):
    """Text that is safe to print where the filter that made it says (see the module)."""

    __slots__ = ()


def _escape(ch: str) -> str:
    o = ord(ch)
    if o < 0x100:
        return f"\\x{o:02x}"
    return f"\\u{o:04x}" if o < 0x10000 else f"\\U{o:08x}"


def c_comment(text: Any) -> CText:
    r"""``text`` escaped for inside a ``/* ... */`` comment, on one line.

    Printable ASCII is kept, except that the second character of ``*/``,
    ``/*`` and ``??`` is escaped; a backslash, a control character and every
    non-ASCII character become ``\xHH``, ``\uHHHH`` or ``\UHHHHHHHH``.

    >>> print(c_comment("t */ #define double float /*"))
    t *\x2f #define double float /\x2a
    >>> print(c_comment("a??/\r\nb \\ é"))
    a?\x3f/\x0d\x0ab \x5c \xe9
    """
    s = str(text)
    out = []
    prev = ""
    for ch in s:
        risky = (
            (ch == "/" and prev == "*")
            or (ch == "*" and prev == "/")
            or (ch == "?" and prev == "?")
            or ch == "\\"
            or not (" " <= ch <= "~")
        )
        out.append(_escape(ch) if risky else ch)
        prev = ch
    return CText("".join(out))


def c_string(text: Any) -> CText:
    r"""``text`` as the content of a C string literal (UTF-8 bytes, octal escapes).

    ``\``, ``"`` and ``?`` (trigraphs) are escaped; a control or non-ASCII
    byte becomes a three-digit octal escape (which, unlike ``\x``, never
    swallows the digits after it).

    >>> print(c_string('say "hi"?? \\ é'))
    say \"hi\"\?\? \\ \303\251
    """
    out = []
    for b in str(text).encode("utf-8"):
        ch = chr(b)
        if ch in '\\"?':
            out.append("\\" + ch)
        elif " " <= ch <= "~":
            out.append(ch)
        else:
            out.append(f"\\{b:03o}")
    return CText("".join(out))


def c_identifier(name: Any, what: str = "name") -> CText:
    """``name`` as a C identifier, or `ParameterError` saying why it cannot be one.

    Refused: anything but letters, digits and ``_`` (not first a digit, at most
    63), C and C++ keywords, reserved names (``_X...``, ``__``), names of the
    macros of ``<float.h>``/``<stddef.h>`` and the ``seapass_`` prefix of the
    generated API.

    >>> c_identifier("kd")
    'kd'
    >>> c_identifier("new", "gain name")
    Traceback (most recent call last):
    ...
    seapass.errors.ParameterError: gain name 'new' is a C++ keyword; rename it in the design
    """
    s = str(name)
    why = None
    if not _IDENTIFIER.fullmatch(s):
        why = "not a C identifier (letters, digits and _, at most 63, not first a digit)"
    elif s in C_KEYWORDS:
        why = "a C keyword"
    elif s in CPP_KEYWORDS:
        why = "a C++ keyword"
    elif s.startswith("__") or re.match(r"_[A-Z]", s) or "__" in s:
        why = "a name C and C++ reserve for the compiler (leading _ or a double __)"
    elif s in HEADER_MACROS:
        why = "a name the C standard headers define"
    elif s.lower().startswith("seapass_"):
        why = "in the seapass_ name space of the generated code"
    if why is not None:
        raise ParameterError(f"{what} {s!r} is {why}; rename it in the design")
    return CText(s)


def c_number(text: Any) -> CText:
    """A numeric literal seapass printed (hexadecimal or decimal), checked.

    >>> c_number("0x1.0624dd2f1a9fcp-9"), c_number("0.002")
    ('0x1.0624dd2f1a9fcp-9', '0.002')
    """
    s = str(text)
    if not _NUMBER.fullmatch(s):
        raise ParameterError(f"{s!r} is not a finite C numeric literal")
    return CText(s)


def c_code(text: str) -> CText:
    """A fragment of C that seapass wrote itself (never user text): printed as is."""
    return CText(text)


def finalize(value: Any) -> Any:
    """The C templates' ``finalize``: escaped text and integers only.

    A plain string reaching a template unfiltered is a bug of seapass (it could
    be user text), so it stops the export instead of being printed.
    """
    if isinstance(value, CText):
        return value
    if isinstance(value, int) and not isinstance(value, bool):
        return str(value)
    raise TypeError(
        f"C template printed {type(value).__name__} {value!r} without a filter "
        "(c_comment, c_string, c_identifier, c_number)"
    )
