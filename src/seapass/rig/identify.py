"""Identify a rig's actuator from a logged run: m, b, b1 and the two Coulomb frictions.

The model is the actuator's equation of motion, with the transmission force
measured through the spring deflection ``δ = x_L − x_A`` (``k1`` from the rig
file)::

    F = m ẍ_A + b ẋ_A + F_cA sgn(ẋ_A) − k1 δ − b1 δ̇ − F_c1 sgn(δ̇) + c

``F`` is the applied force (the logged command after the rig's delay, held
for a period and saturated at its force limit), ``F_cA`` the actuator's and
``F_c1`` the friction damper's Coulomb level and ``c`` a constant force offset
(it also absorbs a sub-count offset of the encoders).  The load side does not
enter: the load may be free, held or loaded, its mass need not be known.

The fit is linear least squares on *modulating-function* moments: over short
windows ``[t0, t0 + T]`` the equation is multiplied by
``φ = sin²(π (t − t0)/T)`` and integrated, and integration by parts moves every
derivative onto ``φ``, so no velocity or acceleration is ever differentiated
from the quantized encoder signals.  The force integral is exact for the
zero-order hold; the positions are integrated through a cubic spline.
Coulomb friction is exact only while sliding, so windows are kept only where
both encoders keep counting (no stick) and neither velocity reverses in the
window's central three quarters; windows are packed greedily without overlap, which
keeps their errors nearly independent.  The normal equations are solved with
`scipy.optimize.lsq_linear` (``m > 0``, ``b, b1, F_cA, F_c1 ≥ 0``);
standard errors use the heteroscedasticity-consistent sandwich estimator HC3
and the intervals Student's t with ``n − 6`` degrees of freedom.

References
----------
.. [1] M. Shinbrot, "On the analysis of linear and nonlinear systems",
   Trans. ASME 79, 1957 (modulating functions).
.. [2] H. A. Preisig and D. W. T. Rippin, "Theory and application of the
   modulating function method", Comput. Chem. Eng. 17(1), 1993.
.. [3] J. G. MacKinnon and H. White, "Some heteroskedasticity-consistent
   covariance matrix estimators with improved finite sample properties",
   J. Econometrics 29(3), 1985 (HC3).
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ParameterError
from ..files.toml import dump_toml, update_toml_text
from ..model.display import html_card, short_repr
from .intervals import FitIntervals, fit_intervals
from .log import RigLog
from .moments import log_moments
from .rigfile import Rig

__all__ = ["FIT_PARAMETERS", "FitParameter", "RigFit", "fit_rig", "rig_text"]

FloatArray = NDArray[np.float64]

FIT_PARAMETERS: tuple[tuple[str, str, str], ...] = (
    ("m", "kg", "actuator mass (carriage + reflected rotor)"),
    ("b", "N·s/m", "actuator viscous damping to ground"),
    ("coulomb", "N", "actuator Coulomb friction to ground"),
    ("b1", "N·s/m", "damper viscous coefficient"),
    ("damper_coulomb", "N", "damper Coulomb friction"),
    ("offset", "N", "constant force offset"),
)
"""``(name, unit, description)`` of the fitted parameters, in the order of the regression."""

_CONFOUNDED = 0.98  # |correlation| beyond which two estimates are not told apart


@dataclass(frozen=True, kw_only=True)
class FitParameter:
    """One fitted parameter with its uncertainty.

    ``low``/``high`` bound the confidence interval; ``at_bound`` says the
    estimate sits on its physical bound (``≥ 0``), where the interval is only
    indicative.
    """

    name: str
    value: float
    stderr: float
    low: float
    high: float
    unit: str
    description: str
    at_bound: bool = False

    @property
    def relative_error(self) -> float:
        """``stderr / |value|`` (``inf`` for a zero estimate)."""
        return self.stderr / abs(self.value) if self.value else math.inf

    def to_dict(self) -> dict[str, Any]:
        return {
            "value": self.value,
            "stderr": self.stderr,
            "interval": [self.low, self.high],
            "unit": self.unit,
            "at_bound": self.at_bound,
        }


@dataclass(frozen=True, repr=False, kw_only=True)
class RigFit:
    """The fitted actuator of a rig, with uncertainties and the data behind the fit.

    Attributes
    ----------
    parameters : tuple of FitParameter
        In the order of `FIT_PARAMETERS`.
    confidence : float
        Level of the intervals.
    rig : Rig
        The rig file the fit started from (``k1``, resolutions, delay, limit).
    windows_used : int
        Windows in the regression.
    samples : int
        Samples in the log.
    t_window : ndarray, shape (w,)
        Window centres [s].
    force_applied, force_model : ndarray, shape (w,)
        Window-weighted mean of the applied force and of the force the fitted
        model needs to move as logged [N].
    residual_std : float
        Standard deviation of ``force_applied − force_model`` [N].
    correlation : ndarray, shape (6, 6)
        Correlation of the estimates (axes: `FIT_PARAMETERS`); near ±1 means
        the log cannot tell the two apart.
    source : str
        The log's source.
    """

    parameters: tuple[FitParameter, ...]
    confidence: float
    rig: Rig
    windows_used: int
    samples: int
    t_window: FloatArray
    force_applied: FloatArray
    force_model: FloatArray
    residual_std: float
    correlation: FloatArray
    source: str = ""

    def __getitem__(self, name: str) -> FitParameter:
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(f"no fitted parameter {name!r}; have {', '.join(self.names)}")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    def confounded(self, name: str) -> tuple[str, ...]:
        """The other parameters whose estimates correlate with ``name``'s beyond ±0.98."""
        i = self.names.index(name)
        return tuple(
            other
            for j, other in enumerate(self.names)
            if j != i and other != "offset" and abs(self.correlation[i, j]) > _CONFOUNDED
        )

    @property
    def poorly_determined(self) -> tuple[str, ...]:
        """Physical parameters this log does not pin down.

        A standard error above a quarter of the estimate, or an estimate
        correlated beyond ±0.98 with another one: then only a combination is
        determined, and a small systematic error moves both far (a square
        wave of force, for one, confounds ``m`` with the Coulomb levels).  A
        damping or friction whose interval holds 0 is not flagged: it is
        `consistent_with_zero` (the rig has none to speak of).
        """
        zero = set(self.consistent_with_zero)
        return tuple(
            p.name
            for p in self.parameters
            if p.name != "offset"
            and ((p.relative_error > 0.25 and p.name not in zero) or self.confounded(p.name))
        )

    @property
    def warnings(self) -> tuple[str, ...]:
        """One note per `poorly_determined` parameter: why, and which log pins it down."""
        out = []
        for name in self.poorly_determined:
            others = self.confounded(name)
            why = (
                f"correlated with {', '.join(others)} beyond ±0.98"
                if others
                else f"standard error {self[name].relative_error:.0%} of the estimate"
            )
            out.append(
                f"{name} is poorly determined by this log ({why}); log a chirp with the load "
                "free to move"
            )
        return tuple(out)

    @property
    def consistent_with_zero(self) -> tuple[str, ...]:
        """Dampings and frictions whose interval holds 0 (or that sit on their bound 0)."""
        return tuple(
            p.name
            for p in self.parameters
            if p.name not in ("m", "offset") and (p.at_bound or p.low <= 0.0)
        )

    def updated_rig(self, *, relative_to: str | os.PathLike[str] | None = None) -> Rig:
        """The rig file's rig with the fitted ``m, b, b1`` and Coulomb levels.

        ``m`` goes into ``transmission.carriage_mass`` (the fitted mass minus the
        rotor inertia the file reflects through gearbox and pulley).  The
        ``description`` names the log; given ``relative_to`` (the file the rig
        is written to), by its path relative to that file's directory, so the
        written file holds no absolute path.

        Raises
        ------
        ParameterError
            When the fitted mass is below that reflected inertia.
        """
        rig = self.rig
        reflected = rig.actuator_mass - rig.transmission.carriage_mass
        carriage = self["m"].value - reflected
        if carriage < 0:
            raise ParameterError(
                f"the fitted mass m = {self['m'].value:.6g} kg is below the rotor inertia the rig "
                f"file reflects to the carriage ({reflected:.6g} kg): check motor.rotor_inertia, "
                "transmission.gear_ratio and transmission.pulley_radius"
            )
        note = f"m, b, b1 and Coulomb friction fitted from {self.log_name(relative_to) or 'a log'}"
        return rig.replace(
            transmission={
                "carriage_mass": carriage,
                "viscous": self["b"].value,
                "coulomb": self["coulomb"].value,
            },
            damper={"b1": self["b1"].value, "coulomb": self["damper_coulomb"].value},
            description=f"{rig.description} ({note})" if rig.description else note,
            intervals=self.intervals(relative_to).to_table(),
        )

    def intervals(self, relative_to: str | os.PathLike[str] | None = None) -> FitIntervals:
        """The intervals of ``m, b, b1`` as a rig file keeps them (``[intervals]``)."""
        dof = self.windows_used - len(self.parameters)
        return fit_intervals(
            self.parameters, confidence=self.confidence, dof=dof if dof > 0 else None,
            source=self.log_name(relative_to),
        )  # fmt: skip

    def log_name(self, relative_to: str | os.PathLike[str] | None = None) -> str:
        """The log's path (`source`), relative to the directory of ``relative_to`` if given.

        >>> fit = RigFit.__new__(RigFit)
        >>> object.__setattr__(fit, "source", "/data/bench/chirp.csv")
        >>> fit.log_name("/data/out/fitted.toml")
        '../bench/chirp.csv'
        """
        if not self.source or relative_to is None or self.source == "twin":
            return self.source
        start = os.path.dirname(os.path.abspath(relative_to))
        try:
            return Path(os.path.relpath(os.path.abspath(self.source), start)).as_posix()
        except ValueError:  # another drive
            return Path(self.source).name

    def updated_rig_text(
        self, text: str | None = None, *, relative_to: str | os.PathLike[str] | None = None
    ) -> str:
        """`updated_rig` as rig-file TOML, written into ``text`` (the rig file as read).

        Every comment and line of ``text`` is kept and only the fitted values
        (and the description) change
        ([`update_toml_text`][seapass.files.toml.update_toml_text]); without
        ``text``, or when it cannot be edited line by line, `Rig.to_toml`.
        """
        return rig_text(self.rig, self.updated_rig(relative_to=relative_to), text)

    def to_dict(self) -> dict[str, Any]:
        return {
            "source": self.source,
            "confidence": self.confidence,
            "parameters": {p.name: p.to_dict() for p in self.parameters},
            "k1": self.rig.damper.k1,
            "windows_used": self.windows_used,
            "samples": self.samples,
            "residual_std": self.residual_std,
            "correlation": self.correlation.tolist(),
            "poorly_determined": list(self.poorly_determined),
            "consistent_with_zero": list(self.consistent_with_zero),
        }

    def plot(self, *, axes: Any = None) -> Any:
        """The fit: applied against model force per window, and the residuals; two Axes."""
        from ..plot.rig import plot_rig_fit

        return plot_rig_fit(self, axes=axes)

    def __repr__(self) -> str:
        fields: dict[str, Any] = {p.name: p.value for p in self.parameters if p.name != "offset"}
        return short_repr("RigFit", {**fields, "windows": self.windows_used})

    def _repr_html_(self) -> str:
        pct = f"{self.confidence * 100:g} %"
        rows = [
            (
                p.name,
                f"{p.value:.6g} ± {p.stderr:.2g} {p.unit} ({pct}: {p.low:.6g} .. {p.high:.6g})",
            )
            for p in self.parameters
        ]
        rows.append(("windows", f"{self.windows_used} of {self.samples} samples"))
        return html_card(f"Rig fit {self.source}".strip(), rows)


