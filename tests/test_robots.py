"""course_dynamics/core/robots.py: shipped robots are found by name, example-robot-data included."""
from __future__ import annotations

import pytest

from course_dynamics import load_robot, robot_names, robot_path
from course_dynamics.core.robots import example_robot_data_share


@pytest.mark.parametrize("name", robot_names())
def test_every_named_robot_exists_and_loads(name):
    path = robot_path(name)
    assert path.is_file(), path
    assert load_robot(name).n >= 1


def test_example_robot_data_robots():
    assert load_robot("ur5").n == 6
    panda = load_robot("panda")
    # panda_finger_joint2 mimics panda_finger_joint1: 8 coordinates, 9 moving bodies
    assert panda.n == 8 and panda.n_bodies == 9 and panda.joint_names[-1] == "panda_finger_joint1"
    continuous = load_robot("double_pendulum_continuous")
    assert [b.joint_type for b in continuous.bodies] == ["continuous", "continuous"]


def test_package_paths_resolve_against_cmeel_share():
    share = example_robot_data_share()
    mesh = "package://example-robot-data/robots/ur_description/meshes/ur5/collision/base.stl"
    assert (share / mesh.removeprefix("package://")).is_file()


def test_unknown_name():
    with pytest.raises(KeyError, match="unknown robot 'r2d2'"):
        robot_path("r2d2")


def test_without_the_installed_package_data_the_checkouts_robots_are_found(monkeypatch):
    """The fallback of a source checkout that is not installed: robots/ beside the package."""
    from importlib import resources

    from course_dynamics.base import robot_files

    def not_installed(name):
        raise ModuleNotFoundError(name)

    monkeypatch.setattr(resources, "files", not_installed)
    assert (robot_files._robots_folder() / "two_link.urdf").is_file()
