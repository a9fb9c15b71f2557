"""Two-port and n-port verdicts (``seapass.ports``) vs python-control's MIMO ``ispassive``.

The same systems for both: the SEA two-port in hybrid form (proper and stable for positive
gains, so python-control's KYP LMI applies; its state space is assembled from SISO realizations
of the four entries, as python-control converts MIMO transfer functions only with Slycot), and
random stable 3×3 state-space systems for the n-port row.  Agreement is counted where the
exact verdict has a margin (least eigenvalue of ``P + P^H`` over a grid, relative to ``|P + P^H|``)
of at least 1e-3, so that the LMI is not judged on cases it cannot resolve.
"""

from __future__ import annotations

import warnings
from fractions import Fraction
from typing import Any

import numpy as np

from _util import Row, rate, timed
from seapass.model.sea import SEA
from seapass.ports import two_port
from seapass.ports.bound import port_intervals
from seapass.ports.check import check_two_port, two_port_passivity
from seapass.ports.mimo import NPort, mimo_is_passive
from seapass.ports.passivity import evaluate

RIG = dict(m=1.0, b=10.0, k1=1000.0, b1=20.0)
SEA_KL = SEA(
    D1="k1 + b1*s", CA="kd + bd*s", CL="kl", values={**RIG, "kd": None, "bd": None, "kl": None}
)


def _designs(n: int, seed: int) -> list[dict[str, float]]:
    rng = np.random.default_rng(seed)
    return [
        {
            "kd": float(rng.uniform(100, 3000)),
            "bd": float(rng.uniform(5, 100)),
            "kl": float(rng.uniform(0, 4000)),
        }
        for _ in range(n)
    ]


def _ss_of_matrix(m: Any) -> Any:
    """A (non-minimal) state space of an exact matrix, assembled from SISO realizations."""
    import control

    n = m.n
    blocks = []
    for i in range(n):
        for j in range(n):
            num = [float(c) for c in reversed(m.num[i][j].coeffs())] or [0.0]
            den = [float(c) for c in reversed(m.den[i][j].coeffs())]
            blocks.append((i, j, control.ss(control.tf(num, den))))
    size = sum(b.nstates for _i, _j, b in blocks)
    a = np.zeros((size, size))
    bm = np.zeros((size, n))
    c = np.zeros((n, size))
    d = np.zeros((n, n))
    k = 0
    for i, j, b in blocks:
        s = slice(k, k + b.nstates)
        a[s, s] = b.A
        bm[s, j] = b.B[:, 0]
        c[i, s] = b.C[0, :]
        d[i, j] = b.D[0, 0]
        k += b.nstates
    return control.ss(a, bm, c, d)


def _peer(sys: Any) -> bool | str:
    import control

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return bool(control.ispassive(sys))
    except Exception as exc:  # the peer's failures are data here
        return f"error ({type(exc).__name__})"


def _margin(m: Any) -> float:
    w = np.geomspace(1e-3, 1e5, 3000)
    p = evaluate(m, w)
    h = p + np.conj(np.swapaxes(p, 1, 2))
    norm = np.linalg.norm(h, axis=(1, 2))
    return float(np.min(np.linalg.eigvalsh(h)[:, 0] / np.maximum(norm, 1e-300)))


def _random_ss(rng: np.random.Generator, n: int, states: int) -> tuple[np.ndarray, ...]:
    q = np.linalg.qr(rng.normal(size=(states, states)))[0]
    a = q @ np.diag(-rng.uniform(0.5, 5.0, states)) @ q.T
    b = rng.normal(size=(states, n))
    c = b.T * rng.uniform(0.2, 1.0) + 0.3 * rng.normal(size=(n, states))
    d = np.eye(n) * rng.uniform(0.5, 3.0) + 0.3 * rng.normal(size=(n, n))
    return a, b, c, d


