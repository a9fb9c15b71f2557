"""Controller blocks compiled into C_A, C_L, checked against independent solutions of the diagram.

Three independent checks of `derive_controller`:

* numerically: each block diagram, coupled to the plant, is written here as a linear
  system at a complex ``s`` (block values from their numbers, never from seapass's
  text or sympy) and solved with numpy; its port stiffness ``F_L/X_L`` and its
  reference response with a load mass must equal those of the compiled
  ``C_A``, ``C_L`` (hypothesis over random blocks);
* symbolically: the issue's cascaded design solved by sympy from its free-body and
  block equations equals seapass's stiffness derived from the compiled ``C_A``, ``C_L``;
* the issue's hand derivation ``C_A = C_f k1 + ba s``, ``C_L = (1 + C_f)(kv + bv s) − C_f k1``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from seapass.errors import ExpressionError, ParameterError
from seapass.model.controller import (
    Controller,
    ControllerDerivation,
    ControllerKind,
    derive_controller,
)
from seapass.model.expr import STANDARD_SYMBOLS, S, parse_expression
from seapass.model.sea import SEA
from seapass.model.stiffness import derive_stiffness

POINTS = (0.7j, 3.1j, 17.0j, 250.0j, 2.5 + 40.0j, 0.3)
"""Complex frequencies where the diagram and the compiled controllers are compared."""


@dataclass(frozen=True)
class Blocks:
    """Random numeric blocks and plant, with their text and their value at any s."""

    kind: str
    cf: tuple[float, float, float, float]  # kp, ki, kd, N  (C_f = kp + ki/s + kd s/(1 + s/N))
    zv: tuple[float, float, float]  # kv, bv, mv
    cv: tuple[float, float]  # kvp, kvi
    ba: float | None
    feedforward: bool
    load_cell: bool  # sensor k1 + b1 s instead of k1
    plant: tuple[float, float, float, float, float]  # m, b, k1, b1, k2

    def controller(self) -> Controller:
        kp, ki, kd, n = self.cf
        force = f"{kp!r} + {ki!r}/s + {kd!r}*s/(1 + s/{n!r})"
        kv, bv, mv = self.zv
        imp = f"{kv!r} + {bv!r}*s + {mv!r}*s**2" if self.kind != "force" else None
        vel = f"{self.cv[0]!r} + {self.cv[1]!r}/s" if self.kind == "velocity-sourced" else None
        return Controller(
            kind=self.kind, force=force, impedance=imp, velocity=vel,
            damping=None if self.ba is None else repr(self.ba), feedforward=self.feedforward,
            sensor="k1 + b1*s" if self.load_cell else "k1",
        )  # fmt: skip

    def values(self, s: complex) -> dict[str, complex]:
        kp, ki, kd, n = self.cf
        kv, bv, mv = self.zv
        m, b, k1, b1, k2 = self.plant
        return {
            "Cf": kp + ki / s + kd * s / (1 + s / n),
            "Zv": kv + bv * s + mv * s**2,
            "Cv": self.cv[0] + self.cv[1] / s,
            "ba": 0.0 if self.ba is None else self.ba,
            "phi": 1.0 if self.feedforward else 0.0,
            "Ks": k1 + b1 * s if self.load_cell else k1,
            "alpha": m * s**2 + b * s,
            "D1": k1 + b1 * s,
            "D2": k2,
        }


def diagram_rows(blk: Blocks, s: complex) -> tuple[np.ndarray, np.ndarray]:
    """Rows ``A u = B [θ, x_L]`` of the controller's diagram, ``u = (x_A, f_d, f_s, v_d, f_A)``.

    Written from the block diagram alone (docs/controllers.md), not from seapass's code.
    """
    v = blk.values(s)
    rows, rhs = [], []
    # f_d = Z_v (θ − x_L), or an external command held at 0 (force control)
    if blk.kind == "force":
        rows.append([0, 1, 0, 0, 0]), rhs.append([0, 0])
    else:
        rows.append([0, 1, 0, 0, 0]), rhs.append([v["Zv"], -v["Zv"]])
    # f_s = K_s (x_A − x_L)
    rows.append([-v["Ks"], 0, 1, 0, 0]), rhs.append([0, -v["Ks"]])
    damp = v["ba"] * s  # b_a s (θ − x_A)
    if blk.kind == "velocity-sourced":
        # v_d = C_f (f_d − f_s);  f_A = φ f_d + C_v (v_d + s (θ − x_A)) + b_a s (θ − x_A)
        rows.append([0, -v["Cf"], v["Cf"], 1, 0]), rhs.append([0, 0])
        rows.append([v["Cv"] * s + damp, -v["phi"], 0, -v["Cv"], 1])
        rhs.append([v["Cv"] * s + damp, 0])
    else:
        # v_d unused (= 0);  f_A = φ f_d + C_f (f_d − f_s) + b_a s (θ − x_A)
        rows.append([0, 0, 0, 1, 0]), rhs.append([0, 0])
        rows.append([damp, -(v["phi"] + v["Cf"]), v["Cf"], 0, 1]), rhs.append([damp, 0])
    return np.array(rows, dtype=complex), np.array(rhs, dtype=complex)


def diagram_port(blk: Blocks, s: complex) -> complex:
    """``F_L/X_L`` of the diagram coupled to the plant (θ = 0, x_L = 1), by numpy."""
    v = blk.values(s)
    a, bm = diagram_rows(blk, s)
    # actuator: α x_A = f_A + D1 (x_L − x_A)
    plant = np.array([[v["alpha"] + v["D1"], 0, 0, 0, -1]], dtype=complex)
    mat = np.vstack([a, plant])
    rhs = np.concatenate([bm @ np.array([0, 1]), [v["D1"]]])
    x_a = np.linalg.solve(mat, rhs)[0]
    return complex(v["D1"] * (1 - x_a) + v["D2"])


def diagram_tracking(blk: Blocks, s: complex, load_mass: float) -> complex:
    """``X_L/Θ`` of the diagram with a load mass at the port, by numpy."""
    v = blk.values(s)
    a, bm = diagram_rows(blk, s)
    # unknowns (x_A, f_d, f_s, v_d, f_A, x_L); θ = 1
    mat = np.zeros((6, 6), dtype=complex)
    mat[:4, :5], mat[:4, 5] = a, -bm[:, 1]
    rhs = np.zeros(6, dtype=complex)
    rhs[:4] = bm[:, 0]
    mat[4] = [v["alpha"] + v["D1"], 0, 0, 0, -1, -v["D1"]]  # actuator
    mat[5] = [-v["D1"], 0, 0, 0, 0, load_mass * s**2 + v["D1"] + v["D2"]]  # load mass
    return complex(np.linalg.solve(mat, rhs)[5])


def compiled(d: ControllerDerivation, blk: Blocks, s: complex) -> tuple[complex, complex]:
    """``C_A(s)``, ``C_L(s)`` of the compiled text, the plant's values put in."""
    _, _, k1, b1, _ = blk.plant
    subs = {sp.Symbol(n, positive=True): sp.Rational(v) for n, v in
            dict(k1=k1, b1=b1).items()}  # fmt: skip
    ca, cl = (parse_expression(t).xreplace(subs).subs(S, s) for t in (d.CA, d.CL))
    return complex(sp.N(ca, 30)), complex(sp.N(cl, 30))


