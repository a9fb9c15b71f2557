"""Compile the generated C with the system compiler and run it from Python (ctypes).

Before flashing a controller, run the very code that will be flashed against
seapass's Python controller and the digital twin: [`compile_c`][seapass.export.compiled.compile_c] builds the
exported files into a shared library with strict warnings
(``-std=c99 -Wall -Wextra -Werror -pedantic``) and returns a
[`CompiledController`][seapass.export.compiled.CompiledController] that drops into [`ControlLoop`][seapass.sampled.runtime.ControlLoop]
like a [`DiscreteController`][seapass.sampled.controllers.DiscreteController]; [`verify_c`][seapass.export.compiled.verify_c]
drives both with the same random input sequence and reports how far apart they are.
"""

from __future__ import annotations

import ctypes
import math
import os
import shutil
import subprocess
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import CompilerError, ParameterError
from .c_code import ExportResult
from .ctext import c_identifier
from .deployment import Deployment

__all__ = [
    "CFLAGS",
    "VERIFY_RTOL",
    "CompiledController",
    "VerifyResult",
    "compile_c",
    "find_c_compiler",
    "verify_c",
]

#: Flags the generated code must compile cleanly under (plus -fPIC -shared here).
CFLAGS = ("-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2", "-ffp-contract=off")
_COMPILE_CPU_SECONDS = 120  # CPU time of each compiler process (work, not wall-clock time)
_MAX_STEPS = 10_000_000

VERIFY_RTOL = 1e-12
"""Largest relative difference between the compiled C and the Python commands that
[`verify_c`][seapass.export.compiled.verify_c] accepts (``VerifyResult.ok``)."""


def _limit_cpu() -> None:
    """In the compiler's process: at most `_COMPILE_CPU_SECONDS` of CPU time (a busy
    machine slows a compile down but never fails it)."""
    import resource

    resource.setrlimit(resource.RLIMIT_CPU, (_COMPILE_CPU_SECONDS, _COMPILE_CPU_SECONDS + 5))


def find_c_compiler() -> str | None:
    """``$CC`` if set, else ``cc``, ``gcc`` or ``clang`` from ``PATH`` (None: no compiler)."""
    env = os.environ.get("CC")
    if env:
        return shutil.which(env)
    for name in ("cc", "gcc", "clang"):
        found = shutil.which(name)
        if found:
            return found
    return None


_SHIM = """\
#include <stddef.h>
#include "seapass_ctrl.h"

size_t seapass_shim_state_size(void) { return sizeof(seapass_ctrl_state); }
unsigned long seapass_shim_saturated(const seapass_ctrl_state *s) { return s->saturated; }

void seapass_shim_run(seapass_ctrl_state *s, long n, const double *x_A, const double *x_L,
                      const double *theta_A, const double *theta_L, double *u)
{
    long k;
    for (k = 0; k < n; k++) {
        u[k] = seapass_ctrl_step(s, x_A[k], x_L[k], theta_A[k], theta_L[k]);
    }
}
"""


def _shim(dep: Deployment) -> str:
    text = _SHIM
    if dep.set_gains:
        names = [c_identifier(g.name, "gain name") for g in dep.gains]
        sets = "".join(f"    g.{n} = v[{i}];\n" for i, n in enumerate(names))
        gets = "".join(f"    v[{i}] = s->gains.{n};\n" for i, n in enumerate(names))
        text += (
            "\nint seapass_shim_set_gains(seapass_ctrl_state *s, const double *v)\n{\n"
            f"    seapass_ctrl_gains g;\n{sets}    return (int)seapass_ctrl_set_gains(s, &g);\n}}\n"
            "\nvoid seapass_shim_get_gains(const seapass_ctrl_state *s, double *v)\n{\n"
            f"{gets}}}\n"
        )
    return text


_HOOK = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_int, ctypes.c_char_p)
_DP = ctypes.POINTER(ctypes.c_double)


