"""course_dynamics/core/cartesian.py: J and J̇ against Pinocchio's frame Jacobians, (6.99) against Pinocchio and example 6.6."""
from __future__ import annotations

import numpy as np
import pytest
from course_dynamics_reference import textbook
from course_dynamics_reference.validate import random_states
from helpers import assert_agrees, tip_frame, urdf_of

from course_dynamics import load_robot
from course_dynamics.core.cartesian import (
    ROW_NAMES,
    SingularityError,
    cartesian_dynamics,
    jacobian,
    jacobian_dot,
)


@pytest.mark.parametrize("expressed_in", ["base", "frame"])
def test_jacobian_and_its_derivative_agree_with_pinocchio(robot, expressed_in):
    name, model, oracle, (q, qd, _) = robot
    frame = tip_frame(model)
    J, J_dot = jacobian(model, q, frame, expressed_in), jacobian_dot(model, q, qd, frame, expressed_in)
    for k in range(len(q)):
        J_ref = oracle.frame_jacobian(q[k], frame, expressed_in)
        assert_agrees(J[k], J_ref, what=f"{name} J({frame}), state {k}")
        scale = np.abs(J_ref).max() * np.abs(qd[k]).max()
        assert_agrees(J_dot[k], oracle.frame_jacobian_dot(q[k], qd[k], frame, expressed_in), scale, what=f"{name} J_dot, state {k}")


def test_every_frame_of_ur5_agrees_with_pinocchio():
    from course_dynamics_reference.pinocchio_oracle import PinocchioOracle

    from course_dynamics import robot_path

    model = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), model.joint_names)
    q, _, _ = random_states(model, 5, seed=1)
    for frame in model.frame_names:
        assert_agrees(jacobian(model, q[0], frame), oracle.frame_jacobian(q[0], frame), 1.0, what=frame)


SQUARE_TASKS = {  # robot: (frame, rows in base coordinates) giving a square Jacobian
    "two_link": ("tool", ["x", "z"]),  # Craig's X0-Y0 plane is the world X-Z plane
    "rp_arm": ("link2", ["x", "z"]),
    "ur5": ("tool0", None),
    "double_pendulum": ("link2", ["y", "rx"]),  # link2's origin lies on joint 2's axis
}  # a tree (awkward.urdf) has no single frame that every joint moves, so no square task


@pytest.mark.parametrize("name", sorted(SQUARE_TASKS))
def test_cartesian_terms_from_pinocchio_quantities(name):
    """Mx = J⁻ᵀ M J⁻¹ equals (J M⁻¹ Jᵀ)⁻¹ built from Pinocchio's J and M; Vx, Gx likewise."""
    from course_dynamics_reference.pinocchio_oracle import PinocchioOracle

    from course_dynamics import load_urdf

    model = load_urdf(urdf_of(name))
    oracle = PinocchioOracle(urdf_of(name), model.joint_names)
    q, qd, _ = random_states(model, 200, seed=5)
    frame, rows = SQUARE_TASKS[name]
    select = list(range(6)) if rows is None else ["x", "y", "z", "rx", "ry", "rz"]
    indices = select if rows is None else [select.index(r) for r in rows]
    checked = 0
    for k in range(len(q)):
        J = oracle.frame_jacobian(q[k], frame)[indices]
        if np.linalg.cond(J) > 1e6:
            continue  # near a singularity (6.99) is ill-conditioned by nature
        checked += 1
        M = oracle.M(q[k])
        # Both sides invert J: round-off grows with cond(J). Measured errors stay below 2e-14 · cond(J);
        # the tolerance is 1e-13 · cond(J).
        rtol = 1e-13 * np.linalg.cond(J)
        terms = cartesian_dynamics(model, q[k], qd[k], frame, rows=rows)
        Mx_ref = np.linalg.inv(J @ np.linalg.solve(M, J.T))
        assert_agrees(terms.Mx, Mx_ref, rtol=rtol, what=f"{name} Mx, state {k}")
        J_inv_T = np.linalg.inv(J).T
        J_dot = oracle.frame_jacobian_dot(q[k], qd[k], frame)[indices]
        Vx_ref = J_inv_T @ (oracle.V(q[k], qd[k]) - M @ np.linalg.solve(J, J_dot @ qd[k]))
        Gx_ref = J_inv_T @ oracle.G(q[k])
        scale = np.abs(Mx_ref).max() * (1 + np.abs(qd[k]).max() ** 2)
        assert_agrees(terms.Vx, Vx_ref, scale, rtol=rtol, what=f"{name} Vx, state {k}")
        assert_agrees(terms.Gx, Gx_ref, scale, rtol=rtol, what=f"{name} Gx, state {k}")
    assert checked >= 150, f"{name}: only {checked} well-conditioned states"


