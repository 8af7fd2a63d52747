"""course_dynamics/core/crba.py: the composite-rigid-body M against Pinocchio's crba, Craig's definition and (6.60)."""
from __future__ import annotations

import numpy as np
import sympy
from helpers import assert_agrees

from course_dynamics import load_robot
from course_dynamics.core import crba
from course_dynamics.core.dynamics import mass_matrix_by_unit_accelerations
from course_dynamics.core.parameters import joint_symbols, symbolic_model


def test_agrees_with_pinocchio_crba(robot):
    name, model, oracle, (q, _, _) = robot
    M = crba.mass_matrix(model, q)
    for k in range(len(q)):
        assert_agrees(M[k], oracle.M(q[k]), what=f"{name} CRBA M, state {k}")


def test_equals_craigs_definition_by_unit_accelerations(robot):
    """Column j of M is τ(Θ, 0, eⱼ) at g = 0 (Craig section 6.8): the two routes agree."""
    name, model, _, (q, _, _) = robot
    np.testing.assert_allclose(crba.mass_matrix(model, q), mass_matrix_by_unit_accelerations(model, q),
                               rtol=1e-12, atol=1e-13)


def test_one_state_equals_the_batch(robot):
    name, model, _, (q, _, _) = robot
    batch = crba.mass_matrix(model, q[:10])
    for k in range(10):
        np.testing.assert_allclose(crba.mass_matrix(model, q[k]), batch[k], rtol=1e-14, atol=1e-15)


def test_symbolic_two_link_is_craig_6_60():
    model, p = symbolic_model(load_robot("two_link"), ("m1", "m2", "l1", "l2"))
    q, _, _ = joint_symbols(model)
    M = crba.mass_matrix(model, q)
    m1, m2, l1, l2 = (p[k] for k in ("m1", "m2", "l1", "l2"))
    c2 = sympy.cos(q[1])
    craig = [[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), l2**2 * m2 + l1 * l2 * m2 * c2],
             [l2**2 * m2 + l1 * l2 * m2 * c2, l2**2 * m2]]  # (6.60)
    for i in range(2):
        for j in range(2):
            assert sympy.simplify(M[i, j] - craig[i][j]) == 0, (i, j, M[i, j])