# ----------------------------------------------------------------------------- regression


def rig_text(before: Rig, after: Rig, text: str | None = None) -> str:
    """``after`` as rig-file TOML written into ``text`` (the file ``before`` was read from).

    Only the values that differ change, every comment and line is kept
    ([`update_toml_text`][seapass.files.toml.update_toml_text]); without ``text``,
    or when it cannot be edited line by line, `Rig.to_toml`.
    """
    if text is not None:
        old, new = before.to_dict(), after.to_dict()
        present = tomllib.loads(text)  # a table the text has but ``before`` lacks: updated
        old.update({k: v for k, v in present.items() if k not in old and isinstance(v, dict)})
        added = {sec: body for sec, body in new.items() if sec not in old}  # [intervals]
        changes = {
            (f"{sec}.{k}" if isinstance(body, dict) else sec): v
            for sec, body in new.items()
            if sec in old
            for k, v in (body.items() if isinstance(body, dict) else [(sec, body)])
            if (old[sec].get(k) if isinstance(body, dict) else old[sec]) != v
        }
        dropped = any(
            set(body) - set(new[sec])
            for sec, body in old.items()
            if isinstance(body, dict) and sec in new
        )  # a key the new rig lacks (a stale standard error) cannot stay: write the whole file
        edited = None if dropped else update_toml_text(text, changes)
        if edited is not None:
            notes = {"intervals": "written by seapass rig fit; read by --robust"}
            tail = "\n" + dump_toml(added, comments=notes) if added else ""
            return edited + tail
    return after.to_toml()


