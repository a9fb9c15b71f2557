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
    "MAX_EXACT_BITS",
    "MAX_EXACT_DEGREE",
    "MAX_EXACT_TERMS",
    "MAX_EXACT_WORK",
    "MAX_EXPONENT",
    "MAX_EXPRESSION_LENGTH",
    "MAX_FREQUENCY_POINTS",
    "MAX_HORIZON",
    "MAX_KD_GAINS",
    "MAX_KD_GAINS_CLI",
    "MAX_LIST_LENGTH",
    "MAX_LOG_BYTES",
    "MAX_LOG_ROWS",
    "MAX_MODEL_DEGREE",
    "MAX_MODEL_TERMS",
    "MAX_NAME_CHARS",
    "MAX_NODES",
    "MAX_PORTS",
    "MAX_REGION_COLUMNS",
    "MAX_RIG_INTEGRATOR_STEPS",
    "MAX_RIG_SAMPLES",
    "MAX_RTOL",
    "MAX_SAMPLED_INTERVAL_BUDGET",
    "MAX_SIM_STEPS",
    "MAX_SWEEP_MANIFEST_BYTES",
    "MAX_S_DEGREE",
    "MAX_TERMS",
    "MAX_TEXT_FILE_BYTES",
    "MAX_TITLE_CHARS",
    "MAX_TOML_DEPTH",
    "MAX_TRAJECTORY_BYTES",
    "MAX_TRAJECTORY_SAMPLES",
    "MAX_TWIN_VALUES",
    "MAX_UNCERTAIN",
    "MAX_UNCERTAIN_MAGNITUDE",
    "MAX_UNCERTAIN_RATIO",
    "MAX_Z_ORDER",
    "MIN_RTOL",
    "SYMBOLIC_TIME_LIMIT",
    "check_count",
    "check_rtol",
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

MAX_LOG_BYTES = 256 << 20
"""A logged rig run (``rig fit LOG.csv``): 256 MiB, read as a stream (memory grows with the
rows kept, 32 bytes each, not with the file)."""

MAX_LOG_ROWS = 2_000_000
"""Samples (rows) of a logged rig run (over an hour at 500 Hz)."""

MAX_SWEEP_MANIFEST_BYTES = 64 << 20
"""A sweep's ``_manifest.json`` (its journal of finished chunks; a real one is a few kB)."""

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
"""Columns of a 2-D passive region (``region --points``)."""

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

MAX_Z_ORDER = 24
"""Order (poles in ``z``) of each transfer function of a controller given in ``z``
([`ZController`][seapass.model.zcontroller.ZController]): bounds its realization and the
degree of the sampled passivity polynomial."""

MAX_UNCERTAIN = 6
"""Uncertain parameters of one robust verdict (``--uncertain``, ``box=``): the certified
branch and bound works on a box of this many dimensions plus frequency."""

MAX_BOX_BUDGET = 1_000_000
"""Largest ``budget`` of one continuous robust verdict (boxes of the Bernstein branch and
bound; the pending boxes are kept in memory, so this also bounds memory)."""

MAX_UNCERTAIN_RATIO = 1e6
"""Largest ``HI/LO`` of one uncertain positive parameter (six decades); a wider box is
split into boxes so small that the budgeted branch and bound cannot end."""

MAX_UNCERTAIN_MAGNITUDE = 1e12
"""Largest ``|LO|``, ``|HI|`` of an uncertain parameter (keeps the exact rationals small)."""

MAX_SAMPLED_INTERVAL_BUDGET = 10_000
"""Most sub-intervals (a plant parameter) or plants (a gain over a box) one robust sampled
bound examines ([`robust_sampled_intervals`][seapass.robust.sampled_intervals.robust_sampled_intervals],
``sampled bound --budget``); each is one certified decision of the robust kernel."""
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
"""Smallest relative width of a certified edge enclosure (``rtol`` of
[`sampled_passive_bound`][seapass.sampled.bound.sampled_passive_bound]); 0 never ends."""

MAX_RTOL = 1e-2
"""Largest relative width of a certified edge enclosure (a coarser edge says little)."""

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

# ------------------------------------------------ the exact path (no sympy), checked per operation

MAX_EXACT_DEGREE = 48
"""Degree in any one variable (``s`` or a parameter) of a polynomial the exact path forms
(`seapass.model.rational`: parsing an element, deriving ``Z_L``), checked before each product.
Numbers do not count: a PID force loop with a filtered derivative inside an impedance loop
has ``Z_L`` of degree 6 over 5 in ``s``."""

MAX_EXACT_TERMS = 5000
"""Terms of one polynomial of the exact path, in ``s`` and every parameter.  The exact path
keeps the parameters as variables so that cancellations are decided for every value (a
factor that cancels only at the given values is a hidden mode); numbers are coefficients
and cost nothing here.  Real designs are far below it: the 72 standard structures need at
most 24 terms, the PID-in-impedance cascade 55, and flint derives either in about a
millisecond."""

MAX_EXACT_WORK = 250_000
"""Term products of one polynomial multiplication of the exact path (``terms(a) ×
terms(b)``), checked before multiplying: bounds the time of each operation (milliseconds)."""

MAX_EXACT_BITS = 20_000
"""Size in bits of the coefficients of one product of the exact path (numerator or
denominator of a rational coefficient), checked before multiplying: ``1e300`` is a
997-bit integer, ``(1e300*s + 1)**12`` about 12,000 bits."""

MAX_PORTS = 6
"""Ports of an n-port immittance matrix (``2^n − 1`` principal minors are decided; 6 ports:
63 minors, the largest a 6×6 determinant of polynomial entries)."""

SYMBOLIC_TIME_LIMIT = 20.0
"""CPU-time budget [s] of one symbolic derivation (``ITIMER_PROF``, main thread only): the
same input passes or fails whatever else runs on the machine."""


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


def check_rtol(rtol: float) -> float:
    """Return ``rtol`` if it is a relative edge width in ``[MIN_RTOL, MAX_RTOL]``, else raise.

    The one check of ``rtol`` (sampled bounds and regions, the C export's
    envelope); the command line shows ``--rtol`` in place of ``rtol``.

    >>> check_rtol(1e-6)
    1e-06
    >>> check_rtol(0.0)
    Traceback (most recent call last):
    ...
    seapass.errors.ParameterError: rtol must be in [1e-12, 0.01], the relative width of a certified edge enclosure; got rtol=0.0
    """
    if (
        isinstance(rtol, bool)
        or not isinstance(rtol, int | float)
        or not (
            MIN_RTOL <= rtol <= MAX_RTOL  # False for nan
        )
    ):
        raise ParameterError(
            f"rtol must be in [{MIN_RTOL:g}, {MAX_RTOL:g}], the relative width of a certified "
            f"edge enclosure; got rtol={rtol!r}",
            argument="rtol",
        )
    return float(rtol)
