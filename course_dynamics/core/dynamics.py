"""The terms of the state-space equation τ = M(Θ)Θ̈ + V(Θ, Θ̇) + G(Θ) (6.59).

G and V are read off the one Newton–Euler recursion
(:mod:`course_dynamics.core.newton_euler`), as Craig suggests in section 6.8. M and
C each have two routes: Craig's definition, kept for teaching and as a check,
and an O(n²) algorithm that is the default:

=============================  ===============================================
term                           how
=============================  ===============================================
G(Θ)          shape (n,)       τ(Θ, 0, 0): gravity only
V(Θ, Θ̇)       shape (n,)       τ(Θ, Θ̇, 0) with g = 0: centrifugal and Coriolis
M(Θ)          shape (n, n)     composite-rigid-body algorithm (:mod:`~course_dynamics.core.crba`);
                               by definition, column j is τ(Θ, 0, eⱼ) with g = 0
                               (:func:`mass_matrix_by_unit_accelerations`)
C(Θ, Θ̇)       shape (n, n)     the Christoffel form Cᵢⱼ = Σₖ Γᵢⱼₖ θ̇ₖ, so that C Θ̇ = V
                               and Ṁ − 2C is skew-symmetric, by Echeandia and
                               Wensing's O(n²) recursion (:mod:`~course_dynamics.core.coriolis`);
                               by definition C = ½ (Ṁ + D − Dᵀ), Ṁ = Σₖ ∂M/∂θₖ θ̇ₖ,
                               D = ∂(M Θ̇)/∂Θ, differentiated exactly with dual
                               numbers (:func:`coriolis_matrix_christoffel`)
=============================  ===============================================

Leading batch axes and sympy object arrays work as in
:func:`course_dynamics.core.newton_euler.inverse_dynamics`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import coriolis, crba
from .algebra import Dual, Vec3
from .kinematics import joint_transforms
from .model import Model
from .newton_euler import inverse_dynamics, torque_entries
from .state import as_state, entries, layout_of

NO_GRAVITY = Vec3(0.0, 0.0, 0.0)  # the recursion at g = 0: V and M Θ̇ alone


def gravity_torques(model: Model, q) -> np.ndarray:
    """G(Θ), shape (n,) or (N, n): the torques that hold the arm still against ``model.gravity``.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        Gravity torques G(Θ), N·m (N for a prismatic joint).

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> np.round(gravity_torques(arm, [0.0, 0.0]), 6)                  # stretched out: the largest G
    array([18.639,  3.924])
    """
    q = as_state(model, q, "q")
    zeros = np.zeros(q.shape[-1:])
    return inverse_dynamics(model, q, zeros, zeros)


def _without_gravity(model: Model, q, qd, qdd) -> np.ndarray:
    """τ(Θ, Θ̇, Θ̈) at g = 0, shape (n,) or (N, n)."""
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    layout = layout_of(q, qd, qdd)
    tau = torque_entries(model, joint_transforms(model, entries(q)), entries(qd), entries(qdd), NO_GRAVITY)
    return layout.assemble(tau, (model.n,))


def velocity_torques(model: Model, q, qd) -> np.ndarray:
    """V(Θ, Θ̇), shape (n,) or (N, n): centrifugal and Coriolis torques.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        Velocity torques V(Θ, Θ̇), N·m (N for a prismatic joint).

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> np.round(velocity_torques(arm, [0.0, 0.5], [1.0, 1.0]), 6)   # Coriolis and centrifugal terms
    array([-0.287655,  0.095885])
    """
    q = as_state(model, q, "q")
    return _without_gravity(model, q, qd, np.zeros(q.shape[-1:]))


def unit_acceleration_entries(model: Model, theta: list, X=None) -> list:
    """M as nested scalars, M[i][j], by definition: column j is τ(Θ, 0, eⱼ) at g = 0 (n Newton–Euler passes).

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> M = unit_acceleration_entries(arm, [0.0, 0.5])                 # Python floats, or sympy, or duals
    >>> round(M[0][1], 6) == round(M[1][0], 6)
    True
    """
    X = joint_transforms(model, theta) if X is None else X
    zero = [0] * model.n
    cols = [torque_entries(model, X, zero, [1 if k == j else 0 for k in range(model.n)], NO_GRAVITY)
            for j in range(model.n)]
    return [[cols[j][i] for j in range(model.n)] for i in range(model.n)]


def mass_matrix(model: Model, q) -> np.ndarray:
    """M(Θ), shape (n, n) or (N, n, n): the joint-space mass matrix (kg·m², kg), by the composite-rigid-body algorithm.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    numpy.ndarray, shape (n, n) or (N, n, n)
        The mass matrix M(Θ), kg·m² between revolute joints (kg between prismatic ones).

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> np.round(mass_matrix(arm, [0.0, 0.5]), 6)
    array([[1.261033, 0.335517],
           [0.335517, 0.16    ]])
    """
    return crba.mass_matrix(model, q)


def mass_matrix_by_unit_accelerations(model: Model, q) -> np.ndarray:
    """M(Θ) by its definition in Craig section 6.8: column j is τ(Θ, 0, eⱼ) with g = 0.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    numpy.ndarray, shape (n, n) or (N, n, n)
        The mass matrix M(Θ), kg·m² (kg), from n Newton–Euler passes.

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> q = [0.3, -1.2]
    >>> np.allclose(mass_matrix_by_unit_accelerations(arm, q), mass_matrix(arm, q), rtol=1e-14)
    True
    """
    q = as_state(model, q, "q")
    return layout_of(q).assemble(unit_acceleration_entries(model, entries(q)), (model.n, model.n))


def coriolis_matrix(model: Model, q, qd) -> np.ndarray:
    """C(Θ, Θ̇), shape (n, n) or (N, n, n), in Christoffel form, by the O(n²) recursion of
    :mod:`~course_dynamics.core.coriolis`.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).

    Returns
    -------
    numpy.ndarray, shape (n, n) or (N, n, n)
        The Coriolis matrix C(Θ, Θ̇), with C Θ̇ = V, kg·m²/s between revolute joints.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> q, qd = np.array([0.0, 0.5]), np.array([1.0, -2.0])
    >>> np.allclose(coriolis_matrix(arm, q, qd) @ qd, velocity_torques(arm, q, qd))   # C Θ̇ = V
    True
    """
    return coriolis.coriolis_matrix(model, q, qd)


def coriolis_matrix_christoffel(model: Model, q, qd) -> np.ndarray:
    """C(Θ, Θ̇) by its definition, ½ (Ṁ + D − Dᵀ), differentiated exactly with dual numbers (no finite differences).

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); numbers.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).

    Returns
    -------
    numpy.ndarray, shape (n, n) or (N, n, n)
        The Coriolis matrix C(Θ, Θ̇), kg·m²/s between revolute joints.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> q, qd = [0.0, 0.5], [1.0, -2.0]
    >>> np.allclose(coriolis_matrix_christoffel(arm, q, qd), coriolis_matrix(arm, q, qd), rtol=1e-13)
    True
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    layout = layout_of(q, qd)
    theta, theta_dot = entries(q), entries(qd)
    n = model.n
    # Ṁ: M evaluated at Θ + ε Θ̇.
    M_dot = [[_derivative(x) for x in row]
             for row in unit_acceleration_entries(model, [Dual(a, b) for a, b in zip(theta, theta_dot)])]
    # D[:, k] = ∂(M Θ̇)/∂θₖ, with M Θ̇ = τ(Θ, 0, Θ̇) at g = 0.
    zero = [0] * n
    D_cols = []
    for k in range(n):
        X = joint_transforms(model, [Dual(a, 1 if j == k else 0) for j, a in enumerate(theta)])
        D_cols.append([_derivative(x) for x in torque_entries(model, X, zero, theta_dot, NO_GRAVITY)])
    C = [[(M_dot[i][j] + D_cols[j][i] - D_cols[i][j]) / 2 for j in range(n)] for i in range(n)]
    return layout.assemble(C, (n, n))