def _exact_ss(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> list[list[str]]:
    """``C (sI − A)⁻¹ B + D`` as exact text entries (sympy on the rationals the floats are)."""
    import sympy as sp

    s = sp.Symbol("s")
    A, B, C, D = (
        sp.Matrix(x.shape[0], x.shape[1], [sp.Rational(Fraction(float(v))) for v in x.flat])
        for x in (a, b, c, d)
    )
    m = s * sp.eye(A.shape[0]) - A
    p = C * (m.adjugate() / m.det()) * B + D
    return [[str(p[i, j]) for j in range(p.shape[1])] for i in range(p.shape[0])]


def run(quick: bool) -> tuple[list[Row], list[str]]:
    rows: list[Row] = []
    notes: list[str] = []
    n = 12 if quick else 60
    designs = _designs(n, 0)
    tp = two_port(SEA_KL)
    two_port(SEA_KL.with_values(**designs[0]))  # derive and compile outside the timing
    check_two_port(tp.with_values(**designs[0]), witness=False)
    t_check = timed(lambda: [check_two_port(tp.with_values(**d), witness=False) for d in designs])
    t_wit = timed(lambda: [check_two_port(tp.with_values(**d)) for d in designs[: max(4, n // 4)]])
    hform = tp.convert("h")
    exact = [two_port_passivity(hform.with_values(**d)) for d in designs]
    systems = [_ss_of_matrix(r.matrix) for r in exact]
    t_peer = timed(lambda: [_peer(s) for s in systems])
    margins = [_margin(r.matrix) for r in exact]
    clear = [i for i in range(n) if abs(margins[i]) >= 1e-3]
    agree = sum(1 for i in clear if t_peer.result[i] == exact[i].passive)
    agree_all = sum(1 for i in range(n) if t_peer.result[i] == exact[i].passive)
    per = 1e3 * t_check.seconds / n
    rows.append(
        Row(
            task="two-port check (SEA, person-environment)",
            ours="check_two_port: Llewellyn + eta + passivity, exact",
            ours_rate=rate(n, t_check.seconds),
            peer="control.ispassive (MIMO LMI), passivity only",
            peer_rate=rate(n, t_peer.seconds),
            note=f"{per:.1f} ms per design (target <= 50 ms); with the witness search "
            f"{1e3 * t_wit.seconds / len(t_wit.result):.0f} ms; passivity agrees on {agree_all}/{n} "
            f"designs, {agree}/{len(clear)} where the margin is >= 1e-3 (a passive SEA two-port is "
            "lossless as w -> 0, so its margin is 0 there)",
        )
    )
    notes.append(
        f"two-port check: {sum(r.passive for r in exact)} of {n} random designs passive, "
        f"{sum(c.absolutely_stable for c in t_check.result)} absolutely stable; python-control "
        f"answered {sum(1 for v in t_peer.result if isinstance(v, str))} with an error."
    )
    # the exact passive set of one gain, against a scan of python-control verdicts
    sea = SEA_KL.with_values(kd=500.0, bd=25.0)
    port_intervals(sea, "kl", 0.0, 5000.0, criterion="passive")
    t_bound = timed(lambda: port_intervals(sea, "kl", 0.0, 5000.0, criterion="passive"), repeat=2)
    t_abs = timed(lambda: port_intervals(sea, "kl", 0.0, 5000.0, criterion="absolute"), repeat=2)
    scan = np.linspace(0.0, 5000.0, 21 if quick else 101)
    h_sea = two_port(sea).convert("h")
    scan_sys = [_ss_of_matrix(h_sea.exact({"kl": float(v)})) for v in scan]
    t_scan = timed(lambda: [_peer(s) for s in scan_sys])
    passing = [float(v) for v, ok in zip(scan, t_scan.result, strict=True) if ok is True]
    rows.append(
        Row(
            task="exact passive set of kl (two-port)",
            ours="port_intervals, exact interval",
            ours_rate=rate(1, t_bound.seconds),
            peer=f"control.ispassive scan of {scan.size} values",
            peer_rate=rate(1, t_scan.seconds),
            note=f"ours {t_bound.seconds:.2f} s (target <= 1 s), absolute stability "
            f"{t_abs.seconds:.2f} s; exact {[(round(a, 2), round(b, 2)) for a, b in t_bound.result.intervals]}, "
            f"the scan passes up to {max(passing) if passing else None}",
        )
    )
    # 3×3 n-ports: random stable state-space systems, the same for both
    rng = np.random.default_rng(5)
    m3 = 6 if quick else 20
    cases = [_random_ss(rng, 3, 2) for _ in range(m3)]
    matrices = [_exact_ss(*c) for c in cases]
    t_parse = timed(lambda: [NPort.from_matrix(z) for z in matrices])
    nports = t_parse.result
    t_mimo = timed(lambda: [mimo_is_passive(z) for z in nports])
    import control

    ss3 = [control.ss(*c) for c in cases]
    t_peer3 = timed(lambda: [_peer(s) for s in ss3])
    margins3 = [_margin(r.matrix) for r in t_mimo.result]
    clear3 = [i for i in range(m3) if abs(margins3[i]) >= 1e-3]
    agree3 = sum(1 for i in clear3 if t_peer3.result[i] == t_mimo.result[i].passive)
    rows.append(
        Row(
            task="3x3 n-port passivity",
            ours="mimo_is_passive (all 7 principal minors)",
            ours_rate=rate(m3, t_mimo.seconds),
            peer="control.ispassive (MIMO LMI)",
            peer_rate=rate(m3, t_peer3.seconds),
            note=f"{1e3 * t_mimo.seconds / m3:.0f} ms per system (target <= 200 ms; parsing the "
            f"text matrix adds {1e3 * t_parse.seconds / m3:.0f} ms); agreement "
            f"{agree3}/{len(clear3)} where the margin is >= 1e-3",
        )
    )
    return rows, notes


__all__ = ["run"]
