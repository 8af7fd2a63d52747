"""course_dynamics/core/coriolis.py: the O(n²) C against Pinocchio, against the Christoffel definition, and its identities."""
from __future__ import annotations

import numpy as np
import sympy
from helpers import assert_agrees

from course_dynamics import load_robot, mass_matrix, velocity_torques
from course_dynamics.core import coriolis
from course_dynamics.core.dynamics import coriolis_matrix_christoffel
from course_dynamics.core.parameters import joint_symbols, symbolic_model

STEP = 1e-30  # complex step


def test_agrees_with_pinocchio(robot):
    name, model, oracle, (q, qd, _) = robot
    C = coriolis.coriolis_matrix(model, q, qd)
    for k in range(len(q)):
        scale = np.abs(oracle.M(q[k])).max() * np.abs(qd[k]).max()
        assert_agrees(C[k], oracle.C(q[k], qd[k]), scale, what=f"{name} C, state {k}")


def test_equals_the_christoffel_definition(robot):
    """Cᵢⱼ = Σₖ Γᵢⱼₖ θ̇ₖ, by exact differentiation with dual numbers: the teaching definition."""
    name, model, _, (q, qd, _) = robot
    ours, definition = coriolis.coriolis_matrix(model, q[:40], qd[:40]), coriolis_matrix_christoffel(model, q[:40], qd[:40])
    for k in range(40):
        scale = np.abs(mass_matrix(model, q[k])).max() * np.abs(qd[k]).max()
        assert_agrees(ours[k], definition[k], scale, rtol=1e-12, what=f"{name} C vs Christoffel, state {k}")


def test_c_times_velocity_is_V_and_M_dot_minus_2C_is_skew(robot):
    name, model, _, (q, qd, _) = robot
    C = coriolis.coriolis_matrix(model, q[:20], qd[:20])
    V = velocity_torques(model, q[:20], qd[:20])
    for k in range(20):
        M = mass_matrix(model, q[k])
        scale = np.abs(M).max() * np.abs(qd[k]).max()
        assert_agrees(C[k] @ qd[k], V[k], scale * np.abs(qd[k]).max(), rtol=1e-12, what=f"{name} C qd = V")
        M_dot = np.imag(mass_matrix(model, q[k] + 1j * STEP * qd[k])) / STEP  # complex step: independent of C
        S = M_dot - 2 * C[k]
        assert np.abs(S + S.T).max() <= 1e-12 * scale, f"{name}: Ṁ − 2C not skew at state {k}"


def test_symbolic_two_link_is_the_christoffel_closed_form():
    """C = h [[−θ̇₂, −(θ̇₁ + θ̇₂)], [θ̇₁, 0]] with h = m₂ l₁ l₂ sin θ₂: it gives Craig's V (6.61)."""
    model, p = symbolic_model(load_robot("two_link"), ("m1", "m2", "l1", "l2"))
    q, qd, _ = joint_symbols(model)
    C = coriolis.coriolis_matrix(model, q, qd)
    h = p["m2"] * p["l1"] * p["l2"] * sympy.sin(q[1])
    expected = [[-h * qd[1], -h * (qd[0] + qd[1])], [h * qd[0], 0]]
    for i in range(2):
        for j in range(2):
            assert sympy.simplify(C[i, j] - expected[i][j]) == 0, (i, j, C[i, j])