class CompiledController:
    """The generated C controller, compiled and loaded; use [`compile_c`][seapass.export.compiled.compile_c].

    Attributes
    ----------
    deployment : Deployment
    messages : list of (int, str)
        Every call of the guard hook: ``(status code, message)``.
    init_status : int
        What ``seapass_ctrl_init`` returned (0: running).
    """

    def __init__(self, library: Path, deployment: Deployment, *, period: float | None = None):
        self.deployment = deployment
        self._lib = lib = ctypes.CDLL(str(library))
        lib.seapass_shim_state_size.restype = ctypes.c_size_t
        lib.seapass_ctrl_init.restype = ctypes.c_int
        lib.seapass_ctrl_init.argtypes = [ctypes.c_void_p, ctypes.c_double, _HOOK, ctypes.c_void_p]
        lib.seapass_ctrl_step.restype = ctypes.c_double
        lib.seapass_ctrl_step.argtypes = [ctypes.c_void_p] + [ctypes.c_double] * 4
        lib.seapass_ctrl_reset.argtypes = [ctypes.c_void_p]
        lib.seapass_ctrl_fault.argtypes = [ctypes.c_void_p]
        lib.seapass_ctrl_fault.restype = ctypes.c_int
        lib.seapass_shim_saturated.argtypes = [ctypes.c_void_p]
        lib.seapass_shim_saturated.restype = ctypes.c_ulong
        lib.seapass_shim_run.argtypes = [ctypes.c_void_p, ctypes.c_long, _DP, _DP, _DP, _DP, _DP]
        if deployment.set_gains:
            lib.seapass_shim_set_gains.argtypes = [ctypes.c_void_p, _DP]
            lib.seapass_shim_set_gains.restype = ctypes.c_int
            lib.seapass_shim_get_gains.argtypes = [ctypes.c_void_p, _DP]
        self._state = ctypes.create_string_buffer(int(lib.seapass_shim_state_size()))
        self.messages: list[tuple[int, str]] = []
        self._hook = _HOOK(self._on_hook)  # kept alive as long as the library may call it
        self.init_status = self.init(float(deployment.period) if period is None else period)

    def _on_hook(self, _user: Any, code: int, message: bytes) -> None:
        self.messages.append((int(code), message.decode("utf-8", "replace")))

    def init(self, period: float) -> int:
        """``seapass_ctrl_init(state, period, hook, NULL)``; returns its status."""
        return int(self._lib.seapass_ctrl_init(self._state, float(period), self._hook, None))

    def reset(self) -> None:
        self._lib.seapass_ctrl_reset(self._state)

    def step(
        self, measurement: tuple[float, float], reference: tuple[float, float] = (0.0, 0.0)
    ) -> float:
        """One period, with `DiscreteController.step`'s signature (delay and saturation included)."""
        xa, xl = measurement
        ta, tl = reference
        return float(self._lib.seapass_ctrl_step(self._state, xa, xl, ta, tl))

    def run(
        self,
        x_A: NDArray[np.float64],
        x_L: NDArray[np.float64],
        theta_A: NDArray[np.float64],
        theta_L: NDArray[np.float64],
    ) -> NDArray[np.float64]:
        """Step through equal-length input sequences (one C loop); returns the commands."""
        arrays = [np.ascontiguousarray(a, dtype=np.float64) for a in (x_A, x_L, theta_A, theta_L)]
        n = arrays[0].shape[0]
        for name, a in zip(("x_A", "x_L", "theta_A", "theta_L"), arrays, strict=True):
            if a.shape != (n,):
                raise ParameterError(f"{name} must have shape ({n},), got {a.shape}")
        if n > _MAX_STEPS:
            raise ParameterError(f"at most {_MAX_STEPS} steps per run, got {n}")
        out = np.empty(n)
        ptrs = [a.ctypes.data_as(_DP) for a in (*arrays, out)]
        self._lib.seapass_shim_run(self._state, n, *ptrs)
        return out

    @property
    def fault(self) -> int:
        return int(self._lib.seapass_ctrl_fault(self._state))

    @property
    def saturated(self) -> int:
        return int(self._lib.seapass_shim_saturated(self._state))

    def set_gains(self, **gains: float) -> int:
        """``seapass_ctrl_set_gains`` with the certified gains updated by ``gains``."""
        if not self.deployment.set_gains:
            raise ParameterError("this controller was exported without set_gains")
        names = [g.name for g in self.deployment.gains]
        unknown = sorted(set(gains) - set(names))
        if unknown:
            raise ParameterError(f"unknown gain {unknown[0]!r}; gains: {', '.join(names)}")
        current = self.gains
        current.update(gains)
        buf = (ctypes.c_double * len(names))(*(float(current[n]) for n in names))
        return int(self._lib.seapass_shim_set_gains(self._state, buf))

    @property
    def gains(self) -> dict[str, float]:
        """The gains in use."""
        if not self.deployment.set_gains:
            return self.deployment.nominal_gains()
        names = [g.name for g in self.deployment.gains]
        buf = (ctypes.c_double * len(names))()
        self._lib.seapass_shim_get_gains(self._state, buf)
        return dict(zip(names, (float(v) for v in buf), strict=True))


def compile_c(
    export: ExportResult, *, compiler: str | None = None, period: float | None = None
) -> CompiledController:
    """Compile the exported files (strict C99 flags) and load them.

    Parameters
    ----------
    export : ExportResult
        What [`export_c`][seapass.export.c_code.export_c] returned.
    compiler : str, optional
        Compiler command; default [`find_c_compiler`][seapass.export.compiled.find_c_compiler].
    period : float, optional
        Period passed to ``seapass_ctrl_init`` (default the certified one; any
        other is refused by the guard, see `CompiledController.init_status`).

    Raises
    ------
    CompilerError
        When no compiler is found or it rejects the code (the message quotes it).
    """
    cc = compiler or find_c_compiler()
    if cc is None:
        raise CompilerError("no C compiler found (set CC or install gcc/clang)")
    src_dir = export.source.parent
    with tempfile.TemporaryDirectory(prefix="seapass-cc-") as tmp:
        shim = Path(tmp) / "seapass_shim.c"
        shim.write_text(_shim(export.deployment), encoding="utf-8")
        lib = Path(tmp) / "libseapass_ctrl.so"
        cmd = [cc, *CFLAGS, "-fPIC", "-shared", f"-I{src_dir}", "-o", str(lib)]
        cmd += [str(export.source), str(shim)]
        try:
            proc = subprocess.run(
                cmd, capture_output=True, text=True, check=False, preexec_fn=_limit_cpu
            )
        except OSError as exc:
            raise CompilerError(f"could not run {cc}: {exc}") from None
        if proc.returncode != 0:
            first = (proc.stderr or proc.stdout).strip().splitlines()[:3]
            raise CompilerError(f"{cc} rejected {export.source.name}: " + " | ".join(first))
        # dlopen keeps the mapping after the file is removed with the temporary directory
        return CompiledController(lib, export.deployment, period=period)


