"""Forward dynamics (6.115): Θ̈ = M⁻¹(Θ) [τ − V(Θ, Θ̇) − G(Θ) − F(Θ̇)].

M, V and G come from our Newton–Euler recursion; the linear system is solved
by Cholesky factorisation (M is symmetric positive definite for a physical
robot). A singular M — a chain ending in massless links, say — is an error,
never a silently huge acceleration.

Anything that maps (Θ, Θ̇, τ) to Θ̈ can drive a simulation: this module's
:func:`accelerations` is the default, and ``simulate(..., dynamics=…)`` takes
any other callable with the same signature (:data:`AccelerationFunction`).
"""
from __future__ import annotations

from functools import partial
from typing import Callable

import numpy as np

from ..base.errors import CourseDynamicsError, StateError
from .dynamics import mass_matrix_and_bias, mass_matrix_and_bias_entries
from .friction import Friction
from .model import Model
from .state import as_state

# Smallest allowed ratio of Cholesky pivots (squared), min/max: below it M is singular.
SINGULAR_PIVOT_RATIO = 1e-14

AccelerationFunction = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
"""(q, qd, tau) → qdd for checked float arrays of shape (n,) or (K, n), friction not included."""


class SingularMassMatrixError(CourseDynamicsError):
    """M(Θ) is singular: some joint moves no mass.

    The message names the state and the joint that moves least mass.

    Examples
    --------

    >>> from course_dynamics import load_urdf
    >>> import tempfile, pathlib
    >>> urdf = pathlib.Path(tempfile.mkdtemp()) / "massless.urdf"
    >>> _ = urdf.write_text('''<robot name="massless"><link name="base"/><link name="tip"/>
    ...   <joint name="j" type="revolute"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/>
    ...   <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>''')
    >>> import textwrap
    >>> try:
    ...     forward_dynamics(load_urdf(urdf), [0.0], [0.0], [1.0])
    ... except SingularMassMatrixError as error:
    ...     print(textwrap.fill(str(error), 100))
    the mass matrix of robot 'massless' is singular at q = [0.0] (smallest eigenvalue 0): joint 'j'
    moves no mass (a massless chain?)
    """


def forward_dynamics(model: Model, q, qd, tau, friction: Friction | None = None) -> np.ndarray:
    """Θ̈ from Θ, Θ̇ and applied τ (6.115): shape (n,) or (N, n), rad/s² or m/s².

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s).
    tau : array_like, shape (n,) or (N, n)
        Applied joint torques τ, N·m (N for a prismatic joint).
    friction : Friction, optional
        Subtracted from τ as F(Θ̇) (6.114); default none.

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        Joint accelerations Θ̈, rad/s² (m/s² for a prismatic joint).

    Raises
    ------
    StateError
        If ``q``, ``qd`` or ``tau`` is not a finite array whose last axis is the model's n joints.
    SingularMassMatrixError
        If M(Θ) is singular (a joint that moves no mass).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> arm = load_robot("pendulum")          # θ̈ = −(g/l) sin θ when released
    >>> forward_dynamics(arm, [0.5], [0.0], [0.0]).round(4)
    array([-4.7032])
    """
    q, qd, tau = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, tau, "tau")
    if friction is not None:
        tau = tau - friction.torques(qd)  # (6.114)
    return accelerations(model, q, qd, tau)


