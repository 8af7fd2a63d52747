"""The errors course_dynamics raises for input it cannot use.

Every one is a :class:`CourseDynamicsError` whose message is one line naming
the file, joint, link, row or option at fault. The command line reports these,
and only these, as ``error: …`` with exit code 2; any other exception is a bug
and keeps its traceback. They are also each a ``ValueError``, so code that expects
the standard exception for a bad value still catches them.

=========================  ====================================================
class                      raised for
=========================  ====================================================
``ModelError``             a robot description the dynamics cannot use
``UnknownRobotError``      a robot name we do not ship (also a ``KeyError``)
``StateError``             a state of the wrong length, not numeric, NaN or inf
``InputError``             a bad file, table or option value
=========================  ====================================================

Modules add their own where a caller may want to tell them apart:
``cartesian.SingularityError``, ``forward_dynamics.SingularMassMatrixError``,
``simulation.SimulationError``, ``parameters.SymbolError``,
``viewer.ViewerError``.

What we can do but the user should know is a :class:`CourseDynamicsWarning`
(or a subclass: ``urdf.InertiaWarning``, ``viewer.MeshWarning``), given to
``warnings.warn``; the command line prints each as one ``warning: …`` line.
"""
from __future__ import annotations


class CourseDynamicsError(ValueError):
    """Input that course_dynamics cannot use; the message is one line."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class ModelError(CourseDynamicsError):
    """A robot description or model parameter that the dynamics cannot use."""


class UnknownRobotError(ModelError, KeyError):
    """A robot name that is neither shipped nor a file."""


class StateError(CourseDynamicsError):
    """A state that does not fit the model: wrong length, not numeric, NaN or inf."""


class InputError(CourseDynamicsError):
    """A file, table or option value that cannot be used (named in the message)."""


class CourseDynamicsWarning(UserWarning):
    """Something done as asked that the user should know of; the command line prints it as ``warning: …``."""


__all__ = ["CourseDynamicsError", "CourseDynamicsWarning", "InputError", "ModelError", "StateError",
           "UnknownRobotError"]
