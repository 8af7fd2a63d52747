"""Cartesian-space dynamics: Jacobians and the operational-space terms (6.91)–(6.105).

=============  ===========  ===================================================
code           Craig        meaning (shape, unit)
=============  ===========  ===================================================
``J``          J(Θ)         frame Jacobian, rows (vx, vy, vz, ωx, ωy, ωz) of the
                            frame origin's velocity (6, n) or selected rows (k, n)
``J_dot``      J̇(Θ, Θ̇)      its time derivative along Θ̇ (exact, dual numbers)
``Mx``         M_x(Θ)       J⁻ᵀ M J⁻¹ (6.99), Cartesian mass matrix
``Vx``         V_x(Θ, Θ̇)    J⁻ᵀ (V − M J⁻¹ J̇ Θ̇) (6.99)
``Gx``         G_x(Θ)       J⁻ᵀ G (6.99)
``Bx``         B_x(Θ)       Coriolis coefficients of (6.105), joint torques
                            (n, n(n−1)/2), N·m per (rad/s)²
``Cx``         C_x(Θ)       centrifugal coefficients of (6.105), joint torques
                            (n, n), N·m per (rad/s)²
=============  ===========  ===================================================

Craig's (6.105) writes (6.104) with the velocity terms in joint space,

    τ = Jᵀ(Θ) M_x(Θ) Ẍ + B_x(Θ)[Θ̇Θ̇] + C_x(Θ)[Θ̇²] + G(Θ)   (6.105)

where B_x[Θ̇Θ̇] + C_x[Θ̇²] = Jᵀ V_x = V − M J⁻¹ J̇ Θ̇ are joint torques (not a force
at the tool) and G is the joint-space gravity (Jᵀ G_x = G). Both V and J̇ Θ̇ are
quadratic in Θ̇, so Jᵀ V_x = Σⱼₖ Tᵢⱼₖ θ̇ⱼθ̇ₖ with Tᵢⱼₖ = Γᵢⱼₖ − (M J⁻¹ ∂J/∂θₖ)ᵢⱼ,
split as (6.63) splits V (:func:`~course_dynamics.core.lagrange.split_velocity_products`).

``expressed_in="base"`` gives the Jacobian in base-frame coordinates (Pinocchio's
LOCAL_WORLD_ALIGNED); ``"frame"`` gives it in the frame's own coordinates, as
Craig's ³J(Θ) of example 6.6 (Pinocchio's LOCAL). J̇ is the time derivative of
the matrix as expressed, which is what (6.97) differentiates.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import CourseDynamicsError, InputError
from .algebra import Dual
from .dynamics import gravity_torques, mass_matrix, velocity_torques
from .lagrange import christoffel_symbols, split_velocity_products
from .kinematics import (
    frame_placement_entries,
    placement_entries,
    point_jacobian_columns,
)
from .model import Model
from .state import as_state, entries, layout_of

#: The names of the task rows, in the order of J's rows (vx, vy, vz, ωx, ωy, ωz).
ROW_NAMES = ("x", "y", "z", "rx", "ry", "rz")
#: The coordinates a Jacobian can be expressed in, the base frame's or the frame's own.
EXPRESSED_IN = ("base", "frame")
#: The largest condition number of J taken by default; beyond it J is treated as singular.
MAX_CONDITION = 1e8


class SingularityError(CourseDynamicsError):
    """The task Jacobian is singular or nearly so at the given state.

    The message gives the frame, the state and the condition number.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> try:   # the two-link arm stretched out (θ₂ = 0) cannot move its tool along the arm
    ...     cartesian_dynamics(load_robot("two_link"), [0.0, 0.0], [0.0, 0.0], "tool", "frame", ("x", "y"))
    ... except SingularityError as error:
    ...     print(str(error).split(" (")[0])
    the Jacobian of frame 'tool' is singular at q = [0.0, 0.0]
    """


def _jacobian_entries(model: Model, theta: list, frame_name: str, expressed_in: str) -> list:
    """J as 6 rows of n per-joint scalars."""
    frame = model.frame(frame_name)
    if frame.body < 0:
        return [[0] * model.n for _ in range(6)]
    placed = placement_entries(model, theta)
    R_frame, P_frame = frame_placement_entries(placed, frame)
    rows = []
    for linear, angular in point_jacobian_columns(model, placed, frame.body, P_frame):
        if expressed_in == "frame":
            linear, angular = R_frame.T @ linear, R_frame.T @ angular
        rows.append((*linear, *angular))
    return [[rows[j][r] for j in range(model.n)] for r in range(6)]


def row_indices(rows) -> list[int]:
    """Indices into (vx, vy, vz, ωx, ωy, ωz) of task rows given by index or name (:data:`ROW_NAMES`); None: all six.

    >>> row_indices(["x", "rz"]), row_indices(None)
    ([0, 5], [0, 1, 2, 3, 4, 5])
    """
    if rows is None:
        return list(range(6))
    indices = []
    for row in rows:
        if isinstance(row, str):
            if row not in ROW_NAMES:
                raise InputError(f"unknown task row '{row}' (rows are {', '.join(ROW_NAMES)})")
            row = ROW_NAMES.index(row)
        elif isinstance(row, bool) or not isinstance(row, (int, np.integer)) or not 0 <= row < 6:
            raise InputError(f"task row {row!r} is neither a name ({', '.join(ROW_NAMES)}) nor an index 0 to 5")
        indices.append(int(row))
    return indices


def _check_expressed_in(expressed_in: str) -> None:
    if expressed_in not in EXPRESSED_IN:
        raise InputError(f"expressed_in must be one of {', '.join(EXPRESSED_IN)}, got '{expressed_in}'")


def jacobian(model: Model, q, frame: str, expressed_in: str = "base", rows=None) -> np.ndarray:
    """J(Θ) of URDF link/frame ``frame``: shape (k, n) or (N, k, n); k = 6 or len(rows).

    Rows are (vx, vy, vz, ωx, ωy, ωz) of the frame origin (m/s and rad/s per unit
    joint rate); ``rows`` selects some by index or name ("x", "y", "z", "rx", "ry", "rz").

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint).
    frame : str
        A URDF link (``model.frame_names``): the frame whose origin is the task point.
    expressed_in : {"base", "frame"}, optional
        The coordinates of J: the base frame's (the default) or the frame's own.
    rows : sequence of int or str, optional
        The task rows, by index or name (:data:`ROW_NAMES`); all six by default.

    Returns
    -------
    numpy.ndarray, shape (k, n) or (N, k, n)
        J(Θ): m/s (rows x, y, z) and rad/s (rows rx, ry, rz) per rad/s of a revolute joint (per m/s of a
        prismatic one).

    Raises
    ------
    StateError
        If a state is not a finite array whose last axis is the model's n joints.
    ModelError
        If the robot has no link ``frame``.
    InputError
        If ``expressed_in`` or a row is unknown.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> jacobian(load_robot("two_link"), [np.pi / 6, np.pi / 6], "tool", rows=("x", "z")).round(3)   # world x, z
    array([[-0.596, -0.346],
           [ 0.633,  0.2  ]])
    """
    _check_expressed_in(expressed_in)
    q = as_state(model, q, "q")
    J = _jacobian_entries(model, entries(q), frame, expressed_in)
    selected = [J[r] for r in row_indices(rows)]
    return layout_of(q).assemble(selected, (len(selected), model.n))


def jacobian_dot(model: Model, q, qd, frame: str, expressed_in: str = "base", rows=None) -> np.ndarray:
    """J̇(Θ, Θ̇) = d/dt J(Θ(t)): same shape as :func:`jacobian`; exact (dual numbers).

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s).
    frame : str
        A URDF link (``model.frame_names``): the frame whose origin is the task point.
    expressed_in : {"base", "frame"}, optional
        The coordinates of J: the base frame's (the default) or the frame's own.
    rows : sequence of int or str, optional
        The task rows, by index or name (:data:`ROW_NAMES`); all six by default.

    Returns
    -------
    numpy.ndarray, shape (k, n) or (N, k, n)
        J̇(Θ, Θ̇), the units of J per second.

    Raises
    ------
    StateError
        If a state is not a finite array whose last axis is the model's n joints.
    ModelError
        If the robot has no link ``frame``.
    InputError
        If ``expressed_in`` or a row is unknown.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> jacobian_dot(load_robot("two_link"), [0.0, np.pi / 2], [0.0, 1.0], "tool", "frame", ("x", "y")).round(3)
    array([[ 0. ,  0. ],
           [-0.5,  0. ]])
    """
    _check_expressed_in(expressed_in)
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    theta = [Dual(a, b) for a, b in zip(entries(q), entries(qd))]
    J = _jacobian_entries(model, theta, frame, expressed_in)
    selected = [[x.b if isinstance(x, Dual) else 0 for x in J[r]] for r in row_indices(rows)]
    return layout_of(q, qd).assemble(selected, (len(selected), model.n))


@dataclass(frozen=True)
class CartesianTerms:
    """F = M_x Ẍ + V_x + G_x (6.91) at one state, for one frame and task rows.

    Parameters
    ----------
    frame : str
        The URDF link whose origin is the task point.
    rows : tuple of str
        The task rows (:data:`ROW_NAMES`), k = n of them.
    J : numpy.ndarray, shape (n, n)
        The task Jacobian J(Θ).
    J_dot : numpy.ndarray, shape (n, n)
        Its time derivative J̇(Θ, Θ̇).
    Mx : numpy.ndarray, shape (n, n)
        M_x(Θ) = J⁻ᵀ M J⁻¹, kg (kg·m² for rotation rows).
    Vx : numpy.ndarray, shape (n,)
        V_x(Θ, Θ̇) = J⁻ᵀ (V − M J⁻¹ J̇ Θ̇), N (N·m for rotation rows).
    Gx : numpy.ndarray, shape (n,)
        G_x(Θ) = J⁻ᵀ G, N (N·m).
    condition : float
        The condition number of J.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> terms = cartesian_dynamics(arm, [np.pi / 6, np.pi / 2], [0.0, 0.0], "tool", "frame", ("x", "y"))
    >>> terms.rows, terms.joint_torques([0.0, 0.0]).round(3)   # Ẍ = 0 at rest: τ = Jᵀ G_x = G
    (('x', 'y'), array([10.782, -1.962]))
    """

    frame: str
    rows: tuple[str, ...]
    J: np.ndarray
    J_dot: np.ndarray
    Mx: np.ndarray
    Vx: np.ndarray
    Gx: np.ndarray
    condition: float

    def joint_torques(self, x_ddot) -> np.ndarray:
        """τ = Jᵀ (M_x Ẍ + V_x + G_x) (6.104) for a task acceleration Ẍ, shape (k,).

        Parameters
        ----------
        x_ddot : array_like, shape (k,)
            The task acceleration Ẍ, m/s² (rad/s² for rotation rows).

        Returns
        -------
        numpy.ndarray, shape (n,)
            Joint torques τ, N·m (N for a prismatic joint).
        """
        return self.J.T @ (self.Mx @ np.asarray(x_ddot, dtype=float) + self.Vx + self.Gx)  # (6.104)


def operational_space_terms(J_inv, J_dot, M, V, G, theta_dot):
    """(M_x, V_x, G_x) of (6.99) from J⁻¹, J̇, M, V, G and Θ̇: numpy arrays or sympy matrices alike.

    The one place (6.99) is written: the numeric path and the symbolic derivation both call it.

    Parameters
    ----------
    J_inv : numpy.ndarray or sympy.Matrix, shape (n, n)
        J⁻¹.
    J_dot : numpy.ndarray or sympy.Matrix, shape (n, n)
        J̇.
    M : numpy.ndarray or sympy.Matrix, shape (n, n)
        M(Θ), kg·m² (kg).
    V : numpy.ndarray or sympy.Matrix, shape (n,)
        V(Θ, Θ̇), N·m (N).
    G : numpy.ndarray or sympy.Matrix, shape (n,)
        G(Θ), N·m (N).
    theta_dot : numpy.ndarray or sympy.Matrix, shape (n,)
        Θ̇, rad/s (m/s).

    Returns
    -------
    tuple
        (M_x, V_x, G_x), of the arguments' kind.

    Examples
    --------

    >>> import numpy as np
    >>> Mx, Vx, Gx = operational_space_terms(np.eye(2), np.zeros((2, 2)), 2 * np.eye(2), np.ones(2), np.ones(2),
    ...                                      np.zeros(2))
    >>> Mx.tolist(), Vx.tolist(), Gx.tolist()
    ([[2.0, 0.0], [0.0, 2.0]], [1.0, 1.0], [1.0, 1.0])
    """
    J_inv_T = J_inv.T
    Mx = J_inv_T @ M @ J_inv  # (6.99)
    Vx = J_inv_T @ (V - M @ J_inv @ J_dot @ theta_dot)  # (6.99)
    Gx = J_inv_T @ G  # (6.99)
    return Mx, Vx, Gx


def _square_jacobian(model: Model, q: np.ndarray, frame: str, expressed_in: str, rows, max_condition: float,
                     caller: str) -> tuple[list[int], np.ndarray, float]:
    """The task rows, J and cond(J) at one numeric state, refused unless J is square and well conditioned."""
    if q.ndim != 1 or q.dtype == object:
        raise InputError(f"{caller} takes one numeric state")
    indices = row_indices(rows)
    if model.n > len(ROW_NAMES):
        raise InputError(f"robot '{model.name}' has {model.n} joints, more than the {len(ROW_NAMES)} task rows: a "
                         "redundant robot has no Cartesian mass matrix of (6.99), which needs a square Jacobian")
    if len(indices) != model.n:
        raise InputError(
            f"the task has {len(indices)} rows but robot '{model.name}' has {model.n} joints: "
            f"(6.99) needs a square Jacobian; choose {model.n} rows"
        )
    J = jacobian(model, q, frame, expressed_in, indices)
    condition = float(np.linalg.cond(J))
    if not condition <= max_condition:
        raise SingularityError(
            f"the Jacobian of frame '{frame}' is singular at q = {q.tolist()} "
            f"(condition number {condition:.3g} > {max_condition:g})"
        )
    return indices, J, condition


def cartesian_dynamics(model: Model, q, qd, frame: str, expressed_in: str = "base", rows=None,
                       max_condition: float = MAX_CONDITION) -> CartesianTerms:
    """M_x, V_x, G_x of (6.99) at one numeric state, for a square task Jacobian.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : array_like, shape (n,)
        Joint velocities Θ̇, rad/s (m/s).
    frame : str
        A URDF link (``model.frame_names``): the frame whose origin is the task point.
    expressed_in : {"base", "frame"}, optional
        The coordinates of J: the base frame's (the default) or the frame's own.
    rows : sequence of int or str, optional
        The task rows, by index or name (:data:`ROW_NAMES`); all six by default.
    max_condition : float, optional
        The largest condition number of J taken (:data:`MAX_CONDITION`).

    Returns
    -------
    CartesianTerms
        J, J̇, M_x, V_x, G_x and cond(J) at the state.

    Raises
    ------
    InputError
        If the selected rows do not make J square (k ≠ n), the state is a batch or symbolic, or
        ``expressed_in`` or a row is unknown.
    StateError
        If a state is not a finite array of the model's n joints.
    ModelError
        If the robot has no link ``frame``.
    SingularityError
        If cond(J) exceeds ``max_condition`` (the message gives the condition number).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> terms = cartesian_dynamics(load_robot("two_link"), [0.0, np.pi / 2], [0.0, 0.0], "tool", "frame", ("x", "y"))
    >>> np.diag(terms.Mx).round(3)   # Craig (6.101): M_x = diag(m₂ + m₁/s₂², m₂), kg
    array([3., 1.])
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    indices, J, condition = _square_jacobian(model, q, frame, expressed_in, rows, max_condition, "cartesian_dynamics")
    J_dot = jacobian_dot(model, q, qd, frame, expressed_in, indices)
    M, V, G = mass_matrix(model, q), velocity_torques(model, q, qd), gravity_torques(model, q)
    Mx, Vx, Gx = operational_space_terms(np.linalg.inv(J), J_dot, M, V, G, qd)
    return CartesianTerms(frame=frame, rows=tuple(ROW_NAMES[i] for i in indices), J=J, J_dot=J_dot,
                          Mx=Mx, Vx=Vx, Gx=Gx, condition=condition)


