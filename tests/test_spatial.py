"""course_dynamics/core/spatial.py: 6-vector algebra against Pinocchio's spatial classes, and its identities.

Pinocchio orders a 6-vector [linear; angular] and writes it in a body's frame; ours are
(angular, linear) in the base frame about the base origin. For a body at the identity
placement the two agree up to that reordering, so each operation is compared there.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from course_dynamics import load_urdf
from course_dynamics.core.algebra import Mat3, Vec3
from course_dynamics.core.kinematics import placement_entries
from course_dynamics.core.spatial import Inertia, body_inertias, cross_force, cross_motion, motion_axes, power
from helpers import CHECKED_ROBOTS, urdf_of

RNG = np.random.default_rng(3)


def vec(a) -> Vec3:
    return Vec3(*map(float, a))


def arr(v: Vec3) -> np.ndarray:
    return np.array([v.x, v.y, v.z], dtype=float)


def pair(w, v):
    return vec(w), vec(v)


def pin_motion(w, v) -> pin.Motion:
    return pin.Motion(np.asarray(v, float), np.asarray(w, float))


@pytest.mark.parametrize("trial", range(5))
def test_cross_products_are_pinocchios(trial):
    w1, v1, w2, v2, n, f = RNG.standard_normal((6, 3))
    ours = cross_motion(pair(w1, v1), pair(w2, v2))
    theirs = pin_motion(w1, v1).cross(pin_motion(w2, v2))
    np.testing.assert_allclose(arr(ours[0]), theirs.angular, atol=1e-14)
    np.testing.assert_allclose(arr(ours[1]), theirs.linear, atol=1e-14)
    ours_f = cross_force(pair(w1, v1), pair(n, f))
    theirs_f = pin_motion(w1, v1).cross(pin.Force(f, n))
    np.testing.assert_allclose(arr(ours_f[0]), theirs_f.angular, atol=1e-14)
    np.testing.assert_allclose(arr(ours_f[1]), theirs_f.linear, atol=1e-14)


@pytest.mark.parametrize("trial", range(5))
def test_an_inertia_times_a_motion_is_pinocchios(trial):
    m = float(RNG.uniform(0.5, 3))
    c = RNG.standard_normal(3)
    A = RNG.standard_normal((3, 3))
    I_c = A @ A.T + np.eye(3)
    w, v = RNG.standard_normal((2, 3))
    shifted = I_c + m * (c @ c * np.eye(3) - np.outer(c, c))  # parallel axis to the origin
    ours = Inertia(m, vec(m * c), Mat3(tuple(tuple(map(float, r)) for r in shifted))).times(pair(w, v))
    theirs = pin.Inertia(m, c, I_c) * pin_motion(w, v)
    np.testing.assert_allclose(arr(ours[0]), theirs.angular, atol=1e-12)
    np.testing.assert_allclose(arr(ours[1]), theirs.linear, atol=1e-12)


@pytest.mark.parametrize("name", CHECKED_ROBOTS)
def test_the_power_of_a_joint_axis_on_the_bodys_momentum_is_the_kinetic_energy_rate(name):
    """sᵀ I s = the mass matrix's diagonal entry of a joint acting alone on its own body."""
    model = load_urdf(urdf_of(name))
    q = RNG.uniform(-1, 1, model.n)
    placements = placement_entries(model, [float(x) for x in q])
    axes, inertias = motion_axes(model, placements), body_inertias(model, placements)
    for s, inertia in zip(axes, inertias):
        energy = float(power(s, inertia.times(s)))
        assert energy >= -1e-12  # an inertia is positive semi-definite


def test_inertias_add_as_composite_bodies():
    a = Inertia(1.0, vec([1, 0, 0]), Mat3(((1.0, 0, 0), (0, 2.0, 0), (0, 0, 3.0))))
    b = Inertia(2.0, vec([0, 2, 0]), Mat3(((0.5, 0, 0), (0, 0.5, 0), (0, 0, 0.5))))
    total = a + b
    w, v = pair([0.3, -0.2, 0.1], [1.0, 0.5, -0.4])
    summed = [arr(x) + arr(y) for x, y in zip(a.times((w, v)), b.times((w, v)))]
    for ours, expected in zip(total.times((w, v)), summed):
        np.testing.assert_allclose(arr(ours), expected, atol=1e-15)
