"""Commands chain: what one command writes, or any log torques reads, another reads (tools/motion.py).

animate --log and simulate --torque-log read through the one reader torques --log uses: tables, UR RTDE
recordings, ROS bags and MCAP files, and the files torques --out, simulate --out and excite --out write.
"""
from __future__ import annotations

import json

import numpy as np
from helpers import ROOT, assert_one_line_error, run

from course_dynamics import load_robot
from course_dynamics.tools.motion import read_motion
from course_dynamics.tools.sources import open_log
from course_dynamics.tools.tables import read_table

EXAMPLES = ROOT / "examples"


def test_animate_plays_a_torques_out_file_with_its_state_and_torques(capsys, tmp_path):
    tau, page = tmp_path / "tau.csv", tmp_path / "tau.html"
    code, _, err = run(capsys, "torques", "ur5", "--log", str(EXAMPLES / "ur5_log.csv"), "--map",
                       str(EXAMPLES / "ur5_log_columns.toml"), "--out", str(tau), "--with-state")
    assert code == 0, err
    written = read_table(tau).columns()
    assert "tau_meas_shoulder_pan_joint" not in written and "qdd_elbow_joint" in written
    code, out, err = run(capsys, "animate", "ur5", "--log", str(tau), "--html", str(page), "--torques", "--json",
                         "--geometry", "stick")
    assert code == 0, err
    assert json.loads(out)["samples"] == len(written["t"]) == 2001 and page.stat().st_size > 10_000
    motion = read_motion(load_robot("ur5"), open_log(tau, load_robot("ur5")))   # what animate drew
    assert motion.tau_from == "tau"
    np.testing.assert_array_equal(motion.tau[:, 2], written["tau_elbow_joint"])
    np.testing.assert_array_equal(motion.q[:, 0], written["q_shoulder_pan_joint"])


def test_animate_plays_a_bag_and_measured_torques_files(capsys, tmp_path):
    ur5 = load_robot("ur5")
    bag = EXAMPLES / "ur5_joint_states.mcap"
    messages = len(open_log(bag, ur5).columns["t"])
    code, out, err = run(capsys, "animate", "ur5", "--log", str(bag), "--html", str(tmp_path / "bag.html"), "--json",
                         "--geometry", "stick")
    assert code == 0, err
    assert json.loads(out)["samples"] == messages > 400
    assert "ignored: gripper_finger_joint" in err    # the bag's own note, as torques prints it
    tau = tmp_path / "tau.csv"   # torques of a bag: the measured torques come along as tau_meas_<joint>
    assert run(capsys, "torques", "ur5", "--log", str(bag), "--out", str(tau), "--with-state")[0] == 0
    assert "tau_meas_wrist_3_joint" in tau.read_text()
    code, out, err = run(capsys, "animate", "ur5", "--trajectory", str(tau), "--html", str(tmp_path / "t.html"),
                         "--torques", "--json", "--geometry", "stick")
    assert code == 0, err   # once "unexpected columns: tau_meas_shoulder_pan_joint, …"
    assert json.loads(out)["samples"] == len(read_table(tau).columns()["t"]) == 501   # three dropped samples filled


def test_simulate_applies_the_torques_a_torques_out_file_holds(capsys, tmp_path):
    first, tau, second = tmp_path / "first.csv", tmp_path / "tau.csv", tmp_path / "second.csv"
    motion = ["simulate", "two_link", "--q0", "0.3,-0.2", "--duration", "1", "--dt", "0.005", "--quiet"]
    assert run(capsys, *motion, "--torque", "2,-0.5", "--out", str(first))[0] == 0
    code, _, err = run(capsys, "torques", "two_link", "--log", str(first), "--out", str(tau), "--with-state")
    assert code == 0, err
    recovered = read_table(tau).columns()
    np.testing.assert_allclose(recovered["tau_theta1"], 2.0, atol=1e-9)    # the logged qd, qdd: nothing differentiated
    code, _, err = run(capsys, *motion, "--torque-log", str(tau), "--out", str(second))
    assert code == 0, err
    a, b = (np.genfromtxt(p, delimiter=",", names=True) for p in (first, second))
    np.testing.assert_allclose(b["q_theta1"], a["q_theta1"], atol=1e-9)
    np.testing.assert_allclose(b["tau_theta2"], -0.5, atol=1e-9)


def test_simulate_takes_a_bags_measured_torques_from_its_first_message(capsys, tmp_path):
    code, out, err = run(capsys, "simulate", "ur5", "--q0", "0,-1.2,1,0,0.5,0", "--duration", "0.2", "--dt", "0.01",
                         "--torque-log", str(EXAMPLES / "ur5_joint_states.mcap"), "--out", str(tmp_path / "s.csv"),
                         "--quiet", "--json")
    assert code == 0, err
    assert "the applied torques are the ones the robot measured" in err and "counted from its first sample" in err
    ur5 = load_robot("ur5")
    effort = read_motion(ur5, open_log(EXAMPLES / "ur5_joint_states.mcap", ur5), torques=True).tau
    applied = np.genfromtxt(tmp_path / "s.csv", delimiter=",", names=True)
    assert applied["tau_elbow_joint"][0] == effort[0, 2]


def test_a_torque_log_without_torques_is_one_error_line(capsys, tmp_path):
    code, _, err = run(capsys, "simulate", "ur5", "--q0", "0,0,0,0,0,0", "--duration", "0.1", "--dt", "0.01",
                       "--torque-log", str(EXAMPLES / "ur5_log.csv"), "--map", str(EXAMPLES / "ur5_log_columns.toml"),
                       "--out", str(tmp_path / "s.csv"))
    assert_one_line_error(code, err, "ur5_log.csv", "missing columns: tau_shoulder_pan_joint", "tau_meas_<joint>")
    assert not (tmp_path / "s.csv").exists()
