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
:func:`~course_dynamics.core.compiled.compile_model`, …) are importable from here too. Every name but the
errors is loaded only when first asked for (PEP 562's module ``__getattr__``): ``import course_dynamics``
loads the errors alone, so a command line that needs nothing else (``course-dynamics --help``) starts at once.

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

# Loaded on first use (``__getattr__``): name → the module that defines it. Nothing but the errors is imported
# with the package, so that ``course-dynamics --help`` and ``import course_dynamics.base`` stay quick.
LAZY = {
    "DynamicsTerms": "course_dynamics.core.dynamics", "dynamics_terms": "course_dynamics.core.dynamics",
    "velocity_torques": "course_dynamics.core.dynamics",
    "coriolis_matrix": "course_dynamics.core.evaluator", "forward_dynamics": "course_dynamics.core.evaluator",
    "gravity_torques": "course_dynamics.core.evaluator", "inverse_dynamics": "course_dynamics.core.evaluator",
    "mass_matrix": "course_dynamics.core.evaluator", "regressor": "course_dynamics.core.evaluator",
    "forward_kinematics": "course_dynamics.core.kinematics", "potential_energy": "course_dynamics.core.kinematics",
    "Body": "course_dynamics.core.model", "Model": "course_dynamics.core.model",
    "LinkQuantities": "course_dynamics.core.newton_euler", "newton_euler_links": "course_dynamics.core.newton_euler",
    "load_robot": "course_dynamics.core.robots", "robot_names": "course_dynamics.core.robots",
    "robot_path": "course_dynamics.core.robots", "load_urdf": "course_dynamics.core.urdf",
    "compile_model": "course_dynamics.core.compiled",
    "INTEGRATORS": "course_dynamics.tools.simulation", "simulate": "course_dynamics.tools.simulation",
    "torques_from_log": "course_dynamics.tools.logs", "identify": "course_dynamics.tools.identification",
    "read_table": "course_dynamics.tools.tables", "open_log": "course_dynamics.tools.sources",
    "parse_column_map": "course_dynamics.tools.columns", "Payload": "course_dynamics.tools.loads",
}
#: The integrators :func:`~course_dynamics.tools.simulation.simulate` offers, loaded with it (declared here, bound
#: on first use by ``__getattr__``).
INTEGRATORS: tuple[str, ...]

__all__ = ["CourseDynamicsError", "InputError", "ModelError", "StateError", "UnknownRobotError", *sorted(LAZY)]


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
