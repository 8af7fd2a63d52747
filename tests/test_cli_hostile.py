"""The command line under hostile or broken input: one ``error:`` line and exit 2, nothing written, nothing run.

Each test names the rule it keeps. Files are made in the test's own folder; nothing outside it is touched.
"""
from __future__ import annotations

import json
import os
import re
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest
from helpers import ROOT, arm_urdf, assert_one_line_error, chain_urdf, run

from course_dynamics import load_urdf
from course_dynamics.core.urdf import MAX_URDF_BYTES

BODY = arm_urdf().split("?>", 1)[1]


# ---------------------------------------------------------------------------- URDF files

EXTREME = "1.7976931348623157e308"  # the largest float, as exporters write "no limit"
EXTREME_URDFS = {
    **{f"{key} at {sign}max": re.sub(rf'\b{key}="([^"]*)"', lambda m, key=key, sign=sign: f'{key}="'
                                      + " ".join([sign + EXTREME] * len(m.group(1).split())) + '"', arm_urdf())
       for key in ("xyz", "rpy", "value", "ixx", "iyy", "ixy", "effort", "velocity") for sign in ("", "-")},
    "limits at ±max": arm_urdf().replace('lower="-1" upper="1"', f'lower="-{EXTREME}" upper="{EXTREME}"'),
    "prismatic limits at ±max": arm_urdf(joint_type="prismatic").replace('lower="-1" upper="1"',
                                                                          f'lower="-{EXTREME}" upper="{EXTREME}"'),
    "friction at max": arm_urdf().replace("</joint>", f'<dynamics damping="{EXTREME}" friction="{EXTREME}"/></joint>'),
    "the smallest mass": arm_urdf(mass="5e-324"),
}


@pytest.mark.parametrize("name", EXTREME_URDFS)
def test_every_urdf_number_at_its_extreme_gives_a_result_or_one_line(capsys, tmp_path, name):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(EXTREME_URDFS[name])
    for argv in (["info"], ["validate", "--samples", "2"], ["terms", "--q", "0.1,0.2", "--qd", "1,-1", "--qdd", "2,1"],
                 ["simulate", "--q0", "0.1,0.2", "--duration", "0.01", "--dt", "0.005", "--out", str(tmp_path / "s.csv"),
                  "--quiet"]):
        code, out, err = run(capsys, argv[0], str(urdf), *argv[1:])
        if code == 2:
            assert_one_line_error(code, err)
        else:
            assert code in (0, 1) and "Traceback" not in err, (argv, err)
            assert not re.search(r"\b(nan|inf)\b", out, re.IGNORECASE), (argv, out)


@pytest.mark.parametrize("name, content, fragment", [
    ("xxe", '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/hostname">]>'
            + BODY.replace('name="probe"', 'name="&x;"'), "declares a DTD"),
    ("billion laughs", '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa">'
                       + "".join(f'<!ENTITY {c} "{("&" + p + ";") * 10}">' for p, c in zip("abcdefg", "bcdefgh"))
                       + "]>" + BODY.replace('name="probe"', 'name="&h;"'), "declares a DTD"),
    ("deep nesting", '<?xml version="1.0"?><robot name="x">' + "<a>" * 5000 + "</a>" * 5000 + "</robot>",
     "malformed XML: Excessive depth"),
    ("empty", "", "empty file"),
    ("blank", "   \n", "empty file"),
])
def test_hostile_xml_is_refused(capsys, tmp_path, name, content, fragment):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(content)
    code, out, err = run(capsys, "info", str(urdf))
    assert_one_line_error(code, err, str(urdf), fragment)
    assert out == "" and "hostname" not in err


def test_the_parser_is_configured_against_entities():
    from lxml import etree

    from course_dynamics.core.urdf import xml_parser

    text = b'<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/hostname">]><r>&x;</r>'
    root = etree.fromstring(text, parser=xml_parser())
    assert etree.tostring(root) == b"<r>&x;</r>"  # the reference stays a reference: nothing is read or substituted


