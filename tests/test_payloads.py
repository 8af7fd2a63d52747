"""course_dynamics/tools/payloads.py: a payload's mass, centre of mass and inertia from a short log, on a known arm."""
from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import assert_agrees, assert_one_line_error, run
from logmakers import write_csv

from course_dynamics import inverse_dynamics, load_robot, load_urdf
from course_dynamics.cli import main
from course_dynamics.core.friction import Friction
from course_dynamics.core.inertia import box, rotate
from course_dynamics.core.regressor import regressor
from course_dynamics.core.sampling import random_states
from course_dynamics.output.urdf_writer import identified_urdf
from course_dynamics.tools.consistency import pseudo_inertia
from course_dynamics.tools.excitation import Fourier
from course_dynamics.tools.loads import Payload, with_payload
from course_dynamics.tools.payloads import flange, flange_link, offset_map, parameters_of, payload_parameters, wrist

MASS, COM, SIZE = 1.7, (0.01, -0.02, 0.06), (0.10, 0.08, 0.12)   # a tool: a box of 1.7 kg, off the flange's axis
ROBOTS = ("ur5", "panda")
SECONDS, NOISE = 10.0, 0.01          # the log: 10 s, 1 % torque noise


def tilted_box():
    """ᶜI of the tool's box turned about an oblique axis: every product of inertia non-zero, kg m²."""
    c, s = np.cos(0.4), np.sin(0.4)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return rotate(box(MASS, *SIZE), R)


@pytest.mark.parametrize("robot", ROBOTS)
def test_payload_columns_times_its_parameters_are_pinocchios_payload_torques(robot):
    """Y_F π_P is what Pinocchio's model gains in τ when the payload is appended to the flange's joint."""
    model = load_robot(robot)
    link = flange_link(model)
    oracle = PinocchioOracle(model.source, model.joint_names)
    q, qd, qdd = random_states(model, 6, seed=3)
    before = np.array([oracle.tau(*state) for state in zip(q, qd, qdd)])
    oracle.add_payload(link, MASS, COM, tilted_box())
    after = np.array([oracle.tau(*state) for state in zip(q, qd, qdd)])
    ours = flange(model, link).regressor(regressor(model, q, qd, qdd)) @ payload_parameters(MASS, COM, tilted_box())
    assert_agrees(ours, after - before, scale=np.abs(after).max(), rtol=1e-9, what=f"{robot} Y_F π_P")


def test_the_offset_map_is_the_pseudo_inertia_moved_rigidly():
    rng = np.random.default_rng(0)
    R = np.linalg.qr(rng.standard_normal((3, 3)))[0]
    P = rng.standard_normal(3)
    pi = payload_parameters(MASS, COM, tilted_box())
    T = np.block([[R, P[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]])
    assert np.allclose(pseudo_inertia(offset_map(R, P) @ pi), T @ pseudo_inertia(pi) @ T.T, rtol=0, atol=1e-14)
    assert np.allclose(parameters_of(pseudo_inertia(pi)), pi, rtol=0, atol=1e-15)


def test_the_default_flange_is_the_arm_s_last_link_before_the_fingers():
    assert flange_link(load_robot("ur5")) == "tool0"
    assert flange_link(load_robot("panda")) == "panda_hand_tcp"     # not a finger: they branch off panda_link7
    assert wrist(load_robot("panda")).tolist() == [False] * 4 + [True] * 3 + [False]


def friction_urdf(robot, folder):
    """The robot's URDF with joint friction (damping and Coulomb friction on every joint), as a file."""
    model = load_robot(robot)
    friction = Friction(viscous=0.05 + 0.01 * np.arange(model.n), coulomb=0.2 + 0.05 * np.arange(model.n))
    path = folder / f"{robot}_friction.urdf"
    path.write_bytes(identified_urdf(Path(model.source).read_bytes(), model, friction))
    return path


@pytest.fixture(scope="module", params=ROBOTS)
def excited(request, tmp_path_factory):
    """(the robot with friction, its URDF, the motion ``excite --scope payload`` wrote, a folder, excite's record)."""
    folder = tmp_path_factory.mktemp(request.param)
    urdf = friction_urdf(request.param, folder)
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):   # capsys is per test
        code = main(["excite", str(urdf), "--duration", str(SECONDS), "--scope", "payload", "--out",
                     str(folder / "motion.csv"), "--json", "--quiet"])
    assert code == 0
    record = json.loads(out.getvalue())
    return load_urdf(urdf), urdf, Fourier(record["duration"], **record["coefficients"]), folder, record


