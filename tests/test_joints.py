"""course_dynamics/core/joints.py: each joint kind's transform, unit motion and Jacobian column, against Pinocchio.

A one-joint robot of each kind with an oblique axis and an offset origin: the kind's
transform must place the child as Pinocchio's joint model does, its unit motion be
Pinocchio's joint motion subspace (in the base frame), and its point column the
derivative of the point's position.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from course_dynamics import load_urdf
from course_dynamics.core.algebra import Vec3
from course_dynamics.core.joints import KINDS, Prismatic, Revolute, kind_of
from course_dynamics.core.kinematics import joint_transforms

URDF = """<?xml version="1.0"?><robot name="one"><link name="base"/>
<link name="body"><inertial><mass value="1"/><origin xyz="0.1 0 0"/>
<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="j" type="{kind}"><parent link="base"/><child link="body"/>
<origin xyz="0.3 -0.2 0.5" rpy="0.4 -0.3 0.9"/><axis xyz="0.2 0.6 0.77"/>
<limit lower="-2" upper="2" effort="1" velocity="1"/></joint></robot>"""


def arr(v: Vec3) -> np.ndarray:
    return np.array([v.x, v.y, v.z], dtype=float)


@pytest.fixture(params=["revolute", "continuous", "prismatic"])
def one_joint(request, tmp_path):
    path = tmp_path / "one.urdf"
    path.write_text(URDF.format(kind=request.param))
    pin_model = pin.buildModelFromUrdf(str(path))
    return request.param, load_urdf(path), pin_model


def pin_q(pin_model, kind, q):
    return np.array([np.cos(q), np.sin(q)]) if kind == "continuous" else np.array([q])


@pytest.mark.parametrize("q", [-1.3, 0.0, 0.7])
def test_the_transform_places_the_body_as_pinocchio_does(one_joint, q):
    kind, model, pin_model = one_joint
    body = model.bodies[0]
    R, P = kind_of(body).transform(body, q)
    data = pin_model.createData()
    pin.forwardKinematics(pin_model, data, pin_q(pin_model, kind, q))
    placement = data.oMi[1]
    np.testing.assert_allclose(np.array([[float(x) for x in row] for row in R.rows]), placement.rotation, atol=1e-14)
    np.testing.assert_allclose(arr(P), placement.translation, atol=1e-14)
    X = joint_transforms(model, [q])
    np.testing.assert_allclose(arr(X.P[0]), placement.translation, atol=1e-14)


def test_the_unit_motion_is_pinocchios_motion_subspace(one_joint):
    kind, model, pin_model = one_joint
    body = model.bodies[0]
    q = 0.4
    data = pin_model.createData()
    pin.forwardKinematics(pin_model, data, pin_q(pin_model, kind, q))
    pin.computeJointJacobians(pin_model, data, pin_q(pin_model, kind, q))
    column = np.asarray(pin.getJointJacobian(pin_model, data, 1, pin.ReferenceFrame.WORLD)).reshape(6, -1)[:, 0]
    R, P = kind_of(body).transform(body, q)
    z = R @ body.axis_v  # the axis in the base frame (the joint is the root)
    w, v = kind_of(body).motion(z, P)  # [linear; angular] about the base origin in Pinocchio's WORLD frame
    np.testing.assert_allclose(arr(v), column[:3], atol=1e-14)
    np.testing.assert_allclose(arr(w), column[3:], atol=1e-14)


def test_the_point_column_is_the_derivative_of_the_points_position(one_joint):
    kind, model, _ = one_joint
    body = model.bodies[0]
    offset = np.array([0.1, -0.05, 0.2])  # a point fixed to the body, in its frame

    def position(q):
        R, P = kind_of(body).transform(body, q)
        Rn = np.array([[float(x) for x in row] for row in R.rows])
        return arr(P) + Rn @ offset

    q, h = 0.3, 1e-6
    R, P = kind_of(body).transform(body, q)
    z = R @ body.axis_v
    dv, dw = kind_of(body).point_column(z, Vec3(*position(q)), P)
    np.testing.assert_allclose(arr(dv), (position(q + h) - position(q - h)) / (2 * h), atol=1e-8)
    assert np.allclose(arr(dw), 0) != kind_of(body).rotates


def test_every_moving_kind_of_the_model_has_its_behaviour():
    from course_dynamics.core.model import JOINT_TYPES
    from course_dynamics.core.urdf import SUPPORTED_TYPES

    assert set(JOINT_TYPES) == set(KINDS) and set(SUPPORTED_TYPES) == set(KINDS) | {"fixed"}
    assert KINDS["revolute"] is KINDS["continuous"] is Revolute and KINDS["prismatic"] is Prismatic
