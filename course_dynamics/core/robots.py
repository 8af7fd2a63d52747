"""Loading the shipped robots by name (:mod:`course_dynamics.base.robot_files` lists them and finds their files).

>>> load_robot("two_link").joint_names
('theta1', 'theta2')
"""
from __future__ import annotations

from ..base.robot_files import (
    COURSE_ROBOTS,
    EXAMPLE_ROBOTS,
    ROBOTS_DIR,
    example_robot_data_share,
    resolve,
    robot_names,
    robot_path,
)
from .model import STANDARD_GRAVITY, Model
from .urdf import load_urdf


def load_robot(name: str, gravity=STANDARD_GRAVITY) -> Model:
    """:func:`~course_dynamics.core.urdf.load_urdf` of a shipped robot, by name.

    Parameters
    ----------
    name : str
        One of :func:`~course_dynamics.base.robot_files.robot_names`.
    gravity : array_like, shape (3,), optional
        The gravity vector g in the base frame, m/s²; (0, 0, −9.81) by default.

    Returns
    -------
    Model
        The robot.

    Raises
    ------
    UnknownRobotError
        If ``name`` is not a shipped robot.
    ModelError
        If ``gravity`` is not three finite numbers.

    Examples
    --------

    >>> load_robot("ur5").n
    6
    >>> load_robot("pendulum", gravity=(0, 0, -1.62)).gravity.tolist()   # on the Moon, m/s²
    [0.0, 0.0, -1.62]
    """
    return load_urdf(robot_path(name), gravity=gravity)


def load(name_or_path, gravity=STANDARD_GRAVITY, allow_nonphysical_inertia: bool = False) -> Model:
    """The robot of a URDF path or a shipped robot's name
    (see :func:`~course_dynamics.base.robot_files.resolve`; flags as
    :func:`~course_dynamics.core.urdf.load_urdf`).

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        A robot name (:func:`~course_dynamics.base.robot_files.robot_names`) or the path of a URDF file.
    gravity : array_like, shape (3,), optional
        The gravity vector g in the base frame, m/s²; (0, 0, −9.81) by default.
    allow_nonphysical_inertia : bool, optional
        Load a link whose inertia tensor no real body can have, with an
        :class:`~course_dynamics.core.urdf.InertiaWarning`, instead of refusing it.

    Returns
    -------
    Model
        The robot.

    Raises
    ------
    UnknownRobotError
        If ``name_or_path`` is neither a shipped robot nor a path.
    InputError
        If the file cannot be read (missing, not a regular file, too large).
    ModelError
        If the URDF is no robot the dynamics can use.

    Examples
    --------

    >>> load("pendulum").joint_names, load(robot_path("rp_arm")).joint_names
    (('theta',), ('theta1', 'd2'))
    """
    return load_urdf(resolve(name_or_path), gravity=gravity, allow_nonphysical_inertia=allow_nonphysical_inertia)


# the catalogue as the base has it, and loading from it
__all__ = ["COURSE_ROBOTS", "EXAMPLE_ROBOTS", "example_robot_data_share", "load", "load_robot",
           "resolve", "robot_names", "robot_path"]
