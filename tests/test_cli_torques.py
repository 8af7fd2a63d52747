"""course_dynamics/cli/commands/torques.py: the engineer's path from a real log to torques and a limits report."""
from __future__ import annotations

import json
import os
import re
import stat

import numpy as np
import pytest
from helpers import ROOT, assert_one_line_error, run

from course_dynamics import load_robot
from course_dynamics.core.friction import Friction
from course_dynamics.tools.loads import Payload, Wrench
from course_dynamics.tools.columns import parse_column_map
from course_dynamics.tools.logs import torques_from_log
from course_dynamics.tools.tables import read_table

LOG = ROOT / "examples" / "ur5_log.csv"
MAP = ROOT / "examples" / "ur5_log_columns.toml"


def sample(*extra):
    return ("torques", "ur5", "--log", str(LOG), "--map", str(MAP)) + extra


def test_the_sample_log_positions_only_semicolons_crlf_extra_columns(capsys, tmp_path):
    out = tmp_path / "tau.csv"
    code, report, err = run(capsys, *sample("--out", str(out)))
    assert code == 0 and "every joint stays within its limits" in report
    assert "note: qd: first Savitzky-Golay derivative" in report
    text = out.read_text()
    assert text.startswith("# course-dynamics torques ur5") and "# qdd: second Savitzky-Golay" in text
    written = read_table(out)
    model = load_robot("ur5")
    expected = torques_from_log(model, read_table(LOG), columns=parse_column_map(str(MAP)))
    assert written.header == ("t",) + tuple(f"tau_{j}" for j in model.joint_names)
    np.testing.assert_array_equal(written.data[:, 1:], expected.tau)
    assert f"wrote {len(expected.t)} rows" in err


def test_a_payload_that_overloads_the_shoulder_exits_1_with_json(capsys):
    code, out, _ = run(capsys, *sample("--payload", "20@tool0", "--json"))
    assert code == 1
    doc = json.loads(out)
    assert doc["exceeded"] is True and doc["rows"] == 2001
    assert {v["joint"] for v in doc["violations"]} == {"shoulder_lift_joint"}
    assert all(v["kind"] == "effort" and v["peak"] > v["limit"] == 150 for v in doc["violations"])
    shoulder = next(j for j in doc["joints"] if j["joint"] == "shoulder_lift_joint")
    assert shoulder["effort_used"] > 1 and shoulder["velocity_limit"] == 3.15


def test_columns_lists_what_is_used(capsys):
    code, out, _ = run(capsys, *sample("--columns"))
    assert code == 0
    assert re.search(r"\njoint1_pos +q_shoulder_pan_joint\n", out) and re.search(r"\nmotor_temp_c +\(ignored\)\n", out)


def test_columns_follows_the_plan_the_reader_would(capsys):
    """--columns refuses a map the reader would refuse, and says which rates a constant joint holds at zero."""
    code, _, err = run(capsys, *sample("--columns", "--map", "qd_wrist_3_joint=no_such_column"))
    assert_one_line_error(code, err, "no column 'no_such_column' (mapped from qd_wrist_3_joint)")
    code, out, _ = run(capsys, "torques", "ur5", "--log", str(LOG), "--columns", "--map", "t=time_s",
                       "--set", "q_wrist_3_joint=0.5")
    assert code == 0 and "q_wrist_3_joint = 0.5 throughout (--set)" in out
    assert "qd_wrist_3_joint" not in out.split("differentiated:")[-1]


def test_out_dash_streams_the_csv_and_moves_the_report_to_stderr(capsys):
    code, out, err = run(capsys, *sample("--out", "-"))
    assert code == 0
    lines = [line for line in out.splitlines() if not line.startswith("#")]
    assert lines[0].startswith("t,tau_shoulder_pan_joint") and len(lines) == 2002
    assert "every joint stays within its limits" in err


def test_out_onto_a_device_writes_into_it_and_never_replaces_it(capsys):
    before = os.stat("/dev/null")
    code, _, _ = run(capsys, *sample("--out", "/dev/null"))
    after = os.stat("/dev/null")
    assert code == 0 and stat.S_ISCHR(after.st_mode) and after.st_ino == before.st_ino


