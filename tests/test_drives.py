"""course_dynamics/core/drives.py: rotor inertias and torque offsets, their TOML file, and every command that reads it.

The oracle is Pinocchio's ``model.armature`` (added to CRBA's diagonal and to RNEA's τ, seen by ABA). The
identification case is the perturbed UR5 of tests/test_identification.py (masses ±20 %, centres ±2 cm,
inertias ±30 %, friction the URDF lacks, recorder noise) with rotor inertias and offsets added: 30 s at 100 Hz.
"""
from __future__ import annotations

import contextlib
import io
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states
from helpers import assert_one_line_error, run, urdf_of
from logmakers import multisine, noisy, write_csv
from test_identification import NOISE_Q, NOISE_QD, NOISE_TAU, RATE, true_robot

from course_dynamics import forward_dynamics, inverse_dynamics, load_robot, mass_matrix
from course_dynamics.base.errors import InputError
from course_dynamics.cli import main
from course_dynamics.core.drives import Driven, Drives, drives_text, parse_drives, read_drives
from course_dynamics.core.evaluator import implementation

RTOL = 1e-9
UR5_DRIVES = Drives(armature=[0.4, 0.4, 0.3, 0.1, 0.1, 0.1], offset=[1.0, -3.0, 1.5, 0.3, -0.3, 0.2])


def relative(a, b) -> float:
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / max(np.abs(np.asarray(b)).max(), 1e-300))


@pytest.mark.parametrize("name", ["ur5", "rp_arm"])
def test_drives_agree_with_pinocchios_armature(name):
    """τ + Iₐ Θ̈, M + diag(Iₐ) and Θ̈ through both, against rnea, crba and aba with model.armature."""
    model = load_robot(name)
    armature = np.random.default_rng(3).uniform(0.05, 0.5, model.n)
    drives = Drives(armature=armature, offset=np.zeros(model.n))
    oracle = PinocchioOracle(urdf_of(name), model.joint_names, model.gravity)
    oracle.set_armature(armature)
    q, qd, qdd = random_states(model, 5, seed=11)
    for k in range(len(q)):
        tau = inverse_dynamics(model, q[k], qd[k], qdd[k]) + drives.torques(qdd[k])
        assert relative(tau, oracle.tau(q[k], qd[k], qdd[k])) < RTOL
        assert relative(drives.mass_matrix(mass_matrix(model, q[k])), oracle.M(q[k])) < RTOL
        assert relative(forward_dynamics(model, q[k], qd[k], tau, drives=drives), oracle.aba(q[k], qd[k], tau)) < RTOL
    driven = Driven(implementation(model), drives)    # the batch path simulate and torques take
    assert relative(driven.inverse_dynamics(q, qd, qdd), np.array([oracle.tau(*s) for s in zip(q, qd, qdd)])) < RTOL


def test_an_offset_is_a_constant_torque_the_dynamics_must_overcome():
    model = load_robot("two_link")
    drives = Drives(armature=[0.0, 0.0], offset=[2.0, -1.0])
    q, qd, tau = np.array([0.3, -0.2]), np.array([0.5, 1.0]), np.array([20.0, 3.0])
    assert np.allclose(forward_dynamics(model, q, qd, tau, drives=drives), forward_dynamics(model, q, qd, tau - [2, -1]),
                       rtol=1e-13)


@pytest.mark.parametrize("armature, offset, fragment", [
    ([-0.1], [0.0], "non-negative"), ([np.nan], [0.0], "finite"), ([0.1], [np.inf], "finite"),
    ([0.1, 0.2], [0.0], "as many"),
])
def test_bad_drives_are_refused(armature, offset, fragment):
    with pytest.raises(InputError, match=fragment):
        Drives(armature=armature, offset=offset)


def test_the_file_reads_back_what_was_written_and_names_missing_joints_zero(tmp_path):
    ur5 = load_robot("ur5")
    errors = (np.full(6, 0.01), np.array([np.nan, 0.02, 0.02, 0.02, 0.02, 0.02]))
    text = drives_text(UR5_DRIVES, ur5, "drives of ur5: a test", errors)
    assert text.startswith("# drives of ur5: a test\n[joint.shoulder_pan_joint]\narmature = 0.4")
    assert "± 0.01" in text and "N·m, not identified" in text
    path = tmp_path / "drives.toml"
    path.write_text(text)
    back = read_drives(path, ur5)
    assert np.array_equal(back.armature, UR5_DRIVES.armature) and np.array_equal(back.offset, UR5_DRIVES.offset)
    some = parse_drives('[joint.elbow_joint]\noffset = -1\n[joint."wrist_3_joint"]\narmature = 0.5\n', ur5)
    assert some.offset.tolist() == [0, 0, -1, 0, 0, 0] and some.armature.tolist() == [0, 0, 0, 0, 0, 0.5]
    rp = load_robot("rp_arm")
    assert "kg\n" in drives_text(Drives.none(rp), rp, "x").split("[joint.", 2)[2]   # a prismatic joint's unit


