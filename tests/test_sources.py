"""course_dynamics/tools/sources.py: an RTDE recording, a table, ROS CSV exports and a bag of one motion agree."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import assert_agrees, assert_one_line_error, run
from logmakers import dropped, multisine, write_csv, write_ur_rtde

from course_dynamics import load_robot, robot_path
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.tools.sources import open_log, rtde_map
from course_dynamics.tools.tables import read_table

UR5 = load_robot("ur5")
MOTION = multisine(UR5, duration=2.0, rate=500.0, seed=11, start=1234.5)   # RTDE times count from controller start
K = np.array([13.0, 13.0, 9.3, 4.5, 4.5, 4.5])                                 # N m/A


@pytest.fixture(scope="module")
def oracle():
    return PinocchioOracle(robot_path("ur5"), UR5.joint_names, UR5.gravity)


@pytest.fixture
def rtde(tmp_path):
    """The motion as UR's recorder writes it: space separated, actual_q_i/actual_qd_i/actual_current_i, a word column."""
    path = tmp_path / "robot_data.csv"
    tau = inverse_dynamics(UR5, MOTION.q, MOTION.qd, MOTION.qdd)
    write_ur_rtde(path, MOTION.t, MOTION.q, MOTION.qd, current=tau / K, target_q=MOTION.q, mode_words=True)
    return path


def test_an_rtde_recording_is_recognised_and_mapped_joint_by_joint(rtde):
    source = open_log(rtde, UR5)
    assert source.format == "ur-rtde" and source.text == ("robot_mode_word",)
    assert source.implied == rtde_map(UR5, read_table(rtde).header, str(rtde))
    assert source.implied["q_elbow_joint"] == "actual_q_2" and source.implied["current_wrist_3_joint"] == "actual_current_5"
    assert "target_q_0" not in source.implied.values()


def test_rtde_torques_through_the_cli_agree_with_pinocchio_and_the_robots_currents(capsys, tmp_path, rtde, oracle):
    out = tmp_path / "tau.csv"
    code, report, _ = run(capsys, "torques", "ur5", "--log", str(rtde), "--torque-constant", ",".join(map(str, K)),
                          "--with-state", "--out", str(out))
    assert code == 0 and "note: read as a UR RTDE recording" in report
    assert "model against the robot (residual = measured - ours; measured: currents times torque constants)" in report
    table = read_table(out)
    cols = table.columns()
    q, qd, qdd = (np.column_stack([cols[f"{k}_{j}"] for j in UR5.joint_names]) for k in ("q", "qd", "qdd"))
    tau = np.column_stack([cols[f"tau_{j}"] for j in UR5.joint_names])
    np.testing.assert_allclose(qd, MOTION.qd, rtol=1e-11, atol=1e-12)            # read as logged, not derived
    for i in range(0, len(tau), 97):
        assert_agrees(tau[i], oracle.tau(q[i], qd[i], qdd[i]), what=f"row {i}")    # the dynamics, exactly
    exact = inverse_dynamics(UR5, MOTION.q, MOTION.qd, MOTION.qdd)
    assert np.abs(tau - exact).max() < 1e-4 * np.abs(exact).max()               # qdd differentiated from qd
    measured = np.column_stack([cols[f"tau_meas_{j}"] for j in UR5.joint_names])
    np.testing.assert_allclose(measured, exact, rtol=1e-9, atol=1e-9)


def test_the_same_motion_as_rtde_and_as_a_plain_csv_gives_the_same_torques(capsys, tmp_path, rtde):
    plain = tmp_path / "plain.csv"
    header = ["t"] + [f"q_{j}" for j in UR5.joint_names] + [f"qd_{j}" for j in UR5.joint_names]
    write_csv(plain, header, [MOTION.t] + list(MOTION.q.T) + list(MOTION.qd.T), fmt="{:.12g}")
    results = []
    for log in (rtde, plain):
        target = tmp_path / f"{log.stem}.tau.csv"
        code, _, _ = run(capsys, "torques", "ur5", "--log", str(log), "--out", str(target))
        assert code == 0
        results.append(read_table(target).data)
    results[1][:, 0] -= MOTION.t[0]          # the recorder's clock is read from the log's start, a table's t as it is
    np.testing.assert_allclose(results[0], results[1], rtol=1e-9, atol=1e-9 * np.abs(results[1]).max())


