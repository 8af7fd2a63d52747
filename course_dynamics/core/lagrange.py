"""The Lagrangian formulation (6.69)–(6.77): its own path to the equations of motion.

Nothing here calls the Newton–Euler recursion; the two agree (tests), which is
the point of computing both.

===================  ===========  ==================================================
code                 Craig        meaning (shape, unit)
===================  ===========  ==================================================
``J_v[i]``           J_vᵢ         Jacobian of the COM of body i, base frame (3, n)
``J_w[i]``           J_ωᵢ         angular-velocity Jacobian of body i (3, n)
``I_base[i]``        ⁰Iᵢ          ⁰ᵢR ᶜⁱIᵢ ⁰ᵢRᵀ: inertia about the COM, base axes (3, 3)
``k``                k            kinetic energy (6.69), (6.71), J
``u``                u            potential energy (6.73), J (kinematics.potential_energy)
``Gamma[i][j][k]``   Γᵢⱼₖ         Christoffel symbols ½(∂ₖMᵢⱼ + ∂ⱼMᵢₖ − ∂ᵢMⱼₖ)
``B``, ``C``         B(Θ), C(Θ)   Craig's Coriolis (n × n(n−1)/2) and centrifugal (n × n)
                                  coefficient matrices of (6.63)
===================  ===========  ==================================================

From k = Σᵢ ½ mᵢ v_Cᵢᵀ v_Cᵢ + ½ ωᵢᵀ ⁰Iᵢ ωᵢ (6.69) with v_Cᵢ = J_vᵢ Θ̇, ωᵢ = J_ωᵢ Θ̇:

* M(Θ) = Σᵢ (mᵢ J_vᵢᵀ J_vᵢ + J_ωᵢᵀ ⁰Iᵢ J_ωᵢ), so that k = ½ Θ̇ᵀ M Θ̇ (6.71);
* G(Θ) = ∂u/∂Θ = −Σᵢ mᵢ J_vᵢᵀ g, since ∂⁰P_Cᵢ/∂Θ = J_vᵢ (6.73);
* ∂M/∂θₖ exactly, by differentiating the Jacobian columns in forward mode
  (dual numbers: no finite differences), hence Γ and C(Θ, Θ̇)ᵢⱼ = Σₖ Γᵢⱼₖ θ̇ₖ;
* τ = M Θ̈ + C Θ̇ + G, the Euler–Lagrange equation (6.77).

Every function takes one state (n,), a batch (N, n) or sympy object arrays.
"""
from __future__ import annotations

from itertools import combinations

import numpy as np

from .algebra import Dual, Vec3, dot
from .kinematics import placement_entries, point_jacobian_columns
from .model import Model
from .state import as_state, entries, layout_of


def _link_jacobians(model: Model, theta: list):
    """Per body: the (J_v, J_ω) columns of its COM and ⁰Iᵢ, from per-joint scalars."""
    placed = placement_entries(model, theta)
    result = []
    for i, body in enumerate(model.bodies):
        R_i = placed.R[i]
        I_base = R_i @ body.I_com_m @ R_i.T
        result.append((point_jacobian_columns(model, placed, i, placed.P_com[i]), I_base))
    return result


def _mass_matrix_entries(model: Model, theta: list) -> list:
    """M[j][k] = Σᵢ mᵢ J_vᵢ[:, j]·J_vᵢ[:, k] + J_ωᵢ[:, j]·⁰Iᵢ J_ωᵢ[:, k] (from (6.69), (6.71))."""
    n = model.n
    M = [[0] * n for _ in range(n)]
    for body, (cols, I_base) in zip(model.bodies, _link_jacobians(model, theta)):
        m = body.mass_s
        moved = [j for j in range(n) if _moves(cols[j])]
        for j in moved:
            v_j, w_j = cols[j]
            I_w_j = I_base @ w_j
            for k in moved:
                if k < j:
                    continue
                v_k, w_k = cols[k]
                M[j][k] = M[j][k] + m * dot(v_j, v_k) + dot(w_k, I_w_j)
    for j in range(n):
        for k in range(j):
            M[j][k] = M[k][j]
    return M


