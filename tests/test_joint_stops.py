"""course_dynamics/tools/joint_stops.py: the impulse of a stop, the held joints' reaction against Pinocchio's
constrained dynamics, and simulate(..., limits="stop") never adding energy on every shipped robot."""
from __future__ import annotations

import numpy as np
import pytest

from course_dynamics import load_robot, load_urdf, robot_path
from course_dynamics.core.evaluator import implementation
from course_dynamics.core.robots import robot_names
from course_dynamics.tools.joint_stops import held_accelerations, hold, limit_bounds, stop_impulse
from course_dynamics.tools.simulation import simulate

LIMITED = [name for name in robot_names() if np.isfinite(limit_bounds(load_robot(name))[0]).any()]
# Semi-implicit Euler is stable on the Panda's light fingers (15 g on 4 cm) only with a step well below 1 ms.
SEMI_IMPLICIT_DT = {"panda": 2e-4}


def toward_limits(model):
    """A start 85 % of the way from the middle of each limited joint to a limit (alternately upper and lower),
    moving toward it at half its range a second: every limited joint reaches its limit within a second."""
    lower, upper = limit_bounds(model)
    limited = np.isfinite(lower)
    sign = np.resize([1.0, -1.0], model.n)
    middle, half = np.where(limited, 0.5 * (lower + upper), 0.0), np.where(limited, 0.5 * (upper - lower), 1.0)
    return middle + 0.85 * half * sign * limited, 1.0 * half * sign * limited


def pinocchio_held(oracle, q, qd, tau, held):
    """Pinocchio's constrained dynamics with the held joints locked (constraint Jacobian rows eᵢᵀ, no drift):
    its accelerations and Lagrange multipliers (M a + b = τ + Jᵀ λ), in our joint order."""
    import pinocchio as pin

    if oracle.has_mimic:  # its forwardDynamics refuses a mimic model: the model without, each coupling a constraint
        return _pinocchio_held_coupled(oracle, q, qd, tau, held)
    rows = oracle.idx_v[np.flatnonzero(held)]
    J = np.zeros((len(rows), oracle.model.nv))
    J[np.arange(len(rows)), rows] = 1.0
    a = pin.forwardDynamics(oracle.model, oracle.data, oracle.configuration(q), oracle.velocity(qd),
                            oracle.velocity(tau), J, np.zeros(len(rows)))
    return np.asarray(a)[oracle.idx_v], np.asarray(oracle.data.lambda_c).copy()


def _pinocchio_held_coupled(oracle, q, qd, tau, held):
    """Pinocchio's constrained dynamics on the model without mimic: the held coordinates' own joints locked and
    every mimic joint tied to its leader (θ̈ₖ − a θ̈ⱼ = 0, the rows of the coupling); τ on the own joints."""
    import pinocchio as pin

    plain, data, S = oracle.plain, oracle.plain_data, oracle.S
    own = np.array([plain.joints[plain.getJointId(name)].idx_v for name in oracle.joint_names])
    mimics = [r for r in range(plain.nv) if r not in own]
    J = np.zeros((int(held.sum()) + len(mimics), plain.nv))
    J[np.arange(int(held.sum())), own[held]] = 1.0
    for row, r in enumerate(mimics, start=int(held.sum())):
        j = int(np.flatnonzero(S[r])[0])
        J[row, r], J[row, own[j]] = 1.0, -S[r, j]
    applied = np.zeros(plain.nv)
    applied[own] = tau
    a = pin.forwardDynamics(plain, data, oracle.plain_configuration(q), S @ qd, applied, J, np.zeros(len(J)))
    return np.asarray(a)[own], np.asarray(data.lambda_c)[:int(held.sum())].copy()


def kkt_held(oracle, q, qd, tau, held):
    """The same multipliers from the KKT system built on Pinocchio's crba and nonLinearEffects."""
    import pinocchio as pin

    n = len(q)
    M = pin.crba(oracle.model, oracle.data, oracle.configuration(q))
    M = np.triu(M) + np.triu(M, 1).T
    b = pin.nonLinearEffects(oracle.model, oracle.data, oracle.configuration(q), oracle.velocity(qd))
    M, b = M[np.ix_(oracle.idx_v, oracle.idx_v)], b[oracle.idx_v]
    E = np.eye(n)[:, np.flatnonzero(held)]
    K = np.block([[M, -E], [E.T, np.zeros((E.shape[1], E.shape[1]))]])
    solution = np.linalg.solve(K, np.concatenate([tau - b, np.zeros(E.shape[1])]))
    return solution[:n], solution[n:]