def test_an_rtde_recordings_times_are_from_its_start_with_the_start_stamp_in_a_note(capsys, tmp_path):
    path = tmp_path / "late.csv"
    t = MOTION.t - MOTION.t[0] + 3021.5
    write_ur_rtde(path, t, MOTION.q, MOTION.qd)
    source = open_log(path, UR5)
    np.testing.assert_allclose(source.columns["timestamp"], t - 3021.5, rtol=0, atol=1e-9)
    assert "t: timestamp (s), from the log's start (stamp 3021.500000 s)" in source.notes
    code, _, _ = run(capsys, "torques", "ur5", "--log", str(path), "--out", str(tmp_path / "tau.csv"))
    written = read_table(tmp_path / "tau.csv").data[:, 0]
    assert code == 0 and written[0] == 0 and written[-1] == pytest.approx(t[-1] - t[0], abs=1e-9)


def test_an_rtde_recording_of_another_arm_or_no_recording_is_refused(capsys, rtde, tmp_path):
    code, _, err = run(capsys, "torques", "panda", "--log", str(rtde), "--log-format", "ur-rtde")
    assert_one_line_error(code, err, "the recording has 6 joints (actual_q_0 … actual_q_5), robot 'panda' has 8")
    plain = tmp_path / "plain.csv"
    write_csv(plain, ["t", "a"], [MOTION.t, MOTION.q[:, 0]])
    code, _, err = run(capsys, "torques", "ur5", "--log", str(plain), "--log-format", "ur-rtde")
    assert_one_line_error(code, err, "not an RTDE recording (it needs the columns timestamp and actual_q_0")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(plain), "--topic", "/joint_states")
    assert_one_line_error(code, err, "--topic is for bags")


def test_a_word_column_is_ignored_until_it_is_read(capsys, rtde):
    code, out, _ = run(capsys, "torques", "ur5", "--log", str(rtde), "--columns")
    assert code == 0 and "robot_mode_word" in out and "(words: ignored)" in out and "(ur-rtde)" in out
    code, _, err = run(capsys, "torques", "ur5", "--log", str(rtde), "--map", "qd_elbow_joint=robot_mode_word")
    assert_one_line_error(code, err, "line 2, column 'robot_mode_word': 'running' is not a number (a column of words, "
                                     "read as qd_elbow_joint)")


def test_json_carries_the_residuals(capsys, rtde):
    code, out, _ = run(capsys, "torques", "ur5", "--log", str(rtde), "--torque-constant", ",".join(map(str, K)),
                       "--json")
    document = json.loads(out)
    assert code == 0 and document["residuals"]["source"] == "currents times torque constants"
    assert [r["joint"] for r in document["residuals"]["joints"]] == list(UR5.joint_names)
    assert all(r["r2"] > 0.999 for r in document["residuals"]["joints"])


def _torques_csv(capsys, tmp_path, robot, log, *extra):
    target = tmp_path / f"{log.name}.tau.csv"
    code, report, err = run(capsys, "torques", robot, "--log", str(log), "--with-state", "--out", str(target), *extra)
    assert code == 0, err
    return read_table(target).columns(), report


