"""All exceptions raised by seapass.

Every class subclasses the builtin that matches its meaning, so callers may
catch either the seapass class or the builtin.  The command line turns any
`SeapassError` into one line on stderr and exit code 2.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = [
    "CompilerError",
    "ContinuousOnlyError",
    "DegenerateModelError",
    "DelayError",
    "ExpressionError",
    "FileFormatError",
    "MissingExtraError",
    "ModelError",
    "NotPassiveError",
    "OutputPathError",
    "ParameterError",
    "SeapassDeprecationWarning",
    "SeapassError",
    "SeapassWarning",
    "SimulationError",
    "SymbolicLimitError",
    "TuningWarning",
    "UnrealizableError",
    "did_you_mean",
]


class SeapassError(Exception):
    """Base class of every error seapass raises on purpose.

    Parameters
    ----------
    *args
        The message, as for any exception.
    argument : str, optional
        The Python argument at fault, as the message names it (``"values['kd']"``,
        ``"load_mass"``); the command line shows its own flag in its place.
    """

    argument: str | None = None

    def __init__(self, *args: object, argument: str | None = None) -> None:
        super().__init__(*args)
        if argument is not None:
            self.argument = argument


class ExpressionError(SeapassError, ValueError):
    """An expression string is malformed, unsafe, or not rational in ``s``."""


class ParameterError(SeapassError, ValueError):
    """A parameter value is missing, non-finite, or out of its physical range."""


class ModelError(SeapassError, ValueError):
    """A model is inconsistent or physically meaningless."""


class DegenerateModelError(ModelError):
    """A model whose port impedance is identically zero or undefined."""


class DelayError(ModelError):
    """A delay ``exp(-NAME*s)`` where a method does not support one, or a delayed model
    outside the structure seapass decides (see ``seapass.delay``)."""


class UnrealizableError(ModelError):
    """A transfer function that cannot be realized (improper where it must be proper)."""


class ContinuousOnlyError(ModelError):
    """A continuous-time analysis asked of a design whose controller is given in ``z``."""


class FileFormatError(SeapassError, ValueError):
    """A TOML design or rig file has an unknown key, wrong type or bad value."""


class OutputPathError(SeapassError, OSError):
    """An output path cannot be used: read-only, a dangling link, not a directory, or a
    directory holding files that seapass did not write where seapass writes its own."""


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


class SeapassWarning(UserWarning):
    """Base class of every warning seapass issues."""


class SeapassDeprecationWarning(SeapassWarning, DeprecationWarning):
    """An old spelling that still works for one release: a keyword argument or a file key.

    The message names the new spelling.  The command line shows it as a
    ``warning:`` line.
    """


class TuningWarning(SeapassWarning):
    """A tuned result needs attention: a gain at the edge of its box, a limit not met."""


def did_you_mean(name: str, choices: Iterable[str]) -> str:
    """``" (did you mean 'kd'?)"`` for the closest of ``choices``, or ``""``.

    >>> did_you_mean("kdd", ["kd", "bd", "k1"])
    " (did you mean 'kd'?)"
    """
    import difflib  # light, and only on the error path

    choices = list(choices)  # an iterator is read twice below
    close = difflib.get_close_matches(name, choices, n=1, cutoff=0.6)
    if not close:
        lowered = {c.lower(): c for c in choices}
        close = [lowered[name.lower()]] if name.lower() in lowered else []
    return f" (did you mean {close[0]!r}?)" if close else ""