@pytest.mark.parametrize("suffix, magic", [(".png", b"\x89PNG"), (".svg", b"<?xml"), (".html", b"<!DOCTYPE html>")])
def test_plots(capsys, tmp_path, suffix, magic):
    plot = tmp_path / f"tau{suffix}"
    code, _, _ = run(capsys, *sample("--payload", "20@tool0", "--plot", str(plot)))
    assert code == 1 and plot.read_bytes().startswith(magic)
    if suffix == ".html":
        page = plot.read_text()
        assert "<svg" in page and "shoulder_lift_joint" in page and "A limit is exceeded." in page


def test_a_bad_plot_name_fails_before_anything_is_written(capsys, tmp_path):
    out = tmp_path / "tau.csv"
    code, _, err = run(capsys, *sample("--out", str(out), "--plot", str(tmp_path / "tau.gif")))
    assert_one_line_error(code, err, "tau.gif: a plot is written as .png, .svg, .html")
    assert list(tmp_path.iterdir()) == []


def test_physics_options_equal_the_api(capsys, tmp_path):
    out = tmp_path / "tau.csv"
    code, _, _ = run(capsys, *sample("--out", str(out), "--gravity", "0,-2,-9", "--friction", "urdf", "--coulomb",
                                     "1,1,1,0.5,0.5,0.5", "--payload", "2.5@wrist_3_link,0,0.01,0.05",
                                     "--payload-size", "0.1,0.1,0.05", "--wrench", "tool0:0,0,-15,0,0.5,0",
                                     "--smooth", "15"))
    assert code == 0
    model = load_robot("ur5")
    expected = torques_from_log(
        model.with_gravity([0, -2, -9]), read_table(LOG), columns=parse_column_map(str(MAP)), window=15,
        friction=Friction(viscous=Friction.from_urdf(model).viscous, coulomb=[1, 1, 1, 0.5, 0.5, 0.5]),
        payload=Payload(2.5, "wrist_3_link", (0, 0.01, 0.05), (0.1, 0.1, 0.05)),
        wrench=Wrench("tool0", (0, 0, -15), (0, 0.5, 0)))
    np.testing.assert_array_equal(read_table(out).data[:, 1:], expected.tau)


def test_a_log_without_times_takes_dt_and_with_state_writes_the_state(capsys, tmp_path):
    log, out = tmp_path / "log.tsv", tmp_path / "tau.csv"
    q = 0.1 * np.sin(np.arange(50)[:, None] * 0.05 * np.array([1.0, 2.0]))
    log.write_text("q_theta1\tq_theta2\n" + "\n".join(f"{a}\t{b}" for a, b in q) + "\n")
    code, _, _ = run(capsys, "torques", "two_link", "--log", str(log), "--dt", "0.01", "--with-state", "--out", str(out))
    assert code == 0
    table = read_table(out)
    assert table.header[:3] == ("t", "q_theta1", "q_theta2") and table.header[-1] == "tau_theta2"
    np.testing.assert_allclose(table.column("t"), np.arange(50) * 0.01)


@pytest.mark.parametrize("extra, fragment", [
    (("--payload", "heavy"), "--payload must be MASS[@LINK][,CX,CY,CZ]"),
    (("--payload", "2@tool0,1,2"), "the centre of mass needs three numbers"),
    (("--payload", "-2"), "payload mass must be a positive number"),
    (("--payload", "2@nowhere"), "robot 'ur5' has no link or frame 'nowhere'"),
    (("--payload", "1", "--payload", "2", "--payload-size", "1,1,1"), "--payload-size describes one payload"),
    (("--map", "t=time_s", "--map", "t=time_s"), "--map: 't' is mapped twice"),
    (("--set", "q_wrist_3_joint"), "--set entries must be OURS=VALUE"),
    (("--set", "q_wrist_3_joint=0"), "q_wrist_3_joint is both given a constant value and read"),
    (("--time-unit", "h"), "argument --time-unit: invalid choice"),
    (("--payload-size", "1,1,1"), "--payload-size needs --payload"),
    (("--wrench", "tool0:1,2"), "--wrench must be LINK:FX,FY,FZ[,NX,NY,NZ]"),
    (("--wrench", "nowhere:1,2,3"), "no link or frame 'nowhere'"),
    (("--smooth", "8"), "odd number of samples"),
    (("--map", "q_elbow=joint3_pos"), "'q_elbow' is none of our columns"),
    (("--map", "q_elbow_joint"), "must be ours=theirs"),
    (("--log-dt", "0.002"), "has a time column; dt (--log-dt) is only for logs without one"),
    (("--gravity", "0,0"), "--gravity needs three finite numbers"),
    (("--out", "-", "--json"), "--out - and --json both want standard output"),
])
def test_bad_options(capsys, tmp_path, extra, fragment):
    out = tmp_path / "tau.csv"
    code, _, err = run(capsys, *sample("--out", str(out), *extra))
    assert_one_line_error(code, err, fragment)
    assert not out.exists()