def test_non_utf8_urdf_names_the_byte(capsys, tmp_path):
    urdf = tmp_path / "robot.urdf"
    urdf.write_bytes(arm_urdf().replace('name="probe"', 'name="prøbe"').encode("latin-1"))
    code, _, err = run(capsys, "info", str(urdf))
    assert_one_line_error(code, err, "not UTF-8 (byte", "0xf8", "no other encoding is declared")


def test_declared_encodings_are_honoured(tmp_path):
    urdf = tmp_path / "robot.urdf"
    urdf.write_bytes(arm_urdf().replace('<?xml version="1.0"?>', '<?xml version="1.0" encoding="UTF-16"?>')
                     .encode("utf-16"))
    assert load_urdf(urdf).n == 2


def test_a_directory_a_fifo_and_a_huge_file_are_not_urdfs(capsys, tmp_path):
    code, _, err = run(capsys, "info", str(tmp_path))
    assert_one_line_error(code, err, "is a directory, not a URDF file")
    fifo = tmp_path / "robot.urdf"
    os.mkfifo(fifo)
    code, _, err = run(capsys, "info", str(fifo))  # reading it would wait forever
    assert_one_line_error(code, err, "not a regular file")
    fifo.unlink()
    with open(fifo, "wb") as handle:  # sparse: no disk used
        handle.truncate(MAX_URDF_BYTES + 1)
    code, _, err = run(capsys, "info", str(fifo))
    assert_one_line_error(code, err, "more than a URDF file may be")


def test_duplicate_joint_names_are_refused(capsys, tmp_path):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(arm_urdf().replace('name="joint2"', 'name="joint1"'))
    code, _, err = run(capsys, "info", str(urdf))
    assert_one_line_error(code, err, "two joints are named 'joint1'")


def test_a_joint_without_origin_is_at_the_identity(tmp_path):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(arm_urdf().replace('<origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>', '<axis xyz="0 0 1"/>', 1))
    model = load_urdf(urdf)
    np.testing.assert_array_equal(model.bodies[0].P, np.zeros(3))
    np.testing.assert_array_equal(model.bodies[0].R0, np.eye(3))


# ---------------------------------------------------------------------------- long chains

def test_a_200_joint_chain_validates(capsys, tmp_path):
    urdf = tmp_path / "chain.urdf"
    urdf.write_text(chain_urdf(200))
    code, out, _ = run(capsys, "validate", str(urdf), "--samples", "2", "--json")
    assert code == 0 and json.loads(out)["ok"]


def test_a_1000_joint_chain_is_computed_and_its_validation_refused_for_memory(capsys, tmp_path):
    urdf = tmp_path / "chain.urdf"
    urdf.write_text(chain_urdf(1000))
    code, out, _ = run(capsys, "terms", str(urdf), "--q", ",".join(["0.01"] * 1000), "--json")
    assert code == 0 and len(json.loads(out)["tau"]) == 1000  # no recursion limit reached, seconds not minutes
    code, _, err = run(capsys, "validate", str(urdf))
    assert_one_line_error(code, err, "robot 'chain' has 1000 joints", "GiB of memory")


# ---------------------------------------------------------------------------- numbers

@pytest.mark.parametrize("argv, fragment", [
    (["terms", "two_link", "--q", "0,0", "--qd", "1e200,0"], "the result is not finite"),
    (["terms", "two_link", "--q", "0,0", "--qd", "1e200,0", "--json"], "the result is not finite"),
    (["trace", "two_link", "--q", "0,0", "--qd", "1e200,0"], "the result is not finite"),
    (["cartesian", "ur5", "--frame", "tool0", "--q", "0,-1.2,1,-0.5,0.5,0", "--qd", "1e200,0,0,0,0,0"],
     "the result is not finite"),
    (["terms", "two_link", "--q", "0,,1"], "--q has an empty value in '0,,1'"),
    (["terms", "two_link", "--q", "0.1,"], "--q has an empty value"),
    (["validate", "two_link", "--tolerance", "nan"], "--tolerance must be a positive finite number, got nan"),
    (["validate", "two_link", "--tolerance", "-1"], "--tolerance must be a positive finite number"),
    (["report", "two_link", "--tolerance", "inf", "--out", "r"], "--tolerance must be a positive finite number"),
])
def test_numbers_out_of_range_are_errors_not_output(capsys, argv, fragment):
    code, out, err = run(capsys, *argv)
    assert_one_line_error(code, err, fragment)
    assert out == ""


