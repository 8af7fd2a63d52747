"""course_dynamics/cli/commands/detect.py: collisions in a log from the command line, its outputs and its errors."""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from collisionlogs import EXAMPLE, FRICTION, PUSH, collision_log, reversal_log, write_log
from helpers import assert_one_line_error, run
from logmakers import write_ur_rtde

from course_dynamics import load_robot
from course_dynamics.tools.tables import read_table

UR5 = load_robot("ur5")
FRICTION_FLAGS = ("--viscous", ",".join(map(str, FRICTION.viscous)), "--coulomb", ",".join(map(str, FRICTION.coulomb)),
                  "--friction-width", str(FRICTION.smoothing))


def detect(*extra, log=EXAMPLE):
    return ("detect", "ur5", "--log", str(log)) + FRICTION_FLAGS + extra


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    return write_log(tmp_path_factory.mktemp("logs") / "clean.csv", collision_log(duration=4.0, pulses=(), seed=8),
                     UR5.joint_names)


def test_the_example_push_is_found_exit_1_with_its_wrench(capsys):
    code, out, _ = run(capsys, *detect("--link", "tool0"))
    assert code == 1
    assert "1 contact event found; the wrench is what the surroundings exert on tool0" in out
    row = next(line for line in out.splitlines() if line.startswith("1 "))
    assert row.split()[1:4] == ["2.0042", "2.3242", "2.0119"]


def test_json_holds_the_events_thresholds_and_the_wrench(capsys):
    code, out, _ = run(capsys, *detect("--link", "tool0", "--json"))
    doc = json.loads(out)
    assert code == 1 and doc["robot"] == "ur5" and doc["rows"] == 1001 and doc["link"] == "tool0"
    (event,) = doc["events"]
    assert 2.0 <= event["start"] <= event["detected"] <= 2.02 and 2.3 <= event["end"] < 2.4
    assert np.linalg.norm(np.subtract(event["force"], PUSH)) < 0.05 * np.linalg.norm(PUSH)
    assert set(doc["threshold"]) == set(UR5.joint_names) and all(v > 0 for v in doc["threshold"].values())
    assert doc["gain"]["elbow_joint"] == 100.0


def test_a_clean_log_exits_0(capsys, clean):
    code, out, _ = run(capsys, *detect(log=clean))
    assert code == 0 and "no contact found" in out


def test_unmodelled_friction_raises_the_thresholds_tenfold(capsys):
    """The same log without its friction: the residual holds the friction, and its noise estimate grows."""
    code, out, _ = run(capsys, "detect", "ur5", "--log", str(EXAMPLE), "--json")
    modelled = json.loads(run(capsys, *detect("--json"))[1])
    assert json.loads(out)["threshold"]["shoulder_pan_joint"] > 5 * modelled["threshold"]["shoulder_pan_joint"]


def test_out_writes_r_of_t_and_plot_draws_it(capsys, tmp_path):
    out, plot = tmp_path / "r.csv", tmp_path / "r.png"
    code, _, err = run(capsys, *detect("--out", str(out), "--plot", str(plot)))
    assert code == 1 and "wrote 1001 rows of r(t)" in err
    written = read_table(out)
    assert written.header == ("t",) + tuple(f"r_{j}" for j in UR5.joint_names)
    assert out.read_text().startswith("# course-dynamics detect ur5")
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    during = (written.data[:, 0] > 2.1) & (written.data[:, 0] < 2.3)
    assert written.data[during, 1].mean() < -20        # the push on the shoulder


def test_a_given_threshold_and_gain_are_used(capsys):
    code, out, _ = run(capsys, *detect("--threshold", "100", "--gain", "50", "--json"))
    doc = json.loads(out)
    assert code == 0 and doc["events"] == [] and doc["threshold"]["wrist_3_joint"] == 100.0
    assert doc["gain"]["wrist_3_joint"] == 50.0 and doc["sigma"]["wrist_3_joint"] is None


