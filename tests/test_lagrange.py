"""course_dynamics/core/lagrange.py: the Lagrangian path against Pinocchio and against our Newton–Euler."""
from __future__ import annotations

import numpy as np
from helpers import assert_agrees

from course_dynamics import potential_energy
from course_dynamics.core import dynamics, lagrange

STEP = 1e-30  # complex step


def test_lagrangian_terms_agree_with_pinocchio(robot):
    name, model, oracle, (q, qd, qdd) = robot
    M, G = lagrange.mass_matrix(model, q), lagrange.gravity_torques(model, q)
    C, tau = lagrange.coriolis_matrix(model, q, qd), lagrange.inverse_dynamics(model, q, qd, qdd)
    V = lagrange.velocity_torques(model, q, qd)
    for k in range(len(q)):
        M_ref = oracle.M(q[k])
        scale = np.abs(M_ref).max()
        speed, accel = np.abs(qd[k]).max(), np.abs(qdd[k]).max()
        assert_agrees(M[k], M_ref, what=f"{name} Lagrange M, state {k}")
        assert_agrees(G[k], oracle.G(q[k]), scale * 9.81, what=f"{name} Lagrange G, state {k}")
        assert_agrees(C[k], oracle.C(q[k], qd[k]), scale * speed, what=f"{name} Lagrange C, state {k}")
        assert_agrees(V[k], oracle.V(q[k], qd[k]), scale * speed**2, what=f"{name} Lagrange V, state {k}")
        assert_agrees(tau[k], oracle.tau(q[k], qd[k], qdd[k]), scale * (accel + speed**2), what=f"{name} Lagrange tau, state {k}")


def test_lagrange_equals_newton_euler(robot):
    name, model, _, (q, qd, qdd) = robot
    np.testing.assert_allclose(lagrange.inverse_dynamics(model, q, qd, qdd), dynamics.inverse_dynamics(model, q, qd, qdd),
                               rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(lagrange.coriolis_matrix(model, q, qd), dynamics.coriolis_matrix(model, q, qd), rtol=1e-10, atol=1e-12)


def test_kinetic_energy_is_the_quadratic_form(robot):
    """Σ kᵢ (6.69) = ½ Θ̇ᵀ M Θ̇ (6.71), with M from Newton–Euler."""
    name, model, _, (q, qd, _) = robot
    k = lagrange.kinetic_energy(model, q, qd)
    quadratic = 0.5 * np.einsum("ki,kij,kj->k", qd, dynamics.mass_matrix(model, q), qd)
    np.testing.assert_allclose(k, quadratic, rtol=1e-12, atol=1e-15)
    assert lagrange.link_kinetic_energies(model, q, qd).shape == q.shape[:-1] + (model.n_bodies,)


def test_gravity_is_the_gradient_of_potential_energy(robot):
    name, model, _, (q, _, _) = robot
    for k in range(10):
        gradient = [np.imag(potential_energy(model, q[k] + 1j * STEP * e)) / STEP for e in np.eye(model.n)]
        np.testing.assert_allclose(lagrange.gravity_torques(model, q[k]), gradient, rtol=1e-12, atol=1e-12)


def test_christoffel_symbols_are_symmetric_and_give_M_dot(robot):
    """Γᵢⱼₖ = Γᵢₖⱼ, and Ṁ = C + Cᵀ with Ṁ by complex step."""
    name, model, _, (q, qd, _) = robot
    Gamma = lagrange.christoffel_symbols(model, q[:5])
    np.testing.assert_allclose(Gamma, np.swapaxes(Gamma, -1, -2), rtol=0, atol=1e-14)
    for k in range(5):
        M_dot = np.imag(lagrange.mass_matrix(model, q[k] + 1j * STEP * qd[k])) / STEP
        C = lagrange.coriolis_matrix(model, q[k], qd[k])
        np.testing.assert_allclose(C + C.T, M_dot, rtol=1e-10, atol=1e-12)


def test_configuration_space_split_reproduces_V(robot):
    """(6.63): V = B(Θ)[Θ̇Θ̇] + C(Θ)[Θ̇²]."""
    name, model, _, (q, qd, _) = robot
    B, C = lagrange.configuration_space_terms(model, q)
    pairs = lagrange.velocity_pairs(model.n)
    products = np.stack([qd[:, j] * qd[:, k] for j, k in pairs], axis=-1) if pairs else np.zeros((len(q), 0))
    V = np.einsum("kip,kp->ki", B, products) + np.einsum("kij,kj->ki", C, qd**2)
    np.testing.assert_allclose(V, dynamics.velocity_torques(model, q, qd), rtol=1e-10, atol=1e-12)
    assert B.shape == (len(q), model.n, model.n * (model.n - 1) // 2)
