"""reference/textbook.py: the course robots against Craig's closed forms, and the URDFs against their parameters."""
from __future__ import annotations

import numpy as np
import pytest
import sympy
from course_dynamics_reference import textbook
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states

from course_dynamics import (
    gravity_torques,
    inverse_dynamics,
    load_robot,
    mass_matrix,
    velocity_torques,
)
from course_dynamics.core.robots import robot_path
from course_dynamics.core.parameters import joint_symbols, rationalize

CLOSED_FORMS = {"two_link": textbook.two_link, "rp_arm": textbook.rp_arm, "pendulum": textbook.pendulum}


@pytest.mark.parametrize("name", sorted(CLOSED_FORMS))
def test_course_robot_matches_closed_form(name):
    model = load_robot(name)
    closed_form = CLOSED_FORMS[name]
    params = textbook.COURSE_PARAMETERS[name]
    q, qd, qdd = random_states(model, 200, seed=11)
    M, V, G = mass_matrix(model, q), velocity_torques(model, q, qd), gravity_torques(model, q)
    tau = inverse_dynamics(model, q, qd, qdd)
    for k in range(len(q)):
        M_ref, V_ref, G_ref = closed_form(q[k], qd[k], **params)
        np.testing.assert_allclose(M[k], M_ref, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(V[k], V_ref, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(G[k], G_ref, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(tau[k], M_ref @ qdd[k] + V_ref + G_ref, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("name", sorted(CLOSED_FORMS))
def test_closed_forms_agree_with_pinocchio(name):
    """The oracle's two paths agree with each other, so the URDFs encode the documented parameters."""
    path = robot_path(name)
    model = load_robot(name)
    oracle = PinocchioOracle(path, model.joint_names)
    q, qd, _ = random_states(model, 20, seed=3)
    for k in range(len(q)):
        M_ref, V_ref, G_ref = CLOSED_FORMS[name](q[k], qd[k], **textbook.COURSE_PARAMETERS[name])
        np.testing.assert_allclose(oracle.M(q[k]), M_ref, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(oracle.V(q[k], qd[k]), V_ref, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(oracle.G(q[k]), G_ref, rtol=1e-12, atol=1e-12)


def test_symbolic_two_link_is_craig_6_60_to_6_62():
    """The Newton–Euler recursion on sympy symbols simplifies to (6.60)–(6.62), exactly."""
    model = rationalize(load_robot("two_link"))
    q, qd, qdd = joint_symbols(model)
    tau = inverse_dynamics(model, q, qd, qdd)
    m1, m2, l1, l2, g = (sympy.nsimplify(textbook.COURSE_PARAMETERS["two_link"][k]) for k in ("m1", "m2", "l1", "l2", "g"))
    t1, t2 = q
    td1, td2 = qd
    tdd1, tdd2 = qdd
    c1, c2, s2, c12 = sympy.cos(t1), sympy.cos(t2), sympy.sin(t2), sympy.cos(t1 + t2)
    tau1 = (m2 * l2**2 * (tdd1 + tdd2) + m2 * l1 * l2 * c2 * (2 * tdd1 + tdd2) + (m1 + m2) * l1**2 * tdd1
            - m2 * l1 * l2 * s2 * td2**2 - 2 * m2 * l1 * l2 * s2 * td1 * td2
            + m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1)  # (6.59) with (6.60)–(6.62)
    tau2 = m2 * l1 * l2 * c2 * tdd1 + m2 * l1 * l2 * s2 * td1**2 + m2 * l2 * g * c12 + m2 * l2**2 * (tdd1 + tdd2)  # (6.59)
    for ours, craig in zip(tau, (tau1, tau2)):
        assert sympy.simplify(sympy.expand_trig(ours - craig)) == 0


def test_symbolic_terms_evaluated_agree_with_pinocchio():
    """M and C from symbols, evaluated at a state, equal Pinocchio's crba and Coriolis matrix."""
    from course_dynamics import coriolis_matrix

    numeric = load_robot("rp_arm")
    model = rationalize(numeric)
    q, qd, _ = joint_symbols(model)
    M = sympy.Matrix(mass_matrix(model, q))
    C = sympy.Matrix(coriolis_matrix(model, q, qd))
    oracle = PinocchioOracle(robot_path("rp_arm"), numeric.joint_names)
    values = {q[0]: 0.4, q[1]: 0.5, qd[0]: -1.2, qd[1]: 0.7}
    np.testing.assert_allclose(np.array(M.subs(values), dtype=float), oracle.M([0.4, 0.5]), rtol=1e-12)
    np.testing.assert_allclose(np.array(C.subs(values), dtype=float), oracle.C([0.4, 0.5], [-1.2, 0.7]), rtol=1e-12,
                               atol=1e-15)