@pytest.mark.parametrize("extra, fragment", [
    (["--duration", "inf", "--dt", "0.01"], "duration must be a positive number of seconds, got inf"),
    (["--duration", "1", "--dt", "1e-300"], "is 1e+300 steps; keeping them would need"),
    (["--duration", "1e12", "--dt", "1e-6"], "EiB of memory"),
    (["--duration", "0.1", "--dt", "0.01", "--qd0", "1e200,0"], "non-finite"),
])
def test_simulate_refuses_what_it_cannot_hold(capsys, tmp_path, extra, fragment):
    out = tmp_path / "sim.csv"
    code, _, err = run(capsys, "simulate", "two_link", "--q0", "0,0", "--out", str(out), "--quiet", *extra)
    assert_one_line_error(code, err, fragment)
    assert list(tmp_path.iterdir()) == []


def test_huge_log_values_are_refused(capsys, tmp_path):
    log, out = tmp_path / "log.csv", tmp_path / "tau.csv"
    log.write_text("t,q_theta1,q_theta2,qd_theta1,qd_theta2,qdd_theta1,qdd_theta2\n0,0,0,1e300,0,0,0\n")
    code, _, err = run(capsys, "torques", "two_link", "--log", str(log), "--out", str(out))
    assert_one_line_error(code, err, "the torques overflow at t = 0 s")
    assert not out.exists()


# ---------------------------------------------------------------------------- symbolic output

@pytest.mark.parametrize("name", ["__import__('os').system('id')", "a-b", "joint 2", "θ2"])
def test_symbolic_paths_refuse_names_that_are_not_identifiers(capsys, tmp_path, name):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(arm_urdf().replace('name="joint2"', f'name="{name}"'))
    for argv in (["derive", str(urdf), "--json"], ["trace", str(urdf), "--symbolic"]):
        code, out, err = run(capsys, *argv)
        assert_one_line_error(code, err, "must be ASCII identifiers")
        assert out == ""


# ---------------------------------------------------------------------------- HTML and meshes

HOSTILE_NAME = '</title><script>alert(1)</script>'


def test_robot_and_joint_names_never_reach_html_unescaped(capsys, tmp_path):
    import html

    urdf = tmp_path / "robot.urdf"
    text = arm_urdf().replace('name="probe"', f'name="{html.escape(HOSTILE_NAME)}"')
    urdf.write_text(text.replace('name="joint2"', f'name="{html.escape(HOSTILE_NAME)}x"'))
    trajectory = tmp_path / "t.csv"
    joint = HOSTILE_NAME + "x"
    trajectory.write_text(f"t,q_joint1,q_{joint}\n0,0,0\n0.1,0.1,0.1\n")
    page = tmp_path / "a.html"
    code, _, err = run(capsys, "animate", str(urdf), "--trajectory", str(trajectory), "--html", str(page))
    assert code == 0, err
    assert "<script>alert(1)" not in page.read_text()
    plot = tmp_path / "tau.html"
    code, _, err = run(capsys, "torques", str(urdf), "--log", str(trajectory), "--plot", str(plot), "--smooth", "5")
    assert code == 2  # two rows are too few to differentiate; nothing written
    log = tmp_path / "full.csv"
    rows = "\n".join(f"{k * 0.01},0,0,0,0,0,0" for k in range(10))
    log.write_text(f"t,q_joint1,q_{joint},qd_joint1,qd_{joint},qdd_joint1,qdd_{joint}\n{rows}\n")
    code, _, err = run(capsys, "torques", str(urdf), "--log", str(log), "--plot", str(plot))
    assert code == 0, err
    assert "<script>alert(1)" not in plot.read_text()