def _moves(column) -> bool:
    linear, angular = column
    return not all(isinstance(c, int) and c == 0 for c in (*linear, *angular))


def _gravity_entries(model: Model, theta: list) -> list:
    """G[j] = ∂u/∂θⱼ = −Σᵢ mᵢ gᵀ J_vᵢ[:, j] (6.73)."""
    g = model.gravity_v
    G = [0] * model.n
    for body, (cols, _) in zip(model.bodies, _link_jacobians(model, theta)):
        for j, (v_j, _) in enumerate(cols):
            G[j] = G[j] - body.mass_s * dot(g, v_j)
    return G


def _mass_matrix_derivatives(model: Model, theta: list) -> list:
    """dM[k][i][j] = ∂Mᵢⱼ/∂θₖ, exactly (forward-mode derivative of the Jacobian columns)."""
    derivatives = []
    for k in range(model.n):
        M = _mass_matrix_entries(model, [Dual(a, 1 if j == k else 0) for j, a in enumerate(theta)])
        derivatives.append([[x.b if isinstance(x, Dual) else 0 for x in row] for row in M])
    return derivatives


def _christoffel_entries(model: Model, theta: list) -> list:
    """Γ[i][j][k] = ½ (∂ₖMᵢⱼ + ∂ⱼMᵢₖ − ∂ᵢMⱼₖ)."""
    dM = _mass_matrix_derivatives(model, theta)
    n = model.n
    return [[[(dM[k][i][j] + dM[j][i][k] - dM[i][j][k]) / 2 for k in range(n)] for j in range(n)] for i in range(n)]


def mass_matrix(model: Model, q) -> np.ndarray:
    """M(Θ) from link Jacobians: shape (n, n) or (N, n, n).

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
        The mass matrix M(Θ), kg·m² (kg between prismatic joints).

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> mass_matrix(load_robot("two_link"), [0.0, 0.0]).round(3)   # as the composite-rigid-body M
    array([[1.31, 0.36],
           [0.36, 0.16]])
    """
    q = as_state(model, q, "q")
    return layout_of(q).assemble(_mass_matrix_entries(model, entries(q)), (model.n, model.n))


def gravity_torques(model: Model, q) -> np.ndarray:
    """G(Θ) = ∂u/∂Θ: shape (n,) or (N, n).

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
    >>> gravity_torques(load_robot("two_link"), [0.0, 0.0]).round(3)   # Craig (6.62) at Θ = 0, N·m
    array([18.639,  3.924])
    """
    q = as_state(model, q, "q")
    return layout_of(q).assemble(_gravity_entries(model, entries(q)), (model.n,))


def christoffel_symbols(model: Model, q) -> np.ndarray:
    """Γ(Θ): shape (n, n, n) or (N, n, n, n), Γ[..., i, j, k] = Γᵢⱼₖ.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    numpy.ndarray, shape (n, n, n) or (N, n, n, n)
        The Christoffel symbols Γᵢⱼₖ of M, kg·m² per rad (between revolute joints).

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> Gamma = christoffel_symbols(load_robot("two_link"), [0.0, np.pi / 2])
    >>> Gamma.shape, float(Gamma[0, 1, 1].round(3))   # Γ₁₂₂ = −m₂ l₁ l₂ s₂
    ((2, 2, 2), -0.2)
    """
    q = as_state(model, q, "q")
    return layout_of(q).assemble(_christoffel_entries(model, entries(q)), (model.n,) * 3)