@pytest.mark.parametrize("extra, fragments", [
    (("--link", "no_such_link"), ("no link or frame 'no_such_link'",)),
    (("--link", "shoulder_link"), ("link 'shoulder_link': no joint with a measured torque moves its origin",)),
    (("--min-duration", "-1"), ("--min-duration must be a non-negative number of seconds, got '-1'",)),
    (("--min-duration", "nan"), ("--min-duration must be a non-negative number of seconds, got 'nan'",)),
    (("--gain", "0"), ("--gain must be positive",)),
    (("--gain", "1,2"), ("--gain takes one value or one per joint: 2 given",)),
    (("--threshold", "-1"), ("--threshold must be positive",)),
    (("--noise-window", "0.01"), ("quiet stretch",)),
    (("--json", "--out", "-"), ("--out - and --json",)),
    (("--plot", "r.gif"), ("r.gif: a plot is written as",)),
])
def test_bad_input_is_one_error_line(capsys, extra, fragments):
    code, _, err = run(capsys, *detect(*extra))
    assert_one_line_error(code, err, *fragments)


def test_a_log_without_measured_torques_is_refused_naming_it(capsys, tmp_path):
    path = write_log(tmp_path / "positions.csv", collision_log(duration=0.5, pulses=()), UR5.joint_names,
                     measured=False)
    code, _, err = run(capsys, *detect(log=path))
    assert_one_line_error(code, err, "positions.csv: no measured torques")


def test_nothing_is_written_on_bad_input(capsys, tmp_path):
    out = tmp_path / "r.csv"
    code, _, _ = run(capsys, *detect("--link", "nowhere", "--out", str(out)))
    assert code == 2 and not out.exists()


@pytest.mark.parametrize("robot, link, axis", [("two_link", "tool", "y of world"), ("rrr_arm", "forearm", "(")])
def test_a_link_seen_in_part_gets_the_force_it_sees_and_the_rest_named(capsys, tmp_path, robot, link, axis):
    """A planar arm's force in its plane; theta3 turns rrr_arm's forearm about its origin: two of three directions."""
    model = load_robot(robot)
    log = collision_log(duration=1.0, pulses=((0.4, 0.3),), seed=3, noise=False, model=model, link=link,
                        friction=None)
    path = write_log(tmp_path / f"{robot}.csv", log, model.joint_names)
    code, out, _ = run(capsys, "detect", robot, "--log", str(path), "--link", link, "--threshold", "0.001")
    assert code == 1 and f"event 1: no measured joint sees the force along {axis}" in out
    code, out, _ = run(capsys, "detect", robot, "--log", str(path), "--link", link, "--threshold", "0.001", "--json")
    (event,) = json.loads(out)["events"]
    assert len(event["unseen"]) == 1 and np.isfinite(event["condition"]) and event["moment"] is None
    u = np.array(event["unseen"][0])
    seen = np.subtract(PUSH, u * (u @ PUSH))
    assert np.linalg.norm(np.subtract(event["force"], seen)) < 0.01 * np.linalg.norm(seen)


def test_a_jittering_clock_is_taken_as_it_is_where_nothing_is_differentiated(capsys, tmp_path):
    """Stamps ±0.2 ms off a 500 Hz clock: detect (which needs no derivative) reads them; torques, which
    differentiates the rates, still asks for an even clock (--repair), and with it detect is unchanged."""
    path = write_log(tmp_path / "jitter.csv", reversal_log(4.0, seed=1, pulses=((2.0, 0.05),), jitter=2e-4),
                     UR5.joint_names)
    code, out, _ = run(capsys, *detect("--json", log=path))
    (event,) = json.loads(out)["events"]
    assert code == 1 and 2.0 <= event["start"] <= event["detected"] <= 2.02
    code, _, err = run(capsys, "torques", "ur5", "--log", str(path))
    assert_one_line_error(code, err, "the samples are not on one clock (median step 2 ms", "--repair resamples on the "
                          "median period")
    code, repaired, _ = run(capsys, *detect("--json", "--repair", log=path))
    assert code == 1 and json.loads(repaired)["events"] == json.loads(out)["events"]
    assert "repair: nothing is differentiated, so the log's stamps are taken as they are" in json.loads(repaired)[
        "notes"]


