"""Every size limit of seapass in one place: files, arrays, step counts, expressions, text.

Each limit bounds the time or memory one input can cost, so that a hostile or
careless input fails at load time with one clear error instead of running for
minutes or exhausting memory.  They are checked where the input enters
seapass (file loaders, model constructors, the command line), before any work
starts.  ``docs/verification.md`` lists them with the reasoning.

The values are generous for real designs and rigs (the paper's need far less)
and keep the worst accepted input well under 1 GB of memory.
"""

from __future__ import annotations

from ..errors import ParameterError

__all__ = [
    "MAX_DELAY_GAINS",
    "MAX_DELAY_MULTIPLE",
    "MAX_DELAY_PIECES",
    "MAX_DELAY_SAMPLES",
    "MAX_DELAY_SECONDS",
    "MAX_DESCRIPTION_CHARS",
    "MAX_DESIGNS",
    "MAX_EXPONENT",
    "MAX_EXPRESSION_LENGTH",
    "MAX_FREQUENCY_POINTS",
    "MAX_HORIZON",
    "MAX_KD_GAINS",
    "MAX_KD_GAINS_CLI",
    "MAX_LIST_LENGTH",
    "MAX_MODEL_DEGREE",
    "MAX_MODEL_TERMS",
    "MAX_NAME_CHARS",
    "MAX_NODES",
    "MAX_REGION_COLUMNS",
    "MAX_RIG_INTEGRATOR_STEPS",
    "MAX_RIG_SAMPLES",
    "MAX_SIM_STEPS",
    "MAX_S_DEGREE",
    "MAX_TERMS",
    "MAX_TEXT_FILE_BYTES",
    "MAX_TITLE_CHARS",
    "MAX_TOML_DEPTH",
    "MAX_TRAJECTORY_BYTES",
    "MAX_TRAJECTORY_SAMPLES",
    "MAX_TWIN_VALUES",
    "MIN_RTOL",
    "SYMBOLIC_TIME_LIMIT",
    "check_count",
]

# --------------------------------------------------------------------------- files

MAX_TEXT_FILE_BYTES = 1 << 20
"""Design and rig TOML files: 1 MiB (a real one is about 2 kB)."""

MAX_TOML_DEPTH = 8
"""Nesting of tables and arrays in a TOML file (design and rig files need 3)."""

MAX_TRAJECTORY_BYTES = 64 << 20
"""A ``simulate --trajectory`` CSV file: 64 MiB."""

MAX_TRAJECTORY_SAMPLES = 1_000_000
"""Samples (rows) of a reference trajectory."""

# --------------------------------------------------------------------------- text fields

MAX_NAME_CHARS = 64
"""A design or rig ``name``."""

MAX_TITLE_CHARS = 200
"""A design ``title`` and a rig's ``motor.name``."""

MAX_DESCRIPTION_CHARS = 2000
"""A rig ``description``."""

# --------------------------------------------------------------------------- arrays

MAX_LIST_LENGTH = 64
"""Lists in design and rig files (``load_masses``)."""

MAX_DESIGNS = 10**12
"""Designs in one sweep (they are streamed in chunks, so memory does not grow with it)."""

MAX_FREQUENCY_POINTS = 100_000
"""Frequencies of one response (``response --points``)."""

MAX_REGION_COLUMNS = 2000
"""Columns of a 2-D passive region (``region --nx``)."""

MAX_KD_GAINS = 10_000
"""Gains of one rig kd sweep through the Python API."""

MAX_KD_GAINS_CLI = 2000
"""Gains of one ``seapass rig sweep``."""

# --------------------------------------------------------------------------- step counts

MAX_SIM_STEPS = 5_000_000
"""Time steps of one simulation (``horizon / dt``)."""

MAX_RIG_SAMPLES = 1_000_000
"""Control periods of one digital-twin run (``horizon × rate``, ``duration × rate``)."""

MAX_RIG_INTEGRATOR_STEPS = 20_000_000
"""Integrator steps of one twin run (control periods × ``substeps``)."""

MAX_TWIN_VALUES = 5_000_000
"""Recorded samples of one batch of twin runs (runs × control periods): the seven float64
arrays recorded (true and measured positions, external force, applied force, command) are
280 MB at this size."""

MAX_HORIZON = 1000.0
"""Simulated time [s] of a design file's step responses and tuning (at the 1 ms step of the
report, 10⁶ steps)."""

MAX_DELAY_SAMPLES = 100
"""Computational delay of a sampled controller, in samples (design files, ``--delay``);
each sample adds 2 to the degree of the sampled passivity polynomial."""

MAX_DELAY_SECONDS = 1000.0
"""A continuous delay ``exp(-NAME*s)``, in seconds (beyond it a value is a unit slip)."""

MAX_DELAY_PIECES = 100_000
"""Initial pieces of the middle band that a certified check at a fixed delay may scan
(``θ = ωτ`` advances at most 1 rad per piece): a longer delay is refused up front unless a
witness or the delay-independent test settles it first."""

MAX_DELAY_MULTIPLE = 4
"""Largest whole multiple ``k`` in ``exp(-k*NAME*s)`` (the power of ``E = e^{-sτ}``)."""

MAX_DELAY_GAINS = 200
"""Gains evaluated by one (gain, delay) region or edge search (each a certified delay margin)."""

MIN_RTOL = 1e-12
"""Smallest relative tolerance of a bisection (``sampled bound --rtol``); 0 never ends."""

# --------------------------------------------------------------------------- expressions

MAX_EXPRESSION_LENGTH = 2000
"""Characters of one expression."""

MAX_NODES = 400
"""Syntax-tree nodes of one expression."""

MAX_EXPONENT = 12
"""Largest integer power in an expression."""

MAX_S_DEGREE = 24
"""Degree in ``s`` of one expression brought to a single fraction ``N/D`` (``deg N + deg D``,
an upper bound computed from the tree without expanding): keeps every later sympy step
(together, cancel, solve) well under a second."""

MAX_TERMS = 4000
"""Terms of one expression as a single fraction (numerator plus denominator)."""

MAX_MODEL_DEGREE = 16
"""Budget of the derivation: ``deg N + deg D`` of ``F_L/X_L`` (see
`seapass.model.stiffness.model_size`), checked before sympy starts."""

MAX_MODEL_TERMS = 200
"""Budget of ``terms(N) + terms(D)`` of ``F_L/X_L`` after the structural cancellation (see
`seapass.model.stiffness.model_size`).  The cost of sympy's multivariate cancellation grows with
the terms, not with the degree in ``s``: models at the limit derive and compile in about ten
seconds, twice the limit can take minutes.  Every standard structure is far below it (the 72
of D1 ∈ {k1, k1 + b1 s}, D2 ∈ {0, k2, b2 s}, C_A ∈ {0, kd, kd + bd s, kd + ki/s},
C_L ∈ {0, kd, kd + bd s}: at most 24 terms; a cascaded torque/velocity-loop impedance
controller on a damped spring: 36; filtered PD and PID on both sides with a spring-damper to
ground: 96)."""

SYMBOLIC_TIME_LIMIT = 20.0
"""Wall-clock budget [s] of one symbolic derivation (SIGALRM, main thread only)."""


def check_count(value: int, limit: int, what: str, hint: str = "") -> int:
    """Return ``value`` if ``0 <= value <= limit``, else raise `ParameterError`.

    >>> check_count(10, MAX_LIST_LENGTH, "load_masses")
    10
    """
    if value > limit:
        raise ParameterError(
            f"{what}: {value:,} exceeds the limit of {limit:,}" + (f"; {hint}" if hint else "")
        )
    return value
