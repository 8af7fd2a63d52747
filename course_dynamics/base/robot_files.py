"""The robots the project ships, by name: the course models and example-robot-data arms, and their URDF files.

==============================  ===============================================
name                            file
==============================  ===============================================
``two_link``                    robots/two_link.urdf (Craig 6.7; installed as package data)
``rp_arm``                      robots/rp_arm.urdf (Craig example 6.5)
``pendulum``                    robots/pendulum.urdf (the notes' pendulum)
``rrr_arm``                     robots/rrr_arm.urdf (a spatial 3R arm, for 3-joint derivations)
``spatial_arm``                 robots/spatial_arm.urdf (skewed axes, products of inertia: the
                                Newton–Euler exercises)
``ur5``                         example-robot-data ur_description/urdf/ur5_robot.urdf
``panda``                       example-robot-data panda_description/urdf/panda.urdf
                                (7 arm joints and both finger joints)
``double_pendulum``             example-robot-data double_pendulum.urdf (revolute)
``double_pendulum_continuous``  example-robot-data double_pendulum_continuous.urdf
==============================  ===============================================

example-robot-data 6.x installs data only, under
``site-packages/cmeel.prefix/share/example-robot-data/robots/``; its
``package://example-robot-data/...`` mesh paths resolve against
``cmeel.prefix/share``.

Finding a robot's file needs no numpy and no dynamics (``course-dynamics --help`` lists the names);
:mod:`course_dynamics.core.robots` loads them.
"""
from __future__ import annotations

import site
import sys
import sysconfig
from pathlib import Path

from .errors import UnknownRobotError


def _robots_folder() -> Path:
    """The course URDFs: the installed package data (``course_dynamics_robots``), else the checkout's robots/."""
    try:
        from importlib import resources

        folder = Path(str(resources.files("course_dynamics_robots")))
        if (folder / "two_link.urdf").is_file():
            return folder
    except (ModuleNotFoundError, TypeError):
        pass
    return Path(__file__).resolve().parents[2] / "robots"  # course_dynamics/base/robot_files.py -> the checkout


ROBOTS_DIR = _robots_folder()

#: The course robots, by name, and their URDF files in the robots folder.
COURSE_ROBOTS = {
    "two_link": "two_link.urdf",
    "rp_arm": "rp_arm.urdf",
    "pendulum": "pendulum.urdf",
    "rrr_arm": "rrr_arm.urdf",
    "spatial_arm": "spatial_arm.urdf",
}

#: The example-robot-data arms, by name, and their URDF files under its ``robots`` folder.
EXAMPLE_ROBOTS = {
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "panda": "panda_description/urdf/panda.urdf",
    "double_pendulum": "double_pendulum_description/urdf/double_pendulum.urdf",
    "double_pendulum_continuous": "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
}


def robot_names() -> tuple[str, ...]:
    """Every robot name :func:`robot_path` knows, course robots first.

    Returns
    -------
    tuple of str
        The names of :data:`COURSE_ROBOTS`, then those of :data:`EXAMPLE_ROBOTS`.

    Examples
    --------

    >>> robot_names()[:4]
    ('two_link', 'rp_arm', 'pendulum', 'rrr_arm')
    """
    return tuple(COURSE_ROBOTS) + tuple(EXAMPLE_ROBOTS)


def example_robot_data_share() -> Path:
    """The ``cmeel.prefix/share`` folder that holds example-robot-data.

    Returns
    -------
    pathlib.Path
        The folder, found on ``sys.path`` or in the site packages.

    Raises
    ------
    FileNotFoundError
        When example-robot-data is not installed.

    Examples
    --------
    >>> (example_robot_data_share() / "example-robot-data" / "robots").is_dir()
    True
    """
    candidates = [Path(p) for p in sys.path if p]
    candidates += [Path(p) for p in site.getsitepackages() + [sysconfig.get_paths()["purelib"]]]
    for base in candidates:
        share = base / "cmeel.prefix" / "share"
        if (share / "example-robot-data" / "robots").is_dir():
            return share
    raise FileNotFoundError("example-robot-data is not installed (pip install example-robot-data)")


def robot_path(name: str) -> Path:
    """The URDF file of a shipped robot, by name (see the module table).

    Parameters
    ----------
    name : str
        One of :func:`robot_names`.

    Returns
    -------
    pathlib.Path
        The robot's URDF file.

    Raises
    ------
    UnknownRobotError
        If ``name`` is not a shipped robot (the message lists those that are).
    FileNotFoundError
        For an example-robot-data arm when example-robot-data is not installed.

    Examples
    --------

    >>> robot_path("two_link").name, robot_path("ur5").name
    ('two_link.urdf', 'ur5_robot.urdf')
    """
    if name in COURSE_ROBOTS:
        return ROBOTS_DIR / COURSE_ROBOTS[name]
    if name in EXAMPLE_ROBOTS:
        return example_robot_data_share() / "example-robot-data" / "robots" / EXAMPLE_ROBOTS[name]
    raise UnknownRobotError(f"unknown robot '{name}'; known robots: {', '.join(robot_names())}")


def resolve(name_or_path) -> Path:
    """A shipped robot's URDF if ``name_or_path`` is a robot name, else the path itself.

    A name that is neither a shipped robot nor an existing path, and has no
    file suffix, is an :class:`~course_dynamics.base.errors.UnknownRobotError`.

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        A robot name (:func:`robot_names`) or the path of a URDF file.

    Returns
    -------
    pathlib.Path
        The URDF file: the shipped robot's, or the path as given (which need not exist when it has a suffix).

    Raises
    ------
    UnknownRobotError
        If ``name_or_path`` is no robot name, no existing path, and has no suffix.

    Examples
    --------
    >>> resolve("two_link").name, str(resolve("my_arm.urdf"))
    ('two_link.urdf', 'my_arm.urdf')
    """
    text = str(name_or_path)
    if text in robot_names():
        return robot_path(text)
    path = Path(text)
    if not path.exists() and not path.suffix:
        raise UnknownRobotError(f"'{text}' is neither a URDF file nor a shipped robot ({', '.join(robot_names())})")
    return path


__all__ = ["COURSE_ROBOTS", "EXAMPLE_ROBOTS", "example_robot_data_share", "resolve", "robot_names",
           "robot_path"]