def test_a_ros1_bag_a_ros2_bag_an_mcap_and_a_csv_of_one_motion_give_the_same_torques(capsys, tmp_path, oracle):
    """JointState at 500 Hz, the joints shuffled in every message, a gripper joint the URDF lacks, efforts measured."""
    from bagmakers import FORMATS, stamped_seconds, write_joint_states

    tau = inverse_dynamics(UR5, MOTION.q, MOTION.qd, MOTION.qdd)
    outputs = {}
    for fmt in FORMATS:
        bag = write_joint_states(tmp_path / f"run-{fmt}", fmt, UR5.joint_names, MOTION.t, MOTION.q, MOTION.qd, tau)
        outputs[fmt], report = _torques_csv(capsys, tmp_path, "ur5", bag)
        assert "measured: tau_meas" in report
    plain = tmp_path / "run.csv"
    header = (["t"] + [f"q_{j}" for j in UR5.joint_names] + [f"qd_{j}" for j in UR5.joint_names]
              + [f"tau_meas_{j}" for j in UR5.joint_names])
    write_csv(plain, header, [stamped_seconds(MOTION.t)] + list(MOTION.q.T) + list(MOTION.qd.T) + list(tau.T),
              fmt="{:.17g}")
    outputs["csv"], _ = _torques_csv(capsys, tmp_path, "ur5", plain)
    reference = outputs["csv"]
    scale = max(np.abs(reference[f"tau_{j}"]).max() for j in UR5.joint_names)
    for fmt, columns in outputs.items():
        assert set(columns) == set(reference)
        for name in reference:
            np.testing.assert_allclose(columns[name], reference[name], rtol=0, atol=1e-9 * scale, err_msg=f"{fmt} {name}")
    columns = outputs["mcap"]
    q, qd, qdd = (np.column_stack([columns[f"{k}_{j}"] for j in UR5.joint_names]) for k in ("q", "qd", "qdd"))
    ours = np.column_stack([columns[f"tau_{j}"] for j in UR5.joint_names])
    for i in range(0, len(ours), 113):
        assert_agrees(ours[i], oracle.tau(q[i], qd[i], qdd[i]), what=f"mcap row {i}")


def test_a_franka_bag_gives_the_arms_torques_and_their_residual(capsys, tmp_path):
    from bagmakers import FRANKA_JOINT_STATES, FRANKA_TOPIC, write_franka

    panda = load_robot("panda")
    arm = panda.joint_names[:7]
    motion = multisine(panda, duration=1.0, rate=1000.0, seed=2, start=50.0)
    q, qd = motion.q[:, :7], motion.qd[:, :7]
    fingers = {f"q_{j}=0.02" for j in panda.joint_names[7:]}
    fingers_held = (len(q), panda.n - 7)  # the first finger (the second mimics it), held at 0.02 m
    tau = inverse_dynamics(panda, np.column_stack([q, np.full(fingers_held, 0.02)]),
                           np.column_stack([qd, np.zeros(fingers_held)]), np.column_stack([motion.qdd[:, :7],
                                                                                         np.zeros(fingers_held)]))[:, :7]
    bag = write_franka(tmp_path / "franka", "ros1", arm, motion.t, q, qd, tau)
    for topic in (FRANKA_TOPIC, FRANKA_JOINT_STATES):
        columns, report = _torques_csv(capsys, tmp_path, "panda", bag, "--topic", topic, "--set", ",".join(sorted(fingers)))
        assert "model against the robot" in report
        assert [f"tau_meas_{j}" in columns for j in arm] == [True] * 7
        ours = np.column_stack([columns[f"tau_{j}"] for j in arm])
        # against the exact motion's τ: Θ̈ is differentiated from the noise-free logged Θ̇ at 1 kHz (the dynamics
        # themselves are held to Pinocchio at 1e-9 above); the filter's error, measured, is 6e-9 of the peak
        np.testing.assert_allclose(ours, tau, rtol=0, atol=1e-7 * np.abs(tau).max())


def test_a_bag_topic_that_is_missing_is_named_with_the_bags_topics(capsys, tmp_path):
    from bagmakers import write_joint_states

    bag = write_joint_states(tmp_path / "run", "ros2-sqlite3", UR5.joint_names, MOTION.t[:50], MOTION.q[:50])
    code, _, err = run(capsys, "torques", "ur5", "--log", str(bag), "--topic", "/robot/joint_states")
    assert_one_line_error(code, err, "/robot/joint_states", "/joint_states")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(bag), "--decimal", "comma")
    assert_one_line_error(code, err, "a bag has no decimal separator to choose")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(bag), "--out", str(bag / "tau.csv"))
    assert_one_line_error(code, err, "the output would be written inside the input folder")
    assert not (bag / "tau.csv").exists()


