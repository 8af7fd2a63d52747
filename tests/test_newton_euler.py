"""course_dynamics/core/newton_euler.py: τ by Craig's iterations against Pinocchio's rnea."""
from __future__ import annotations

import numpy as np
import pytest
from helpers import assert_agrees

from course_dynamics import inverse_dynamics, load_robot, newton_euler_links
from course_dynamics.core.state import StateError


def test_tau_agrees_with_pinocchio_rnea(robot):
    name, model, oracle, (q, qd, qdd) = robot
    for k in range(len(q)):
        ref = oracle.tau(q[k], qd[k], qdd[k])
        scale = np.abs(oracle.M(q[k])).max() * (np.abs(qdd[k]).max() + np.abs(qd[k]).max() ** 2)
        assert_agrees(inverse_dynamics(model, q[k], qd[k], qdd[k]), ref, scale, what=f"{name} tau, state {k}")


def test_batch_equals_single_states(robot):
    name, model, _, (q, qd, qdd) = robot
    batch = inverse_dynamics(model, q, qd, qdd)
    assert batch.shape == q.shape
    single = np.array([inverse_dynamics(model, q[k], qd[k], qdd[k]) for k in range(len(q))])
    np.testing.assert_allclose(batch, single, rtol=1e-13, atol=1e-12)


def test_gravity_argument_overrides_model_gravity():
    arm = load_robot("pendulum")
    zero_g = inverse_dynamics(arm.with_gravity([0.0, 0.0, 0.0]), [0.5], [0.0], [0.0])
    assert zero_g[0] == 0.0
    assert inverse_dynamics(arm, [0.5], [0.0], [0.0])[0] > 0  # holding the bob up against gravity


def test_link_quantities_are_consistent_with_tau(robot):
    name, model, oracle, (q, qd, qdd) = robot
    links = newton_euler_links(model, q[0], qd[0], qdd[0])
    assert links.omega.shape == (model.n_bodies, 3)
    scale = np.abs(oracle.M(q[0])).max() * (np.abs(qdd[0]).max() + np.abs(qd[0]).max() ** 2)
    # τ = Sᵀ τ_bodies: a mimic joint's own torque maps onto its leader's coordinate
    assert_agrees(model.S.T @ links.tau, oracle.tau(q[0], qd[0], qdd[0]), scale, what=f"{name} link-by-link tau")
    # (6.49): ⁱFᵢ = mᵢ ⁱv̇_Cᵢ, body by body
    masses = np.array([b.mass for b in model.bodies])
    np.testing.assert_allclose(links.F, masses[:, None] * links.v_dot_c, rtol=1e-14, atol=1e-14)
    # (6.44)/(6.53): τᵢ is the axis component of ⁱnᵢ (revolute) or ⁱfᵢ (prismatic)
    for i, body in enumerate(model.bodies):
        load = links.f[i] if body.is_prismatic else links.n[i]
        assert links.tau[i] == pytest.approx(load @ body.axis, rel=1e-14, abs=1e-14)


def test_two_link_worked_example_link_by_link():
    """The notes' section 6.7 example, the quantities as Craig derives them by hand."""
    arm = load_robot("two_link")
    m2, l1, g = 1.0, 0.5, 9.81  # robots/two_link.urdf
    t1, t2, td1, td2, tdd1, tdd2 = 0.3, -0.8, 1.1, 0.6, -0.4, 0.9
    links = newton_euler_links(arm, [t1, t2], [td1, td2], [tdd1, tdd2])
    s1, c1, s2, c2 = np.sin(t1), np.cos(t1), np.sin(t2), np.cos(t2)
    # ¹v̇₁ = ¹₀R (0, g, 0) = (g s1, g c1, 0)
    np.testing.assert_allclose(links.v_dot[0], [g * s1, g * c1, 0], atol=1e-12)
    # ¹v̇_C1 = (−l1 θ̇1² + g s1, l1 θ̈1 + g c1, 0): Craig's result (the notes print g s1 in y: a misprint)
    np.testing.assert_allclose(links.v_dot_c[0], [-l1 * td1**2 + g * s1, l1 * tdd1 + g * c1, 0], atol=1e-12)
    np.testing.assert_allclose(links.omega[1], [0, 0, td1 + td2], atol=1e-15)
    np.testing.assert_allclose(links.omega_dot[1], [0, 0, tdd1 + tdd2], atol=1e-15)
    # ²v̇₂ = ²₁R ¹v̇_C1 (the COM of link 1 is the origin of frame 2)
    R21 = np.array([[c2, s2, 0], [-s2, c2, 0], [0, 0, 1]])
    np.testing.assert_allclose(links.v_dot[1], R21 @ links.v_dot_c[0], atol=1e-12)
    np.testing.assert_allclose(links.N, 0, atol=1e-15)  # point masses: no moments
    np.testing.assert_allclose(links.F[1], m2 * links.v_dot_c[1], atol=1e-12)


@pytest.mark.parametrize("bad, message", [
    ([0.1], "has 1 values but robot 'two_link' has 2 joints"),
    ([0.1, float("nan")], "joint 'theta2' is nan"),
    ([0.1, float("inf")], "joint 'theta2' is inf"),
    (["a", "b"], "must be numbers"),
])
def test_bad_state_is_a_clear_error(bad, message):
    arm = load_robot("two_link")
    with pytest.raises(StateError, match=message):
        inverse_dynamics(arm, bad, [0, 0], [0, 0])
