"""Lazy exports for a package ``__init__`` (PEP 562): import a name's module on first use.

`lazy_exports` builds the module-level ``__getattr__`` and ``__dir__`` of a package
whose public names live in its submodules, so ``import seapass`` (and
``import seapass.model``) stay light: sympy, numpy and friends load only when a name
that needs them is first touched.  This module imports nothing of seapass.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Mapping, MutableMapping
from typing import Any

__all__ = ["lazy_exports"]


def lazy_exports(
    package: str,
    names: Mapping[str, str],
    namespace: MutableMapping[str, Any],
    *,
    submodules: Iterable[str] = (),
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``(__getattr__, __dir__)`` for ``package``.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    names : mapping of str to str
        Public name -> submodule (relative to ``package``) that defines it.
    namespace : mutable mapping
        The package's ``globals()``: a resolved name is cached there, so each
        is imported once.
    submodules : iterable of str, optional
        Submodules reachable as attributes (``seapass.robust``) without an import.

    Examples
    --------
    >>> ns: dict = {}
    >>> getattr_, dir_ = lazy_exports("json", {"JSONEncoder": "encoder"}, ns)
    >>> dir_()
    ['JSONEncoder']
    >>> getattr_("JSONEncoder").__name__, "JSONEncoder" in ns
    ('JSONEncoder', True)
    """
    subs = frozenset(submodules)

    def __getattr__(name: str) -> Any:
        if name in names:
            value = getattr(importlib.import_module(f"{package}.{names[name]}"), name)
            namespace[name] = value
            return value
        if name in subs:
            return importlib.import_module(f"{package}.{name}")
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        return sorted({*namespace, *names, *subs})

    return __getattr__, __dir__