@pytest.mark.parametrize("suffix", [".html", ".svg", ".png"])
def test_the_plot_draws_the_measured_torques_beneath_ours(capsys, tmp_path, suffix):
    from bagmakers import write_joint_states

    tau = inverse_dynamics(UR5, MOTION.q, MOTION.qd, MOTION.qdd)
    bag = write_joint_states(tmp_path / "run", "mcap", UR5.joint_names, MOTION.t[:400], MOTION.q[:400],
                             MOTION.qd[:400], tau[:400] + 0.5)
    plot = tmp_path / f"fit{suffix}"
    code, _, _ = run(capsys, "torques", "ur5", "--log", str(bag), "--plot", str(plot))
    assert code == 0 and plot.stat().st_size > 1000
    if suffix == ".png":
        assert plot.read_bytes().startswith(b"\x89PNG")
        return
    text = plot.read_text()
    assert "measured" in text and "residual rms 0.5" in text                  # the legend and each panel's title
    if suffix == ".html":
        assert "The model against the robot (measured: tau_meas)" in text and "<svg" in text


# ---- what a red-team pass found: each a regression test


def test_no_output_replaces_the_urdf_or_a_map_file(capsys, tmp_path, rtde):
    urdf = tmp_path / "arm.urdf"
    urdf.write_bytes(robot_path("ur5").read_bytes())
    before = urdf.read_bytes()
    code, _, err = run(capsys, "torques", str(urdf), "--log", str(rtde), "--out", str(urdf))
    assert_one_line_error(code, err, "the output would overwrite the input")
    mapping = tmp_path / "m.toml"
    mapping.write_text('t = "timestamp"\n')
    code, _, err = run(capsys, "torques", "ur5", "--log", str(rtde), "--map", str(mapping), "--out", str(mapping))
    assert_one_line_error(code, err, "the output would overwrite the input")
    assert urdf.read_bytes() == before and mapping.read_text() == 't = "timestamp"\n'


def test_a_loop_of_links_is_one_error(capsys, tmp_path, rtde):
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    for argv in (("--log", str(tmp_path / "a")), ("--log", str(rtde), "--out", str(tmp_path / "a"))):
        code, _, err = run(capsys, "torques", "ur5", *argv)
        assert_one_line_error(code, err, "a loop of symbolic links")


def test_a_clock_that_jitters_or_drifts_within_the_tolerance_is_read(capsys, tmp_path):
    for name, t in (("jitter", MOTION.t + np.random.default_rng(3).uniform(-0.05, 0.05, len(MOTION.t)) / 500),
                    ("drift", MOTION.t[0] + np.arange(len(MOTION.t)) * 1.06 / 500)):
        log = tmp_path / f"{name}.csv"
        header = ["t"] + [f"q_{j}" for j in UR5.joint_names]
        write_csv(log, header, [t] + list(MOTION.q.T), fmt="{:.12g}")
        code, _, err = run(capsys, "torques", "ur5", "--log", str(log))
        assert code == 0, err


EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("export, clock", [("ur5_rostopic.csv", "a rostopic CSV's stamps are read as nanoseconds"),
                                           ("ur5_plotjuggler.csv", "a PlotJuggler CSV's __time is in seconds")])
def test_a_ros_export_knows_its_clock_and_refuses_a_time_unit(capsys, export, clock):
    code, _, err = run(capsys, "torques", "ur5", "--log", str(EXAMPLES / export), "--time-unit", "ns")
    assert_one_line_error(code, err, f"{clock}; --time-unit is for tables")


def test_units_that_cannot_be_right_are_refused(capsys, tmp_path, rtde):
    code, _, err = run(capsys, "torques", "ur5", "--log", str(rtde), "--time-unit", "ms")
    assert_one_line_error(code, err, "a ur-rtde log's times are in seconds; --time-unit is for tables")
    degrees = tmp_path / "deg.csv"
    header = ["t"] + [f"q_{j}" for j in UR5.joint_names] + [f"qd_{j}" for j in UR5.joint_names]
    write_csv(degrees, header, [MOTION.t] + list(MOTION.q.T) + list(np.degrees(MOTION.qd).T), fmt="{:.12g}")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(degrees))
    assert_one_line_error(code, err, "times the rate of q_shoulder_pan_joint", "57.3 is degrees")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(rtde), "--set", "qd_elbow_joint=0.3")
    assert_one_line_error(code, err, "qd_elbow_joint can be set only for a joint whose q is set too")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(rtde), "--torque-constant", "0,0,0,0,0,0")
    assert_one_line_error(code, err, "none zero")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(rtde), "--resample", "1e7")
    assert_one_line_error(code, err, "resampling at 1e+07 Hz a log recorded at about 500 Hz")


