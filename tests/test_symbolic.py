"""course_dynamics/core/symbolic.py (and the exact models of core/parameters.py): closed forms, two derivations
that agree, and Craig's printed results."""
from __future__ import annotations

import numpy as np
import pytest
import sympy
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states
from helpers import derivation

from course_dynamics import load_robot
from course_dynamics.core.robots import robot_path
from course_dynamics.core.parameters import SymbolError, parameter_values, symbolic_model
from course_dynamics.core.symbolic import canonical, derive, numeric_functions

NOTES_SYMBOLS = {
    "two_link": ("m1", "m2", "l1", "l2", "g"),
    "rp_arm": ("m1", "m2", "l1", "Izz1", "Izz2", "g"),
    "pendulum": ("m", "l", "g"),
    "rrr_arm": (),
}


@pytest.fixture(scope="module", params=sorted(NOTES_SYMBOLS))
def derivations(request):
    name, symbols = request.param, NOTES_SYMBOLS[request.param]
    return name, load_robot(name), derivation(name, symbols, "newton-euler"), derivation(name, symbols, "lagrange")


def assert_same(a, b, angles):
    assert sympy.expand(canonical(a, angles) - canonical(b, angles)) == 0, (a, b)


def test_newton_euler_and_lagrange_give_identical_expressions(derivations):
    name, model, ne, lg = derivations
    for key in ("tau", "V", "G"):
        for a, b in zip(getattr(ne, key), getattr(lg, key)):
            assert_same(a, b, ne.q)
    for row_a, row_b in zip(ne.M + ne.B + ne.C, lg.M + lg.B + lg.C):
        for a, b in zip(row_a, row_b):
            assert_same(a, b, ne.q)


def test_split_rebuilds_tau(derivations):
    """τ = M Θ̈ + B[Θ̇Θ̇] + C[Θ̇²] + G (6.63)."""
    name, model, ne, _ = derivations
    n = model.n
    for i in range(n):
        rebuilt = (sum(ne.M[i][j] * ne.qdd[j] for j in range(n)) + sum(ne.B[i][p] * ne.qd[j] * ne.qd[k] for p, (j, k) in enumerate(ne.pairs))
                   + sum(ne.C[i][j] * ne.qd[j] ** 2 for j in range(n)) + ne.G[i])
        assert_same(rebuilt, ne.tau[i], ne.q)


def test_two_link_is_craig_6_60_to_6_63_with_symbols():
    d = derivation("two_link", NOTES_SYMBOLS["two_link"])
    m1, m2, l1, l2, g = (d.parameters[k] for k in ("m1", "m2", "l1", "l2", "g"))
    t1, t2 = d.q
    td1, td2 = d.qd
    s2, c2, c1, c12 = sympy.sin(t2), sympy.cos(t2), sympy.cos(t1), sympy.cos(t1 + t2)
    M = [[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), l2**2 * m2 + l1 * l2 * m2 * c2],
         [l2**2 * m2 + l1 * l2 * m2 * c2, l2**2 * m2]]  # (6.60)
    V = [-m2 * l1 * l2 * s2 * td2**2 - 2 * m2 * l1 * l2 * s2 * td1 * td2, m2 * l1 * l2 * s2 * td1**2]  # (6.61)
    G = [m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12]  # (6.62)
    B = [[-2 * m2 * l1 * l2 * s2], [0]]  # (6.63) for the two-link arm
    C = [[0, -m2 * l1 * l2 * s2], [m2 * l1 * l2 * s2, 0]]
    for ours, craig in [(d.M, M), (d.B, B), (d.C, C), ([d.V], [V]), ([d.G], [G])]:
        for row_o, row_c in zip(ours, craig):
            for a, b in zip(row_o, row_c):
                assert sympy.simplify(a - b) == 0, (a, b)


def test_rp_arm_is_craig_example_6_5_with_symbols():
    d = derivation("rp_arm", NOTES_SYMBOLS["rp_arm"], "lagrange")
    m1, m2, l1, Izz1, Izz2, g = (d.parameters[k] for k in ("m1", "m2", "l1", "Izz1", "Izz2", "g"))
    t1, d2 = d.q
    td1, dd2 = d.qd
    tdd1, ddd2 = d.qdd
    tau1 = (m1 * l1**2 + Izz1 + Izz2 + m2 * d2**2) * tdd1 + 2 * m2 * d2 * dd2 * td1 + (m1 * l1 + m2 * d2) * g * sympy.cos(t1)
    tau2 = m2 * ddd2 - m2 * d2 * td1**2 + m2 * g * sympy.sin(t1)
    assert sympy.simplify(d.tau[0] - tau1) == 0
    assert sympy.simplify(d.tau[1] - tau2) == 0


def test_pendulum_is_the_notes_equation():
    d = derivation("pendulum", NOTES_SYMBOLS["pendulum"])
    m, l, g = (d.parameters[k] for k in ("m", "l", "g"))
    (theta,), (theta_ddot,) = d.q, d.qdd
    assert sympy.simplify(d.tau[0] - (m * l**2 * theta_ddot + m * g * l * sympy.sin(theta))) == 0


