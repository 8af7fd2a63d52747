"""course_dynamics/cli.py: every command, its JSON, and every bad input (one line, exit 2, no file)."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from helpers import AWKWARD, BAD_URDFS, assert_one_line_error, run

from course_dynamics import dynamics_terms, inverse_dynamics, load_robot
from course_dynamics.cli import main


def test_info_json(capsys):
    code, out, _ = run(capsys, "info", str(AWKWARD), "--json")
    assert code == 0
    info = json.loads(out)
    assert [j["name"] for j in info["joints"]] == ["shoulder", "telescope", "wrist_roll", "side_joint"]
    assert info["joints"][2]["type"] == "continuous" and info["joints"][2]["lower"] is None
    assert info["joints"][1]["parent_link"] == "elbow_housing"
    assert info["bodies"][0]["mass"] == pytest.approx(3.7)


def test_info_table(capsys):
    code, out, _ = run(capsys, "info", "ur5")
    assert code == 0 and "shoulder_pan_joint" in out and "moving body" in out


def test_terms_json_keys_and_values(capsys):
    code, out, _ = run(capsys, "terms", "two_link", "--q", "-0.3,0.5", "--qd", "1,2", "--qdd", "0.1,-0.2", "--json")
    assert code == 0
    doc = json.loads(out)
    assert list(doc) == ["joints", "tau", "M", "C", "V", "G"]
    terms = dynamics_terms(load_robot("two_link"), [-0.3, 0.5], [1, 2], [0.1, -0.2])
    for key in ("tau", "M", "C", "V", "G"):
        np.testing.assert_array_equal(doc[key], getattr(terms, key))


def test_terms_gravity_option(capsys):
    code, out, _ = run(capsys, "terms", "pendulum", "--q", "0.5", "--gravity", "0,0,0", "--json")
    assert code == 0 and json.loads(out)["G"] == [0.0]


def test_terms_table(capsys):
    code, out, _ = run(capsys, "terms", "rp_arm", "--q", "0.2,0.5")
    assert code == 0 and "M(q)" in out and "d2" in out


def write_trajectory(path, model, rng, rows=25):
    q, qd, qdd = rng.uniform(-1, 1, (3, rows, model.n))
    t = np.arange(rows) * 0.01
    header = ["t"] + [f"{k}_{j}" for k in ("q", "qd", "qdd") for j in model.joint_names]
    data = np.column_stack([t, q, qd, qdd])
    path.write_text(",".join(header) + "\n" + "\n".join(",".join(repr(float(x)) for x in row) for row in data) + "\n")
    return q, qd, qdd


def test_torques_csv(capsys, tmp_path):
    model = load_robot("panda")
    q, qd, qdd = write_trajectory(tmp_path / "in.csv", model, np.random.default_rng(1))
    code, out, _ = run(capsys, "torques", "panda", "--trajectory", str(tmp_path / "in.csv"), "--out", str(tmp_path / "out.csv"))
    # Uniform rates in [-1, 1] rad/s exceed the fingers' 0.2 m/s: reported, and exit status 1 as for validate.
    assert code == 1 and "LIMIT EXCEEDED: joint 'panda_finger_joint1': velocity" in out
    lines = (tmp_path / "out.csv").read_text().splitlines()
    assert lines[0].split(",") == ["t"] + [f"tau_{j}" for j in model.joint_names]
    data = np.loadtxt(tmp_path / "out.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(data[:, 1:], inverse_dynamics(model, q, qd, qdd))


def test_validate_agrees_and_json(capsys):
    code, out, _ = run(capsys, "validate", "two_link", str(AWKWARD), "--samples", "20", "--json")
    assert code == 0
    report = json.loads(out)
    assert report["ok"] and len(report["robots"]) == 2
    assert set(report["robots"][1]["terms"]) == {"tau", "M", "C", "V", "G"}


def test_validate_every_bundled_robot(capsys):
    code, out, _ = run(capsys, "validate", "--samples", "5")
    assert code == 0
    for name in ("two_link", "rp_arm", "pendulum", "ur5", "panda", "double_pendulum", "double_pendulum_continuous"):
        assert name in out
    assert "all robots agree" in out


def test_validate_keeps_its_columns_with_a_long_file_name(capsys, tmp_path):
    from course_dynamics import robot_path

    long = tmp_path / ("a_robot_exported_with_a_long_name_" * 2 + ".urdf")
    long.write_text(robot_path("two_link").read_text())
    code, out, _ = run(capsys, "validate", str(long), "two_link", "--samples", "3")
    header, first, second = out.splitlines()[1:4]
    assert code == 0 and header.index(" n ") == first.index(" 2 ") == second.index(" 2 ")
    assert header.index("agree") == first.index("yes") == second.index("yes")


def test_validate_reports_disagreement_with_exit_1(capsys, monkeypatch):
    """A wrong gravity term in our dynamics must be caught."""
    import course_dynamics_reference.validate as validate_module

    real = validate_module.gravity_torques
    monkeypatch.setattr(validate_module, "gravity_torques", lambda model, q: real(model, q) * (1 + 1e-7))
    code, out, _ = run(capsys, "validate", "ur5", "--samples", "3")
    assert code == 1 and "NO" in out


@pytest.mark.parametrize("case", sorted(BAD_URDFS))
def test_bad_urdf_through_cli(capsys, tmp_path, case):
    text, message = BAD_URDFS[case]
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    code, _, err = run(capsys, "terms", str(path), "--q", "0,0")
    assert_one_line_error(code, err, str(path), message)


@pytest.mark.parametrize("argv, fragments", [
    (["info", "missing.urdf"], ["missing.urdf: no such file"]),
    (["info", "no_such_robot"], ["'no_such_robot' is neither a URDF file nor a shipped robot (two_link,"]),
    (["terms", "two_link", "--q", "0.1"], ["q has 1 values but robot 'two_link' has 2 joints (theta1, theta2)"]),
    (["terms", "two_link", "--q", "0.1,abc"], ["--q must be comma-separated numbers"]),
    (["terms", "two_link", "--q", "0.1,nan"], ["joint 'theta2' is nan"]),
    (["terms", "two_link", "--q", "0,0", "--qd", "inf,0"], ["qd for joint 'theta1' is inf"]),
    (["terms", "two_link", "--q", "0,0", "--qdd", "1,2,3"], ["qdd has 3 values"]),
    (["terms", "two_link", "--q", "0,0", "--gravity", "0,-9.81"], ["--gravity needs three finite numbers"]),
    (["terms", "two_link"], ["the following arguments are required: --q"]),
    (["frobnicate"], ["invalid choice"]),
    (["validate", "two_link", "--samples", "0"], ["--samples must be between 1 and"]),
])
def test_bad_arguments(capsys, argv, fragments):
    code, _, err = run(capsys, *argv)
    assert_one_line_error(code, err, *fragments)


@pytest.mark.parametrize("edit, fragment", [
    (lambda h, rows: (h.replace(",qdd_theta2", ""), [r.rsplit(",", 1)[0] for r in rows]),
     "3 rows are too few to differentiate"),  # qdd_theta2 would be differentiated, from three samples
    (lambda h, rows: (h.replace(",q_theta2", ""), [",".join(r.split(",")[:2] + r.split(",")[3:]) for r in rows]),
     "missing columns: q_theta2"),
    (lambda h, rows: (h + ",t", [r + ",1" for r in rows]), "line 1: column 't' appears twice"),
    (lambda h, rows: (h, [rows[0].replace(rows[0].split(",")[1], "oops", 1)] + rows[1:]), "line 2, column 'q_theta1': 'oops' is not a number"),
    (lambda h, rows: (h, [rows[0].replace(rows[0].split(",")[1], "nan", 1)] + rows[1:]), "line 2, column 'q_theta1': value is nan"),
    (lambda h, rows: (h, [rows[0] + ",3"] + rows[1:]), "line 2 has 8 values, the header has 7"),
    (lambda h, rows: (h, []), "no data rows"),
])
def test_bad_trajectory_writes_no_output(capsys, tmp_path, edit, fragment):
    model = load_robot("two_link")
    source = tmp_path / "in.csv"
    write_trajectory(source, model, np.random.default_rng(2), rows=3)
    header, *rows = source.read_text().splitlines()
    header, rows = edit(header, rows)
    source.write_text("\n".join([header] + rows) + "\n")
    out = tmp_path / "out.csv"
    code, _, err = run(capsys, "torques", "two_link", "--trajectory", str(source), "--out", str(out))
    assert_one_line_error(code, err, str(source), fragment)
    assert not out.exists() and list(tmp_path.iterdir()) == [source]


def test_unwritable_output(capsys, tmp_path):
    model = load_robot("two_link")
    write_trajectory(tmp_path / "in.csv", model, np.random.default_rng(3), rows=2)
    code, _, err = run(capsys, "torques", "two_link", "--trajectory", str(tmp_path / "in.csv"),
                       "--out", str(tmp_path / "no_dir" / "out.csv"))
    assert_one_line_error(code, err, "does not exist")


def test_console_script_error_has_no_traceback(tmp_path):
    """The installed entry point, end to end: one line on stderr, exit 2."""
    result = subprocess.run([sys.executable, "-m", "course_dynamics.cli", "terms", "two_link", "--q", "1"],
                            capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.startswith("error: ") and result.stderr.count("\n") == 1
    assert result.stdout == ""


def test_help_explains(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--help"])
    out = capsys.readouterr().out
    assert exit_info.value.code == 0
    for command in ("info", "terms", "torques", "validate"):
        assert command in out
    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0 and capsys.readouterr().out.startswith("course-dynamics ")


def test_simulate_then_torques_round_trip(capsys, tmp_path):
    out, back = tmp_path / "sim.csv", tmp_path / "tau.csv"
    code, stdout, _ = run(capsys, "simulate", "ur5", "--q0", "0,-1,1,0,0.5,0", "--duration", "0.2", "--dt", "0.001",
                          "--torque", "1,2,3,0.5,0.2,0.1", "--out", str(out), "--json")
    assert code == 0
    summary = json.loads(stdout)
    assert summary["samples"] == 201 and summary["integrator"] == "rk4"
    header = out.read_text().splitlines()[0].split(",")
    joints = load_robot("ur5").joint_names
    assert header == ["t"] + [f"{k}_{j}" for k in ("q", "qd", "qdd", "tau") for j in joints] + ["energy"]
    code, report, _ = run(capsys, "torques", "ur5", "--trajectory", str(out), "--out", str(back))
    # Falling for 0.2 s, the wrist swings faster than its 3.2 rad/s: the limits report says so (exit 1).
    assert code == 1 and "joint 'wrist_1_joint': velocity" in report
    np.testing.assert_allclose(np.loadtxt(back, delimiter=",", skiprows=1)[:, 1:],
                               np.tile([1, 2, 3, 0.5, 0.2, 0.1], (201, 1)), rtol=1e-9, atol=1e-9)


def test_simulate_torque_csv_friction_and_limit_warning(capsys, tmp_path):
    torque = tmp_path / "torque.csv"
    torque.write_text("t,tau_theta1,tau_d2\n0,0,5\n1,0,5\n")
    out = tmp_path / "sim.csv"
    code, _, err = run(capsys, "simulate", "rp_arm", "--q0", "0,0.5", "--duration", "1", "--dt", "0.002",
                       "--torque-log", str(torque), "--viscous", "0.1,0.1", "--out", str(out), "--quiet",
                       "--plot", str(tmp_path / "sim.png"))
    assert code == 0
    import matplotlib.image

    picture = matplotlib.image.imread(tmp_path / "sim.png")
    assert picture.shape[0] > 400 and picture.shape[1] > 400
    assert picture[..., :3].std() > 0.05  # curves drawn, not a blank canvas
    assert "warning: t = " in err and "joint 'd2' passed its upper limit 0.8" in err
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 8], 5.0)  # tau_d2 column


def test_cartesian_json_and_singularity(capsys):
    code, out, _ = run(capsys, "cartesian", "two_link", "--frame", "tool", "--q", "0.3,0.7", "--qd", "1,2",
                       "--rows", "x,y", "--expressed-in", "frame", "--json")
    assert code == 0
    doc = json.loads(out)
    assert list(doc) == ["joints", "frame", "rows", "J", "J_dot", "Mx", "Vx", "Gx", "condition"]
    np.testing.assert_allclose(doc["Mx"], [[1.0 + 2.0 / np.sin(0.7) ** 2, 0], [0, 1.0]], atol=1e-12)  # (6.101), m1 = 2, m2 = 1
    code, _, err = run(capsys, "cartesian", "two_link", "--frame", "tool", "--q", "0.3,0", "--rows", "x,z")
    assert_one_line_error(code, err, "Jacobian of frame 'tool' is singular", "condition number")


@pytest.mark.parametrize("extra, fragments", [
    (["--dt", "0"], ["dt must be a positive number"]),
    (["--dt", "-0.01"], ["dt must be a positive number"]),
    (["--dt", "0.01", "--duration", "-1"], ["duration must be a positive number"]),
    (["--dt", "0.01", "--torque", "nan,0"], ["--torque must be finite"]),
    (["--dt", "0.01", "--torque", "1,2,3"], ["--torque has 3 values but robot 'two_link' has 2 joints"]),
    (["--dt", "0.01", "--q0", "0"], ["--q0 has 1 values"]),
    (["--dt", "0.01", "--viscous", "-1,0"], ["viscous friction coefficients must be finite and non-negative"]),
])
def test_simulate_bad_arguments_write_nothing(capsys, tmp_path, extra, fragments):
    out = tmp_path / "sim.csv"
    argv = ["simulate", "two_link", "--q0", "0,0", "--duration", "0.1", "--out", str(out)] + extra
    code, _, err = run(capsys, *argv)
    assert_one_line_error(code, err, *fragments)
    assert not out.exists()


@pytest.mark.parametrize("content, fragment", [
    ("t,tau_theta1\n0,1\n", "missing columns: tau_theta2"),
    ("tau_theta1,tau_theta2\n1,2\n", "no column 't'"),
    ("t,tau_theta1,tau_theta2\n0,1,inf\n", "value is inf"),
    ("t,tau_theta1,tau_theta2\n0,1,2\n0,1,2\n", "line 3: t = 0 s does not come after 0 s"),
])
def test_simulate_bad_torque_csv(capsys, tmp_path, content, fragment):
    torque, out = tmp_path / "torque.csv", tmp_path / "sim.csv"
    torque.write_text(content)
    code, _, err = run(capsys, "simulate", "two_link", "--q0", "0,0", "--duration", "0.1", "--dt", "0.01",
                       "--torque-log", str(torque), "--out", str(out))
    assert_one_line_error(code, err, fragment)
    assert not out.exists()


def test_simulate_singular_mass_matrix(capsys, tmp_path):
    from helpers import arm_urdf

    urdf, out = tmp_path / "massless.urdf", tmp_path / "sim.csv"
    urdf.write_text(arm_urdf(mass="0", ixx="0", iyy="0", izz="0"))
    code, _, err = run(capsys, "simulate", str(urdf), "--q0", "0,0", "--duration", "0.1", "--dt", "0.01", "--out", str(out))
    assert_one_line_error(code, err, "mass matrix of robot 'probe' is singular", "joint 'joint2' moves no mass")
    assert not out.exists() and list(tmp_path.iterdir()) == [urdf]


def test_trace_json_and_symbolic(capsys):
    code, out, _ = run(capsys, "trace", "two_link", "--q", "0.3,-0.8", "--qd", "1.1,0.6", "--qdd", "-0.4,0.9", "--json")
    assert code == 0
    doc = json.loads(out)
    np.testing.assert_allclose([link["tau"] for link in doc["links"]],
                               inverse_dynamics(load_robot("two_link"), [0.3, -0.8], [1.1, 0.6], [-0.4, 0.9]))
    code, out, _ = run(capsys, "trace", "pendulum", "--symbolic", "--symbols", "m,l,g")
    assert code == 0 and "tau_1 = l*m*(g*sin(q_theta) + l*qdd_theta)" in out


def test_derive_json_parses_and_evaluates(capsys):
    import sympy

    code, out, _ = run(capsys, "derive", "rp_arm", "--symbols", "m2,g", "--method", "lagrange", "--json")
    assert code == 0
    doc = json.loads(out)
    assert list(doc) == ["joints", "tau", "M", "V", "G", "B", "C"]
    values = {"q_theta1": 0.4, "q_d2": 0.6, "qd_theta1": -1.0, "qd_d2": 0.3, "qdd_theta1": 0.2, "qdd_d2": -0.5, "m2": 1.5, "g": 9.81}
    tau = [float(sympy.sympify(e).subs(values)) for e in doc["tau"]]
    np.testing.assert_allclose(tau, inverse_dynamics(load_robot("rp_arm"), [0.4, 0.6], [-1.0, 0.3], [0.2, -0.5]), rtol=1e-12)


def test_derive_latex_and_markdown(capsys):
    code, out, _ = run(capsys, "derive", "two_link", "--symbols", "m1,m2,l1,l2,g", "--latex")
    assert code == 0 and r"\begin{align*}" in out and r"B(\Theta)" in out
    code, out, _ = run(capsys, "derive", "pendulum")
    assert code == 0 and "$$ M(\\Theta)" in out


@pytest.mark.parametrize("argv, fragments", [
    (["derive", "ur5"], ["robot 'ur5' has 6 joints; the symbolic path handles at most 4"]),
    (["derive", "two_link", "--symbols", "m1,mass2"], ["unknown symbol 'mass2' for robot 'two_link'; known: g, l1, l2, lc1, lc2, m1, m2"]),
    (["trace", "panda", "--symbolic"], ["robot 'panda' has 8 joints"]),
    (["trace", "two_link"], ["--q is required unless --symbolic is given"]),
    (["derive", "missing.urdf"], ["missing.urdf: no such file"]),
])
def test_symbolic_bad_input(capsys, argv, fragments):
    code, _, err = run(capsys, *argv)
    assert_one_line_error(code, err, *fragments)


def test_simulate_ensemble_writes_members_and_plots_divergence(capsys, tmp_path):
    out, plot = tmp_path / "chaos.csv", tmp_path / "chaos.png"
    code, stdout, _ = run(capsys, "simulate", "double_pendulum_continuous", "--q0", "0.5,0.5", "--duration", "0.5",
                          "--dt", "0.005", "--ensemble", "5", "--perturbation", "1e-6", "--out", str(out),
                          "--plot", str(plot), "--json", "--quiet")
    assert code == 0
    summary = json.loads(stdout)
    assert summary["members"] == 5 and summary["samples"] == 101 and 0 < summary["final_spread"] < 1e-3
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert out.read_text().split("\n")[0].startswith("t,member,q_joint1")
    assert data.shape == (101 * 5, 2 + 4 * 2 + 1) and set(data[:, 1]) == {0, 1, 2, 3, 4}
    np.testing.assert_array_equal(data[data[:, 1] == 0][0, 2:4], [0.5, 0.5])  # member 0 starts at --q0
    import matplotlib.image

    assert matplotlib.image.imread(plot)[..., :3].std() > 0.05


def test_simulate_compiled_and_interpreted_write_the_same_run(capsys, tmp_path):
    argv = ["simulate", "ur5", "--q0", "0,-1,1,0,0.5,0", "--duration", "0.2", "--dt", "0.001", "--quiet"]
    assert run(capsys, *argv, "--out", str(tmp_path / "a.csv"))[0] == 0
    assert run(capsys, *argv, "--out", str(tmp_path / "b.csv"), "--no-compile")[0] == 0
    a, b = (np.loadtxt(tmp_path / name, delimiter=",", skiprows=1) for name in ("a.csv", "b.csv"))
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-10)


@pytest.mark.parametrize("extra, fragment", [
    (["--ensemble", "0"], "--ensemble must be at least 1"),
    (["--ensemble", "3", "--perturbation", "-1"], "--perturbation must be a non-negative number"),
    (["--ensemble", "3", "--html", "x.html"], "--html animates one run"),
])
def test_bad_ensemble_options(capsys, tmp_path, extra, fragment):
    out = tmp_path / "sim.csv"
    code, _, err = run(capsys, "simulate", "two_link", "--q0", "0,0", "--duration", "0.1", "--dt", "0.01",
                       "--out", str(out), *extra)
    assert_one_line_error(code, err, fragment)
    assert not out.exists()


def test_info_json_has_effort_and_velocity_limits(capsys):
    code, out, _ = run(capsys, "info", "ur5", "--json")
    joints = json.loads(out)["joints"]
    model = load_robot("ur5")
    assert [j["effort"] for j in joints] == model.effort.tolist()
    assert [j["velocity"] for j in joints] == model.velocity.tolist()
    code, out, _ = run(capsys, "info", "double_pendulum", "--json")
    assert {j["effort"] for j in json.loads(out)["joints"]} == {None}  # no limit in the URDF


GRAVITY = ["--gravity", "1.5,-2,-7"]


@pytest.mark.parametrize("argv", [
    ["terms", "ur5", "--q", "0.1,0.2,0.3,0.4,0.5,0.6", "--json"],
    ["trace", "two_link", "--q", "0.3,0.4", "--json"],
    ["cartesian", "ur5", "--frame", "tool0", "--q", "0,-1.2,1,-0.5,0.5,0", "--json"],
    ["simulate", "two_link", "--q0", "0.3,0.4", "--duration", "0.05", "--dt", "0.01", "--json", "--out", "-"],
    ["derive", "pendulum", "--json"],
])
def test_every_dynamics_command_takes_gravity(capsys, argv):
    """The same command under another gravity gives other numbers, and the library's under that gravity."""
    code, standard, _ = run(capsys, *argv)
    assert code == 0
    code, other, _ = run(capsys, *argv, *GRAVITY)
    assert code == 0 and other != standard