def mesh_urdf(filename: str) -> str:
    visual = f'<visual><geometry><mesh filename="{filename}"/></geometry></visual>'
    return arm_urdf().replace('<link name="link1">', '<link name="link1">' + visual)


@pytest.mark.parametrize("filename, fragment", [
    ("/etc/hostname", "lies outside the URDF's folder and its packages"),
    ("../secret.stl", "lies outside the URDF's folder and its packages"),
    ("package://pkg/../../../../../../etc/hostname", "lies outside"),
    ("http://127.0.0.1:9/x.stl", "is a URL: meshes are never fetched"),
    ("https://example.com/x.stl", "is a URL: meshes are never fetched"),
])
def test_meshes_outside_the_urdfs_folder_are_not_read(capsys, tmp_path, filename, fragment):
    folder = tmp_path / "robot"
    folder.mkdir()
    (tmp_path / "secret.stl").write_text("solid secret\nendsolid secret\n")
    urdf = folder / "robot.urdf"
    urdf.write_text(mesh_urdf(filename))
    trajectory = folder / "t.csv"
    trajectory.write_text("t,q_joint1,q_joint2\n0,0,0\n0.1,0.1,0.1\n")
    page = folder / "a.html"
    code, _, err = run(capsys, "animate", str(urdf), "--trajectory", str(trajectory), "--html", str(page))
    assert code == 0
    warnings = [line for line in err.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1 and fragment in warnings[0] and "stick model" in warnings[0]


def test_meshes_outside_are_read_when_asked(capsys, tmp_path):
    from course_dynamics.output.viewer import robot_geometry

    (tmp_path / "part.stl").write_text("solid p\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                       "vertex 0 1 0\nendloop\nendfacet\nendsolid p\n")
    folder = tmp_path / "robot"
    folder.mkdir()
    urdf = folder / "robot.urdf"
    urdf.write_text(mesh_urdf("../part.stl"))
    model = load_urdf(urdf)
    with pytest.warns(UserWarning, match="from outside the URDF's folder, as asked"):
        geometry = robot_geometry(model, urdf, "visual", mesh_anywhere=True)
    assert geometry.kind == "visual"


# ---------------------------------------------------------------------------- outputs

def test_out_dash_is_standard_output_not_a_file(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, _ = run(capsys, "simulate", "two_link", "--q0", "0,0", "--duration", "0.02", "--dt", "0.01", "--out", "-",
                       "--quiet")
    assert code == 0 and out.startswith("t,q_theta1") and not (tmp_path / "-").exists()


def test_simulate_writes_nothing_when_a_later_output_fails(capsys, tmp_path):
    out = tmp_path / "sim.csv"
    code, _, err = run(capsys, "simulate", "two_link", "--q0", "0,0", "--duration", "0.02", "--dt", "0.01",
                       "--out", str(out), "--plot", str(tmp_path / "plot.gif"), "--quiet")
    assert_one_line_error(code, err, "plot.gif: a plot is written as .png, .svg")
    assert list(tmp_path.iterdir()) == []


def test_a_planted_link_at_the_html_target_is_replaced_not_followed(capsys, tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    page = tmp_path / "a.html"
    page.symlink_to(victim)
    trajectory = tmp_path / "t.csv"
    trajectory.write_text("t,q_theta1,q_theta2\n0,0,0\n0.1,0.1,0.1\n")
    code, _, _ = run(capsys, "animate", "two_link", "--trajectory", str(trajectory), "--html", str(page))
    assert code == 0 and victim.read_text() == "precious"
    assert not page.is_symlink() and page.read_text().startswith("<!DOCTYPE html>")
    assert stat.S_IMODE(page.stat().st_mode) & 0o044  # follows the umask, not 0600


def _long_torques_log(tmp_path):
    """A log whose torques take seconds (500 000 rows: 200 000 took 1.8 s, within some of the delays below)."""
    log = tmp_path / "log.csv"
    t = np.arange(500_000) * 1e-3
    q = 0.3 * np.sin(np.outer(t, np.arange(1, 7)))
    np.savetxt(log, np.column_stack([t, q]), delimiter=",", comments="",
               header="t," + ",".join(f"q_{j}" for j in ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                                          "wrist_1_joint", "wrist_2_joint", "wrist_3_joint")))
    return log


# The console script, as pip writes it for the entry point in pyproject.toml.
ENTRY_POINT = [sys.executable, "-c", "import sys, course_dynamics_command; sys.exit(course_dynamics_command.main())"]


def _interrupted(argv, out, when):
    """Run the command, send SIGINT when ``when()`` says so, and return its stderr once it has ended."""
    process = subprocess.Popen([*ENTRY_POINT, *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        when(process)
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=60)
    finally:
        process.kill()
        process.wait()
    assert process.returncode == 130, err
    assert err == "error: interrupted\n"
    assert not out.exists() and not [p for p in out.parent.iterdir() if p.name.startswith(f".{out.name}.")]


@pytest.mark.parametrize("command", ["simulate", "torques"])
def test_ctrl_c_exits_130_with_one_line_and_no_file(tmp_path, command):
    out = tmp_path / "out.csv"
    if command == "simulate":
        argv = ["simulate", "ur5", "--q0", "0,-1,1,0,0.5,0", "--duration", "60", "--dt", "0.0005", "--no-compile",
                "--out", str(out), "--quiet"]
    else:
        argv = ["torques", "ur5", "--log", str(_long_torques_log(tmp_path)), "--out", str(out), "--no-compile"]
    _interrupted(argv, out, lambda process: time.sleep(2.5))


@pytest.mark.parametrize("offset", [0.4, 0.7, 1.0, 1.5, 2.0])
def test_ctrl_c_in_the_first_seconds_is_not_lost(tmp_path, offset):
    # Imports run in these seconds, among them trimesh's, which catches BaseException in its optional imports.
    out = tmp_path / "out.csv"
    argv = ["torques", "ur5", "--log", str(_long_torques_log(tmp_path)), "--out", str(out), "--no-compile"]
    _interrupted(argv, out, lambda process: time.sleep(offset))


def test_ctrl_c_while_the_output_is_written_leaves_no_file(tmp_path):
    out = tmp_path / "out.csv"
    argv = ["torques", "ur5", "--log", str(_long_torques_log(tmp_path)), "--out", str(out), "--no-compile"]

    def once_the_partial_file_exists(process):
        deadline = time.monotonic() + 60
        while not [p for p in tmp_path.iterdir() if p.name.startswith(".out.csv.")]:
            assert process.poll() is None and time.monotonic() < deadline, "the command ended before writing"
            time.sleep(0.002)

    _interrupted(argv, out, once_the_partial_file_exists)


# ---------------------------------------------------------------------------- found by trying to break it

def test_full_devices_and_unusable_paths_are_one_line(capsys, tmp_path):
    code, _, err = run(capsys, "simulate", "two_link", "--q0", "0,0", "--duration", "0.1", "--dt", "0.01",
                       "--out", "/dev/full", "--quiet")
    assert_one_line_error(code, err, "/dev/full: cannot write: No space left on device")
    result = subprocess.run([sys.executable, "-m", "course_dynamics.cli", "info", "two_link"],
                            stdout=open("/dev/full", "w"), stderr=subprocess.PIPE, text=True)
    assert result.returncode == 2 and result.stderr == "error: standard output: cannot write: No space left on device\n"
    (tmp_path / "afile").write_text("x")
    code, _, err = run(capsys, "student-notebooks", str(tmp_path / "afile" / "sub"))
    assert_one_line_error(code, err, "Not a directory")
    code, _, err = run(capsys, "info", "a" * 5000)
    assert_one_line_error(code, err, "File name too long")
    code, _, err = run(capsys, "student-notebooks", "")
    assert_one_line_error(code, err, "an output name is empty")


@pytest.mark.parametrize("argv, fragment", [
    (["validate", "two_link", "--seed", "-1"], "--seed must be a non-negative integer"),
    (["validate", "two_link", "--samples", "100000000"], "--samples must be between 1 and 100000"),
    (["simulate", "two_link", "--q0", "0,0", "--duration", "1", "--dt", "0.1", "--ensemble", "2", "--seed", "-1",
      "--out", "x.csv"], "--seed must be a non-negative integer"),
    (["cartesian", "ur5", "--frame", "tool0", "--q", "0,0,0,0,0,0", "--max-condition", "inf"], "--max-condition must be"),
    (["simulate", "two_link", "--q0", "0,0", "--duration", "1", "--dt", "1e9", "--out", "x.csv"],
     "dt = 1e+09 s is longer than the duration"),
    (["simulate", "two_link", "--q0", "0,0", "--qd0", "1e10,0", "--duration", "1", "--dt", "0.01", "--integrator",
      "adaptive", "--out", "x.csv", "--quiet"], "the adaptive integrator needed more than"),
    (["trace", "two_link", "--symbolic", "--digits", "0"], "decimals must be a whole number of digits from 1 to 30"),
    (["terms", "two_link", "--q", "0,0", "--gravity", "1e308,0,0"], "--gravity components must be at most"),
])
def test_out_of_range_options(capsys, tmp_path, monkeypatch, argv, fragment):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, *argv)
    assert_one_line_error(code, err, fragment)
    assert list(tmp_path.iterdir()) == []


def test_terms_refuses_a_robot_too_large_for_memory(capsys, monkeypatch):
    monkeypatch.setattr("course_dynamics.base.resources.memory_budget", lambda: 1000)
    code, _, err = run(capsys, "terms", "ur5", "--q", "0,0,0,0,0,0")
    assert_one_line_error(code, err, "robot 'ur5' has 6 joints", "more than half of this machine's")


@pytest.mark.parametrize("edit, fragment", [
    (lambda t: t.replace('<origin xyz="0 0 0.1"', '<origin xyz="0 0 1e308"', 1), "more than 1e+09 in size"),
    (lambda t: t.replace('<mass value="1.0"/>', '<mass value="1e300"/>', 1), "more than 1e+09 in size"),
    (lambda t: t.replace('name="joint2"', 'name="evil&#10;error: fake"'), r"joint name 'evil\nerror: fake' holds"),
])
def test_urdf_values_and_names_no_robot_has(capsys, tmp_path, edit, fragment):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(edit(arm_urdf()))
    code, _, err = run(capsys, "validate", str(urdf), "--json")
    assert_one_line_error(code, err, fragment)


def test_control_characters_in_messages_are_escaped(capsys, tmp_path):
    log = tmp_path / "log.csv"
    log.write_text("t,q_theta1,q_theta2\n0,0,0\n0.1,\x1b]0;PWN\x07,0\n")
    code, _, err = run(capsys, "torques", "two_link", "--log", str(log))
    assert_one_line_error(code, err, r"'\x1b]0;PWN\x07' is not a number")
    assert "\x1b" not in err


def test_dollar_signs_in_names_are_text_in_plots(capsys, tmp_path):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(arm_urdf().replace('name="joint2"', r'name="$\frac{a}$"'))
    log = tmp_path / "log.csv"
    rows = "\n".join(f"{k * 0.01},{0.1 * k},0" for k in range(20))
    log.write_text("t,q_joint1,q_$\\frac{a}$\n" + rows + "\n")
    for suffix in ("png", "svg", "html"):
        code, _, err = run(capsys, "torques", str(urdf), "--log", str(log), "--plot", str(tmp_path / f"p.{suffix}"))
        assert code in (0, 1) and err == "" and (tmp_path / f"p.{suffix}").stat().st_size > 0, err  # 1: beyond 1 N m


def test_torques_with_huge_but_finite_values_stay_finite(capsys, tmp_path):
    log = tmp_path / "log.csv"
    rows = "\n".join(f"{k * 0.01},0,0,0,0,{1e160 if k == 3 else 0},0" for k in range(10))
    log.write_text("t,q_theta1,q_theta2,qd_theta1,qd_theta2,qdd_theta1,qdd_theta2\n" + rows + "\n")
    code, out, err = run(capsys, "torques", "two_link", "--log", str(log), "--json")
    assert code == 1, err
    doc = json.loads(out)  # valid JSON: no inf, no nan
    assert doc["exceeded"] and np.isfinite(doc["joints"][0]["rms_tau"])


@pytest.mark.parametrize("t, fragment", [("1e-300", "sample step"), ("1e300", "sample step")])
def test_torques_with_absurd_sample_steps(capsys, tmp_path, t, fragment):
    log = tmp_path / "log.csv"
    log.write_text("t,q_theta1,q_theta2\n" + "\n".join(f"{k * float(t)!r},{k * 0.01},0" for k in range(20)) + "\n")
    code, _, err = run(capsys, "torques", "two_link", "--log", str(log))
    assert_one_line_error(code, err, fragment)


def test_payload_box_too_large_is_refused(capsys):
    code, _, err = run(capsys, "torques", "ur5", "--log", str(ROOT / "examples" / "ur5_log.csv"), "--map",
                       str(ROOT / "examples" / "ur5_log_columns.toml"), "--payload", "1", "--payload-size", "1e200,1,1")
    assert_one_line_error(code, err, "payload box size must be three numbers")


def test_urdfs_pinocchio_cannot_read_are_refused_for_comparison(capsys, tmp_path):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(arm_urdf().replace('<limit lower="-1" upper="1" effort="1" velocity="1"/>', ""))
    code, _, err = run(capsys, "validate", str(urdf), "--samples", "2")
    assert code == 2
    errors = [line for line in err.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and "Pinocchio cannot read this URDF" in errors[0] and "does not specify limits" in errors[0]
    assert all(line.startswith(("error:", "warning:")) for line in err.splitlines())


def test_grading_refuses_names_of_the_class_files_and_formulas_in_the_gradebook(capsys, tmp_path):
    from course_dynamics.grading.feedback import gradebook_csv
    from course_dynamics.grading.grade import student_names

    (tmp_path / "summary.py").write_text("")
    with pytest.raises(Exception, match="would overwrite the class's summary file"):
        student_names([tmp_path / "summary.py"])

    class Grade:
        student, total, status, sandbox, flag_codes = "=1+2", 0.0, "ok", "bubblewrap", []

        def points(self, term):
            return 0.0

    class Assignment:
        terms = ("tau",)

    assert "\n'=1+2,0,0,ok,bubblewrap,\n" in gradebook_csv([Grade()], Assignment())


def test_report_never_writes_through_a_planted_figures_link(capsys, tmp_path):
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    out.mkdir()
    elsewhere.mkdir()
    (out / "figures").symlink_to(elsewhere)
    code, _, err = run(capsys, "report", "pendulum", "--samples", "2", "--out", str(out), "--quiet")
    assert_one_line_error(code, err, "figures: is not a plain folder")
    assert list(elsewhere.iterdir()) == []


def test_meshes_too_large_or_with_non_finite_sizes_draw_sticks(capsys, tmp_path):
    folder = tmp_path / "robot"
    folder.mkdir()
    with open(folder / "huge.stl", "wb") as handle:  # sparse
        handle.truncate(300 * 2**20)
    trajectory = folder / "t.csv"
    trajectory.write_text("t,q_joint1,q_joint2\n0,0,0\n0.1,0.1,0.1\n")
    for visual, fragment in (('<mesh filename="huge.stl"/>', "MiB, more than 200 MiB"),
                             ('<box size="nan 1 1"/>', "non-finite size")):
        urdf = folder / "robot.urdf"
        urdf.write_text(arm_urdf().replace('<link name="link1">',
                                           f'<link name="link1"><visual><geometry>{visual}</geometry></visual>'))
        code, _, err = run(capsys, "animate", str(urdf), "--trajectory", str(trajectory), "--html",
                           str(folder / "a.html"), "--geometry", "visual")
        warnings = [line for line in err.splitlines() if line.startswith("warning:")]
        assert code == 0 and len(warnings) == 1 and fragment in warnings[0], err


def test_ctrl_c_while_publishing_notebooks(tmp_path):
    out = tmp_path / "site"
    process = subprocess.Popen([sys.executable, "-m", "course_dynamics.cli", "publish-notebooks", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    time.sleep(6)
    os.killpg(process.pid, signal.SIGINT)  # as the terminal does: the whole process group
    _, err = process.communicate(timeout=120)
    assert process.returncode == 130 and err == "error: interrupted\n", err


def _manifest_naming(name: str, content: bytes) -> bytes:
    import hashlib

    version = {"bytes": len(content), "sha256": hashlib.sha256(content).hexdigest()}
    return json.dumps({"course-dynamics": 1, "files": {name: {"command": "report", "versions": [version]}}}).encode()


@pytest.mark.parametrize("kind", ["not JSON", "names ../victim.txt", "names an absolute path", "a link to a list",
                                  "lists index.html for another command"])
def test_a_planted_manifest_authorises_no_write(capsys, tmp_path, kind):
    """An output folder's manifest says which files course-dynamics may replace; one it did not write says nothing."""
    from course_dynamics.output.folders import MANIFEST

    out, victim = tmp_path / "out", tmp_path / "victim.txt"
    out.mkdir()
    victim.write_bytes(b"precious")
    (out / "index.html").write_bytes(b"my page")
    manifest = out / MANIFEST
    if kind == "not JSON":
        manifest.write_bytes(b"\x00" * 100)
    elif kind == "names ../victim.txt":
        manifest.write_bytes(_manifest_naming("../victim.txt", b"precious"))
    elif kind == "names an absolute path":
        manifest.write_bytes(_manifest_naming(str(out / "index.html"), b"my page"))
    elif kind == "a link to a list":
        (tmp_path / "list.json").write_bytes(_manifest_naming("index.html", b"my page"))
        manifest.symlink_to(tmp_path / "list.json")
    else:
        manifest.write_bytes(_manifest_naming("index.html", b"my page").replace(b'"report"', b'"grade"'))
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    code, _, err = run(capsys, "report", "pendulum", "--samples", "2", "--out", str(out), "--quiet")
    assert_one_line_error(code, err, "nothing was written")
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before
    assert sorted(p.name for p in out.iterdir()) == sorted([MANIFEST, "index.html"])


def test_grading_output_folders_can_use_the_same_manifest(tmp_path):
    """The API the grader's --out writes through: a class's files, replaced run after run, a teacher's file kept."""
    from course_dynamics import InputError
    from course_dynamics.output.folders import check_folder, write_folder

    (tmp_path / "rubric.md").write_text("the teacher's")
    files = {"gradebook.csv": "student,total\n", "summary.html": "<p/>", "alice.md": "ok"}
    check_folder(tmp_path, list(files), "grade")
    write_folder(tmp_path, files, "grade")
    write_folder(tmp_path, {**files, "gradebook.csv": "student,total\nalice,1\n"}, "grade")
    assert (tmp_path / "gradebook.csv").read_text().endswith("alice,1\n")
    with pytest.raises(InputError, match="rubric.md: exists and was not written by course-dynamics"):
        write_folder(tmp_path, {"rubric.md": "x"}, "grade")
    assert (tmp_path / "rubric.md").read_text() == "the teacher's"