def test_positions_only_without_a_map_names_the_missing_columns(capsys):
    code, _, err = run(capsys, "torques", "ur5", "--log", str(LOG))
    assert_one_line_error(code, err, str(LOG), "missing columns: q_shoulder_pan_joint", "a column map can name")


def test_an_output_never_overwrites_the_log_or_another_output(capsys, tmp_path):
    log = tmp_path / "log.csv"
    log.write_bytes(LOG.read_bytes())
    code, _, err = run(capsys, "torques", "ur5", "--log", str(log), "--map", str(MAP), "--out", str(log))
    assert_one_line_error(code, err, "the output would overwrite the input")
    assert log.read_bytes() == LOG.read_bytes()
    code, _, err = run(capsys, *sample("--out", str(tmp_path / "x.png"), "--plot", str(tmp_path / "x.png")))
    assert_one_line_error(code, err, "named for two outputs")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log.csv"]


def test_repeated_payloads_and_wrenches_all_count(capsys, tmp_path):
    out = tmp_path / "tau.csv"
    code, _, _ = run(capsys, *sample("--out", str(out), "--payload", "2", "--payload", "1@wrist_1_link,0,0,0.1",
                                     "--wrench", "tool0:0,0,-15", "--wrench", "wrist_2_link:3,0,0,0,0,1"))
    assert code == 0
    model = load_robot("ur5")
    expected = torques_from_log(model, read_table(LOG), columns=parse_column_map(str(MAP)),
                                payload=[Payload(2.0), Payload(1.0, "wrist_1_link", (0, 0, 0.1))],
                                wrench=[Wrench("tool0", (0, 0, -15)), Wrench("wrist_2_link", (3, 0, 0), (0, 0, 1))])
    np.testing.assert_array_equal(read_table(out).data[:, 1:], expected.tau)
    header = [line for line in out.read_text().splitlines() if line.startswith("#")]
    assert "# payload 2 kg at tool0, centre [0.0, 0.0, 0.0] m, point mass" in header
    assert sum(line.startswith("# wrench at") for line in header) == 2


def test_a_controller_export_in_milliseconds_with_unlogged_fingers(capsys, tmp_path):
    """Panda logs record seven arm joints; the fingers are held with --set, t is in ms, lines end in ';'."""
    model = load_robot("panda")
    arm = [j for j in model.joint_names if "finger" not in j]
    t = np.arange(0, 2, 0.004)
    q = 0.2 * np.sin(np.outer(t, np.arange(1, 8))) + [0, -0.8, 0, -2.3, 0, 1.6, 0.8]
    lines = ["time_ms;" + ";".join(f"q{i + 1}" for i in range(7)) + ";"]
    lines += [f"{1000 * a:.0f};" + ";".join(repr(float(x)) for x in row) + ";" for a, row in zip(t, q)]
    log, out = tmp_path / "franka.csv", tmp_path / "tau.csv"
    log.write_text("\n".join(lines) + "\n")
    mapping = ",".join(["t=time_ms"] + [f"q_{j}=q{i + 1}" for i, j in enumerate(arm)])
    argv = ["torques", "panda", "--log", str(log), "--map", mapping, "--out", str(out),
            "--set", "q_panda_finger_joint1=0.02"]  # the second finger mimics the first: no column of its own
    code, report, err = run(capsys, *argv)
    assert f"warning: {log}: the samples are 4 s apart; if t is not in seconds, give --time-unit" in err
    for command, option in (("identify", "--out"), ("detect", "--out"), ("animate", "--html")):  # every reader warns
        _, _, err = run(capsys, command, *argv[1:4], "--map", mapping, "--set", "q_panda_finger_joint1=0.02",
                        option, str(tmp_path / f"{command}.out"))
        assert f"warning: {log}: the samples are 4 s apart" in err, (command, err)
    code, report, err = run(capsys, *argv, "--time-unit", "ms")
    assert "warning" not in err and "500 samples over 1.996 s" in report
    fingers = {f"q_{j}": 0.02 for j in model.joint_names if "finger" in j}
    expected = torques_from_log(model, {"t": t, **{f"q_{j}": q[:, i] for i, j in enumerate(arm)}}, constants=fingers)
    np.testing.assert_allclose(read_table(out).data[:, 1:], expected.tau, rtol=1e-9, atol=1e-9)