def cartesian_configuration_space_terms(model: Model, q, frame: str, expressed_in: str = "base", rows=None,
                                        max_condition: float = MAX_CONDITION) -> tuple[np.ndarray, np.ndarray]:
    """Craig's B_x(Θ) and C_x(Θ) of (6.105): B_x[Θ̇Θ̇] + C_x[Θ̇²] = Jᵀ V_x = V − M J⁻¹ J̇ Θ̇, joint torques.

    With them τ = Jᵀ M_x Ẍ + B_x[Θ̇Θ̇] + C_x[Θ̇²] + G (6.105), G the joint-space gravity. The coefficients
    Tᵢⱼₖ = Γᵢⱼₖ − (M J⁻¹ ∂J/∂θₖ)ᵢⱼ of Jᵀ V_x are split as (6.63) splits V (module docstring); ∂J/∂θₖ is J̇ at
    Θ̇ = eₖ, exact. In general B_x ≠ B and C_x ≠ C: the difference is the torque that keeps the tool on
    Ẍ's course while the joints move.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,)
        Joint positions Θ, rad (m for a prismatic joint).
    frame : str
        A URDF link (``model.frame_names``): the frame whose origin is the task point.
    expressed_in : {"base", "frame"}, optional
        The coordinates of J: the base frame's (the default) or the frame's own.
    rows : sequence of int or str, optional
        The task rows, by index or name (:data:`ROW_NAMES`); all six by default; n of them.
    max_condition : float, optional
        The largest condition number of J taken (:data:`MAX_CONDITION`).

    Returns
    -------
    tuple of (numpy.ndarray, numpy.ndarray)
        B_x(Θ), shape (n, n(n−1)/2), columns in :func:`~course_dynamics.core.lagrange.velocity_pairs` order
        ([Θ̇Θ̇] (6.64)), and C_x(Θ), shape (n, n) ([Θ̇²] (6.65)); joint torques per (rad/s)², N·m·s² (kg·m²
        between revolute joints).

    Raises
    ------
    InputError
        If the selected rows do not make J square (k ≠ n), the state is a batch or symbolic, or
        ``expressed_in`` or a row is unknown.
    StateError
        If ``q`` is not a finite array of the model's n joints.
    ModelError
        If the robot has no link ``frame``.
    SingularityError
        If cond(J) exceeds ``max_condition``.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> Bx, Cx = cartesian_configuration_space_terms(load_robot("two_link"), [0.0, np.pi / 2], "tool", "frame",
    ...                                              ("x", "y"))
    >>> Bx.round(3).tolist()   # J̇Θ̇ = (l₁c₂, −l₁s₂)ᵀ θ̇₁θ̇₂: B − M J⁻¹ (l₁c₂, −l₁s₂)ᵀ = (−0.4, 0)ᵀ + (0.2, 0.2)ᵀ
    [[-0.2], [0.2]]
    >>> (Cx.round(3) + 0.0).tolist()   # in frame {3}, J̇Θ̇ has no θ̇ᵢ² term: C_x = C here
    [[0.0, -0.2], [0.2, 0.0]]
    """
    q = as_state(model, q, "q")
    indices, J, _ = _square_jacobian(model, q, frame, expressed_in, rows, max_condition,
                                     "cartesian_configuration_space_terms")
    n = model.n
    dJ = np.array([jacobian_dot(model, q, unit, frame, expressed_in, indices) for unit in np.eye(n)])  # ∂J/∂θₖ
    M_J_inv = np.linalg.solve(J.T, mass_matrix(model, q).T).T  # M J⁻¹
    T = christoffel_symbols(model, q) - np.einsum("ir,krj->ijk", M_J_inv, dJ)  # Jᵀ V_x = Σⱼₖ Tᵢⱼₖ θ̇ⱼθ̇ₖ
    Bx, Cx = split_velocity_products(T, n)  # (6.105), split as (6.63)
    return np.array(Bx, dtype=float).reshape(n, n * (n - 1) // 2), np.array(Cx, dtype=float)


__all__ = ["CartesianTerms", "EXPRESSED_IN", "MAX_CONDITION", "ROW_NAMES", "SingularityError",
           "cartesian_configuration_space_terms", "cartesian_dynamics", "jacobian", "jacobian_dot",
           "operational_space_terms"]