def coriolis_matrix(model: Model, q, qd) -> np.ndarray:
    """C(Θ, Θ̇)ᵢⱼ = Σₖ Γᵢⱼₖ θ̇ₖ: shape (n, n) or (N, n, n).

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
        The Coriolis matrix C(Θ, Θ̇), kg·m²/s (between revolute joints).

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> coriolis_matrix(load_robot("two_link"), [0.0, np.pi / 2], [1.0, 0.0]).round(3)
    array([[ 0. , -0.2],
           [ 0.2,  0. ]])
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    Gamma, theta_dot = _christoffel_entries(model, entries(q)), entries(qd)
    n = model.n
    C = [[sum((Gamma[i][j][k] * theta_dot[k] for k in range(n)), 0) for j in range(n)] for i in range(n)]
    return layout_of(q, qd).assemble(C, (n, n))


def velocity_torques(model: Model, q, qd) -> np.ndarray:
    """V(Θ, Θ̇) = C(Θ, Θ̇) Θ̇: shape (n,) or (N, n).

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
    >>> velocity_torques(load_robot("two_link"), [0.0, np.pi / 2], [1.0, 1.0]).round(3)   # Craig (6.61), N·m
    array([-0.6,  0.2])
    """
    C, qd = coriolis_matrix(model, q, qd), as_state(model, qd, "qd")
    return np.einsum("...ij,...j->...i", C, qd) if C.dtype != object else C @ qd


def inverse_dynamics(model: Model, q, qd, qdd) -> np.ndarray:
    """τ = M Θ̈ + C Θ̇ + G: the Euler–Lagrange equation (6.77), shape (n,) or (N, n).

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

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        Joint torques τ, N·m (N for a prismatic joint).

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> inverse_dynamics(load_robot("pendulum"), [0.5], [0.0], [0.0]).round(4)   # m g l sin θ, as Newton–Euler
    array([4.7032])
    """
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    M, C, G = mass_matrix(model, q), coriolis_matrix(model, q, qd), gravity_torques(model, q)
    if M.dtype == object:
        return M @ qdd + C @ qd + G  # (6.77)
    return np.einsum("...ij,...j->...i", M, qdd) + np.einsum("...ij,...j->...i", C, qd) + G  # (6.77)


def link_kinetic_energies(model: Model, q, qd) -> np.ndarray:
    """kᵢ = ½ mᵢ v_Cᵢᵀ v_Cᵢ + ½ ωᵢᵀ ⁰Iᵢ ωᵢ (6.69) per body, J: shape (n,) or (N, n).

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
        Each body's kinetic energy kᵢ, J.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> link_kinetic_energies(load_robot("two_link"), [0.0, 0.0], [1.0, 0.0]).round(3)   # ½ m v², J
    array([0.25 , 0.405])
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    theta_dot = entries(qd)
    energies = []
    for body, (cols, I_base) in zip(model.bodies, _link_jacobians(model, entries(q))):
        v_c, w = Vec3(0, 0, 0), Vec3(0, 0, 0)
        for (v_j, w_j), rate in zip(cols, theta_dot):
            v_c, w = v_c + rate * v_j, w + rate * w_j
        energies.append(body.mass_s * dot(v_c, v_c) / 2 + dot(w, I_base @ w) / 2)  # (6.69)
    return layout_of(q, qd).assemble(energies, (model.n_bodies,))


def kinetic_energy(model: Model, q, qd) -> np.ndarray:
    """k = Σ kᵢ (6.71), J.

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
    numpy.ndarray, shape () or (N,)
        The kinetic energy k, J.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> float(kinetic_energy(load_robot("two_link"), [0.0, 0.0], [1.0, 0.0]).round(3))   # ½ Θ̇ᵀ M Θ̇ = ½ M₁₁, J
    0.655
    """
    return np.sum(link_kinetic_energies(model, q, qd), axis=-1)


def velocity_pairs(n: int) -> list[tuple[int, int]]:
    """The (j, k), j < k, of Craig's [Θ̇Θ̇] = (θ̇₁θ̇₂, θ̇₁θ̇₃, …, θ̇ₙ₋₁θ̇ₙ) (6.64), zero-based.

    Parameters
    ----------
    n : int
        The number of joints.

    Returns
    -------
    list of tuple of (int, int)
        The n(n−1)/2 pairs, in the order of B's columns.

    Examples
    --------

    >>> velocity_pairs(3)   # θ̇₁θ̇₂, θ̇₁θ̇₃, θ̇₂θ̇₃
    [(0, 1), (0, 2), (1, 2)]
    """
    return list(combinations(range(n), 2))