def test_a_measured_torque_no_robot_could_make_is_refused_before_any_file_is_written(capsys, tmp_path):
    log = tmp_path / "huge.csv"
    tau = inverse_dynamics(UR5, MOTION.q, MOTION.qd, MOTION.qdd)
    tau[100, 2] = 1e160
    header = (["t"] + [f"q_{j}" for j in UR5.joint_names] + [f"qd_{j}" for j in UR5.joint_names]
              + [f"tau_meas_{j}" for j in UR5.joint_names])
    write_csv(log, header, [MOTION.t] + list(MOTION.q.T) + list(MOTION.qd.T) + list(tau.T), fmt="{:.12g}")
    out = tmp_path / "o.csv"
    code, _, err = run(capsys, "torques", "ur5", "--log", str(log), "--out", str(out), "--plot", str(tmp_path / "p.html"))
    assert_one_line_error(code, err, "line 102, column 'tau_meas_elbow_joint': a measured torque of 1e+160 is beyond "
                          "any robot's")
    assert not out.exists() and not (tmp_path / "p.html").exists()


def test_a_file_inside_a_ros2_bag_points_to_its_folder_and_clock_times_print_in_full(capsys, tmp_path):
    from bagmakers import write_joint_states

    tau = inverse_dynamics(UR5, MOTION.q, MOTION.qd, MOTION.qdd)
    bag = write_joint_states(tmp_path / "run", "ros2-sqlite3", UR5.joint_names, MOTION.t + 1.7e9, MOTION.q,
                             MOTION.qd, tau + 1.0)
    code, _, err = run(capsys, "torques", "ur5", "--log", str(next(bag.glob("*.db3"))))
    assert_one_line_error(code, err, "part of a ROS 2 bag", "give the bag's folder")
    code, out, _ = run(capsys, "torques", "ur5", "--log", str(bag))
    assert code == 0 and "1.7e+09" not in out and "1700001234." in out      # the residual's "at t", in full


def _ros_exports(tmp_path):
    """One motion (a message lost) as ``rostopic echo -p`` and PlotJuggler write it, and as our CSV with the times each
    reads (s from the log's start, as the tools' text gives them) and the values as each writes them."""
    from examplelogs import EPOCH_NS, write_plotjuggler, write_rostopic

    motion = dropped(MOTION, (400,))
    tau = inverse_dynamics(UR5, motion.q, motion.qd, motion.qdd)
    header = (["t"] + [f"q_{j}" for j in UR5.joint_names] + [f"qd_{j}" for j in UR5.joint_names]
              + [f"tau_meas_{j}" for j in UR5.joint_names])
    logs = {}
    rostopic = write_rostopic(tmp_path / "joint_states.csv", UR5.joint_names, motion.t, motion.q, motion.qd, tau)
    stamps = (EPOCH_NS + np.round((motion.t - motion.t[0]) * 1e9).astype(np.int64)).astype(float)
    logs[rostopic] = [(stamps - stamps[0]) * 1e-9] + list(motion.q.T) + list(motion.qd.T) + list(tau.T)
    juggler = write_plotjuggler(tmp_path / "plotjuggler.csv", UR5.joint_names, motion.t, motion.q, motion.qd, tau)
    seconds = np.array([float(f"{x:.6f}") for x in EPOCH_NS * 1e-9 + (motion.t - motion.t[0])])
    logs[juggler] = [seconds - seconds[0]] + [np.array([float(f"{v:.9f}") for v in x]) for x in
                                              list(motion.q.T) + list(motion.qd.T) + list(tau.T)]
    plains = {}
    for log, columns in logs.items():
        plains[log] = tmp_path / f"{log.stem}.plain.csv"
        write_csv(plains[log], header, columns, fmt="{:.17g}")
    return plains


