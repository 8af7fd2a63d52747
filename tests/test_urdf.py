"""course_dynamics/core/urdf.py: what the loader reads, merges and rejects."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from helpers import AWKWARD, BAD_URDFS, arm_urdf, assert_one_line_error, run

from course_dynamics import ModelError, load_urdf, mass_matrix


@pytest.mark.parametrize("case", sorted(BAD_URDFS))
def test_bad_urdf_is_rejected_with_a_named_cause(tmp_path, case):
    text, message = BAD_URDFS[case]
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    with pytest.raises(ModelError) as caught:
        load_urdf(path)
    assert message in str(caught.value)
    assert str(path) in str(caught.value)
    assert "\n" not in str(caught.value)


def test_missing_file(tmp_path):
    with pytest.raises(ModelError, match="no such file"):
        load_urdf(tmp_path / "nowhere.urdf")


def test_point_masses_with_zero_inertia_are_accepted(tmp_path):
    path = tmp_path / "point.urdf"
    path.write_text(arm_urdf(ixx="0", iyy="0", izz="0"))
    assert load_urdf(path).bodies[1].I_com.max() == 0


def test_awkward_robot_structure():
    model = load_urdf(AWKWARD)
    assert model.joint_names == ("shoulder", "telescope", "wrist_roll", "side_joint")
    parents = [b.parent for b in model.bodies]
    assert parents == [-1, 0, 1, 0]  # a branch at the upper arm
    assert [b.joint_type for b in model.bodies] == ["revolute", "prismatic", "continuous", "revolute"]
    np.testing.assert_allclose([np.linalg.norm(b.axis) for b in model.bodies], 1.0)
    assert model.bodies[1].mass == 0.0  # the massless slider


def test_fixed_joints_are_lumped_as_pinocchio_does():
    """Mass, COM and inertia of the merged bodies equal Pinocchio's body inertias."""
    model = load_urdf(AWKWARD)
    pin_model = pin.buildModelFromUrdf(str(AWKWARD))
    for body in model.bodies:
        inertia = pin_model.inertias[pin_model.getJointId(body.joint)]
        assert body.mass == pytest.approx(inertia.mass, rel=1e-14)
        np.testing.assert_allclose(body.p_com, inertia.lever, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(body.I_com, inertia.inertia, rtol=1e-12, atol=1e-15)
    assert model.bodies[0].mass == pytest.approx(2.5 + 1.2)  # upper arm + welded elbow housing
    assert model.bodies[3].mass == pytest.approx(1.1 + 0.6)  # side arm + welded tool


def test_links_fixed_to_the_base_do_not_count():
    model = load_urdf(AWKWARD)
    assert sum(b.mass for b in model.bodies) == pytest.approx(2.5 + 1.2 + 0.8 + 1.1 + 0.6)
    assert np.all(np.linalg.eigvalsh(mass_matrix(model, np.zeros(model.n))) > 0)


def test_model_is_immutable():
    model = load_urdf(AWKWARD)
    with pytest.raises(AttributeError):
        model.name = "other"
    with pytest.raises(ValueError):
        model.bodies[0].P[0] = 1.0


def test_gravity_can_be_set():
    model = load_urdf(AWKWARD, gravity=(0, 0, -1.62))
    assert model.gravity.tolist() == [0, 0, -1.62]
    with pytest.raises(ModelError, match="gravity"):
        load_urdf(AWKWARD, gravity=(0, float("nan"), 0))


@pytest.mark.parametrize("value, message", [
    ("1_0", "'1_0' is not a number as URDF writes them"),
    ("\u0661", "is not a number as URDF writes them"),        # an Arabic-Indic digit: float() reads it as 1
    ("\uff11", "is not a number as URDF writes them"),        # a full-width 1
    ("0x10", "'0x10' is not a number as URDF writes them"),
    ("1e-400", "'1e-400' is too small for a double and would be read as 0"),
])
def test_numbers_are_read_only_as_urdf_writes_them(tmp_path, capsys, value, message):
    """float() accepts all of these; each would be a mass nobody wrote on purpose."""
    path = tmp_path / "odd.urdf"
    path.write_text(arm_urdf(mass=value), encoding="utf-8")
    code, _, err = run(capsys, "info", str(path))
    assert_one_line_error(code, err, str(path), "link 'link2': <mass value=", message)


@pytest.mark.parametrize("text, message", [
    (arm_urdf(axis="0 1"), "joint 'joint2': <axis xyz=\"0 1\">: 2 values, expected 3"),
    (arm_urdf().replace('rpy="0 0 0"', 'rpy="1e300 0 0"', 1), "an angle of 1e+300 rad, more than 10000 in size"),
    (arm_urdf().replace('name="joint2"', 'name=""'), "a joint has an empty name"),
    (arm_urdf().replace('name="joint2"', 'name="' + "j" * 5000 + '"'), "a joint name has 5000 characters, more than 1000"),
])
def test_extreme_attributes_are_refused_with_the_element(tmp_path, capsys, text, message):
    path = tmp_path / "odd.urdf"
    path.write_text(text)
    code, _, err = run(capsys, "info", str(path))
    assert_one_line_error(code, err, str(path), message)


def test_reading_a_urdf_does_not_load_trimesh_until_a_mesh_is_wanted():
    """yourdfpy imports trimesh (scipy, networkx: 1.5–2 s); reading a URDF defers it, and the first use of
    trimesh itself, as the viewer's mesh reader makes, gets the whole package. The models read either way are
    the same."""
    import subprocess
    import sys

    script = (
        "import sys, json\n"
        "first = sys.argv[1] == 'trimesh-first'\n"
        "if first:\n"
        "    import trimesh\n"
        "from course_dynamics import load_robot\n"
        "m = load_robot('panda')\n"
        "deferred = 'trimesh.base' not in sys.modules\n"
        "import trimesh\n"
        "box = trimesh.creation.box((1, 2, 3))\n"
        "print(json.dumps(dict(deferred=deferred, volume=float(box.volume), "
        "numbers=[float(b.mass) for b in m.bodies] + [float(x) for b in m.bodies for x in b.I_com.ravel()])))\n")
    import json

    runs = {how: json.loads(subprocess.run([sys.executable, "-c", script, how], capture_output=True, text=True,
                                           check=True).stdout) for how in ("deferred", "trimesh-first")}
    assert runs["deferred"]["deferred"] and not runs["trimesh-first"]["deferred"]
    assert runs["deferred"]["volume"] == pytest.approx(6.0) == runs["trimesh-first"]["volume"]
    assert runs["deferred"]["numbers"] == runs["trimesh-first"]["numbers"]
