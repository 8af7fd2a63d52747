"""course_dynamics/core/dynamics.py: M, V, G and the Coriolis matrix against Pinocchio, and their identities."""
from __future__ import annotations

import numpy as np
from helpers import assert_agrees

from course_dynamics import (
    coriolis_matrix,
    dynamics_terms,
    gravity_torques,
    load_robot,
    mass_matrix,
    potential_energy,
    velocity_torques,
)

STEP = 1e-30  # complex-step size: derivatives exact to round-off, no subtraction


def test_mass_matrix_agrees_with_crba(robot):
    name, model, oracle, (q, _, _) = robot
    batch = mass_matrix(model, q)
    for k in range(len(q)):
        assert_agrees(batch[k], oracle.M(q[k]), what=f"{name} M, state {k}")


def test_coriolis_matrix_agrees_with_pinocchio(robot):
    name, model, oracle, (q, qd, _) = robot
    batch = coriolis_matrix(model, q, qd)
    for k in range(len(q)):
        scale = np.abs(oracle.M(q[k])).max() * np.abs(qd[k]).max()
        assert_agrees(batch[k], oracle.C(q[k], qd[k]), scale, what=f"{name} C, state {k}")


def test_velocity_terms_agree_with_nonlinear_effects(robot):
    name, model, oracle, (q, qd, _) = robot
    batch = velocity_torques(model, q, qd)
    for k in range(len(q)):
        scale = np.abs(oracle.M(q[k])).max() * np.abs(qd[k]).max() ** 2
        assert_agrees(batch[k], oracle.V(q[k], qd[k]), scale, what=f"{name} V, state {k}")


def test_gravity_agrees_with_generalized_gravity(robot):
    name, model, oracle, (q, _, _) = robot
    batch = gravity_torques(model, q)
    for k in range(len(q)):
        scale = np.abs(oracle.M(q[k])).max() * 9.81
        assert_agrees(batch[k], oracle.G(q[k]), scale, what=f"{name} G, state {k}")


def test_mass_matrix_is_symmetric_positive_definite(robot):
    name, model, _, (q, _, _) = robot
    M = mass_matrix(model, q)
    np.testing.assert_allclose(M, np.swapaxes(M, -1, -2), rtol=0, atol=1e-14 * np.abs(M).max())
    assert np.all(np.linalg.eigvalsh(M) > 0), f"{name}: M not positive definite"


def test_coriolis_times_velocity_is_V(robot):
    name, model, _, (q, qd, _) = robot
    Cqd = np.einsum("kij,kj->ki", coriolis_matrix(model, q, qd), qd)
    V = velocity_torques(model, q, qd)
    M = mass_matrix(model, q)
    for k in range(len(q)):
        assert_agrees(Cqd[k], V[k], np.abs(M[k]).max() * np.abs(qd[k]).max() ** 2, what=f"{name} C qd = V")


def test_M_dot_minus_2C_is_skew_symmetric(robot):
    """Ṁ by complex step, independent of the dual numbers inside coriolis_matrix."""
    name, model, _, (q, qd, _) = robot
    for k in range(20):
        M_dot = np.imag(mass_matrix(model, q[k] + 1j * STEP * qd[k])) / STEP
        S = M_dot - 2 * coriolis_matrix(model, q[k], qd[k])
        scale = np.abs(M_dot).max() + np.abs(mass_matrix(model, q[k])).max() * np.abs(qd[k]).max()
        assert np.abs(S + S.T).max() <= 1e-12 * scale, f"{name}: Ṁ − 2C not skew at state {k}"


def test_G_is_the_gradient_of_potential_energy(robot):
    name, model, _, (q, _, _) = robot
    for k in range(20):
        gradient = [np.imag(potential_energy(model, q[k] + 1j * STEP * e)) / STEP for e in np.eye(model.n)]
        G = gravity_torques(model, q[k])
        assert_agrees(G, gradient, np.abs(mass_matrix(model, q[k])).max() * 9.81, what=f"{name} G = ∂u/∂Θ")


def test_dynamics_terms_fit_the_state_space_equation():
    """τ = M Θ̈ + V + G (6.59), all from one call."""
    arm = load_robot("panda")
    rng = np.random.default_rng(7)
    q, qd, qdd = rng.uniform(-1, 1, (3, arm.n))
    terms = dynamics_terms(arm, q, qd, qdd)
    np.testing.assert_allclose(terms.tau, terms.M @ qdd + terms.V + terms.G, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(terms.C @ qd, terms.V, rtol=1e-12, atol=1e-12)
    assert terms.joints == arm.joint_names


def test_dynamics_terms_gravity_override():
    arm = load_robot("two_link")
    terms = dynamics_terms(arm.with_gravity([0, 0, 0]), [0.2, 0.3], [0, 0], [0, 0])
    np.testing.assert_array_equal(terms.G, 0)