def test_rostopic_and_plotjuggler_csvs_give_the_torques_of_the_same_motion_as_our_csv(capsys, tmp_path, oracle):
    """No map: the format by its header, joints by name (a gripper's ignored), ns stamps, times from the start."""
    for log, plain in _ros_exports(tmp_path).items():
        ours, report = _torques_csv(capsys, tmp_path, "ur5", log)
        reference, _ = _torques_csv(capsys, tmp_path, "ur5", plain)
        assert "measured: tau_meas" in report and "over 2 s" in report
        assert ours["t"][0] == 0 and set(ours) == set(reference)
        scale = max(np.abs(reference[f"tau_{j}"]).max() for j in UR5.joint_names)
        for name in reference:
            np.testing.assert_allclose(ours[name], reference[name], rtol=0, atol=1e-9 * scale, err_msg=f"{log} {name}")
        q, qd, qdd = (np.column_stack([ours[f"{k}_{j}"] for j in UR5.joint_names]) for k in ("q", "qd", "qdd"))
        tau = np.column_stack([ours[f"tau_{j}"] for j in UR5.joint_names])
        for i in range(0, len(tau), 151):
            assert_agrees(tau[i], oracle.tau(q[i], qd[i], qdd[i]), what=f"{log.name} row {i}")


def test_columns_shows_how_a_rostopic_and_a_plotjuggler_csv_are_read(capsys, tmp_path):
    rostopic, juggler = _ros_exports(tmp_path)
    code, out, err = run(capsys, "torques", "ur5", "--log", str(rostopic), "--columns")
    rows = {line.split()[0]: " ".join(line.split()[1:]) for line in out.splitlines() if line.startswith("field.")}
    assert code == 0 and "(rostopic)" in out, err
    assert rows["field.header.stamp"] == "t" and rows["field.header.frame_id"] == "(ignored)"
    assert rows["field.position2"] == "q_shoulder_pan_joint" and rows["field.effort0"] == "tau_meas_elbow_joint"
    assert rows["field.position6"] == "(ignored)" and rows["field.name0"] == "(words: ignored)"
    code, out, err = run(capsys, "torques", "ur5", "--log", str(juggler), "--columns")
    assert code == 0 and "(plotjuggler)" in out, err
    rows = {line.split()[0]: " ".join(line.split()[1:]) for line in out.splitlines() if line.startswith(("/", "__"))}
    assert rows["__time"] == "t" and rows["/joint_states/wrist_3_joint/velocity"] == "qd_wrist_3_joint"
    assert rows["/gripper/joint_states/finger_joint/position"] == rows["/joint_states/header/stamp"] == "(ignored)"


def test_a_ros_export_of_another_robot_or_a_table_with_an_empty_cell_is_refused(capsys, tmp_path):
    rostopic, _ = _ros_exports(tmp_path)
    code, _, err = run(capsys, "torques", "panda", "--log", str(rostopic))
    assert_one_line_error(code, err, "joint_states.csv: none of the rostopic CSV's joints (elbow_joint, "
                                     "shoulder_lift_joint, ", "is one of robot 'panda'")
    plain = tmp_path / "gap.csv"
    plain.write_text("t,q_theta1,q_theta2\n0,1,2\n0.1,,2\n")
    code, _, err = run(capsys, "torques", "two_link", "--log", str(plain))
    assert_one_line_error(code, err, "gap.csv: line 3, column 'q_theta1': empty cell")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(plain), "--log-format", "plotjuggler")
    assert_one_line_error(code, err, "not a PlotJuggler CSV (its first column must be __time)")
    twice = tmp_path / "two_topics.csv"
    twice.write_text("__time,/joint_states/elbow_joint/position,/joint_states_desired/elbow_joint/position\n"
                     "1700000000.000512,0.100000000,0.100000000\n")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(twice))
    assert_one_line_error(code, err, "columns '/joint_states/elbow_joint/position' and "
                                     "'/joint_states_desired/elbow_joint/position' are both the position of joint "
                                     "'elbow_joint' (two topics)")
