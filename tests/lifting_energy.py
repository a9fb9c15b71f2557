"""Independent energy check of a sampled-data port, by lifting over one period.

Written apart from ``seapass.sampled`` (no alias sums, no Colgate–Schenkel formula): the
continuous plant is integrated exactly (matrix exponentials in arb balls), the port velocity
is piecewise constant on ``M`` sub-steps of each period, and the energy the environment
supplies in one period is a quadratic form in the lifted input ``V ∈ R^M`` and the lifted
state ``X``:

``X⁺ = A X + B V``,  ``E = Vᵀ Qvv V + Vᵀ Qvx X``.

A lifted input ``V e^{jθk}`` supplies on average ``½ Vᴴ Φ(θ) V`` per period with
``Φ = He(Qvv) + He(Qvx (e^{jθ} − A)⁻¹ B)``.  A negative eigenvalue of ``Φ(θ)`` is a port
velocity that extracts net energy.  Restricting the input to ``M`` sub-steps can hide energy
extraction but never invents it, so a negative eigenvalue proves "not passive".  The
arithmetic is done in balls at 192 bits so that the large anti-Hermitian terms (the port
position integrates the velocity) cancel before anything is rounded to a double.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import sympy as sp
from flint import acb, acb_mat, arb, arb_mat, ctx, fmpq

from seapass.model.sea import SEA

S = sp.Symbol("s")


def _q(x: object) -> fmpq:
    r = sp.Rational(x)
    return fmpq(int(r.p), int(r.q))


def _proper_realization(expr: sp.Expr) -> tuple[list[list[fmpq]], list[fmpq], list[fmpq], fmpq]:
    """Controllable canonical form ``(A, B, C, D)`` of a proper rational function of ``s``."""
    num, den = sp.fraction(sp.cancel(sp.together(expr)))
    pn = [_q(c) for c in sp.Poly(num, S).all_coeffs()]
    pd = [_q(c) for c in sp.Poly(den, S).all_coeffs()]
    n = len(pd) - 1
    if len(pn) - 1 > n:
        raise ValueError("improper element")
    pd = [c / pd[0] for c in pd]
    pn = [c / _q(sp.Poly(den, S).LC()) for c in pn]
    pn = [fmpq(0)] * (n + 1 - len(pn)) + pn
    D = pn[0]
    r = [pn[i] - D * pd[i] for i in range(n + 1)][1:]
    A = [[fmpq(0)] * n for _ in range(n)]
    for i in range(n - 1):
        A[i][i + 1] = fmpq(1)
    for j in range(n):
        A[n - 1][j] = -pd[n - j]
    B = [fmpq(0)] * n
    if n:
        B[n - 1] = fmpq(1)
    return A, B, [r[n - 1 - j] for j in range(n)], D


def _controller_realization(tf: object) -> tuple[list[list[fmpq]], list[fmpq], list[fmpq], fmpq]:
    """``(A, B, C, D)`` of a causal transfer function in ``z⁻¹`` (direct form II transposed)."""
    num = [fmpq(c.numerator, c.denominator) for c in tf.num]  # type: ignore[attr-defined]
    den = [fmpq(c.numerator, c.denominator) for c in tf.den]  # type: ignore[attr-defined]
    n = max(len(num), len(den))
    b = num + [fmpq(0)] * (n - len(num))
    a = den + [fmpq(0)] * (n - len(den))
    k = n - 1
    A = [[fmpq(0)] * k for _ in range(k)]
    for i in range(k):
        A[i][0] = -a[i + 1]
        if i + 1 < k:
            A[i][i + 1] = fmpq(1)
    return (
        A,
        [b[i + 1] - a[i + 1] * b[0] for i in range(k)],
        [fmpq(int(i == 0)) for i in range(k)],
        b[0],
    )


class LiftedPort:
    """Lifted energy form of a sampled-data port.

    ``plant = (A, Bv, Bu, CF, DF, sensors, DU)``: continuous ``ẋ = A x + Bv v + Bu u``, port
    force ``F = CF x + DF v + DU u`` (the environment supplies ``F v``), ``sensors`` = states the
    controllers read; ``controllers`` = one discrete transfer function per sensor, and
    ``u_k = −Σ K_i(z) x_sensor_i``, held over the period.
    """

    def __init__(
        self, plant: tuple, controllers: list, period: Fraction, *, M: int = 8, prec: int = 192
    ):
        self.M, self.prec = M, prec
        with ctx.workprec(prec):
            self._build(plant, controllers, period, M)

    def _build(self, plant: tuple, controllers: list, period: Fraction, M: int) -> None:
        A, Bv, Bu, CF, DF, sensors, DU = plant
        n = len(A)
        h = arb(fmpq(period.numerator, period.denominator)) / M
        # one exponential gives the sub-step map and the integral of the state over it
        N = 2 * n + 2
        big = arb_mat(N, N)
        for r in range(n):
            for c in range(n):
                big[r, c] = arb(A[r][c])
            big[r, 2 * n], big[r, 2 * n + 1] = arb(Bv[r]), arb(Bu[r])
            big[n + r, r] = arb(1)
        E = (big * h).exp()

        def block(r0: int, c0: int, rows: int, cols: int) -> arb_mat:
            return arb_mat([[E[r0 + i, c0 + j] for j in range(cols)] for i in range(rows)])

        Ex, gv, gu = block(0, 0, n, n), block(0, 2 * n, n, 1), block(0, 2 * n + 1, n, 1)
        J, jv, ju = block(n, 0, n, n), block(n, 2 * n, n, 1), block(n, 2 * n + 1, n, 1)
        cf = arb_mat([[arb(c) for c in CF]])
        reals = [_controller_realization(tf) for tf in controllers]
        nc = sum(len(r[0]) for r in reals)
        nz = n + nc + M  # everything as linear maps of Z = [x(kT), controller states, V]
        urow = arb_mat(1, nz)
        off = n
        for (Ak, _Bk, Ck, Dk), s in zip(reals, sensors, strict=True):
            urow[0, s] -= arb(Dk)
            for j in range(len(Ak)):
                urow[0, off + j] -= arb(Ck[j])
            off += len(Ak)
        x = arb_mat(n, nz)
        for r in range(n):
            x[r, r] = arb(1)
        Qz = arb_mat(M, nz)
        for i in range(M):
            vsel = arb_mat(1, nz)
            vsel[0, n + nc + i] = arb(1)
            f = cf * (J * x + jv * vsel + ju * urow) + urow * (arb(DU) * h)
            for c in range(nz):
                Qz[i, c] = f[0, c]
            Qz[i, n + nc + i] += arb(DF) * h
            x = Ex * x + gv * vsel + gu * urow
        ny = n + nc
        self.A = arb_mat(ny, ny)
        self.B = arb_mat(ny, M)
        for r in range(n):
            for c in range(ny):
                self.A[r, c] = x[r, c]
            for j in range(M):
                self.B[r, j] = x[r, ny + j]
        off = n
        for (Ak, Bk, _Ck, _Dk), s in zip(reals, sensors, strict=True):
            for r in range(len(Ak)):
                for c in range(len(Ak)):
                    self.A[off + r, off + c] = arb(Ak[r][c])
                self.A[off + r, s] = arb(Bk[r])
            off += len(Ak)
        qvx = arb_mat([[Qz[i, c] for c in range(ny)] for i in range(M)])
        qvv = arb_mat([[Qz[i, ny + j] for j in range(M)] for i in range(M)])
        self._qvx = acb_mat(qvx)
        self._qvv = acb_mat((qvv + qvv.transpose()) * arb(0.5))
        self._b = acb_mat(self.B)
        self.n_plant = n

    def loop_eigenvalues(self, held: list[int]) -> np.ndarray:
        """Eigenvalues of the lifted loop with the port held (the ``held`` states removed)."""
        a = np.array([[float(x.mid()) for x in row] for row in self.A.tolist()])
        keep = [i for i in range(a.shape[0]) if i not in held]
        return np.linalg.eigvals(a[np.ix_(keep, keep)])

    def phi(self, theta: float) -> np.ndarray:
        with ctx.workprec(self.prec):
            ny = self.A.nrows()
            z = acb(0, arb(theta)).exp()
            m = acb_mat(ny, ny)
            for r in range(ny):
                for c in range(ny):
                    m[r, c] = (z if r == c else acb(0)) - self.A[r, c]
            q = self._qvx * m.solve(self._b)
            h = (q + q.conjugate().transpose()) * acb(0.5) + self._qvv
            return np.array([[complex(x.mid()) for x in row] for row in h.tolist()])

    def min_energy(self, theta: float) -> float:
        """Smallest eigenvalue of ``Φ(θ)`` over the largest in modulus."""
        w = np.linalg.eigvalsh(self.phi(theta))
        return float(w[0] / max(abs(w[-1]), 1e-300))

    def search(self, extra: tuple[float, ...] = (), smallest: float = 1e-11) -> tuple[float, float]:
        """Most negative relative energy over a log grid of ``θ``, refined: ``(value, θ)``."""
        from scipy.optimize import minimize_scalar

        grid = np.r_[
            np.logspace(math.log10(smallest), -1.2, 30), np.linspace(0.06, math.pi, 40), extra
        ]
        vals = np.array([self.min_energy(float(t)) for t in grid])
        best, where = float(vals.min()), float(grid[vals.argmin()])
        for i in np.argsort(vals)[:3]:
            t = float(grid[i])
            r = minimize_scalar(
                self.min_energy, bounds=(0.7 * t, min(1.3 * t + 1e-3, math.pi)), method="bounded",
                options={"xatol": 1e-4 * t + 1e-12, "maxiter": 25},
            )  # fmt: skip
            if r.fun < best:
                best, where = float(r.fun), float(r.x)
        return best, where


def sea_port(sea: SEA, ka: object, kl: object, period: float, **kw: object) -> LiftedPort:
    """The SEA of ``seapass.model``: states ``x_A, v_A, x_L`` and the element realizations."""
    e = {k: sea.numeric(v) for k, v in sea.elements().items()}
    m, b = _q(e["m"]), _q(e["b"])
    A1, B1, C1, d1 = _proper_realization(e["D1"] / S)
    A2, B2, C2, d2 = _proper_realization(e["D2"] / S) if e["D2"] != 0 else ([], [], [], fmpq(0))
    n1, n2 = len(A1), len(A2)
    n = 3 + n1 + n2
    A = [[fmpq(0)] * n for _ in range(n)]
    Bv, Bu, CF = [fmpq(0)] * n, [fmpq(0)] * n, [fmpq(0)] * n
    i1, i2 = 3, 3 + n1
    A[0][1] = fmpq(1)  # x_A' = v_A
    for j in range(n1):  # m v_A' = C1 xi1 + d1 (v - v_A) - b v_A + u
        A[1][i1 + j] = C1[j] / m
    A[1][1] = (-d1 - b) / m
    Bv[1], Bu[1] = d1 / m, 1 / m
    Bv[2] = fmpq(1)  # x_L' = v
    for r in range(n1):  # transmission driven by the relative velocity v - v_A
        for c in range(n1):
            A[i1 + r][i1 + c] = A1[r][c]
        A[i1 + r][1] -= B1[r]
        Bv[i1 + r] += B1[r]
    for r in range(n2):
        for c in range(n2):
            A[i2 + r][i2 + c] = A2[r][c]
        Bv[i2 + r] += B2[r]
    for j in range(n1):
        CF[i1 + j] += C1[j]
    CF[1] -= d1
    for j in range(n2):
        CF[i2 + j] += C2[j]
    plant = (A, Bv, Bu, CF, d1 + d2, [0, 2], fmpq(0))
    return LiftedPort(plant, [ka, kl], Fraction(repr(float(period))), **kw)  # type: ignore[arg-type]


def wall_port(b: float, controller: object, period: float, **kw: object) -> LiftedPort:
    """Colgate–Schenkel's rigid device: massless, damper ``b``, controller on its position."""
    bq = fmpq(*Fraction(b).as_integer_ratio())
    # state: the port position; F = b v - u (the controller force acts on the port directly)
    plant = ([[fmpq(0)]], [fmpq(1)], [fmpq(0)], [fmpq(0)], bq, [0], fmpq(-1))
    return LiftedPort(plant, [controller], Fraction(repr(float(period))), **kw)  # type: ignore[arg-type]