def kinetic_energy(model: Model, q, qd) -> np.ndarray:
    """k = ½ Θ̇ᵀ M(Θ) Θ̇ (6.71), J: shape () or (N,). One pass: M Θ̇ = τ(Θ, 0, Θ̇) at g = 0.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).

    Returns
    -------
    float or numpy.ndarray, shape (N,)
        The kinetic energy k, J. A sympy expression for a symbolic state.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> qd = np.array([1.0, 0.0])
    >>> (float(np.round(kinetic_energy(arm, [0.0, 0.5], qd), 6)),
    ...  float(np.round(qd @ mass_matrix(arm, [0.0, 0.5]) @ qd / 2, 6)))
    (0.630517, 0.630517)
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    M_qd = _without_gravity(model, q, np.zeros(q.shape[-1:]), qd)
    return 0.5 * np.sum(qd * M_qd, axis=-1)  # (6.71)


def mass_matrix_and_bias(model: Model, q, qd) -> tuple[np.ndarray, np.ndarray]:
    """M(Θ) and V(Θ, Θ̇) + G(Θ) for numeric states, sharing one set of joint transforms.

    The pair forward dynamics needs; shapes (n, n), (n,) or batched (N, n, n), (N, n).

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> M, bias = mass_matrix_and_bias(arm, [0.0, 0.5], [1.0, 0.0])
    >>> np.allclose(bias, velocity_torques(arm, [0.0, 0.5], [1.0, 0.0]) + gravity_torques(arm, [0.0, 0.5]))
    True
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    layout = layout_of(q, qd)
    M, bias = mass_matrix_and_bias_entries(model, entries(q), entries(qd))
    return layout.assemble(M, (model.n, model.n)), layout.assemble(bias, (model.n,))