def test_columns_names_what_is_missing(capsys):
    code, out, _ = run(capsys, "torques", "panda", "--log", str(LOG), "--columns", "--map", "t=time_s")
    assert code == 0
    assert "missing (map them, or --set a constant): q_panda_joint1," in out
    assert "qd, qdd: differentiated from q for every joint" in out


def test_streamed_csv_comes_after_the_report(capsys):
    code, out, err = run(capsys, *sample("--out", "-", "--payload", "20"))
    assert code == 1 and "a limit is exceeded" in err and out.lstrip().startswith("#")


def cli(*argv, timeout=60):
    """The CLI in a child process with 3 GiB of address space: a log read whole fails fast instead of filling memory."""
    import resource
    import subprocess
    import sys

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, 3 * 2**30))

    return subprocess.run([sys.executable, "-m", "course_dynamics.cli", *argv], capture_output=True, text=True,
                          timeout=timeout, preexec_fn=limit)


@pytest.mark.parametrize("special, fragment", [
    ("/dev/zero", "/dev/zero: not a regular file (a character device), not a table"),
    ("fifo", "log.csv: not a regular file (a named pipe), not a table"),
])
def test_a_log_that_is_a_device_or_a_pipe_is_one_error_line_at_once(tmp_path, special, fragment):
    log = tmp_path / "log.csv"
    if special == "fifo":
        os.mkfifo(log)  # nobody writes: reading would wait forever
    result = cli("torques", "two_link", "--log", "/dev/zero" if special == "/dev/zero" else str(log),
                 "--out", str(tmp_path / "tau.csv"))
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and fragment in result.stderr, result.stderr
    assert not (tmp_path / "tau.csv").exists()


def test_a_log_larger_than_memory_allows_says_how_much_it_would_need(capsys, tmp_path, monkeypatch):
    monkeypatch.setattr("course_dynamics.base.resources.memory_budget", lambda: 2**20)
    out = tmp_path / "tau.csv"
    code, _, err = run(capsys, *sample("--out", str(out)))
    assert_one_line_error(code, err, str(LOG), "rows of 9 values: reading and using them would need about",
                          "more than half of this machine's 2 MiB")
    assert not out.exists()


def test_an_ambiguous_decimal_separator_is_refused_unless_given(capsys, tmp_path):
    log = tmp_path / "log.csv"
    rows = "".join(f"{k};{k + 1},{k:03d};0\n" for k in range(20))  # 1,000 2,001 …: decimal or thousands?
    log.write_text("t;q_theta1;q_theta2\n" + rows)
    code, _, err = run(capsys, "torques", "two_link", "--log", str(log))
    assert_one_line_error(code, err, f"{log}: line 2, column 'q_theta1': '1,000' could be 1.000 with a decimal comma "
                                     "or 1000 with a thousands separator", "--decimal comma")
    code, out, err = run(capsys, "torques", "two_link", "--log", str(log), "--decimal", "comma", "--out", "-")
    assert code in (0, 1), err
    table = np.loadtxt(out.splitlines(), delimiter=",", skiprows=next(i for i, line in enumerate(out.splitlines())
                                                                      if line.startswith("t,")) + 1)
    assert len(table) == 20


