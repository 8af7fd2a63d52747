"""course_dynamics/core/kinematics.py: placements of every body and every URDF frame, and u, against Pinocchio."""
from __future__ import annotations

import numpy as np
from helpers import assert_agrees

from course_dynamics import forward_kinematics, potential_energy
from course_dynamics.core.kinematics import (
    frame_placement,
    joint_transforms,
    placement_entries,
)


def test_body_placements_agree_with_pinocchio_frames(robot):
    """⁰ᵢR and ⁰Pᵢ of every body, batched, against Pinocchio's oMf of the body's URDF link."""
    name, model, oracle, (q, _, _) = robot
    placed = forward_kinematics(model, q[:20])
    assert placed.R.shape == (20, model.n_bodies, 3, 3) and placed.P.shape == (20, model.n_bodies, 3)
    for k in range(20):
        for i, body in enumerate(model.bodies):
            R_ref, P_ref = oracle.frame_placement(q[k], body.name)
            assert_agrees(placed.R[k, i], R_ref, 1.0, what=f"{name} R of {body.name}, state {k}")
            assert_agrees(placed.P[k, i], P_ref, 1.0, what=f"{name} P of {body.name}, state {k}")


def test_every_frame_agrees_with_pinocchio(robot):
    """Every URDF link, merged by fixed joints or fixed to the base included."""
    name, model, oracle, (q, _, _) = robot
    for frame in model.frame_names:
        R, P = frame_placement(model, q[0], frame)
        R_ref, P_ref = oracle.frame_placement(q[0], frame)
        assert_agrees(R, R_ref, 1.0, what=f"{name} R of frame {frame}")
        assert_agrees(P, P_ref, 1.0, what=f"{name} P of frame {frame}")


def test_potential_energy_agrees_with_pinocchio(robot):
    """u = −Σ mᵢ gᵀ ⁰P_Cᵢ (6.73): this also checks every ⁰P_Cᵢ, weighted by mass."""
    name, model, oracle, (q, _, _) = robot
    u = potential_energy(model, q[:20])
    total_mass = sum(float(b.mass) for b in model.bodies)
    for k in range(20):
        assert_agrees(u[k], oracle.potential_energy(q[k]), total_mass * 9.81, what=f"{name} u, state {k}")


def test_joint_transforms_compose_to_placements(robot):
    """⁰ᵢR = ⁰ₚR ᵖᵢR and ⁰Pᵢ = ⁰Pₚ + ⁰ₚR ᵖPᵢ, and R_T is the transpose."""
    name, model, _, (q, _, _) = robot
    theta = q[0].tolist()
    X, placed = joint_transforms(model, theta), placement_entries(model, theta)
    for i, body in enumerate(model.bodies):
        R_i = np.array(X.R[i].rows)
        np.testing.assert_allclose(np.array(X.R_T[i].rows), R_i.T, atol=0)
        np.testing.assert_allclose(R_i @ R_i.T, np.eye(3), atol=1e-14)
        if body.parent >= 0:
            R_p, P_p = np.array(placed.R[body.parent].rows), np.array(tuple(placed.P[body.parent]))
            np.testing.assert_allclose(np.array(placed.R[i].rows), R_p @ R_i, atol=1e-14)
            np.testing.assert_allclose(np.array(tuple(placed.P[i])), P_p + R_p @ np.array(tuple(X.P[i])), atol=1e-14)
