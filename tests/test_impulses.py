"""course_dynamics/core/compiled/impulses.py (in the native run with joint stops): one impulse through M stops
the joints running into their limits as P = −(Eᵀ M⁻¹ E)⁻¹ Eᵀ Θ̇⁻ says, keeping the other joints' momentum and
taking kinetic energy; a held joint's reaction is Pinocchio's Lagrange multiplier; a joint the motion pulls
off its limit is let go; and the records it keeps are what the Python stops hold."""
from __future__ import annotations

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import chain_urdf
from test_joint_stops import pinocchio_held

from course_dynamics import load_robot, load_urdf, robot_path
from course_dynamics.core.compiled import native
from course_dynamics.core.compiled.impulses import STOP_RECORD
from course_dynamics.core.evaluator import implementation
from course_dynamics.tools import simulation
from course_dynamics.tools.joint_stops import limit_bounds, stop_impulse
from course_dynamics.tools.simulation import simulate

pytestmark = pytest.mark.skipif(native.compiler() is None,
                                reason="no C compiler: the package was installed without the native run")


def native_only(monkeypatch):
    """Fail the test if simulate would take its Python steps."""
    original = simulation.rollout

    def checked(*arguments):
        done = original(*arguments)
        assert done is not None and done.stops is not None, "the run did not go native"
        return done

    monkeypatch.setattr(simulation, "rollout", checked)


def test_one_impulse_stops_joints_together_as_its_closed_form_says(tmp_path, monkeypatch):
    """A three-joint chain started on its limits, two joints running into them and one leaving: the state after
    the contact at t = 0 is Θ̇⁻ + M⁻¹ E P with P = −(Eᵀ M⁻¹ E)⁻¹ Eᵀ Θ̇⁻ for the two (to 1e-12), the joint
    leaving keeps its momentum, the energy the record holds is ½ Θ̇ᵀ M Θ̇ before and after, and it fell."""
    native_only(monkeypatch)
    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(3).replace('lower="-1" upper="1"', 'lower="-0.3" upper="0.3"'))
    model = load_urdf(path)
    q0, qd0 = np.array([0.3, -0.3, 0.3]), np.array([2.0, -1.0, -3.0])  # joints 1, 2 into their limits, 3 leaving
    run = simulate(model, q0, qd0, duration=0.002, dt=1e-3, limits="stop", torque=np.zeros(3))
    first = run.stops[0]
    assert first.t == 0.0 and first.joints == model.joint_names[:2] and first.sides == ("upper", "lower")
    M = implementation(model).mass_matrix(q0)
    E = np.eye(3)[:, :2]
    inverse = np.linalg.inv(M)
    P = -np.linalg.solve(E.T @ inverse @ E, E.T @ qd0)
    after = qd0 + inverse @ E @ P
    np.testing.assert_allclose(run.qd[0], np.where([True, True, False], 0.0, after), rtol=0, atol=1e-12)
    assert first.kinetic_before == pytest.approx(0.5 * qd0 @ M @ qd0, rel=1e-12)
    assert first.kinetic_after == pytest.approx(0.5 * after @ M @ after, rel=1e-12)
    assert first.energy < 0
    np.testing.assert_allclose((M @ run.qd[0])[2], (M @ qd0)[2], rtol=1e-12)  # the free joint's momentum kept
    python = stop_impulse(M, qd0, np.array([True, True, True]), np.array([1, -1, 1]))
    np.testing.assert_allclose(python[0], run.qd[0], rtol=0, atol=1e-12)


@pytest.mark.parametrize("push", [5.0, -5.0])
def test_a_joint_pushed_is_held_with_pinocchios_multiplier_and_one_pulled_is_let_go(push, monkeypatch):
    """rp_arm started at rest on d2's upper limit (a contact at t = 0 that takes no energy): pushed into it
    (+5 N) it is held at every sample, its λ Pinocchio's Lagrange multiplier for the locked joint (1e-9); pulled
    off it (−5 N) it leaves at once, λ = 0."""
    native_only(monkeypatch)
    model = load_robot("rp_arm")
    oracle = PinocchioOracle(robot_path("rp_arm"), model.joint_names, model.gravity)
    run = simulate(model, [0.0, 0.8], [0.0, 0.0], duration=0.2, dt=1e-3, torque=[0.2, push], limits="stop")
    assert [(stop.t, stop.joints, stop.energy) for stop in run.stops] == [(0.0, ("d2",), 0.0)]
    if push < 0:
        assert np.all(run.reaction == 0.0) and np.all(np.diff(run.q[:, 1]) < 0)
        return
    assert np.all(run.q[:, 1] == 0.8) and np.all(run.reaction[:, 1] < 0)
    for k in range(0, len(run.t), 40):
        a, multiplier = pinocchio_held(oracle, run.q[k], run.qd[k], run.tau[k], np.array([False, True]))
        np.testing.assert_allclose(run.reaction[k, 1], multiplier[0], rtol=1e-9)
        np.testing.assert_allclose(run.qdd[k], a, rtol=1e-9, atol=1e-12)


def test_the_records_are_the_stops_a_user_reads(monkeypatch):
    """The record's layout (STOP_RECORD) read back as Stop: t, joints, sides and limits within the bounds."""
    native_only(monkeypatch)
    model = load_robot("rrr_arm")
    run = simulate(model, [0.0, 1.5, 2.0], [1.0, 2.0, 3.0], duration=0.5, dt=1e-3, limits="stop")
    lower, upper = limit_bounds(model)
    assert len(STOP_RECORD) == 6 and run.stops
    for stop in run.stops:
        for joint, side, limit in zip(stop.joints, stop.sides, stop.limits):
            j = model.joint_names.index(joint)
            assert limit == (upper[j] if side == "upper" else lower[j])
        assert 0 < stop.t < 0.5 and stop.member is None and stop.kinetic_after <= stop.kinetic_before
