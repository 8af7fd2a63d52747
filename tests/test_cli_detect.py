"""course_dynamics/cli/commands/detect.py: collisions in a log from the command line, its outputs and its errors."""
from __future__ import annotations

import json

import numpy as np
import pytest
from collisionlogs import EXAMPLE, FRICTION, PUSH, collision_log, write_log
from helpers import assert_one_line_error, run

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
    (("--link", "upper_arm_link"), ("upper_arm_link' is moved by 2 joint",)),
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