def _solve(
    X: FloatArray, y: FloatArray, groups: NDArray[np.int64]
) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
    """Feasibly weighted bounded least squares: estimate, HC3 covariance, active bounds.

    Windows of different lengths have different noise (a short window
    differentiates more), so a first fit estimates the residual spread of each
    ``groups`` value and the second weights the rows by its inverse.
    """
    theta, _cov, _active = _bounded_fit(X, y)
    e = y - X @ theta
    w = np.ones(y.size)
    for g in np.unique(groups):
        pick = groups == g
        spread = float(np.sqrt(np.mean(e[pick] ** 2)))
        w[pick] = 1.0 / spread if spread > 0 else 1.0
    w /= w.max()
    return _bounded_fit(X * w[:, None], y * w)


def _bounded_fit(X: FloatArray, y: FloatArray) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
    """Bounded least squares; returns the estimate, its HC3 covariance and the active bounds."""
    from scipy.optimize import lsq_linear

    scale = np.linalg.norm(X, axis=0)
    scale[scale == 0] = 1.0
    Xs = X / scale
    lower = np.array([1e-12, 0.0, 0.0, 0.0, 0.0, -np.inf])
    res = lsq_linear(Xs, y, bounds=(lower * scale, np.full(6, np.inf)), lsmr_tol="auto")
    theta = res.x / scale
    active = res.active_mask != 0
    e = y - X @ theta
    gram_inv = np.linalg.pinv(Xs.T @ Xs)
    leverage = np.einsum("ij,jk,ik->i", Xs, gram_inv, Xs)
    u = Xs * (e / np.clip(1.0 - leverage, 1e-12, None))[:, None]
    cov_s = gram_inv @ (u.T @ u) @ gram_inv
    cov = cov_s / np.outer(scale, scale)
    return theta, cov, active