def accelerations(model: Model, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """(6.115) without friction for already checked float arrays, (n,) or (K, n): the default backend.

    Parameters
    ----------
    model : Model
        The robot.
    q : numpy.ndarray, shape (n,) or (K, n)
        Joint positions Θ, rad (m), as :func:`~course_dynamics.core.state.as_state` gives them.
    qd : numpy.ndarray, shape (n,) or (K, n)
        Joint velocities Θ̇, rad/s (m/s).
    tau : numpy.ndarray, shape (n,) or (K, n)
        Joint torques τ, N·m (N), friction already taken off.

    Returns
    -------
    numpy.ndarray, shape (n,) or (K, n)
        Joint accelerations Θ̈, rad/s² (m/s²).

    Raises
    ------
    SingularMassMatrixError
        If M(Θ) is singular.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("pendulum")
    >>> np.round(accelerations(arm, np.array([[0.5], [-0.5]]), np.zeros((2, 1)), np.zeros((2, 1))), 4)
    array([[-4.7032],
           [ 4.7032]])
    """
    if q.ndim == 1 and qd.ndim == 1:
        M, bias = mass_matrix_and_bias_entries(model, q.tolist(), qd.tolist())  # floats: the fast path
        M, bias = np.array(M), np.array(bias)
    else:
        M, bias = mass_matrix_and_bias(model, q, qd)
    return solve(model, M, tau - bias, q)  # (6.115)


def newton_euler_dynamics(model: Model) -> AccelerationFunction:
    """The default :data:`AccelerationFunction` of ``model``: M and V + G by Newton–Euler, Cholesky solve.

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    AccelerationFunction
        :func:`accelerations` bound to ``model``: (q, qd, tau) → qdd.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> qdd_of = newton_euler_dynamics(load_robot("pendulum"))      # what simulate calls: (q, qd, tau) -> qdd
    >>> np.round(qdd_of(np.array([0.5]), np.array([0.0]), np.array([0.0])), 4)
    array([-4.7032])
    """
    return partial(accelerations, model)


def solve(model: Model, M: np.ndarray, rhs: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Θ̈ = M⁻¹ rhs for M (…, n, n), rhs (…, n), after checking that M is positive definite.

    Parameters
    ----------
    model : Model
        The robot.
    M : numpy.ndarray, shape (n, n) or (K, n, n)
        The mass matrix M(Θ), kg·m² (kg).
    rhs : numpy.ndarray, shape (n,) or (K, n)
        τ − V − G (− F), N·m (N).
    q : numpy.ndarray, shape (n,) or (K, n)
        The joint positions Θ, rad (m), named in a refusal.

    Returns
    -------
    numpy.ndarray, shape (n,) or (K, n)
        Joint accelerations Θ̈, rad/s² (m/s²).

    Raises
    ------
    SingularMassMatrixError
        If a Cholesky pivot of M is within round-off of zero (naming the state and the joint).
    StateError
        If M or rhs is not finite: a finite state whose terms overflow float64 (naming the state).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> solve(arm, np.diag([2.0, 4.0]), np.array([1.0, 1.0]), np.zeros(2))
    array([0.5 , 0.25])
    """
    if not (np.all(np.isfinite(M)) and np.all(np.isfinite(rhs))):
        finite = np.isfinite(rhs).all(axis=-1) & np.isfinite(M).all(axis=(-2, -1))
        k = np.unravel_index(np.argmin(finite), finite.shape)
        raise StateError(f"the dynamics of robot '{model.name}' overflow at q = "
                         f"{np.broadcast_to(q, finite.shape + (model.n,))[k].tolist()}: M(Θ) or the torques "
                         "are not finite")
    _check_positive_definite(model, M, q)
    return np.linalg.solve(M, rhs[..., None])[..., 0]


def _check_positive_definite(model: Model, M: np.ndarray, q: np.ndarray) -> None:
    """Cholesky pivots all well above round-off, or SingularMassMatrixError naming the joint."""
    try:
        pivots = np.diagonal(np.linalg.cholesky(M), axis1=-2, axis2=-1) ** 2
        if np.all(pivots.min(axis=-1) > SINGULAR_PIVOT_RATIO * pivots.max(axis=-1)):
            return
    except np.linalg.LinAlgError:
        pass
    eigenvalues = np.linalg.eigvalsh(M)
    q = np.broadcast_to(q, M.shape[:-1])
    k = np.unravel_index(np.argmin(eigenvalues[..., 0] / np.maximum(eigenvalues[..., -1], 1e-300)),
                         eigenvalues.shape[:-1])
    weakest = np.linalg.eigh(M[k])[1][:, 0]
    joint = model.joint_names[int(np.argmax(np.abs(weakest)))]
    raise SingularMassMatrixError(
        f"the mass matrix of robot '{model.name}' is singular at q = {np.round(q[k], 6).tolist()} "
        f"(smallest eigenvalue {eigenvalues[k][0]:.3g}): joint '{joint}' moves no mass (a massless chain?)"
    )


__all__ = ["AccelerationFunction", "SingularMassMatrixError", "accelerations", "forward_dynamics",
           "newton_euler_dynamics", "solve"]
