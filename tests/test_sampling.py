"""course_dynamics/core/sampling.py: seeded states within limits, smooth trajectories, the error measure."""
from __future__ import annotations

import numpy as np
import pytest

from course_dynamics import gravity_torques, load_robot, load_urdf
from course_dynamics.core.sampling import (
    gravity_free,
    reach,
    random_states,
    relative_error,
    sampling_bounds,
    smooth_trajectory,
    term_scales,
)
from helpers import CHECKED_ROBOTS, arm_urdf, urdf_of


@pytest.mark.parametrize("name", CHECKED_ROBOTS)
def test_states_are_seeded_and_within_the_joint_limits(name):
    model = load_urdf(urdf_of(name))
    q, qd, qdd = random_states(model, 50, seed=4)
    again = random_states(model, 50, seed=4)
    for ours, repeat in zip((q, qd, qdd), again):
        np.testing.assert_array_equal(ours, repeat)
        assert ours.shape == (50, model.n)
    lower, upper = sampling_bounds(model)
    assert np.all((lower <= q) & (q <= upper))
    assert not np.array_equal(q, random_states(model, 50, seed=5)[0])


def test_joints_without_limits_are_sampled_over_a_turn():
    model = load_robot("double_pendulum_continuous")
    lower, upper = sampling_bounds(model)
    np.testing.assert_array_equal(lower, -np.pi)
    np.testing.assert_array_equal(upper, np.pi)


def test_a_smooth_trajectory_has_exact_derivatives():
    model = load_robot("ur5")
    t, q, qd, qdd = smooth_trajectory(model, duration=1.0, samples=2001)
    dt = t[1] - t[0]
    lower, upper = sampling_bounds(model)
    # The tolerance is np.gradient's own truncation error, dt²/6 · max|x⁽³⁾|, for the documented amplitudes
    # (a third of the half-range) and ω ≤ 3 rad/s: a ω³ for Θ̇, a ω⁴ for Θ̈ (here 2.4e-6 and 7.1e-6).
    amplitude = float(np.max(upper - lower)) / 6
    np.testing.assert_allclose(np.gradient(q, dt, axis=0)[1:-1], qd[1:-1], rtol=0, atol=dt**2 / 6 * amplitude * 3**3)
    np.testing.assert_allclose(np.gradient(qd, dt, axis=0)[1:-1], qdd[1:-1], rtol=0, atol=dt**2 / 6 * amplitude * 3**4)
    assert np.all((lower <= q) & (q <= upper))


def test_relative_error_is_the_documented_measure():
    assert relative_error([1.0, 2.0], [1.0, 2.5]) == pytest.approx(0.5 / 2.5)
    assert relative_error([1e-17], [0.0], scale=1.0) == pytest.approx(1e-17)  # a zero term judged at its scale
    assert relative_error([0.0], [0.0]) == 0.0
    assert relative_error([1.0], [0.0]) > 1e300  # no scale: any error of a zero term is infinitely large


def test_term_scales_follow_the_table():
    M, G = np.array([[2.0, 0.5], [0.5, 1.0]]), np.array([3.0, -1.0])
    scales = term_scales(M, G, qd=[0.5, -2.0], qdd=[1.0, 0.0], gravity=[0, 0, -9.81])
    assert scales == pytest.approx(dict(tau=2.0 * (1.0 + 4.0) + 3.0, M=2.0, C=2.0 * 2.0, V=2.0 * 4.0, G=2.0 * 9.81))


def test_gravity_free_is_a_robot_on_which_gravity_cannot_act():
    arm = load_robot("two_link")
    assert not gravity_free(arm)
    upright = arm.with_gravity(9.81 * (arm.bodies[0].R0 @ arm.bodies[0].axis))  # along the (parallel) joint axes
    assert gravity_free(upright)
    assert np.abs(gravity_torques(upright, np.array([0.3, -0.4]))).max() < 1e-12


def test_limits_at_the_largest_floats_are_no_limits(tmp_path):
    # Exporters write ±1.8e308 for "no limit"; their distance is no float, so uniform sampling cannot use them.
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(arm_urdf().replace('lower="-1" upper="1"', 'lower="-1.7976931348623157e308" upper="1.7976931348623157e308"'))
    lower, upper = sampling_bounds(load_urdf(urdf))
    np.testing.assert_array_equal(lower, [-np.pi, -np.pi])
    np.testing.assert_array_equal(upper, [np.pi, np.pi])
    q, _, _ = random_states(load_urdf(urdf), 20, seed=0)
    assert np.all(np.abs(q) <= np.pi)


@pytest.mark.parametrize("limits, expected", [
    ((-1e10, 1e10), lambda window: (-window, window)),   # ten reaches either side of 0
    ((5.0, 1e300), lambda window: (5.0, 5.0 + window)),  # from the end nearest 0, one way only
    ((-0.5, 0.25), lambda window: (-0.5, 0.25)),         # a range within the window is kept as it is
])
def test_a_prismatic_joint_is_sampled_within_ten_reaches(tmp_path, limits, expected):
    urdf = tmp_path / "robot.urdf"
    text = arm_urdf(joint_type="prismatic")
    last = text.rindex('lower="-1" upper="1"')
    urdf.write_text(text[:last] + f'lower="{limits[0]!r}" upper="{limits[1]!r}"' + text[last + len('lower="-1" upper="1"'):])
    model = load_urdf(urdf)
    lower, upper = sampling_bounds(model)
    assert (lower[0], upper[0]) == (-1.0, 1.0)   # the revolute joint keeps its limits
    assert (lower[1], upper[1]) == expected(10 * reach(model))