def fit_rig(
    log: RigLog,
    rig: Rig,
    *,
    window: int = 16,
    delay: int | None = None,
    confidence: float = 0.95,
) -> RigFit:
    """Fit ``m, b, b1`` and the Coulomb levels of ``rig``'s actuator to ``log``.

    Parameters
    ----------
    log : RigLog
        A logged run with the actuator moving: a chirp (see
        [`chirp_command`][seapass.rig.log.chirp_command]) or steps, with the
        load free to move relative to the actuator (so ``b`` and ``b1`` differ).
    rig : Rig
        Gives ``k1``, the encoder resolutions, the force limit and the delay.
    window : int, default 16
        Samples per modulating window; about a quarter of the shortest period
        of interest works well.
    delay : int, optional
        Samples between a logged command and its action (default: the rig's
        ``control.delay``).
    confidence : float, default 0.95
        Level of the intervals.

    Returns
    -------
    RigFit

    Raises
    ------
    ParameterError
        For a window under 4 samples, a confidence outside (0, 1), or a log
        with too few usable windows (too short, or the actuator barely moves).
    """
    from scipy.stats import t as student

    if not 4 <= int(window) <= 10_000:
        raise ParameterError(f"window must be between 4 and 10000 samples, got {window}")
    if not 0 < confidence < 1:
        raise ParameterError(f"confidence must lie in (0, 1), got {confidence}")
    if abs(1 / log.period - rig.control.rate) > 0.01 * rig.control.rate:
        raise ParameterError(
            f"the log is sampled at {1 / log.period:.6g} Hz but the rig's control.rate is "
            f"{rig.control.rate:g} Hz: log at the control rate (the force is a zero-order hold)"
        )
    mom = log_moments(log, rig, int(window), delay=delay)
    n, p = mom.X.shape
    if n < 4 * p:
        raise ParameterError(
            f"only {n} usable windows in the log (at least {4 * p} needed): log longer, or "
            "excite more (both encoders must keep counting: no sticking)"
        )
    theta, cov, active = _solve(mom.X, mom.y, mom.length)
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    q = float(student.ppf(0.5 + confidence / 2, n - p))
    params = tuple(
        FitParameter(
            name=name,
            value=float(v),
            stderr=float(s),
            low=float(v - q * s),
            high=float(v + q * s),
            unit=unit,
            description=desc,
            at_bound=bool(a),
        )
        for (name, unit, desc), v, s, a in zip(FIT_PARAMETERS, theta, se, active, strict=True)
    )
    model = mom.X @ theta - mom.spring
    applied = mom.force
    return RigFit(
        parameters=params,
        confidence=confidence,
        rig=rig,
        windows_used=n,
        samples=log.size,
        t_window=mom.centre,
        force_applied=applied,
        force_model=model,
        residual_std=float(np.std(applied - model, ddof=p)),
        correlation=cov / np.outer(np.where(se > 0, se, 1.0), np.where(se > 0, se, 1.0)),
        source=log.source,
    )