def write_log(path, model, motion, payload=None, seed=0, still=None, rate=200.0, noise=NOISE):
    """A log of ``motion`` (t with jittered stamps, q, qd, tau_meas with 1 % noise, or ``noise``) of ``model``
    carrying ``payload``; the joints ``still`` do not move."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, SECONDS, 1 / rate)
    t = t + rng.uniform(-0.05, 0.05, len(t)) / rate          # a recorder's stamps, never exactly on the clock
    q, qd, qdd = motion(t)
    if still is not None:
        q[:, still], qd[:, still], qdd[:, still] = q[:1, still], 0.0, 0.0
    carried = model if payload is None else with_payload(model, payload)
    tau = inverse_dynamics(carried, q, qd, qdd) + Friction.from_urdf(model).torques(qd)
    tau += noise * np.sqrt(np.mean(tau**2, axis=0)) * rng.standard_normal(tau.shape)
    columns = {"t": t, **{f"{kind}_{j}": v[:, i] for kind, v in (("q", q), ("qd", qd), ("tau_meas", tau))
                          for i, j in enumerate(model.joint_names)}}
    write_csv(path, list(columns), list(columns.values()), fmt="{:.12g}")
    return path


def test_a_payload_from_a_ten_second_log_through_the_command(capsys, excited):
    model, urdf, motion, folder, record = excited
    link = flange_link(model)
    assert record["flange"] == link and record["scope"] == "payload"
    moving = wrist(model)
    assert np.allclose(np.ptp(motion(np.linspace(0, SECONDS, 50))[0][:, ~moving], axis=0), 0)   # the others rest
    log = write_log(folder / "carried.csv", model, motion, Payload(MASS, link=link, com=COM, size=SIZE))
    out = folder / "carried.urdf"
    code, text, err = run(capsys, "identify", str(urdf), "--log", str(log), "--scope", "payload", "--out", str(out),
                          "--json")
    assert code == 0, err
    found = json.loads(text)
    assert found["detected"] and found["determined"] == {"mass": True, "com": True, "inertia": True}
    assert abs(found["mass"] - MASS) < 0.02 * MASS, found["mass"]
    assert np.linalg.norm(np.subtract(found["com"], COM)) < 0.005, found["com"]
    assert 0 < found["mass_sigma"] < 0.02 * MASS and all(0 < s < 0.005 for s in found["com_sigma"])
    forms = found["robot_forms"]          # each robot's own form, in its flange frame
    if "ur" in forms:
        assert list(forms) == ["ur"] and forms["ur"]["frame"] == "tool0" == link
        assert forms["ur"]["call"].startswith("set_payload(1.7")
    else:
        assert list(forms) == ["franka"] and forms["franka"]["frame"] == "panda_link8"
        c_F, c_8 = np.array(found["com"]), np.array(forms["franka"]["com"])
        F, L8 = model.frame(link), model.frame("panda_link8")     # one point, seen from two frames of one body
        assert np.allclose(F.R @ c_F + F.P, L8.R @ c_8 + L8.P, rtol=0, atol=1e-12)
        inertia = np.reshape(forms["franka"]["inertia"], (3, 3), order="F")
        assert np.allclose(inertia, inertia.T) and np.all(np.linalg.eigvalsh(inertia) > 0)
    written = load_urdf(out)                  # the payload link, lumped into the flange's body when read
    body = model.frame(link).body
    assert abs(written.bodies[body].mass - model.bodies[body].mass - found["mass"]) < 1e-9
    code, text, err = run(capsys, "identify", str(out), "--log", str(log), "--scope", "payload", "--out",
                          str(folder / "twice.urdf"))
    assert_one_line_error(code, err, "link 'payload' already")
    report = folder / "report"
    code, text, err = run(capsys, "identify", str(urdf), "--log", str(log), "--scope", "payload", "--out",
                          str(report), "--quiet")
    assert code == 0, err
    assert sorted(p.name for p in report.iterdir()) == [".course-dynamics-files.json", "identified.urdf",
                                                         "report.html", "report.json", "report.md"]
    assert (report / "identified.urdf").read_bytes() == out.read_bytes()
    assert "mass m" in text and "mass m" in (report / "report.html").read_text()
    assert json.loads((report / "report.json").read_text())["mass"] == found["mass"]


def test_a_log_without_a_payload_detects_none_and_writes_nothing(capsys, excited):
    model, urdf, motion, folder, _ = excited
    log = write_log(folder / "empty.csv", model, motion, seed=1)
    out = folder / "empty.urdf"
    code, text, err = run(capsys, "identify", str(urdf), "--log", str(log), "--scope", "payload", "--out", str(out))
    assert code == 1 and not out.exists(), err
    assert "no payload is detected: no URDF written" in err and "no payload detected: the least-squares mass" in text
    code, text, _ = run(capsys, "identify", str(urdf), "--log", str(log), "--scope", "payload", "--out", str(out),
                        "--json")
    found = json.loads(text)
    assert code == 1 and not found["detected"] and found["robot_forms"] is None and found["out"] is None
    assert abs(found["mass"]) < 3 * found["mass_sigma"] < 0.05, (found["mass"], found["mass_sigma"])
    assert found["parameters"][0]["identified"] == found["mass"] and found["solver"] == "least squares"  # one mass
    folder_out = out.parent / "no_payload_report"
    code, text, err = run(capsys, "identify", str(urdf), "--log", str(log), "--scope", "payload", "--out",
                          str(folder_out))
    assert code == 1 and not folder_out.exists() and "wrote" not in err, err   # nothing written, not even a report
    assert found["com"] == [None] * 3 and found["inertia"] == [None] * 9      # no mass, so no centre of mass


def test_a_quiet_log_without_a_payload_shows_no_gram_of_one(capsys, excited):
    """With a hundredth of the noise the standard error is tiny, and the bias of the differentiated Θ̈ would pass
    for a payload of a gram: below 0.1 % of the arm's mass is no payload either."""
    model, urdf, motion, folder, _ = excited
    log = write_log(folder / "quiet.csv", model, motion, seed=2, noise=NOISE / 100)
    out = folder / "quiet.urdf"
    code, text, err = run(capsys, "identify", str(urdf), "--log", str(log), "--scope", "payload", "--out", str(out),
                          "--json")
    found = json.loads(text)
    assert code == 1 and not out.exists() and not found["detected"], err
    assert found["determined"] == {"mass": True, "com": False, "inertia": False}
    assert abs(found["mass"]) < 1e-3 * sum(b.mass for b in model.bodies)
    assert any(n.startswith("no payload detected: the least-squares mass") for n in found["notes"])