def configuration_space_terms(model: Model, q) -> tuple[np.ndarray, np.ndarray]:
    """Craig's B(Θ) (n, n(n−1)/2) and C(Θ) (n, n) of (6.63): V = B [Θ̇Θ̇] + C [Θ̇²].

    From Christoffel symbols: Cᵢⱼ = Γᵢⱼⱼ (centrifugal) and Bᵢ,(ⱼ,ₖ) = Γᵢⱼₖ + Γᵢₖⱼ = 2Γᵢⱼₖ (Coriolis).

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    tuple of (numpy.ndarray, numpy.ndarray)
        B(Θ), shape (n, n(n−1)/2), columns in :func:`velocity_pairs` order, and C(Θ), shape (n, n); batch axes
        first. Both kg·m² (between revolute joints).

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> B, C = configuration_space_terms(load_robot("two_link"), [0.0, np.pi / 2])
    >>> B.round(3).tolist(), C.round(3).tolist()   # Craig (6.63): B = (−2m₂l₁l₂s₂, 0)ᵀ
    ([[-0.4], [0.0]], [[0.0, -0.2], [0.2, 0.0]])
    """
    q = as_state(model, q, "q")
    n = model.n
    B, C = split_velocity_products(_christoffel_entries(model, entries(q)), n)
    layout = layout_of(q)
    return layout.assemble(B, (n, n * (n - 1) // 2)), layout.assemble(C, (n, n))


def split_velocity_products(T, n: int) -> tuple[list, list]:
    """Craig's split (6.63) of Σⱼₖ Tᵢⱼₖ θ̇ⱼθ̇ₖ into B [Θ̇Θ̇] + C [Θ̇²]: Bᵢ,(ⱼ,ₖ) = Tᵢⱼₖ + Tᵢₖⱼ, Cᵢⱼ = Tᵢⱼⱼ.

    The one place the split is made: B(Θ), C(Θ) of (6.63) from the Christoffel symbols
    (:func:`configuration_space_terms`), and B_x(Θ), C_x(Θ) of (6.105)
    (:func:`~course_dynamics.core.cartesian.cartesian_configuration_space_terms`). T need not be symmetric in j, k.

    Parameters
    ----------
    T : array_like or nested sequence, shape (m, n, n)
        The coefficients: row i of the quadratic form is Σⱼₖ T[i][j][k] θ̇ⱼθ̇ₖ; floats, numpy batches or sympy
        expressions (any scalar the algebra runs on).
    n : int
        The number of joints.

    Returns
    -------
    tuple of (list, list)
        B as m rows of n(n−1)/2 entries, columns in :func:`velocity_pairs` order, and C as m rows of n entries;
        the units of T (N·m per (rad/s)² for a torque row between revolute joints).

    Examples
    --------

    >>> B, C = split_velocity_products([[[1.0, 2.0], [3.0, 4.0]]], 2)   # θ̇₁² + 5 θ̇₁θ̇₂ + 4 θ̇₂²
    >>> B, C
    ([[5.0]], [[1.0, 4.0]])
    """
    pairs = velocity_pairs(n)
    B = [[T[i][j][k] + T[i][k][j] for j, k in pairs] for i in range(len(T))]  # (6.63), (6.64)
    C = [[T[i][j][j] for j in range(n)] for i in range(len(T))]  # (6.63), (6.65)
    return B, C


__all__ = ["christoffel_symbols", "configuration_space_terms", "coriolis_matrix", "gravity_torques", "inverse_dynamics",
           "kinetic_energy", "link_kinetic_energies", "mass_matrix", "split_velocity_products", "velocity_pairs",
           "velocity_torques"]