def mass_matrix_and_bias_entries(model: Model, theta: list, theta_dot: list) -> tuple[list, list]:
    """M[i][j] (composite rigid bodies) and the bias V + G = τ(Θ, Θ̇, 0) (Newton–Euler) as scalars.

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> M, bias = mass_matrix_and_bias_entries(arm, [0.0, 0.5], [0.0, 0.0])
    >>> [round(b, 6) for b in bias]                                    # at rest the bias is G
    [18.158634, 3.443634]
    """
    X = joint_transforms(model, theta)
    bias = torque_entries(model, X, theta_dot, [0] * model.n, model.gravity_v)
    return crba.mass_matrix_entries(model, theta), bias


def _derivative(x):
    return x.b if isinstance(x, Dual) else 0


@dataclass(frozen=True)
class DynamicsTerms:
    """Every term of (6.59) at one state (or a batch), joints in model order.

    Each has a leading batch axis (N, …) for a batch of states.

    Parameters
    ----------
    joints : tuple of str
        The joints, in the order of every term's entries.
    tau : numpy.ndarray, shape (n,)
        τ = M(Θ)Θ̈ + V(Θ, Θ̇) + G(Θ), N·m (N for a prismatic joint).
    M : numpy.ndarray, shape (n, n)
        The mass matrix M(Θ), kg·m² (kg).
    C : numpy.ndarray, shape (n, n)
        The Coriolis matrix C(Θ, Θ̇), kg·m²/s.
    V : numpy.ndarray, shape (n,)
        Velocity torques V(Θ, Θ̇), N·m (N).
    G : numpy.ndarray, shape (n,)
        Gravity torques G(Θ), N·m (N).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> terms = dynamics_terms(arm, [0.0, 0.5], [1.0, 0.0], [0.0, 0.0])
    >>> np.allclose(terms.tau, terms.M @ [0.0, 0.0] + terms.V + terms.G)   # (6.59)
    True
    """

    joints: tuple[str, ...]
    tau: np.ndarray
    M: np.ndarray
    C: np.ndarray
    V: np.ndarray
    G: np.ndarray


def dynamics_terms(model: Model, q, qd, qdd, progress=None) -> DynamicsTerms:
    """τ, M, C, V and G at one state, under ``model.gravity``.

    ``progress``, if given, is called with the name of each term just computed (five calls).

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).
    qdd : array_like, shape (n,) or (N, n)
        Joint accelerations Θ̈, rad/s² (m/s² for a prismatic joint).
    progress : callable, optional
        Called with ``"tau"``, ``"M"``, ``"C"``, ``"V"``, ``"G"`` as each is done.

    Returns
    -------
    DynamicsTerms
        τ, M, C, V and G.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> done = []
    >>> terms = dynamics_terms(arm, [0.0, 0.5], [1.0, 0.0], [0.0, 1.0], progress=done.append)
    >>> done, terms.M.shape
    (['tau', 'M', 'C', 'V', 'G'], (2, 2))
    """
    steps = (("tau", lambda: inverse_dynamics(model, q, qd, qdd)), ("M", lambda: mass_matrix(model, q)),
             ("C", lambda: coriolis_matrix(model, q, qd)), ("V", lambda: velocity_torques(model, q, qd)),
             ("G", lambda: gravity_torques(model, q)))
    values = {}
    for name, compute in steps:
        values[name] = compute()
        if progress is not None:
            progress(name)
    return DynamicsTerms(joints=model.joint_names, **values)


__all__ = ["DynamicsTerms", "coriolis_matrix", "coriolis_matrix_christoffel", "dynamics_terms", "gravity_torques",
           "kinetic_energy", "mass_matrix", "mass_matrix_by_unit_accelerations", "velocity_torques"]
