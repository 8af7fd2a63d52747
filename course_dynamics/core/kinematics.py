"""Kinematics: joint transforms, placements in the base frame, point Jacobians, potential energy.

Both paths to the dynamics start here: the Newton–Euler recursion uses the
joint transforms ᵖᵢR, ᵖPᵢ (frame i in its parent p), the Lagrangian path and
Cartesian dynamics use the base-frame placements and point Jacobians.

================  =========  ==================================================
code              Craig      meaning (shape, unit)
================  =========  ==================================================
``X.R[i]``        ᵖᵢR        orientation of frame i in its parent at Θ (3, 3)
``X.R_T[i]``      ⁱₚR        its transpose: maps parent-frame vectors into frame i
``X.P[i]``        ᵖPᵢ        origin of frame i in its parent at Θ (3,), m
``R[i]``          ⁰ᵢR        orientation of frame i in the base (3, 3)
``P[i]``          ⁰Pᵢ        origin of frame i in the base (3,), m
``P_com[i]``      ⁰P_Cᵢ      centre of mass of body i in the base (3,), m
``u``             u          potential energy (6.73), J, with u_ref = 0
================  =========  ==================================================

Functions ending in ``_entries`` work on per-joint scalars (see
:mod:`course_dynamics.core.state`) and return :class:`~course_dynamics.core.algebra.Vec3`,
:class:`~course_dynamics.core.algebra.Mat3` or scalars, so one state, a batch and
sympy symbols go through the same lines.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .algebra import Mat3, Vec3, dot
from .joints import kind_of
from .model import Frame, Model
from .state import as_state, entries, layout_of


@dataclass(frozen=True)
class JointTransforms:
    """ᵖᵢR, its transpose ⁱₚR, and ᵖPᵢ for every body at one configuration Θ.

    Each field is a list of n entries, one per body, of :class:`~course_dynamics.core.algebra.Mat3` or
    :class:`~course_dynamics.core.algebra.Vec3` whose components are per-joint scalars.

    Parameters
    ----------
    R : list of Mat3
        ᵖᵢR, the orientation of frame i in its parent.
    R_T : list of Mat3
        ⁱₚR, its transpose: maps parent-frame vectors into frame i.
    P : list of Vec3
        ᵖPᵢ, the origin of frame i in its parent, m.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> X = joint_transforms(load_robot("two_link"), [0.0, 0.0])
    >>> list(X.P[1]), X.R_T[1].rows == X.R[1].T.rows
    ([0.5, 0.0, 0.0], True)
    """

    R: list
    R_T: list
    P: list


def joint_transforms(model: Model, theta: list) -> JointTransforms:
    """ᵖᵢR(θᵢ) and ᵖPᵢ(θᵢ) of every body, from per-joint scalars θ.

    Parameters
    ----------
    model : Model
        The robot.
    theta : list
        Θ, one scalar per joint (a float, an (N,) array or a sympy expression; as
        :func:`~course_dynamics.core.state.entries` gives them), rad (m for a prismatic joint).

    Returns
    -------
    JointTransforms
        ᵖᵢR, ⁱₚR and ᵖPᵢ of every body.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> X = joint_transforms(load_robot("rrr_arm"), [0.0, 0.0, 0.0])
    >>> list(X.P[1]), list(X.P[2])   # ¹P₂ and ²P₃, m
    ([0.0, 0.0, 0.3], [0.4, 0.0, 0.0])
    """
    R, P = [], []
    for body, q in zip(model.bodies, model.body_entries(theta)):  # θ_bodies = S Θ + b (mimic joints)
        R_i, P_i = kind_of(body).transform(body, q)
        R.append(R_i)
        P.append(P_i)
    return JointTransforms(R, [r.T for r in R], P)


@dataclass(frozen=True)
class BasePlacements:
    """⁰ᵢR, ⁰Pᵢ and ⁰P_Cᵢ of every body, as Mat3/Vec3 of per-joint scalars.

    >>> from course_dynamics import load_robot
    >>> placed = placement_entries(load_robot("rrr_arm"), [0.0, 0.0, 0.0])
    >>> [list(p) for p in placed.P]   # ⁰Pᵢ, m
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.3], [0.4, 0.0, 0.3]]
    """

    R: list
    P: list
    P_com: list


def placement_entries(model: Model, theta: list) -> BasePlacements:
    """Where every body is in the base frame: ⁰ᵢR = ⁰ₚR ᵖᵢR, ⁰Pᵢ = ⁰Pₚ + ⁰ₚR ᵖPᵢ.

    >>> from course_dynamics import load_robot
    >>> placed = placement_entries(load_robot("rrr_arm"), [0.0, 0.0, 0.0])
    >>> list(placed.P_com[2])   # ⁰P_C₃: the forearm's COM 0.15 m beyond its joint, m
    [0.55, 0.0, 0.3]
    """
    X = joint_transforms(model, theta)
    R, P, P_com = [], [], []
    for i, body in enumerate(model.bodies):
        R_i, P_i, P_com_i = placement_link(body, X.R[i], X.P[i], None if body.parent < 0 else
                                           (R[body.parent], P[body.parent]))
        R.append(R_i)
        P.append(P_i)
        P_com.append(P_com_i)
    return BasePlacements(R, P, P_com)


def placement_link(body, R_joint: Mat3, P_joint: Vec3, parent: tuple | None) -> tuple[Mat3, Vec3, Vec3]:
    """One body's ⁰ᵢR = ⁰ₚR ᵖᵢR, ⁰Pᵢ = ⁰Pₚ + ⁰ₚR ᵖPᵢ and ⁰P_Cᵢ, from its joint transform and its parent's placement.

    Parameters
    ----------
    body : Body
        The body.
    R_joint : Mat3
        ᵖᵢR at Θ.
    P_joint : Vec3
        ᵖPᵢ at Θ, m.
    parent : tuple of (Mat3, Vec3) or None
        The parent's ⁰ₚR and ⁰Pₚ; None for a body on the base.

    Returns
    -------
    tuple of (Mat3, Vec3, Vec3)
        ⁰ᵢR, ⁰Pᵢ and ⁰P_Cᵢ (m).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> arm = load_robot("rrr_arm")
    >>> X = joint_transforms(arm, [0.0, 0.0, 0.0])
    >>> list(placement_link(arm.bodies[1], X.R[1], X.P[1], (X.R[0], X.P[0]))[1])   # ⁰P₂, m
    [0.0, 0.0, 0.3]
    """
    if parent is None:
        R_i, P_i = R_joint, P_joint
    else:
        R_p, P_p = parent
        R_i, P_i = R_p @ R_joint, P_p + R_p @ P_joint
    return R_i, P_i, P_i + R_i @ body.p_com_v


def frame_placement_entries(placements: BasePlacements, frame: Frame) -> tuple[Mat3, Vec3]:
    """⁰R_F and ⁰P_F of a URDF link frame, from the placements of the body that carries it.

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> R, P = frame_placement_entries(placement_entries(arm, [0.0, 0.0]), arm.frame("tool"))
    >>> [round(x, 3) for x in P]   # ⁰P of the tool frame, m
    [0.9, 0.0, 0.0]
    """
    R_F, P_F = Mat3.of(frame.R), Vec3.of(frame.P)
    if frame.body < 0:
        return R_F, P_F
    R_b, P_b = placements.R[frame.body], placements.P[frame.body]
    return R_b @ R_F, P_b + R_b @ P_F


def point_jacobian_columns(model: Model, placements: BasePlacements, body: int, point: Vec3) -> list:
    """Columns (J_v[:, j], J_ω[:, j]) of a point fixed to ``body``, base coordinates.

    ``point`` is ⁰P of the point. Joint j moves the point when body j is
    ``body`` or one of its ancestors: a revolute joint adds ⁰Ẑⱼ × (⁰P − ⁰Pⱼ) to
    its velocity and ⁰Ẑⱼ to the angular velocity, a prismatic joint adds ⁰Ẑⱼ
    and no rotation. Other columns are zero.

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("rrr_arm")
    >>> placed = placement_entries(arm, [0.0, 0.0, 0.0])
    >>> columns = point_jacobian_columns(arm, placed, 2, placed.P_com[2])   # the forearm's COM
    >>> [[round(x, 3) for x in v] for v, w in columns]   # J_v[:, j], m/rad
    [[0.0, 0.55, 0.0], [0.0, 0.0, -0.55], [0.0, 0.0, -0.15]]
    """
    zero = Vec3(0, 0, 0)
    cols = [(zero, zero)] * model.n_bodies
    j = body
    while j >= 0:
        joint = model.bodies[j]
        z = placements.R[j] @ joint.axis_v  # ⁰Ẑⱼ
        cols[j] = kind_of(joint).point_column(z, point, placements.P[j])
        j = joint.parent
    if not model.has_mimic:
        return cols
    # J = J_bodies S: a mimic body's column joins its leader's, scaled by the multiplier
    return list(zip(model.coordinate_entries([v for v, _ in cols]), model.coordinate_entries([w for _, w in cols])))


@dataclass(frozen=True)
class Placements:
    """Base-frame placements of every body: R (n, 3, 3), P and P_com (n, 3); batch axes lead.

    Parameters
    ----------
    R : numpy.ndarray, shape (n, 3, 3) or (N, n, 3, 3)
        ⁰ᵢR, the orientation of each body's frame in the base.
    P : numpy.ndarray, shape (n, 3) or (N, n, 3)
        ⁰Pᵢ, the origin of each body's frame in the base, m.
    P_com : numpy.ndarray, shape (n, 3) or (N, n, 3)
        ⁰P_Cᵢ, each body's centre of mass in the base, m.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> placed = forward_kinematics(load_robot("two_link"), np.zeros((4, 2)))   # a batch of 4 states
    >>> placed.R.shape, placed.P.shape
    ((4, 2, 3, 3), (4, 2, 3))
    """

    R: np.ndarray
    P: np.ndarray
    P_com: np.ndarray


def forward_kinematics(model: Model, q) -> Placements:
    """Where every body is at Θ (shape (n,) or (N, n)).

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    Placements
        ⁰ᵢR, ⁰Pᵢ and ⁰P_Cᵢ of every body, batch axes first.

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> forward_kinematics(arm, [0.0, 0.0]).P_com[1].round(3)   # m: both links along world X
    array([0.9, 0. , 0. ])
    """
    q = as_state(model, q, "q")
    layout = layout_of(q)
    placed = placement_entries(model, entries(q))
    n = model.n_bodies
    return Placements(
        R=layout.assemble([r.rows for r in placed.R], (n, 3, 3)),
        P=layout.assemble([tuple(p) for p in placed.P], (n, 3)),
        P_com=layout.assemble([tuple(p) for p in placed.P_com], (n, 3)),
    )


def frame_placement(model: Model, q, frame: str) -> tuple[np.ndarray, np.ndarray]:
    """⁰R_F (3, 3) and ⁰P_F (3,) of URDF link ``frame`` at Θ; batch axes lead.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    frame : str
        A URDF link (``model.frame_names``).

    Returns
    -------
    tuple of (numpy.ndarray, numpy.ndarray)
        ⁰R_F, shape (3, 3) or (N, 3, 3), and ⁰P_F, shape (3,) or (N, 3), m.

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.
    ModelError
        If the robot has no link ``frame``.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> R, P = frame_placement(load_robot("rrr_arm"), [0.0, 0.0, 0.0], "forearm")
    >>> P.tolist()   # ⁰P of the forearm's frame (joint 3), m
    [0.4, 0.0, 0.3]
    """
    q = as_state(model, q, "q")
    layout = layout_of(q)
    R, P = frame_placement_entries(placement_entries(model, entries(q)), model.frame(frame))
    return layout.assemble(R.rows, (3, 3)), layout.assemble(tuple(P), (3,))


def potential_energy_entry(model: Model, theta: list):
    """u = Σᵢ −mᵢ ⁰gᵀ ⁰P_Cᵢ (6.73) from per-joint scalars (u_ref = 0).

    >>> from course_dynamics import load_robot
    >>> potential_energy_entry(load_robot("pendulum"), [0.0])   # 1 kg hanging 1 m below the pivot, J
    -9.81
    """
    g = model.gravity_v
    u = 0
    for body, p in zip(model.bodies, placement_entries(model, theta).P_com):
        u = u - body.mass_s * dot(g, p)  # (6.73)
    return u


def potential_energy(model: Model, q) -> np.ndarray:
    """u(Θ), J: shape () for one state, (N,) for a batch.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    numpy.ndarray, shape () or (N,)
        The potential energy u = Σᵢ −mᵢ ⁰gᵀ ⁰P_Cᵢ of (6.73), J, with u_ref = 0.

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> potential_energy(load_robot("pendulum"), [[0.0], [np.pi]]).round(2)   # hanging, upright; J
    array([-9.81,  9.81])
    """
    q = as_state(model, q, "q")
    return layout_of(q).assemble(potential_energy_entry(model, entries(q)), ())


__all__ = ["JointTransforms", "Placements", "forward_kinematics", "frame_placement", "joint_transforms",
           "potential_energy"]
