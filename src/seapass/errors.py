"""All exceptions raised by seapass.

Every class subclasses the builtin that matches its meaning, so callers may
catch either the seapass class or the builtin.  The command line turns any
`SeapassError` into one line on stderr and exit code 2.
"""

from __future__ import annotations

__all__ = [
    "CompilerError",
    "DegenerateModelError",
    "ExpressionError",
    "FileFormatError",
    "MissingExtraError",
    "ModelError",
    "NotPassiveError",
    "ParameterError",
    "SeapassError",
    "SimulationError",
    "SymbolicLimitError",
    "UnrealizableError",
]


class SeapassError(Exception):
    """Base class of every error seapass raises on purpose."""


class ExpressionError(SeapassError, ValueError):
    """An expression string is malformed, unsafe, or not rational in ``s``."""


class ParameterError(SeapassError, ValueError):
    """A parameter value is missing, non-finite, or out of its physical range."""


class ModelError(SeapassError, ValueError):
    """A model is inconsistent or physically meaningless."""


class DegenerateModelError(ModelError):
    """A model whose port impedance is identically zero or undefined."""


class UnrealizableError(ModelError):
    """A transfer function that cannot be realized (improper where it must be proper)."""


class FileFormatError(SeapassError, ValueError):
    """A TOML design or rig file has an unknown key, wrong type or bad value."""


class SymbolicLimitError(SeapassError, RuntimeError):
    """A symbolic computation exceeded its size or time budget."""


class SimulationError(SeapassError, RuntimeError):
    """A simulation could not be set up (not raised for unstable runs: those are results)."""


class NotPassiveError(SeapassError, ValueError):
    """Raised by ``throw=True`` entry points when a design is not passive."""


class CompilerError(SeapassError, RuntimeError):
    """The C compiler is missing or rejected generated code (``seapass export c --verify``)."""


class MissingExtraError(SeapassError, ImportError):
    """An optional extra (``seapass[dask]``, ``seapass[mujoco]``, ...) is needed but not installed."""
