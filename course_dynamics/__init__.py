"""course-dynamics: Craig's chapter 6 (manipulator dynamics), executable.

Load any fixed-base URDF and compute, in Craig's notation, the Newton–Euler
torques τ, the mass matrix M(Θ), the velocity terms V(Θ, Θ̇), gravity G(Θ) and
the Coriolis matrix C(Θ, Θ̇), for one state, a batch of states or sympy symbols.

>>> from course_dynamics import load_robot, inverse_dynamics
>>> arm = load_robot("two_link")
>>> arm.joint_names
('theta1', 'theta2')

The tools the guides show (:func:`~course_dynamics.tools.simulation.simulate`,
:func:`~course_dynamics.tools.logs.torques_from_log`, :func:`~course_dynamics.tools.identification.identify`,
:func:`~course_dynamics.core.compiled.compile_model`, …) are importable from here too, and
loaded only when first asked for: ``import course_dynamics`` loads the base and
the core alone (PEP 562's module ``__getattr__``).

>>> import course_dynamics
>>> course_dynamics.simulate is course_dynamics.tools.simulation.simulate
True
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

# Loaded on first use (``__getattr__``): name → the module that defines it.
LAZY = {
    "INTEGRATORS": "course_dynamics.tools.simulation", "simulate": "course_dynamics.tools.simulation",
    "torques_from_log": "course_dynamics.tools.logs", "identify": "course_dynamics.tools.identification",
    "read_table": "course_dynamics.tools.tables", "open_log": "course_dynamics.tools.sources",
    "parse_column_map": "course_dynamics.tools.columns", "Payload": "course_dynamics.tools.loads",
    "compile_model": "course_dynamics.core.compiled",
}
#: The integrators :func:`~course_dynamics.tools.simulation.simulate` offers, loaded with it (declared here, bound
#: on first use by ``__getattr__``).
INTEGRATORS: tuple[str, ...]

__all__ = [
    "Body", "CourseDynamicsError", "DynamicsTerms", "InputError", "LinkQuantities", "Model", "ModelError",
    "StateError", "UnknownRobotError",
    "coriolis_matrix", "dynamics_terms", "forward_dynamics", "forward_kinematics", "gravity_torques",
    "inverse_dynamics", "load_robot", "load_urdf", "mass_matrix", "newton_euler_links", "potential_energy",
    "robot_names", "robot_path", "velocity_torques",
    *sorted(LAZY),
]


def __getattr__(name: str):
    """A tool of :data:`LAZY`, imported now and kept; AttributeError for any other name."""
    import importlib

    if name not in LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(LAZY[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(LAZY))