def compiled_port(d: ControllerDerivation, blk: Blocks, s: complex) -> complex:
    """``F_L/X_L`` of the compiled C_A, C_L (the free-body solution of ``seapass.model.stiffness``:
    ``[D1 (α + C_A) + D2 (α + C_A + D1) + D1 C_L] / (α + C_A + D1)``)."""
    m, b, k1, b1, k2 = blk.plant
    ca, cl = compiled(d, blk, s)
    alpha, d1 = m * s**2 + b * s, k1 + b1 * s
    return (d1 * (alpha + ca) + k2 * (alpha + ca + d1) + d1 * cl) / (alpha + ca + d1)


def compiled_tracking(
    d: ControllerDerivation, blk: Blocks, s: complex, load_mass: float
) -> complex:
    """``X_L/Θ`` of the free-body equations with ``f_A = C_A (θ − x_A) + C_L (θ − x_L)``."""
    m, b, k1, b1, k2 = blk.plant
    ca, cl = compiled(d, blk, s)
    alpha, d1 = m * s**2 + b * s, k1 + b1 * s
    # (α + D1 + C_A) x_A − (D1 − C_L) x_L = (C_A + C_L) θ;  −D1 x_A + (m_L s² + D1 + D2) x_L = 0
    mat = np.array([[alpha + d1 + ca, -(d1 - cl)], [-d1, load_mass * s**2 + d1 + k2]])
    return complex(np.linalg.solve(mat, np.array([ca + cl, 0]))[1])