@pytest.mark.parametrize("name", LIMITED)
def test_held_reaction_is_pinocchios_lagrange_multiplier(name):
    """λ of the held joints equals Pinocchio's lambda_c (forwardDynamics) and the crba/nonLinearEffects KKT
    solution, to 1e-9, for one held joint and for several."""
    from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
    from course_dynamics_reference.validate import random_states

    model = load_robot(name)
    oracle = PinocchioOracle(robot_path(name), model.joint_names, model.gravity)
    run = implementation(model, compiled=False)
    q, qd, _ = random_states(model, 6, seed=11)
    tau = np.random.default_rng(3).normal(0.0, 5.0, q.shape)
    rng = np.random.default_rng(8)
    for k in range(len(q)):
        held = np.zeros(model.n, dtype=bool)
        held[rng.choice(model.n, size=1 if k % 2 else min(3, model.n), replace=False)] = True
        qdd, reaction = held_accelerations(run.mass_matrix(q[k]), run.bias(q[k], qd[k]), tau[k], held)
        a_pin, lambda_pin = pinocchio_held(oracle, q[k], qd[k], tau[k], held)
        a_kkt, lambda_kkt = kkt_held(oracle, q[k], qd[k], tau[k], held)
        scale = 1.0 + np.abs(lambda_pin).max()
        np.testing.assert_allclose(reaction[held], lambda_pin, rtol=1e-9, atol=1e-9 * scale)
        np.testing.assert_allclose(reaction[held], lambda_kkt, rtol=1e-9, atol=1e-9 * scale)
        np.testing.assert_allclose(qdd, a_pin, rtol=1e-9, atol=1e-9 * (1.0 + np.abs(a_pin).max()))
        assert np.all(qdd[held] == 0.0) and np.all(reaction[~held] == 0.0)


def test_one_joint_stop_is_the_impulse_through_m():
    """Δθ̇ = −M⁻¹eᵢ (eᵢᵀθ̇)/(M⁻¹)ᵢᵢ; the other joints' momentum (M θ̇)ⱼ, j ≠ i, is kept; kinetic energy drops by
    ½ θ̇ᵢ² / (M⁻¹)ᵢᵢ."""
    model = load_robot("panda")
    run = implementation(model, compiled=False)
    rng = np.random.default_rng(2)
    for i in range(model.n):
        q, qd = rng.uniform(-1.0, 1.0, model.n), rng.normal(0.0, 1.0, model.n)
        M = run.mass_matrix(q)
        W = np.linalg.inv(M)
        side = np.zeros(model.n, dtype=int)
        side[i] = 1 if qd[i] > 0 else -1
        after, stopped, impulse = stop_impulse(M, qd, side != 0, side)
        expected = qd - W[:, i] * qd[i] / W[i, i]
        expected[i] = 0.0
        np.testing.assert_allclose(after, expected, rtol=1e-12, atol=1e-12)
        others = np.arange(model.n) != i
        np.testing.assert_allclose((M @ after)[others], (M @ qd)[others], rtol=1e-10, atol=1e-10)
        lost = 0.5 * qd @ M @ qd - 0.5 * after @ M @ after
        assert lost == pytest.approx(0.5 * qd[i] ** 2 / W[i, i], rel=1e-9)
        assert stopped[i] and side[i] * impulse[i] < 0


def test_several_joints_stop_at_once_and_one_pulling_is_let_go():
    """Two or three joints reaching limits at one instant: one impulse, the complementarity of a stop for each
    (stopped: rate zero and an impulse that pushes; let go: an impulse of zero and a rate away from the limit),
    and kinetic energy down. Both outcomes occur among the states drawn."""
    model = load_robot("ur5")
    run = implementation(model, compiled=False)
    rng = np.random.default_rng(6)
    outcomes = set()
    for _ in range(40):
        q, qd = rng.uniform(-2.0, 2.0, 6), rng.normal(0.0, 1.5, 6)
        M = run.mass_matrix(q)
        at = rng.choice(6, size=rng.integers(2, 4), replace=False)
        side = np.zeros(6, dtype=int)
        side[at] = np.where(qd[at] > 0, 1, -1)  # each runs into its limit
        after, stopped, impulse = stop_impulse(M, qd, side != 0, side)
        assert np.all(after[stopped] == 0.0) and np.all(side[stopped] * impulse[stopped] <= 0)
        let_go = (side != 0) & ~stopped
        assert np.all(impulse[let_go] == 0.0) and np.all(side[let_go] * after[let_go] <= 1e-12)
        assert 0.5 * after @ M @ after <= 0.5 * qd @ M @ qd
        E = np.eye(6)[:, stopped]
        np.testing.assert_allclose(E.T @ np.linalg.solve(M, E @ impulse[stopped]), -qd[stopped], rtol=1e-10,
                                   atol=1e-12)
        outcomes.add(bool(let_go.any()))
    assert outcomes == {True, False}


def test_a_reaction_that_would_pull_lets_the_joint_go():
    model = load_robot("rp_arm")  # horizontal: d2 is pushed only by the applied force
    run = implementation(model, compiled=False)
    q, qd, upper = np.array([0.0, 0.8]), np.zeros(2), np.array([0, 1])
    for force, kept in ((5.0, True), (-5.0, False)):
        held, qdd, reaction = hold(run.mass_matrix(q), run.bias(q, qd), np.array([0.0, force]),
                                   np.array([False, True]), upper)
        assert held[1] == kept
        assert (reaction[1] == pytest.approx(-force, rel=1e-12)) if kept else (qdd[1] < 0 and reaction[1] == 0)


