"""course_dynamics/urdf.py: what the loader reads, merges and rejects."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from course_dynamics import ModelError, load_urdf, mass_matrix
from tests.conftest import AWKWARD

LINK = '<link name="{name}"><inertial><origin xyz="0.1 0 0" rpy="0 0 0"/><mass value="{mass}"/>' \
       '<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="0" ixz="0" iyz="0"/></inertial></link>'
JOINT = '<joint name="{name}" type="{type}"><parent link="{parent}"/><child link="{child}"/>' \
        '<origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="{axis}"/>' \
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'


def arm_urdf(mass="1.0", ixx="0.01", iyy="0.01", izz="0.01", joint_type="revolute", axis="0 0 1", extra=""):
    """A two-link arm as URDF text, with one thing changed at a time."""
    return (
        '<?xml version="1.0"?><robot name="probe"><link name="base"/>'
        + LINK.format(name="link1", mass="1.0", ixx="0.01", iyy="0.01", izz="0.01")
        + LINK.format(name="link2", mass=mass, ixx=ixx, iyy=iyy, izz=izz)
        + JOINT.format(name="joint1", type="revolute", parent="base", child="link1", axis="0 0 1")
        + JOINT.format(name="joint2", type=joint_type, parent="link1", child="link2", axis=axis)
        + extra + "</robot>"
    )


BAD_URDFS = {
    "floating joint": (arm_urdf(joint_type="floating"), "joint 'joint2': type 'floating' is not supported"),
    "planar joint": (arm_urdf(joint_type="planar"), "joint 'joint2': type 'planar' is not supported"),
    "kinematic loop": (
        arm_urdf(extra=JOINT.format(name="loop", type="revolute", parent="base", child="link2", axis="1 0 0")),
        "kinematic loop: link 'link2' is the child of both joint 'joint2' and joint 'loop'"),
    "two roots": (arm_urdf(extra='<link name="stray"/>'), "2 root links (base, stray)"),
    "negative mass": (arm_urdf(mass="-1"), "link 'link2': negative mass"),
    "inertia not positive": (arm_urdf(ixx="-0.01"), "link 'link2': inertia tensor is not positive semi-definite"),
    "triangle inequality": (arm_urdf(ixx="0.01", iyy="0.01", izz="0.05"), "link 'link2': inertia breaks the triangle inequality"),
    "zero axis": (arm_urdf(axis="0 0 0"), "joint 'joint2': zero axis"),
    "NaN mass": (arm_urdf(mass="nan"), "link 'link2' inertial mass has a non-finite value"),
    "inf axis": (arm_urdf(axis="0 inf 0"), "joint 'joint2' axis has a non-finite value"),
    "non-numeric mass": (arm_urdf(mass="heavy"), "malformed URDF: could not convert string to float: 'heavy'"),
    "malformed XML": ('<robot name="x"><link name="a"></robot>', "malformed XML"),
    "undefined link": (arm_urdf(extra=JOINT.format(name="j3", type="fixed", parent="link2", child="ghost", axis="1 0 0")),
                       "joint 'j3': child link 'ghost' is not defined"),
    "nothing moves": ('<robot name="x"><link name="a"/></robot>', "nothing moves"),
}


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