def test_two_link_is_craig_example_6_6():
    model = load_robot("two_link")
    params = textbook.COURSE_PARAMETERS["two_link"]
    q, qd, qdd = random_states(model, 200, seed=66)
    for k in range(len(q)):
        if abs(np.sin(q[k][1])) < 0.05:
            continue  # s2 = 0 is the singularity of example 6.6
        J, Mx, Vx, Gx = textbook.two_link_cartesian(q[k], qd[k], **params)
        terms = cartesian_dynamics(model, q[k], qd[k], "tool", expressed_in="frame", rows=["x", "y"])
        np.testing.assert_allclose(terms.J, J, rtol=1e-12, atol=1e-13)
        np.testing.assert_allclose(terms.Mx, Mx, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(terms.Vx, Vx, rtol=1e-10, atol=1e-10 * np.abs(Mx).max())
        np.testing.assert_allclose(terms.Gx, Gx, rtol=1e-10, atol=1e-10 * np.abs(Mx).max())
        # (6.104): τ = Jᵀ (Mx Ẍ + Vx + Gx) with Ẍ = J Θ̈ + J̇ Θ̇ reproduces the joint-space torque
        x_ddot = terms.J @ qdd[k] + terms.J_dot @ qd[k]
        from course_dynamics import inverse_dynamics

        np.testing.assert_allclose(terms.joint_torques(x_ddot), inverse_dynamics(model, q[k], qd[k], qdd[k]), rtol=1e-9, atol=1e-9)


def test_singularity_is_a_clear_error():
    model = load_robot("two_link")
    with pytest.raises(SingularityError, match=r"singular at q = \[0.3, 0.0\] \(condition number"):
        cartesian_dynamics(model, [0.3, 0.0], [0, 0], "tool", rows=["x", "y"])


def test_non_square_task_and_unknown_names():
    model = load_robot("two_link")
    with pytest.raises(ValueError, match="the task has 3 rows but robot 'two_link' has 2 joints"):
        cartesian_dynamics(model, [0.3, 0.5], [0, 0], "tool", rows=["x", "y", "z"])
    with pytest.raises(ValueError, match="no link or frame 'hand'"):
        jacobian(model, [0.3, 0.5], "hand")
    with pytest.raises(ValueError, match="unknown task row 'w'"):
        jacobian(model, [0.3, 0.5], "tool", rows=["w"])


@pytest.mark.parametrize("name", sorted(SQUARE_TASKS))
def test_6_105_with_B_x_and_C_x_agrees_with_pinocchio(name):
    """τ = Jᵀ M_x Ẍ + B_x[Θ̇Θ̇] + C_x[Θ̇²] + G (6.105) against Pinocchio's M Θ̈ + C Θ̇ + G with Θ̈ = J⁻¹(Ẍ − J̇ Θ̇), J
    and J̇ Pinocchio's (getFrameJacobian, getFrameJacobianTimeVariation); and B_x[Θ̇Θ̇] + C_x[Θ̇²] = Jᵀ V_x."""
    from course_dynamics_reference.pinocchio_oracle import PinocchioOracle

    from course_dynamics import gravity_torques, load_urdf
    from course_dynamics.core.cartesian import cartesian_configuration_space_terms
    from course_dynamics.core.lagrange import velocity_pairs

    model = load_urdf(urdf_of(name))
    oracle = PinocchioOracle(urdf_of(name), model.joint_names)
    q, qd, _ = random_states(model, 40, seed=105)
    x_ddot = np.random.default_rng(105).uniform(-2.0, 2.0, (len(q), model.n))  # m/s², rad/s²
    frame, rows = SQUARE_TASKS[name]
    indices = list(range(6)) if rows is None else [ROW_NAMES.index(r) for r in rows]
    checked = 0
    for k in range(len(q)):
        J = oracle.frame_jacobian(q[k], frame)[indices]
        if np.linalg.cond(J) > 1e4:
            continue  # Θ̈ = J⁻¹(…) amplifies round-off by cond(J); the agreement below is 1e-9 relative
        checked += 1
        J_dot = oracle.frame_jacobian_dot(q[k], qd[k], frame)[indices]
        theta_ddot = np.linalg.solve(J, x_ddot[k] - J_dot @ qd[k])  # (6.97)
        tau_ref = oracle.M(q[k]) @ theta_ddot + oracle.C(q[k], qd[k]) @ qd[k] + oracle.G(q[k])
        Bx, Cx = cartesian_configuration_space_terms(model, q[k], frame, rows=rows)
        assert Bx.shape == (model.n, model.n * (model.n - 1) // 2) and Cx.shape == (model.n, model.n)
        products = np.array([qd[k][i] * qd[k][j] for i, j in velocity_pairs(model.n)])  # [Θ̇Θ̇] (6.64)
        velocity = Bx @ products + Cx @ qd[k] ** 2
        terms = cartesian_dynamics(model, q[k], qd[k], frame, rows=rows)
        tau = J.T @ terms.Mx @ x_ddot[k] + velocity + gravity_torques(model, q[k])  # (6.105)
        scale = np.abs(oracle.M(q[k])).max() * (1 + np.abs(qd[k]).max() ** 2 + np.abs(theta_ddot).max())
        assert_agrees(tau, tau_ref, scale, rtol=1e-9, what=f"{name} τ by (6.105), state {k}")
        Mx_ref = np.linalg.inv(J @ np.linalg.solve(oracle.M(q[k]), J.T))
        assert_agrees(velocity, oracle.C(q[k], qd[k]) @ qd[k] - J.T @ Mx_ref @ J_dot @ qd[k], scale, rtol=1e-9,
                      what=f"{name} B_x[Θ̇Θ̇] + C_x[Θ̇²] = V − Jᵀ M_x J̇ Θ̇, state {k}")
    assert checked >= 20, f"{name}: only {checked} well-conditioned states"


def test_B_x_and_C_x_differ_from_B_and_C():
    """(6.105)'s B_x, C_x are not (6.63)'s B, C: they carry −M J⁻¹ J̇ Θ̇. Example 6.6 in frame {3}:
    J̇ Θ̇ = (l₁c₂, −l₁s₂)ᵀ θ̇₁θ̇₂ has no square, so C_x = C and B_x = B − M J⁻¹ (l₁c₂, −l₁s₂)ᵀ; in base
    coordinates J̇ also turns with the tool and C_x ≠ C."""
    from course_dynamics.core.cartesian import cartesian_configuration_space_terms
    from course_dynamics.core.lagrange import configuration_space_terms

    model = load_robot("two_link")
    q = np.array([0.4, 0.9])  # rad
    l1, s2, c2 = 0.5, np.sin(q[1]), np.cos(q[1])  # m
    B, C = configuration_space_terms(model, q)
    Bx, Cx = cartesian_configuration_space_terms(model, q, "tool", "frame", ("x", "y"))
    terms = cartesian_dynamics(model, q, [0.0, 0.0], "tool", "frame", ("x", "y"))
    M = textbook.two_link(q, [0.0, 0.0], **textbook.COURSE_PARAMETERS["two_link"])[0]
    np.testing.assert_allclose(Bx[:, 0], B[:, 0] - M @ np.linalg.solve(terms.J, [l1 * c2, -l1 * s2]), rtol=1e-12)
    np.testing.assert_allclose(Cx, C, rtol=1e-12, atol=1e-15)
    assert np.abs(Bx - B).max() > 0.1
    Bx_base, Cx_base = cartesian_configuration_space_terms(model, q, "tool", "base", ("x", "z"))
    assert np.abs(Cx_base - C).max() > 0.1