def test_terms_under_gravity_equal_the_library(capsys):
    code, out, _ = run(capsys, "terms", "ur5", "--q", "0.1,0.2,0.3,0.4,0.5,0.6", "--json", *GRAVITY)
    expected = dynamics_terms(load_robot("ur5", gravity=[1.5, -2, -7]), [0.1, 0.2, 0.3, 0.4, 0.5, 0.6], np.zeros(6),
                              np.zeros(6))
    np.testing.assert_array_equal(json.loads(out)["G"], expected.G)


def test_validate_and_report_compare_under_the_given_gravity(capsys, tmp_path):
    code, out, err = run(capsys, "validate", "ur5", "--samples", "5", "--json", *GRAVITY)
    assert code == 0 and json.loads(out)["ok"] and "warning" not in err
    code, _, _ = run(capsys, "report", "two_link", "--samples", "3", "--out", str(tmp_path / "r"), "--quiet", *GRAVITY)
    assert code == 0
    report = json.loads((tmp_path / "r" / "report.json").read_text())
    assert report["robots"][0]["textbook"] is None  # the printed closed forms hold for the course's gravity only


@pytest.mark.parametrize("command", [["validate", "two_link", "--samples", "4"], ["terms", "two_link", "--q", "0.1,0.2"]])
def test_gravity_that_cannot_act_is_said_once(capsys, command):
    """two_link's joint axes are along the base's y axis: gravity along y gives G ≡ 0."""
    code, _, err = run(capsys, *command, "--gravity", "0,9.81,0")
    assert code == 0
    warnings = [line for line in err.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1 and "G(q) = 0 at every sampled state" in warnings[0]
    code, _, err = run(capsys, *command)
    assert "warning" not in err


def test_nonphysical_inertia_is_refused_with_a_hint_or_loaded_with_a_warning(capsys, tmp_path):
    from helpers import arm_urdf

    urdf = tmp_path / "planar.urdf"
    urdf.write_text(arm_urdf(ixx="0", iyy="0", izz="0.05"))  # only izz, as classroom URDFs give
    args = ["--q", "0.1,0.2", "--gravity", "0,-9.81,0"]  # the arm is planar in x-y: gravity along -y acts on it
    code, _, err = run(capsys, "terms", str(urdf), *args)
    assert_one_line_error(code, err, "link 'link2': inertia", "triangle", "--allow-nonphysical-inertia")
    code, out, err = run(capsys, "terms", str(urdf), *args, "--json", "--allow-nonphysical-inertia")
    assert code == 0 and json.loads(out)["tau"]
    assert [line for line in err.splitlines() if line.startswith("warning:")] == [
        f"warning: {urdf}: link 'link2': inertia {err.split('inertia ', 1)[1].split('; loaded anyway')[0]}; loaded anyway"]


def test_every_warning_line_comes_through_the_warnings_path(capsys, monkeypatch):
    """A warning of ours is a ``warnings.warn`` with a course_dynamics class, printed by the entry point's one warning
    line (control characters escaped, every time it comes); no module prints ``warning:`` on stderr itself."""
    import ast
    import warnings
    from pathlib import Path

    import course_dynamics
    from course_dynamics.base.errors import CourseDynamicsWarning
    from course_dynamics.cli.commands import info

    printed = []
    package = Path(course_dynamics.__file__).parent
    for path in package.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if (isinstance(node, ast.Call) and getattr(node.func, "id", "") == "print" and node.args
                    and "warning:" in ast.unparse(node.args[0])[:12]
                    and any(k.arg == "file" and ast.unparse(k.value) == "sys.stderr" for k in node.keywords)):
                printed.append((path.relative_to(package).as_posix(), node.lineno))
    assert [name for name, _ in printed] == ["cli/__init__.py"], printed  # its warning_line alone

    shown = info.run

    def run(args):
        for _ in range(2):
            warnings.warn("robot 'x'\nerror: forged", CourseDynamicsWarning)
        return shown(args)

    monkeypatch.setattr(info, "run", run)
    assert main(["info", "two_link"]) == 0
    assert capsys.readouterr().err.splitlines() == ["warning: robot 'x'\\nerror: forged"] * 2


def test_running_out_of_memory_is_one_error_line_and_no_output(capsys, monkeypatch, tmp_path):
    """The safety net under the size checks: a MemoryError nobody foresaw ends in one line, exit 2, no file."""
    from course_dynamics.cli.commands import simulate

    out = tmp_path / "run.csv"

    def run_out_of_memory(args):
        raise MemoryError("Unable to allocate 2.68 GiB for an array with shape (100000, 60, 60)")

    monkeypatch.setattr(simulate, "run", run_out_of_memory)
    code, _, err = run(capsys, "simulate", "pendulum", "--q0", "0", "--duration", "1", "--dt", "0.1", "--out", str(out))
    assert_one_line_error(code, err, "error: ran out of memory (Unable to allocate 2.68 GiB", "--samples",
                          "COURSE_DYNAMICS_MEMORY_BUDGET")
    assert not out.exists()