@pytest.mark.parametrize("integrator", ["rk4", "semi-implicit"])
@pytest.mark.parametrize("name", LIMITED)
def test_no_stop_adds_energy(name, integrator):
    """No torque, no friction, every limited joint run into a limit: each stop's kinetic-energy change is ≤ 0 (to
    round-off), the energy under 'stop' stays at or below the start's plus the integrator's own drift under
    'report', and what the stops took is what the run lost."""
    model = load_robot(name)
    dt = SEMI_IMPLICIT_DT.get(name, 1e-3) if integrator == "semi-implicit" else 1e-3
    q0, qd0 = toward_limits(model)
    report = simulate(model, q0, qd0, duration=1.0, dt=dt, integrator=integrator, limits="report")
    stop = simulate(model, q0, qd0, duration=1.0, dt=dt, integrator=integrator, limits="stop")
    start = report.energy[0]
    drift = np.abs(report.energy - start).max()
    assert stop.stops and len(stop.events) == len(stop.stops)
    for each in stop.stops:
        assert each.energy <= 1e-12 * (1.0 + each.kinetic_before), each.sentence()
    assert stop.energy.max() <= start + drift + 1e-12 * abs(start), (stop.energy.max() - start, drift)
    taken = sum(each.energy for each in stop.stops)
    assert abs(stop.energy[-1] - start - taken) <= 2 * drift + 1e-9 * abs(start)
    lower, upper = limit_bounds(model)
    assert np.all(stop.q >= lower) and np.all(stop.q <= upper)


def test_a_panda_stopped_at_its_limits_keeps_its_energy():
    """The Panda released from (0, 0, 0, −1.5, 0, 1.5, 0.7, 0.02) with no torque: under 'stop' the energy
    never rises above the start (zeroing a joint's rate instead had taken it from 90.7 J to 659.8 J)."""
    model = load_robot("panda")
    q0 = [0, 0, 0, -1.5, 0, 1.5, 0.7, 0.02]  # the second finger mimics the first
    report = simulate(model, q0, np.zeros(8), duration=2.0, dt=1e-3, limits="report")
    stop = simulate(model, q0, np.zeros(8), duration=2.0, dt=1e-3, limits="stop")
    drift = np.abs(report.energy - report.energy[0]).max()
    assert drift < 1e-4 and stop.energy.max() <= report.energy[0] + drift
    first = stop.stops[0]
    assert first.joints == ("panda_joint2",) and first.sides == ("upper",) and first.energy < -10.0


def test_a_chain_hitting_several_limits_in_one_step(tmp_path):
    """A four-joint chain whose joints reach their limits at once (a start on the limits, running into them) and
    again within single steps: one impulse stops them together, and no stop adds energy."""
    from helpers import chain_urdf

    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(4).replace('lower="-1" upper="1"', 'lower="-0.3" upper="0.3"'))
    model = load_urdf(path)
    lower, upper = limit_bounds(model)
    assert np.all(upper == 0.3), "the chain's limits are what this test narrows"
    q0, qd0 = np.array([0.3, -0.3, 0.3, -0.3]), np.array([1.0, -1.0, 1.0, -1.0])
    for integrator in ("rk4", "semi-implicit"):
        report = simulate(model, q0, qd0, duration=2.0, dt=1e-3, integrator=integrator, limits="report")
        stop = simulate(model, q0, qd0, duration=2.0, dt=1e-3, integrator=integrator, limits="stop")
        assert stop.stops[0].t == 0.0 and len(stop.stops[0].joints) > 1
        assert all(each.energy <= 1e-12 * (1.0 + each.kinetic_before) for each in stop.stops)
        drift = np.abs(report.energy - report.energy[0]).max()
        assert stop.energy.max() <= report.energy[0] + drift + 1e-12 * abs(report.energy[0])
        assert np.all(stop.q >= lower) and np.all(stop.q <= upper)


def test_trajectory_reaction_is_pinocchios_multiplier_at_held_samples():
    """rp_arm pushed into d2's upper limit by 5 N: held there, its reaction at every held sample equals Pinocchio's
    Lagrange multiplier for the locked joint, and the acceleration reported is the constrained one."""
    from course_dynamics_reference.pinocchio_oracle import PinocchioOracle

    model = load_robot("rp_arm")
    oracle = PinocchioOracle(robot_path("rp_arm"), model.joint_names, model.gravity)
    run = simulate(model, [0.0, 0.5], [0.4, 0.0], duration=1.0, dt=1e-3, torque=[0.3, 5.0], limits="stop")
    held = run.reaction != 0.0
    assert held[:, 1].sum() > 100 and not held[:, 0].any()
    for k in np.flatnonzero(held[:, 1])[::25]:
        a, multiplier = pinocchio_held(oracle, run.q[k], run.qd[k], run.tau[k], held[k])
        np.testing.assert_allclose(run.reaction[k, 1], multiplier[0], rtol=1e-9)
        np.testing.assert_allclose(run.qdd[k], a, rtol=1e-9, atol=1e-12)
        assert run.q[k, 1] == 0.8 and run.qd[k, 1] == 0.0 and run.reaction[k, 1] < 0
