"""course_dynamics/tools/residuals.py: our model against torques a robot measured, here a perturbed robot."""
from __future__ import annotations

import numpy as np
import pytest
from logmakers import multisine, noisy

from course_dynamics import InputError, load_robot
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.tools.loads import Payload, with_payload
from course_dynamics.tools.logs import torques_from_log
from course_dynamics.tools.residuals import residual_report

UR5 = load_robot("ur5")
MOTION = multisine(UR5, duration=2.0, rate=250.0, seed=5)
# "the robot": the URDF with a 1.5 kg tool the URDF does not have
ROBOT = with_payload(UR5, Payload(mass=1.5, link="tool0", com=(0.0, 0.0, 0.05)))


def logged(measured=None, currents=None):
    data = {"t": MOTION.t}
    for i, j in enumerate(UR5.joint_names):
        data |= {f"q_{j}": MOTION.q[:, i], f"qd_{j}": MOTION.qd[:, i], f"qdd_{j}": MOTION.qdd[:, i]}
        if measured is not None:
            data[f"tau_meas_{j}"] = measured[:, i]
        if currents is not None:
            data[f"current_{j}"] = currents[:, i]
    return data


def test_a_perfect_model_explains_everything():
    tau = inverse_dynamics(UR5, MOTION.q, MOTION.qd, MOTION.qdd)
    report = torques_from_log(UR5, logged(measured=tau)).residuals
    assert report.source == "tau_meas" and [r.joint for r in report.joints] == list(UR5.joint_names)
    assert all(r.rms < 1e-9 * r.rms_measured and r.r2 > 1 - 1e-12 for r in report.joints)


def test_a_missing_tool_shows_in_the_residual_of_the_joints_that_carry_it():
    measured = noisy(inverse_dynamics(ROBOT, MOTION.q, MOTION.qd, MOTION.qdd), 0.05, seed=1)
    result = torques_from_log(UR5, logged(measured=measured))
    rows = {r.joint: r for r in result.residuals.joints}
    missing = measured - result.tau                                      # what the tool adds, plus noise
    for i, j in enumerate(UR5.joint_names):
        assert rows[j].rms == pytest.approx(np.sqrt(np.mean(missing[:, i] ** 2)), rel=1e-12)
        assert rows[j].peak == pytest.approx(np.abs(missing[:, i]).max(), rel=1e-12)
        spread = np.sum((measured[:, i] - measured[:, i].mean()) ** 2)
        assert rows[j].r2 == pytest.approx(1 - np.sum(missing[:, i] ** 2) / spread, rel=1e-12)
    assert rows["shoulder_lift_joint"].rms > 20 * 0.05                   # the tool's weight, far above the noise
    header, data = result.table()
    assert header[-6:] == [f"tau_meas_{j}" for j in UR5.joint_names]
    np.testing.assert_array_equal(data[:, -6:], measured)


def test_currents_times_torque_constants_are_the_measured_torques():
    tau = inverse_dynamics(ROBOT, MOTION.q, MOTION.qd, MOTION.qdd)
    k = np.array([13.0, 13.0, 9.3, 4.5, 4.5, 4.5])                      # N m/A, per joint
    result = torques_from_log(UR5, logged(currents=tau / k), torque_constants=k)
    assert result.residuals.source == "currents times torque constants"
    np.testing.assert_allclose(result.log.measured, tau, rtol=1e-12)
    without = torques_from_log(UR5, logged(currents=tau / k))
    assert without.residuals is None and any("--torque-constant" in n for n in without.notes)
    with pytest.raises(InputError, match="torque constants: 6 finite numbers, none zero, are needed"):
        torques_from_log(UR5, logged(currents=tau / k), torque_constants=[1.0, 2.0])
    with pytest.raises(InputError, match="the log has no motor currents"):
        torques_from_log(UR5, logged(), torque_constants=k)


def test_only_measured_joints_are_reported_and_a_constant_torque_has_no_r2():
    t = np.linspace(0, 1, 11)
    predicted = np.column_stack([t, t, t])
    measured = np.column_stack([t + 0.1, np.full_like(t, 2.0), np.full_like(t, np.nan)])
    report = residual_report(("a", "b", "c"), t, predicted, measured, "tau_meas")
    assert [r.joint for r in report.joints] == ["a", "b"]
    assert report.joints[0].rms == pytest.approx(0.1) and report.joints[0].r2 == pytest.approx(1 - 0.01 / np.var(t + 0.1))
    assert report.joints[1].r2 is None and report.record()["joints"][1]["r2"] is None