def test_friction_fitted_with_the_payload_is_never_below_zero(capsys, excited):
    """--friction-fit both bounds both coefficients at 0; the solver's round-off below it is the bound itself."""
    model, urdf, motion, folder, _ = excited
    log = write_log(folder / "carried_both.csv", model, motion, Payload(MASS, link=flange_link(model), com=COM,
                                                                         size=SIZE), seed=3)
    code, text, err = run(capsys, "identify", str(urdf), "--log", str(log), "--scope", "payload", "--friction-fit",
                          "both", "--out", str(folder / "both.urdf"), "--json")
    assert code == 0, err
    found = json.loads(text)
    assert abs(found["mass"] - MASS) < 0.02 * MASS, found["mass"]
    fitted = [v for kind in ("viscous", "coulomb") for v in found["friction"][kind].values() if v is not None]
    assert fitted and min(fitted) >= 0, found["friction"]


def test_a_log_where_the_wrist_does_not_move_reports_what_it_does_not_determine(capsys, excited):
    model, urdf, motion, folder, _ = excited
    still = np.flatnonzero(wrist(model))
    log = write_log(folder / "stiff.csv", model, lambda t: _base_only(model, t), Payload(MASS, link=flange_link(model),
                    com=COM, size=SIZE), seed=2, still=still)
    out = folder / "stiff.urdf"
    code, text, err = run(capsys, "identify", str(urdf), "--log", str(log), "--scope", "payload", "--out", str(out),
                          "--json")
    found = json.loads(text)
    assert code == 1 and not out.exists() and not found["determined"]["com"], found["determined"]
    assert found["com"] == [None] * 3 and any("not determined by the log" in n for n in found["notes"])


def _base_only(model, t):
    """The first joint swinging, every other resting in the middle of its range."""
    mid = np.where(np.isfinite(model.lower) & np.isfinite(model.upper), (model.lower + model.upper) / 2, 0.0)
    q = np.tile(mid, (len(t), 1))
    qd, qdd = np.zeros_like(q), np.zeros_like(q)
    q[:, 0], qd[:, 0], qdd[:, 0] = 0.8 * np.sin(t), 0.8 * np.cos(t), -0.8 * np.sin(t)
    return q, qd, qdd


@pytest.mark.parametrize("extra, fragments", [
    (["--flange", "no_such_link"], ["no_such_link"]),
    (["--flange", "base_link"], ["fixed to the base", "base_link"]),
    (["--prior-weight", "1"], ["--prior-weight is for --scope robot"]),
])
def test_a_flange_that_is_no_link_of_the_arm_is_refused(capsys, tmp_path, extra, fragments):
    log = tmp_path / "log.csv"
    write_csv(log, ["t", "q_shoulder_pan_joint"], [np.arange(3.0), np.zeros(3)])
    code, _, err = run(capsys, "identify", "ur5", "--log", str(log), "--scope", "payload", "--out",
                       str(tmp_path / "x.urdf"), *extra)
    assert_one_line_error(code, err, *fragments)
    assert not (tmp_path / "x.urdf").exists()