@pytest.mark.parametrize("name", ["two_link", "rp_arm", "pendulum", "rrr_arm"])
def test_generated_functions_agree_with_pinocchio(name):
    model = load_robot(name)
    d = derivation(name, NOTES_SYMBOLS[name])
    functions = numeric_functions(d, {k: parameter_values(model)[k if k in parameter_values(model) else k + "1"]
                                      for k in NOTES_SYMBOLS[name]})
    oracle = PinocchioOracle(robot_path(name), model.joint_names)
    q, qd, qdd = random_states(model, 200, seed=9)
    M, V, G, tau = functions["M"](q), functions["V"](q, qd), functions["G"](q), functions["tau"](q, qd, qdd)
    assert M.shape == (200, model.n, model.n) and tau.shape == (200, model.n)
    for k in range(len(q)):
        scale = np.abs(oracle.M(q[k])).max()
        np.testing.assert_allclose(M[k], oracle.M(q[k]), rtol=1e-9, atol=1e-9 * scale)
        np.testing.assert_allclose(V[k], oracle.V(q[k], qd[k]), rtol=1e-9, atol=1e-9 * scale * (1 + np.abs(qd[k]).max() ** 2))
        np.testing.assert_allclose(G[k], oracle.G(q[k]), rtol=1e-9, atol=1e-9 * scale)
        np.testing.assert_allclose(tau[k], oracle.tau(q[k], qd[k], qdd[k]), rtol=1e-9, atol=1e-9 * scale * 10)


def test_parameter_names_and_errors():
    two_link = load_robot("two_link")
    assert parameter_values(two_link) == {"m1": 2.0, "l1": 0.5, "lc1": 0.5, "m2": 1.0, "l2": 0.4, "lc2": 0.4, "g": 9.81}
    model, table = symbolic_model(two_link, ("l1",))
    assert model.bodies[0].p_com[0] == table["l1"] and model.bodies[1].P[0] == table["l1"]
    with pytest.raises(SymbolError, match="unknown symbol 'm3' for robot 'two_link'; known: g, l1, l2, lc1, lc2, m1, m2"):
        symbolic_model(two_link, ("m3",))
    with pytest.raises(SymbolError, match="robot 'ur5' has 6 joints; the symbolic path handles at most 4"):
        derive(load_robot("ur5"))
    with pytest.raises(SymbolError, match="give values for the parameter symbols m1"):
        numeric_functions(derive(two_link, ("m1",)))


def test_centre_of_mass_symbols_keep_length_and_com_apart():
    """lc<i> replaces ⁱP_Cᵢ alone: Craig's two-link arm with its masses off the tips."""
    d = derivation("two_link", ("m1", "m2", "l1", "l2", "lc1", "lc2", "g"))
    m1, m2, l1, l2, lc1, lc2, g = (d.parameters[k] for k in ("m1", "m2", "l1", "l2", "lc1", "lc2", "g"))
    t1, t2 = d.q
    expected_M11 = m1 * lc1**2 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * sympy.cos(t2))
    expected_G1 = m1 * g * lc1 * sympy.cos(t1) + m2 * g * (l1 * sympy.cos(t1) + lc2 * sympy.cos(t1 + t2))
    assert sympy.simplify(d.M[0][0] - expected_M11) == 0
    assert sympy.simplify(d.G[0] - expected_G1) == 0
    assert parameter_values(load_robot("two_link"))["lc1"] == 0.5


def test_decimals_make_real_robots_readable():
    exact = derivation("rrr_arm", ())
    rounded = derive(load_robot("rrr_arm"), (), decimals=4)
    assert any(isinstance(a, sympy.Rational) and a.q > 1000 for a in sympy.sympify(exact.G[1]).atoms(sympy.Rational))
    assert not [a for a in sympy.sympify(rounded.G[1]).atoms(sympy.Rational) if not a.is_Integer]
    values = {q: 0.3 for q in exact.q}
    assert float(sympy.sympify(rounded.G[1]).subs(values)) == pytest.approx(float(sympy.sympify(exact.G[1]).subs(values)),
                                                                          rel=1e-3)
    with pytest.raises(SymbolError, match="decimals must be a whole number"):
        derive(load_robot("pendulum"), (), decimals=0)


def test_cartesian_closed_forms_are_craig_example_6_6():
    """M_x = diag(m2 + m1/s2², m2) (6.101), V_x (6.102), G_x (6.103): the two-link arm in its tool frame."""
    from course_dynamics_reference import textbook

    from course_dynamics.core.symbolic import derive_cartesian

    d = derive_cartesian(load_robot("two_link"), "tool", rows=["x", "y"], expressed_in="frame",
                         symbols=("m1", "m2", "l1", "l2", "g"))
    m1, m2, l1, l2, g = (d.parameters[k] for k in ("m1", "m2", "l1", "l2", "g"))
    t1, t2 = d.q
    assert sympy.simplify(d.J - sympy.Matrix([[l1 * sympy.sin(t2), 0], [l1 * sympy.cos(t2) + l2, l2]])) == sympy.zeros(2)
    assert sympy.simplify(d.Mx - sympy.diag(m2 + m1 / sympy.sin(t2) ** 2, m2)) == sympy.zeros(2)
    numbers = {m1: 2.0, m2: 1.0, l1: 0.5, l2: 0.4, g: 9.81, t1: 0.4, t2: 0.9, d.qd[0]: 0.7, d.qd[1]: -1.2}
    _, Mx, Vx, Gx = textbook.two_link_cartesian([0.4, 0.9], [0.7, -1.2], **textbook.COURSE_PARAMETERS["two_link"])
    np.testing.assert_allclose(np.array(d.Vx.subs(numbers), dtype=float).ravel(), Vx, rtol=1e-12)
    np.testing.assert_allclose(np.array(d.Gx.subs(numbers), dtype=float).ravel(), Gx, rtol=1e-12)