def test_a_huge_torque_beside_a_dropped_sample_is_named_at_its_line(capsys, tmp_path):
    log = collision_log(duration=1.0, pulses=())
    keep = np.arange(len(log.t)) != 100            # a dropped sample: the huge value is on line 102 (after the header)
    tau = log.tau.copy()
    tau[101, 0] = 1e300
    header = ["t"] + [f"{k}_{j}" for k in ("q", "qd", "tau_meas") for j in UR5.joint_names]
    path = tmp_path / "huge.csv"
    path.write_text(",".join(header) + "\n" + "\n".join(",".join(f"{x:.10g}" for x in row) for row in
                                                        np.column_stack([log.t, log.q, log.qd, tau])[keep]) + "\n")
    fragment = "line 102, column 'tau_meas_shoulder_pan_joint': a measured torque of 1e+300 is beyond any robot's"
    for command in (detect(log=path), ("torques", "ur5", "--log", str(path))):
        code, _, err = run(capsys, *command)
        assert_one_line_error(code, err, f"{path}: {fragment}")


def test_short_logs_and_gains_name_what_to_change(capsys, tmp_path):
    log = collision_log(duration=1.0, pulses=())
    rows = {}
    for count in (1, 2, 10):
        rows[count] = write_log(tmp_path / f"rows{count}.csv", collision_log(duration=(count - 1) / 250, pulses=()),
                                UR5.joint_names)
    for count in (1, 2):
        code, _, err = run(capsys, *detect(log=rows[count]))
        assert_one_line_error(code, err, f"rows{count}.csv: the quiet stretch", "--gain")
        assert "qdd" not in err and "at least 5" not in err
    code, _, err = run(capsys, *detect("--gain", "1e-6", log=rows[10]))
    assert_one_line_error(code, err, "rows10.csv: the quiet stretch from 5e+06 s", "holds 0 of the log's 10 samples",
                          "a larger gain (--gain, 1/s) settles sooner, or give a longer log")
    path = write_log(tmp_path / "second.csv", log, UR5.joint_names)
    code, out, _ = run(capsys, *detect("--noise-window", "1e9", log=path))
    assert code == 0 and "note: thresholds: |median r| + 6 sigma of r over the whole log" in out
    assert "(the quiet window, 1e+09 s, is longer than the" in out
    code, out, _ = run(capsys, *detect("--gain", "1e12", log=path))
    assert code in (0, 1) and "note: gain K = 1e+12 1/s is more than one over the sample step" in out


def test_an_rtde_recordings_events_are_from_its_start(capsys, tmp_path):
    log = collision_log(duration=4.0, pulses=((2.0, 0.3),), seed=0)
    k = np.array([13.0, 13.0, 9.3, 4.5, 4.5, 4.5])
    path = tmp_path / "robot_data.csv"
    write_ur_rtde(path, log.t + 3021.5, log.q, log.qd, current=log.tau / k)
    code, out, _ = run(capsys, *detect("--torque-constant", ",".join(map(str, k)), log=path))
    assert code == 1 and "note: t: timestamp (s), from the log's start (stamp 3021.500000 s)" in out
    row = next(line for line in out.splitlines() if line.startswith("1 "))
    assert 2.0 <= float(row.split()[1]) < 2.02


def test_the_guide_says_how_soon_the_example_push_is_found(capsys):
    guide = (Path(__file__).resolve().parent.parent / "docs" / "guides" / "engineer-detect.md").read_text()
    said = float(re.search(r"the push is found (\d+) ms after it starts", guide).group(1))
    code, out, _ = run(capsys, *detect("--json"))
    (event,) = json.loads(out)["events"]
    assert said == round(1000 * (event["detected"] - 2.0))


def test_a_clock_beyond_any_sample_step_is_refused_with_rates_logged(capsys, tmp_path):
    """Nothing is differentiated when the log has its rates, and the clock is checked all the same."""
    log = tmp_path / "huge.csv"
    t = np.arange(50) * 0.004 * 1e300
    rows = ["t,q_theta1,q_theta2,qd_theta1,qd_theta2,tau_meas_theta1,tau_meas_theta2"]
    rows += [f"{float(a)!r},0.1,0.2,0,0,1,2" for a in t]
    log.write_text("\n".join(rows) + "\n")
    for command, extra in (("detect", []), ("animate", ["--html", str(tmp_path / "a.html")])):  # every reader
        code, _, err = run(capsys, command, "two_link", "--log", str(log), *extra)
        assert_one_line_error(code, err, str(log), "the sample step 4e+297 s is outside 1e-9 s to 1e6 s")
    assert not (tmp_path / "a.html").exists()