_pos = st.floats(0.1, 50.0)
blocks = st.builds(
    Blocks,
    kind=st.sampled_from([k.value for k in ControllerKind]),
    cf=st.tuples(
        _pos,
        st.sampled_from([0.0, 3.0, 40.0]),
        st.sampled_from([0.0, 0.01, 0.2]),
        st.sampled_from([50.0, 500.0]),
    ),
    zv=st.tuples(st.floats(10.0, 3000.0), _pos, st.sampled_from([0.0, 0.05])),
    cv=st.tuples(st.floats(10.0, 500.0), st.sampled_from([0.0, 100.0, 2000.0])),
    ba=st.one_of(st.none(), _pos),
    feedforward=st.booleans(),
    load_cell=st.booleans(),
    plant=st.tuples(
        st.floats(0.1, 5.0),
        st.floats(0.0, 10.0),
        st.floats(100.0, 5000.0),
        st.floats(0.0, 20.0),
        st.sampled_from([0.0, 300.0]),
    ),
)


@settings(max_examples=40, deadline=None)
@given(blk=blocks)
def test_compiled_controllers_render_the_diagrams_port_stiffness(blk: Blocks) -> None:
    d = derive_controller(blk.controller())
    for s in POINTS:
        want = diagram_port(blk, s)
        got = compiled_port(d, blk, s)
        assert abs(got - want) <= 1e-8 * max(1.0, abs(want)), (s, got, want, d.CA, d.CL)


@settings(max_examples=40, deadline=None)
@given(blk=blocks, load_mass=st.floats(0.1, 20.0))
def test_compiled_controllers_track_like_the_diagram(blk: Blocks, load_mass: float) -> None:
    """The reference path too: every block acts on errors, so θ enters as C_A + C_L."""
    d = derive_controller(blk.controller())
    for s in POINTS:
        want = diagram_tracking(blk, s, load_mass)
        got = compiled_tracking(d, blk, s, load_mass)
        assert abs(got - want) <= 1e-8 * max(1.0, abs(want)), (s, got, want)


def test_cascaded_design_matches_a_sympy_free_body_solution() -> None:
    """The issue's cascade, every parameter symbolic: F_L/X_L solved by sympy from the
    free-body and block equations equals seapass's stiffness of the compiled C_A, C_L."""
    m, b, k1, b1, kp, ki, kv, bv, ba = sp.symbols("m b k1 b1 kp ki kv bv ba", positive=True)
    s = S
    x_a, f_a, f_d, f_s = sp.symbols("x_A f_A f_d f_s")
    x_l, theta = 1, 0
    cf = kp + ki / s
    eqs = [
        sp.Eq(f_d, (kv + bv * s) * (theta - x_l)),
        sp.Eq(f_s, k1 * (x_a - x_l)),
        sp.Eq(f_a, f_d + cf * (f_d - f_s) + ba * s * (theta - x_a)),
        sp.Eq((m * s**2 + b * s) * x_a, f_a + (k1 + b1 * s) * (x_l - x_a)),
    ]
    sol = sp.solve(eqs, [x_a, f_a, f_d, f_s], dict=True)[0]
    want = (k1 + b1 * s) * (x_l - sol[x_a])
    d = derive_controller(Controller(kind="impedance", force="kp + ki/s", impedance="kv + bv*s",
                                     damping="ba", feedforward=True))  # fmt: skip
    sea = SEA(D1="k1 + b1*s", CA=d.CA, CL=d.CL,
              values=dict(kp=None, kv=None, bv=None, ba=None))  # fmt: skip
    got = derive_stiffness(sea).stiffness
    assert sp.cancel(sp.together(got - want)) == 0


def test_the_issues_hand_derivation() -> None:
    d = derive_controller(Controller(kind="impedance", force="kp + ki/s", impedance="kv + bv*s",
                                     damping="ba", feedforward=True))  # fmt: skip
    assert d.general == {"CA": "C_f*K_s + b_a*s", "CL": "-C_f*K_s + Z_v*(C_f + 1)"}
    names = ["kp", "ki", "kv", "bv", "ba"]
    ca, cl = (parse_expression(t, [*STANDARD_SYMBOLS, *names]) for t in (d.CA, d.CL))
    kp, ki, kv, bv, ba, k1 = (sp.Symbol(n, positive=True) for n in (*names, "k1"))
    c_f = kp + ki / S
    assert sp.cancel(ca - (c_f * k1 + ba * S)) == 0
    assert sp.cancel(cl - ((1 + c_f) * (kv + bv * S) - c_f * k1)) == 0


