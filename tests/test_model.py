"""course_dynamics/core/model.py: the frozen model, its checks, and what it derives from the URDF's numbers."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from course_dynamics import ModelError, load_robot, load_urdf
from helpers import CHECKED_ROBOTS, urdf_of


@pytest.mark.parametrize("name", CHECKED_ROBOTS)
def test_a_model_cannot_be_changed_while_algorithms_run(name):
    model = load_urdf(urdf_of(name))
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.name = "other"
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.bodies[0].mass = 2.0
    for array in (model.gravity, model.bodies[0].R0, model.bodies[0].P, model.bodies[0].I_com):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 1.0


@pytest.mark.parametrize("name", CHECKED_ROBOTS)
def test_parents_come_first_and_children_are_their_inverse(name):
    model = load_urdf(urdf_of(name))
    for i, body in enumerate(model.bodies):
        assert -1 <= body.parent < i
        assert all(model.bodies[j].parent == i for j in model.children[i])
    assert sum(len(c) for c in model.children) == sum(b.parent >= 0 for b in model.bodies)


def test_a_parent_after_its_child_is_refused():
    model = load_robot("two_link")
    first, second = model.bodies
    with pytest.raises(ModelError, match="does not come before it"):
        dataclasses.replace(model, bodies=(dataclasses.replace(first, parent=1), second))


def test_a_body_with_a_wrong_shape_is_named():
    body = load_robot("two_link").bodies[0]
    with pytest.raises(ModelError, match="axis: expected shape"):
        dataclasses.replace(body, axis=np.array([0.0, 1.0]))


def test_derived_quantities_are_the_urdf_numbers_in_craigs_form():
    """R0 is a rotation, the axis a unit vector, and R0 @ axis is the axis in the parent frame."""
    for name in CHECKED_ROBOTS:
        for body in load_urdf(urdf_of(name)).bodies:
            np.testing.assert_allclose(body.R0 @ body.R0.T, np.eye(3), atol=1e-12)
            assert np.linalg.det(body.R0) == pytest.approx(1.0)
            assert np.linalg.norm(body.axis) == pytest.approx(1.0)
            z = body.R0_axis_v
            np.testing.assert_allclose(np.array([z.x, z.y, z.z], dtype=float), body.R0 @ body.axis, atol=1e-15)


def test_with_gravity_is_a_new_model_and_leaves_the_old_one():
    model = load_robot("two_link")
    moon = model.with_gravity([0.0, 0.0, -1.62])
    assert moon is not model and moon.gravity.tolist() == [0.0, 0.0, -1.62]
    assert model.gravity.tolist() == [0.0, 0.0, -9.81]
    with pytest.raises(ModelError):
        model.with_gravity([0.0, 0.0])


def test_limits_are_arrays_in_joint_order_with_inf_for_none():
    ur5 = load_robot("ur5")
    assert ur5.lower.shape == ur5.upper.shape == ur5.effort.shape == ur5.velocity.shape == (6,)
    assert np.all(ur5.lower < ur5.upper) and np.all(ur5.effort > 0)
    pendulum = load_robot("pendulum")
    assert pendulum.n == 1 and pendulum.joint_names == (pendulum.bodies[0].joint,)


def test_an_unknown_frame_names_the_known_ones():
    with pytest.raises(ModelError, match="has no link or frame 'nowhere' \\(frames: "):
        load_robot("two_link").frame("nowhere")