def test_odd_joint_names_are_quoted_and_read_back():
    model = load_robot("two_link")
    odd = replace(model, bodies=(replace(model.bodies[0], joint='a.b "c"'), model.bodies[1]))
    text = drives_text(Drives([0.1, 0.2], [0.3, 0.4]), odd, "odd")
    assert parse_drives(text, odd).armature.tolist() == [0.1, 0.2]


@pytest.mark.parametrize("text, fragments", [
    ("[joint.nope]\narmature = 1\n", ["no moving joint 'nope'", "shoulder_pan_joint"]),
    ("[joint.elbow_joint]\narmature = 1\n[joint.elbow_joint]\noffset = 1\n", ["not a TOML file", "'elbow_joint'"]),
    ("[joint.wrist_1_joint]\noffset = 0\n[joint.elbow_joint]\narmature = 1\narmature = 2\n",
     ["line 5", "joint 'elbow_joint'"]),
    ("[joint.elbow_joint]\narmature = 1e308\n", ["joint 'elbow_joint'", "armature 1e+308", "more than"]),
    ("[joint.elbow_joint]\noffset = -3e9\n", ["joint 'elbow_joint'", "offset", "more than"]),
    ("joint = 3\n", ["'joint' is a value"]),
    ("x = " + "[" * 5000 + "]" * 5000 + "\n", ["nested too deeply"]),
    ("joint = {elbow_joint = " + "{a = " * 4000 + "1" + "}" * 4001 + "\n", ["nested too deeply"]),
    ("[joint.elbow_joint]\narmature = -1\n", ["joint 'elbow_joint'", "non-negative"]),
    ("[joint.elbow_joint]\narmature = nan\n", ["joint 'elbow_joint'", "finite"]),
    ("[joint.elbow_joint]\narmature = inf\n", ["finite"]),
    ("[joint.elbow_joint]\narmature = true\n", ["finite number"]),
    ("[joint.elbow_joint]\narmature = '0.1'\n", ["finite number"]),
    ("[joint.elbow_joint]\ndamping = 0.1\n", ["unknown key 'damping'"]),
    ("[robot]\nname = 'ur5'\n", ["tables only", "'robot'"]),
    ("# nothing\n", ["it has none"]),
    ("[joint]\nelbow_joint = 3\n", ["must be a table"]),
    ("armature = [1, 2\n", ["not a TOML file"]),
])
def test_a_hostile_file_is_one_line_naming_the_file(tmp_path, capsys, text, fragments):
    path = tmp_path / "drives.toml"
    path.write_text(text)
    code, _, err = run(capsys, "torques", "ur5", "--log", str(tmp_path / "missing.csv"), "--drives", str(path))
    assert_one_line_error(code, err, str(path), *fragments)


def test_torques_says_which_drives_file_it_applied(tmp_path, capsys):
    path = tmp_path / "drives.toml"
    path.write_text("[joint.elbow_joint]\narmature = 0.25\noffset = -1.5\n")
    log = Path(__file__).parent.parent / "examples" / "ur5_rtde.csv"
    out_csv = tmp_path / "tau.csv"
    code, out, err = run(capsys, "torques", "ur5", "--log", str(log), "--drives", str(path), "--out", str(out_csv))
    assert code == 0, err
    said = f"drives from {path}: rotor inertias I_a [0.0, 0.0, 0.25, 0.0, 0.0, 0.0]"
    assert f"note: {said}" in out
    assert f"# {said}" in out_csv.read_text()
    code, out, err = run(capsys, "torques", "ur5", "--log", str(log), "--drives", str(path), "--json")
    assert code == 0, err
    assert any(note.startswith(said) and "offsets tau_0 [0.0, 0.0, -1.5," in note for note in json.loads(out)["notes"])


def test_a_file_too_large_or_not_text_is_refused(tmp_path):
    ur5 = load_robot("ur5")
    big = tmp_path / "big.toml"
    big.write_text("#" * 1_000_001)
    with pytest.raises(InputError, match="big.toml"):
        read_drives(big, ur5)
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xff\xfe[joint]")
    with pytest.raises(InputError, match="not UTF-8"):
        read_drives(binary, ur5)


def test_a_mimic_joint_is_named_as_one():
    panda = load_robot("panda")
    mimic = next(b.joint for b in panda.bodies if b.mimic)
    with pytest.raises(InputError, match="mimic joint"):
        parse_drives(f"[joint.{mimic}]\narmature = 0.1\n", panda)