@pytest.mark.parametrize(
    ("kind", "extra", "ca", "cl", "ref"),
    [
        ("force", {}, "C_f*K_s", "-C_f*K_s", "C_f"),
        ("force", {"feedforward": True}, "C_f*K_s", "-C_f*K_s", "C_f + 1"),
        ("impedance", {"impedance": "kv"}, "C_f*K_s", "C_f*(-K_s + Z_v)", None),
        ("velocity-sourced", {"impedance": "kv", "velocity": "kvp", "damping": "ba",
                              "feedforward": True},
         "C_v*(C_f*K_s + s) + b_a*s", "C_f*C_v*(-K_s + Z_v) + Z_v", None),
    ],
)  # fmt: skip
def test_general_forms(kind: str, extra: dict, ca: str, cl: str, ref: str | None) -> None:
    d = derive_controller(Controller(kind=kind, force="kp", **extra))
    assert (d.general["CA"], d.general["CL"]) == (ca, cl)
    assert (d.reference is None) == (ref is None)
    if ref is not None:
        assert d.reference == ref.replace("C_f", "kp")
    assert d.to_dict()["CA"] == d.CA and "C_A" in "\n".join(d.lines())
    assert repr(d).startswith("ControllerDerivation(kind=") and "<table>" in d._repr_html_()


def test_blocks_keep_the_users_text_and_numbers_exact() -> None:
    d = derive_controller(Controller(kind="impedance", force="kp + kd*s/(1 + 0.002*s)",
                                     impedance="kv + 0.1*s"))  # fmt: skip
    assert "0.002" in d.CA and "0.1*s" in d.CL
    ca = parse_expression(d.CA, [*STANDARD_SYMBOLS, "kp"])
    assert sp.Rational(1, 500) not in ca.atoms(sp.Rational)  # 0.002 is the double it denotes
    assert sp.Rational(0.002) in ca.atoms(sp.Rational)


def test_controller_round_trips_its_table() -> None:
    c = Controller(kind="velocity-sourced", force="kf", impedance="kv", velocity="kvp",
                   sensor="k1 + b1*s", feedforward=True)  # fmt: skip
    assert Controller.from_table(c.to_table()) == c
    assert c.kind is ControllerKind.VELOCITY_SOURCED
    assert (
        repr(Controller(kind="force", force="kp"))
        == "Controller(kind='force', force='kp', sensor='k1')"
    )


@pytest.mark.parametrize(
    ("kw", "arg", "words"),
    [
        ({"kind": "admittance", "force": "kp"}, "kind", "unknown controller kind"),
        ({"kind": "impedance", "force": "kp"}, "impedance", "needs the target impedance"),
        ({"kind": "velocity-sourced", "force": "kp", "impedance": "kv"}, "velocity",
         "needs the motor-velocity loop"),
        ({"kind": "force", "force": "kp", "impedance": "kv"}, "impedance", "has no target"),
        ({"kind": "impedance", "force": "kp", "impedance": "kv", "velocity": "kvp"}, "velocity",
         "belongs to kind 'velocity-sourced'"),
        ({"kind": "force", "force": "  "}, "force", "expected an expression"),
        ({"kind": "force", "force": "kp", "feedforward": 1}, "feedforward", "true or false"),
    ],
)  # fmt: skip
def test_bad_controllers_name_the_argument(kw: dict, arg: str, words: str) -> None:
    with pytest.raises(ParameterError, match=words) as err:
        Controller(**kw)
    assert err.value.argument == arg


@pytest.mark.parametrize(
    ("kw", "arg", "words"),
    [
        ({"force": "kp + kd*s"}, "force", "improper"),
        ({"force": "kp", "damping": "ba*s"}, "damping", "improper"),
        ({"force": "kp", "sensor": "k1*s**2"}, "sensor", "at most 1"),
        ({"force": "kp + ki/"}, "force", "cannot parse"),
        ({"force": "exp(s)"}, "force", "function call"),
    ],
)
def test_bad_blocks_name_the_block(kw: dict, arg: str, words: str) -> None:
    with pytest.raises(ExpressionError, match=words) as err:
        derive_controller(Controller(kind="force", **kw))
    assert err.value.argument == arg and str(err.value).startswith(f"{arg}: ")


def test_a_block_missing_its_gain() -> None:
    c = Controller(kind="impedance", force="kp + ki/s", impedance="kv + bv*s")
    with pytest.raises(ExpressionError, match=r"impedance: unknown symbol 'bv'.*values=\{'bv'"):
        derive_controller(c, parameters=["kp", "kv"])
    assert derive_controller(c, parameters=["kp", "kv", "bv"]).CA == "(kp + ki/s)*k1"
