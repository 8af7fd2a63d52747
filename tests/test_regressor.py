"""course_dynamics/core/regressor.py: Y π against our τ, Y and π against Pinocchio's, the base parameters."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import sympy
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import arm_urdf, assert_agrees

from course_dynamics import ModelError, inverse_dynamics, load_robot, load_urdf
from course_dynamics.core.parameters import joint_symbols, link_length, parameter_values
from course_dynamics.core.regressor import (
    PARAMETER_NAMES,
    base_parameters,
    parameter_names,
    parameter_symbols,
    parameters,
    regressor,
    with_parameters,
)
from course_dynamics.core.sampling import random_states

RTOL_TAU = 1e-10  # Y π against our own τ


def pinocchio_columns(model, oracle) -> np.ndarray:
    """Pinocchio's regressor columns in our order: body i is Pinocchio's joint of the same name, 10 columns each
    (a mimic joint's body has its own ten, in the model built without mimic)."""
    ids = [oracle.plain.getJointId(body.joint) for body in model.bodies]
    return np.concatenate([np.arange(10 * (j - 1), 10 * j) for j in ids])


def tau_scale(oracle, q, qd, qdd) -> float:
    """The τ scale of course_dynamics.core.sampling, so that a τ near zero is not judged on round-off."""
    return np.abs(oracle.M(q)).max() * (np.abs(qdd).max() + np.abs(qd).max() ** 2) + np.abs(oracle.G(q)).max()


def perturbed(model, seed: int):
    """The robot with every body's mass, centre of mass and inertia changed (still physical)."""
    rng = np.random.default_rng(seed)
    bodies = []
    for body in model.bodies:
        A = 0.03 * rng.standard_normal((3, 3))
        bodies.append(replace(body, mass=body.mass * rng.uniform(0.8, 1.2) + 0.1,
                              p_com=body.p_com + 0.02 * rng.standard_normal(3), I_com=body.I_com + A @ A.T))
    return replace(model, bodies=tuple(bodies))


def test_parameters_are_pinocchios(robot):
    """π in Pinocchio's order is ``Inertia.toDynamicParameters`` of each joint's body, fixed links merged alike."""
    name, model, oracle, _ = robot
    ids = [oracle.plain.getJointId(body.joint) for body in model.bodies]
    theirs = np.concatenate([oracle.plain.inertias[j].toDynamicParameters() for j in ids])
    assert_agrees(parameters(model), theirs, rtol=1e-14, what=f"{name} π")


def test_regressor_times_parameters_is_tau(robot):
    name, model, oracle, (q, qd, qdd) = robot
    pi = parameters(model)
    batch = regressor(model, q, qd, qdd)
    tau = inverse_dynamics(model, q, qd, qdd)
    for k in range(len(q)):
        scale = tau_scale(oracle, q[k], qd[k], qdd[k])
        assert_agrees(batch[k] @ pi, tau[k], scale, rtol=RTOL_TAU, what=f"{name} Y π, batch state {k}")
    for k in range(0, len(q), 20):
        scale = tau_scale(oracle, q[k], qd[k], qdd[k])
        single = regressor(model, q[k], qd[k], qdd[k])
        assert_agrees(single @ pi, tau[k], scale, rtol=RTOL_TAU, what=f"{name} Y π, state {k}")


def test_regressor_agrees_with_pinocchio(robot):
    name, model, oracle, (q, qd, qdd) = robot
    columns = pinocchio_columns(model, oracle)
    batch = regressor(model, q, qd, qdd)
    assert batch.shape == (len(q), model.n, 10 * model.n_bodies)
    for k in range(len(q)):
        assert_agrees(batch[k], oracle.regressor(q[k], qd[k], qdd[k])[:, columns], what=f"{name} Y, state {k}")


def test_batch_equals_single_states(robot):
    _, model, _, (q, qd, qdd) = robot
    batch = regressor(model, q[:10], qd[:10], qdd[:10])
    single = np.array([regressor(model, q[k], qd[k], qdd[k]) for k in range(10)])
    assert single.shape == (10, model.n, 10 * model.n_bodies)
    np.testing.assert_allclose(batch, single, rtol=1e-14, atol=1e-14)


def test_with_parameters_of_parameters_is_the_same_robot(robot):
    name, model, oracle, (q, qd, qdd) = robot
    again = with_parameters(model, parameters(model))
    np.testing.assert_allclose(parameters(again), parameters(model), rtol=1e-13, atol=1e-15)
    tau, tau_again = inverse_dynamics(model, q, qd, qdd), inverse_dynamics(again, q, qd, qdd)
    for k in range(len(q)):
        scale = tau_scale(oracle, q[k], qd[k], qdd[k])
        assert_agrees(tau_again[k], tau[k], scale, rtol=1e-12, what=f"{name} state {k}")


def test_perturbed_parameters_give_the_perturbed_robots_tau(robot):
    name, model, _, (q, qd, qdd) = robot
    other = perturbed(model, seed=len(name))
    pi = parameters(other)
    tau = inverse_dynamics(other, q, qd, qdd)
    Y = regressor(model, q, qd, qdd)
    np.testing.assert_array_equal(regressor(other, q, qd, qdd), Y)  # Y reads the geometry, never π
    rebuilt = inverse_dynamics(with_parameters(model, pi), q, qd, qdd)
    for k in range(len(q)):
        scale = np.abs(tau[k]).max() + 1.0
        assert_agrees(Y[k] @ pi, tau[k], scale, rtol=RTOL_TAU, what=f"{name} perturbed Y π, state {k}")
        assert_agrees(rebuilt[k], tau[k], scale, rtol=1e-12, what=f"{name} with_parameters, state {k}")


def test_base_parameters_reproduce_Y_pi(robot):
    """Y_b β π = Y π for any π, on states other than those β came from; r is the rank of Pinocchio's Y too."""
    name, model, oracle, (q, qd, qdd) = robot
    base = base_parameters(model, seed=7)
    Y = regressor(model, q, qd, qdd)
    pi = np.random.default_rng(3).standard_normal(10 * model.n_bodies)  # need not be physical
    np.testing.assert_allclose(base.regressor(Y) @ base.values(pi), Y @ pi, rtol=1e-9, atol=1e-9 * np.abs(Y @ pi).max())
    W = base.regressor(Y).reshape(-1, base.rank)
    singular = np.linalg.svd(W / np.linalg.norm(W, axis=0), compute_uv=False)
    assert singular[-1] > 1e-6, f"{name}: Y_b is not of full column rank ({singular[-1]:.1e})"
    stacked = np.concatenate([oracle.regressor(q[k], qd[k], qdd[k]) for k in range(len(q))])
    norms = np.linalg.norm(stacked, axis=0)
    acting = stacked[:, norms > 1e-12 * norms.max()]
    assert np.linalg.matrix_rank(acting / np.linalg.norm(acting, axis=0), tol=1e-9) == base.rank


def test_two_link_base_parameters_are_the_known_ones():
    """Craig's planar RR arm: m₂ is only seen through Izz_1 + l₁² m_2 and mcx_1 + l₁ m_2, six combinations in all."""
    arm = load_robot("two_link")
    base = base_parameters(arm)
    names = parameter_names(arm)
    assert base.rank == 6
    assert [names[k] for k in base.independent] == ["mcx_1", "mcy_1", "Izz_1", "mcx_2", "mcy_2", "Izz_2"]
    l1 = link_length(arm, 0)
    expected = np.zeros((6, 20))
    for row, k in enumerate(base.independent):
        expected[row, k] = 1.0
    expected[0, names.index("m_2")] = l1
    expected[2, names.index("m_2")] = l1**2
    np.testing.assert_allclose(base.beta, expected, atol=1e-12)
    q, qd, qdd = random_states(arm, 20, seed=11)
    Y = regressor(arm, q, qd, qdd)
    for pi in np.random.default_rng(0).standard_normal((5, 20)):
        np.testing.assert_allclose(base.regressor(Y) @ (base.beta @ pi), Y @ pi, rtol=1e-12, atol=1e-12)


def test_describe_gives_the_course_robots_in_the_notes_symbols():
    lines = base_parameters(load_robot("rrr_arm")).describe(list(parameter_values(load_robot("rrr_arm")))).splitlines()
    assert len(lines) == 15
    assert "π_b2 = mcx_2 + l2·m_3 = l2·m3 + lc2·m2" in lines
    assert base_parameters(load_robot("pendulum")).describe(["m", "l"]).splitlines()[1] == "π_b2 = mcz_1 = -l·m"


def test_a_massless_body(tmp_path):
    """A link of zero mass and inertia: its π is zero, Y still agrees with Pinocchio, with_parameters keeps it."""
    path = tmp_path / "massless.urdf"
    path.write_text(arm_urdf(mass="0", ixx="0", iyy="0", izz="0"))
    model = load_urdf(path)
    oracle = PinocchioOracle(path, model.joint_names, model.gravity)
    assert model.bodies[1].mass == 0
    np.testing.assert_array_equal(parameters(model)[10:], 0.0)
    q, qd, qdd = random_states(model, 20, seed=5)
    Y = regressor(model, q, qd, qdd)
    columns = pinocchio_columns(model, oracle)
    for k in range(len(q)):
        assert_agrees(Y[k], oracle.regressor(q[k], qd[k], qdd[k])[:, columns], what=f"massless Y, state {k}")
    np.testing.assert_allclose(Y @ parameters(model), inverse_dynamics(model, q, qd, qdd), rtol=1e-12, atol=1e-14)
    again = with_parameters(model, parameters(model))
    assert again.bodies[1].mass == 0.0
    np.testing.assert_array_equal(again.bodies[1].p_com, model.bodies[1].p_com)


@pytest.mark.parametrize("entries, message", [
    ({10: -1.0}, r"body 2 'link2' \(joint 'theta2'\): mass -1 kg"),
    ({10: 0.0, 11: 0.4}, r"body 2 'link2' \(joint 'theta2'\): mass 0 kg with first moment m c = \(0.4, 0, 0\)"),
])
def test_non_physical_parameters_are_refused(entries, message):
    arm = load_robot("two_link")
    pi = parameters(arm)
    for k, value in entries.items():
        pi[k] = value
    with pytest.raises(ModelError, match=message):
        with_parameters(arm, pi)


def test_parameters_of_the_wrong_length_are_refused():
    with pytest.raises(ModelError, match="robot 'two_link' has 2 bodies, so π has 20 entries"):
        with_parameters(load_robot("two_link"), np.zeros(10))


def test_names_and_symbols():
    arm = load_robot("rrr_arm")
    names, symbols = parameter_names(arm), parameter_symbols(arm)
    assert len(names) == len(set(names)) == len(symbols) == len(set(symbols)) == 30
    assert names[:10] == [f"{p}_1" for p in PARAMETER_NAMES] and names[29] == "Izz_3"
    assert symbols[29] == "I₃,zz"


def test_symbolic_states_give_a_symbolic_regressor():
    """The same lines on sympy symbols: Y π is the symbolic τ."""
    arm = load_robot("pendulum")
    q, qd, qdd = joint_symbols(arm)
    Y = regressor(arm, q, qd, qdd)
    difference = (Y @ parameters(arm))[0] - inverse_dynamics(arm, q, qd, qdd)[0]
    assert sympy.simplify(difference) == 0