def ur5_log(folder: Path, seconds: float = 30.0, seed: int = 1) -> Path:
    """A log of the perturbed UR5 with friction (as tests/test_identification.py) and :data:`UR5_DRIVES`."""
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    motion = multisine(ur5, duration=seconds, rate=RATE, seed=seed)
    tau = (inverse_dynamics(true, motion.q, motion.qd, motion.qdd) + friction.torques(motion.qd)
           + UR5_DRIVES.torques(motion.qdd))
    measured = noisy(tau, NOISE_TAU * np.sqrt(np.mean(tau**2, axis=0)), seed + 1)
    q, qd = noisy(motion.q, NOISE_Q, seed + 2), noisy(motion.qd, NOISE_QD, seed + 3)
    columns = {"t": motion.t}
    for j, joint in enumerate(ur5.joint_names):
        columns |= {f"q_{joint}": q[:, j], f"qd_{joint}": qd[:, j], f"tau_meas_{joint}": measured[:, j]}
    path = folder / f"ur5-drives-{seed}.csv"
    write_csv(path, list(columns), list(columns.values()))
    return path


@pytest.fixture(scope="module")
def identified(tmp_path_factory):
    """identify --armature --offset --drives-out on the UR5 log: (folder, log, stdout, drives file)."""
    folder = tmp_path_factory.mktemp("drives")
    log = ur5_log(folder)
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["identify", "ur5", "--log", str(log), "--friction-fit", "both", "--armature", "--offset",
                     "--out", str(folder / "report"), "--drives-out", str(folder / "drives.toml")])
    assert code == 0
    return folder, log, out.getvalue(), folder / "drives.toml"


def test_identify_recovers_armatures_and_offsets_within_ten_percent(identified):
    folder, _, out, path = identified
    found = read_drives(path, load_robot("ur5"))
    # The first two UR5 joints' rotors turn with their bodies' inertias about the axes (joint 2 ⊥ joint 1):
    # those armatures are not told apart, and said so; every other armature and every offset is recovered.
    assert found.armature[:2].tolist() == [0.0, 0.0]
    assert "armature of joint 'shoulder_pan_joint' cannot be told apart from π_b" in out
    assert "armature of joint 'shoulder_lift_joint' cannot be told apart from π_b" in out
    assert np.all(np.abs(found.armature[2:] / UR5_DRIVES.armature[2:] - 1) < 0.10), found.armature
    assert np.all(np.abs(found.offset / UR5_DRIVES.offset - 1) < 0.10), found.offset
    text = path.read_text()
    assert text.startswith("# drives of ur5: identified by course-dynamics from ") and "kg·m² ±" in text
    report = json.loads((folder / "report" / "report.json").read_text())
    elbow = report["drives"]["elbow_joint"]
    assert 0 < elbow["armature_error"] < 0.05 * elbow["armature"]   # with its standard error
    assert "Drives (rotor inertia, torque offset)" in (folder / "report" / "report.md").read_text()
    assert "armature I_a" in out and "offset τ₀" in out


def test_torques_reads_the_drives_back_and_matches_the_measured_torques_better(identified, capsys):
    folder, log, _, path = identified
    urdf = folder / "report" / "identified.urdf"

    def rms(*extra):
        code, out, err = run(capsys, "torques", str(urdf), "--log", str(log), "--friction", "urdf", "--json", *extra)
        assert code == 0, err
        return np.array([j["rms"] for j in json.loads(out)["residuals"]["joints"]])
    without, with_drives = rms(), rms("--drives", str(path))
    assert np.all(with_drives < without / 2), (with_drives, without)    # measured: 2.7–45 times smaller
    code, _, err = run(capsys, "torques", str(urdf), "--log", str(log), "--drives", str(path), "--retime")
    assert_one_line_error(code, err, "--retime", "--drives")


def test_identify_with_a_drives_file_subtracts_what_it_does_not_fit(identified, capsys, tmp_path):
    _, log, _, path = identified
    code, out, err = run(capsys, "identify", "ur5", "--log", str(log), "--friction-fit", "both", "--drives",
                         str(path), "--out", str(tmp_path / "id.urdf"), "--json")
    assert code == 0, err
    document = json.loads(out)
    assert document["drives"]["wrist_1_joint"]["armature"] == pytest.approx(read_drives(path, load_robot("ur5"))
                                                                            .armature[3])
    assert document["drives"]["wrist_1_joint"]["armature_error"] is None       # given, not fitted


def test_drives_out_needs_something_to_write(capsys, tmp_path, identified):
    _, log, _, _ = identified
    code, _, err = run(capsys, "identify", "ur5", "--log", str(log), "--out", str(tmp_path / "x.urdf"),
                       "--drives-out", str(tmp_path / "d.toml"))
    assert_one_line_error(code, err, "--drives-out", "--armature")
    assert not (tmp_path / "x.urdf").exists() and not (tmp_path / "d.toml").exists()