@pytest.mark.parametrize("plot", ["tau.png", "tau.html"])
def test_a_plot_of_more_joints_than_panels_is_refused_before_reading_the_log(capsys, tmp_path, plot):
    """One panel per joint, at most 24: a 25-joint chain's --plot is refused in one line, and nothing is written."""
    from helpers import chain_urdf

    from course_dynamics.output.plotting import MAX_PANELS

    urdf = tmp_path / "chain25.urdf"
    urdf.write_text(chain_urdf(MAX_PANELS + 1))
    log = tmp_path / "log.csv"
    t = np.arange(0, 1, 0.01)
    log.write_text("t," + ",".join(f"q_joint{i}" for i in range(1, 26)) + "\n"
                   + "".join(f"{x:.2f}," + ",".join(f"{0.1 * np.sin(x + i):.6f}" for i in range(25)) + "\n" for x in t))
    out, picture = tmp_path / "tau.csv", tmp_path / plot
    code, _, err = run(capsys, "torques", str(urdf), "--log", str(log), "--out", str(out), "--plot", str(picture))
    assert_one_line_error(code, err, "--plot draws one panel per joint, at most 24", "robot 'chain' has 25 joints")
    assert not out.exists() and not picture.exists()


def test_a_sample_step_at_the_ends_of_its_range_is_taken(capsys, tmp_path):
    # The clock made from --log-dt 1e-9 is 9.99999999999996e-10 s by round-off: the message's own end is accepted.
    log = tmp_path / "log.csv"
    q = 1e-9 * np.sin(0.1 * np.outer(np.arange(50), np.arange(1, 3)))
    np.savetxt(log, q, delimiter=",", header="q_theta1,q_theta2", comments="")
    code, _, err = run(capsys, "torques", "two_link", "--log", str(log), "--log-dt", "1e-9")
    assert code in (0, 1) and "outside 1e-9 s to 1e6 s" not in err, err
    code, _, err = run(capsys, "torques", "two_link", "--log", str(log), "--log-dt", "0.99e-9")
    assert_one_line_error(code, err, "the sample step 9.9e-10 s is outside 1e-9 s to 1e6 s")


def test_a_real_log_runs_with_one_option(capsys, tmp_path):
    """Jitter (every step within ±20 %), a 40-period gap, a lone sample between two gaps and two dropped rows
    (``test_resampling.REAL``, positions only): one error line names all of it, and ``--repair`` alone mends it."""
    from logmakers import sampled_at, write_csv
    from test_resampling import REAL, columns

    from course_dynamics.core.newton_euler import inverse_dynamics

    data = columns(REAL)
    path = tmp_path / "real.csv"
    write_csv(path, list(data), list(data.values()), fmt="{:.17g}")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(path))
    assert_one_line_error(code, err, f"error: {path}: the samples are not on one clock (median step 2 ms, steps from "
                          "1.61 ms to 3.85 ms; ", "and it has 3 gaps longer than 5 sample periods (79.6 ms = 39.8 "
                          "periods after t = 0.600159 s, before line 302; ", "and 1 lone sample cut off by the gaps "
                          "(line 563, t = 1.24007 s, between two gaps): --repair resamples on the median period, "
                          "splits at the gaps and drops the lone sample")
    out = tmp_path / "tau.csv"
    code, stdout, err = run(capsys, "torques", "ur5", "--log", str(path), "--repair", "--out", str(out), "--json")
    assert code == 0, err
    notes = json.loads(stdout)["notes"]
    assert notes[0].startswith("resampled on the median period 2 ms (500.259 Hz") and notes[1].startswith(
        "split at 3 long gaps") and notes[2] == ("dropped 1 lone sample cut off by the gaps (line 563, t = 1.24007 s, "
                                                 "between two gaps): 3 segments left")
    written = read_table(out).data
    exact = sampled_at(load_robot("ur5"), written[:, 0], seed=3)
    tau = inverse_dynamics(load_robot("ur5"), exact.q, exact.qd, exact.qdd)
    # the resampling moves q by under 1e-9 rad (the spline's bound, tests/test_resampling.py): what is left is the
    # differentiation's error, held to 1e-3 of the peak as for an even log (measured 8e-5)
    assert np.abs(written[:, 1:] - tau).max() < 1e-3 * np.abs(tau).max()
    code, again, _ = run(capsys, "torques", "ur5", "--log", str(path), "--repair", "--split-gaps", "--json")
    assert code == 0 and json.loads(again)["notes"] == notes                         # --split-gaps is redundant
    code, rated, _ = run(capsys, "torques", "ur5", "--log", str(path), "--repair", "--resample", "250", "--json")
    assert code == 0 and json.loads(rated)["notes"][0] == "resampled to 250 Hz (461 samples from 921) by cubic splines"
