"""course-dynamics: Craig's chapter 6 (manipulator dynamics), executable.

Load any fixed-base URDF and compute, in Craig's notation, the Newton–Euler
torques τ, the mass matrix M(Θ), the velocity terms V(Θ, Θ̇), gravity G(Θ) and
the Coriolis matrix C(Θ, Θ̇), for one state, a batch of states or sympy symbols.

>>> from course_dynamics import load_robot, inverse_dynamics
>>> arm = load_robot("two_link")
>>> arm.joint_names
('theta1', 'theta2')
"""
from .base.errors import (
    CourseDynamicsError,
    InputError,
    ModelError,
    StateError,
    UnknownRobotError,
)
from .core.dynamics import DynamicsTerms, dynamics_terms, velocity_torques
from .core.evaluator import coriolis_matrix, forward_dynamics, gravity_torques, inverse_dynamics, mass_matrix
from .core.kinematics import forward_kinematics, potential_energy
from .core.model import Body, Model
from .core.newton_euler import LinkQuantities, newton_euler_links
from .core.robots import load_robot, robot_names, robot_path
from .core.urdf import load_urdf

__all__ = [
    "Body", "CourseDynamicsError", "DynamicsTerms", "InputError", "LinkQuantities", "Model", "ModelError",
    "StateError", "UnknownRobotError",
    "coriolis_matrix", "dynamics_terms", "forward_dynamics", "forward_kinematics", "gravity_torques",
    "inverse_dynamics", "load_robot", "load_urdf", "mass_matrix", "newton_euler_links", "potential_energy",
    "robot_names", "robot_path", "velocity_torques",
]
