"""course_dynamics/core/forward_dynamics.py: (6.115) against Pinocchio's aba, singular mass matrices and terms that
overflow."""
from __future__ import annotations

import numpy as np
import pytest
from helpers import arm_urdf, assert_agrees

from course_dynamics import inverse_dynamics, load_robot, load_urdf
from course_dynamics.base.errors import StateError
from course_dynamics.core.forward_dynamics import (
    SingularMassMatrixError,
    forward_dynamics,
    solve,
)
from course_dynamics.core.friction import Friction


def test_forward_dynamics_agrees_with_aba(robot):
    name, model, oracle, (q, qd, tau) = robot
    batch = forward_dynamics(model, q, qd, tau)
    for k in range(len(q)):
        ref = oracle.aba(q[k], qd[k], tau[k])
        assert_agrees(forward_dynamics(model, q[k], qd[k], tau[k]), ref, what=f"{name} qdd, state {k}")
        assert_agrees(batch[k], ref, what=f"{name} batched qdd, state {k}")


def test_forward_then_inverse_is_identity(robot):
    name, model, _, (q, qd, tau) = robot
    friction = Friction(viscous=np.full(model.n, 0.3), coulomb=np.full(model.n, 0.2))
    qdd = forward_dynamics(model, q, qd, tau, friction)
    recovered = inverse_dynamics(model, q, qd, qdd) + friction.torques(qd)  # (6.114)
    np.testing.assert_allclose(recovered, tau, rtol=1e-10, atol=1e-10)


def test_massless_chain_is_a_clear_error(tmp_path):
    path = tmp_path / "massless.urdf"
    path.write_text(arm_urdf(mass="0", ixx="0", iyy="0", izz="0"))
    model = load_urdf(path)
    with pytest.raises(SingularMassMatrixError, match="joint 'joint2' moves no mass"):
        forward_dynamics(model, [0.1, 0.2], [0, 0], [0, 0])
    with pytest.raises(SingularMassMatrixError):
        forward_dynamics(model, np.zeros((3, 2)), np.zeros((3, 2)), np.zeros((3, 2)))


def test_terms_that_overflow_are_named_as_such_not_as_a_singular_mass_matrix():
    """A finite state whose M or torques are not finite in float64: the state is named, singularity is not claimed."""
    model = load_robot("two_link")
    with pytest.raises(StateError, match="robot 'two_link' overflow at q = \\[0.0, 0.5\\]: M"):
        solve(model, np.full((2, 2), np.nan), np.ones(2), np.array([0.0, 0.5]))
    states = np.array([[0.1, 0.2], [0.3, 0.4]])
    with pytest.raises(StateError, match="at q = \\[0.3, 0.4\\]"):
        solve(model, np.stack([np.eye(2), np.eye(2)]), np.array([[1.0, 1.0], [np.inf, 1.0]]), states)
    with pytest.raises(StateError, match="overflow"), np.errstate(over="ignore"):
        forward_dynamics(model, [0.0, 0.5], [-1.0, -1.0], [1e308, 1e308],
                         Friction(viscous=[0.0, 0.0], coulomb=[1e308, 1e308]))