@dataclass(frozen=True, kw_only=True)
class VerifyResult:
    """How closely the compiled C follows the Python controller ([`verify_c`][seapass.export.compiled.verify_c]).

    Attributes
    ----------
    steps : int
    max_abs : float
        Largest ``|u_C − u_Python|`` over the run (N).
    max_rel : float
        ``max_abs`` over the largest ``|u_Python|``.
    identical : bool
        Every command equal bit for bit.
    saturated : int
        Commands the C code clipped at the force limit.
    rtol : float
        The largest ``max_rel`` accepted (`VERIFY_RTOL`).
    """

    steps: int
    max_abs: float
    max_rel: float
    identical: bool
    saturated: int
    rtol: float = VERIFY_RTOL

    @property
    def ok(self) -> bool:
        """The compiled C follows the Python controller within ``rtol``."""
        return self.max_rel <= self.rtol

    def to_dict(self) -> dict[str, Any]:
        return {
            "steps": self.steps,
            "max_abs": self.max_abs,
            "max_rel": self.max_rel,
            "identical": self.identical,
            "saturated": self.saturated,
            "rtol": self.rtol,
            "ok": self.ok,
        }


def equivalence_inputs(steps: int, seed: int = 0, scale: float = 0.01) -> NDArray[np.float64]:
    """``(4, steps)`` input sequences ``x_A, x_L, θ_A, θ_L`` (m) for equivalence runs.

    Random walks of the positions with occasional jumps (to drive the
    derivative paths into saturation) and piecewise-constant references.
    """
    rng = np.random.default_rng(seed)
    walk = np.cumsum(rng.normal(0.0, scale / 100, size=(2, steps)), axis=1)
    offsets = rng.uniform(-3 * scale, 3 * scale, size=(2, steps // 1000 + 1))
    x = walk + np.repeat(offsets, 1000, axis=1)[:, :steps]
    levels = rng.uniform(-2 * scale, 2 * scale, size=(2, steps // 500 + 1))
    refs = np.repeat(levels, 500, axis=1)[:, :steps]
    return np.vstack([x, refs])


def reference_commands(
    dep: Deployment, inputs: NDArray[np.float64], gains: Mapping[str, float] | None = None
) -> NDArray[np.float64]:
    """Python reference of the deployed loop: controller, saturation (as ``ControlLoop``), delay line."""
    ctrl = dep.reference_controller(gains)
    ctrl.reset()
    limit = dep.force_limit
    line = [0.0] * dep.code_delay
    out = np.empty(inputs.shape[1])
    for k in range(inputs.shape[1]):
        xa, xl, ta, tl = inputs[:, k]
        u = ctrl.step((float(xa), float(xl)), (float(ta), float(tl)))
        if abs(u) > limit:
            u = math.copysign(limit, u)
        line.append(u)
        out[k] = line.pop(0)
    return out


def verify_c(
    export: ExportResult, *, steps: int = 10_000, seed: int = 0, compiler: str | None = None
) -> VerifyResult:
    """Compile the exported C and compare it with the Python controller on ``steps`` inputs.

    The Python side is [`DiscreteController`][seapass.sampled.controllers.DiscreteController] at the
    certified gains, saturated like [`ControlLoop`][seapass.sampled.runtime.ControlLoop] and
    delayed by the code's delay line; inputs come from [`equivalence_inputs`][seapass.export.compiled.equivalence_inputs].
    """
    if not (isinstance(steps, int) and 1 <= steps <= _MAX_STEPS):
        raise ParameterError(f"steps must be a whole number in [1, {_MAX_STEPS}], got {steps!r}")
    ctrl = compile_c(export, compiler=compiler)
    if ctrl.init_status != 0:
        raise CompilerError(f"seapass_ctrl_init refused the certified period: {ctrl.messages}")
    inputs = equivalence_inputs(steps, seed)
    got = ctrl.run(*inputs)
    want = reference_commands(export.deployment, inputs)
    diff = np.abs(got - want)
    scale = float(np.max(np.abs(want))) or 1.0
    return VerifyResult(
        steps=steps,
        max_abs=float(np.max(diff)),
        max_rel=float(np.max(diff)) / scale,
        identical=bool(np.array_equal(got, want)),
        saturated=ctrl.saturated,
    )
