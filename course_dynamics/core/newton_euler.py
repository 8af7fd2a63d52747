"""Craig's recursive Newton–Euler dynamics, eqs. (6.45)–(6.53); prismatic joints by (6.35) and (6.44).

Notation (every vector is expressed in the frame of the link it belongs to;
i is a body, p its parent, frames as in :mod:`course_dynamics.core.model`):

===================  ===========  ===============================================
code                 Craig        meaning (unit)
===================  ===========  ===============================================
``R[i]``             ᵖᵢR          orientation of frame i in its parent at Θ
``P[i]``             ᵖPᵢ          origin of frame i in its parent at Θ (m)
``omega[i]``         ⁱωᵢ          angular velocity of link i (rad/s)
``omega_dot[i]``     ⁱω̇ᵢ          angular acceleration (rad/s²)
``v_dot[i]``         ⁱv̇ᵢ          linear acceleration of the origin of frame i (m/s²),
                                  classical (not spatial), including the −g base lift
``v_dot_c[i]``       ⁱv̇_Cᵢ        linear acceleration of the centre of mass (m/s²)
``F[i]``, ``N[i]``   ⁱFᵢ, ⁱNᵢ     inertial force (N) and moment (N·m) at the COM
``f[i]``, ``n[i]``   ⁱfᵢ, ⁱnᵢ     force and moment exerted on link i by its parent
``tau[i]``           τᵢ           joint torque (N·m) or force (N, prismatic)
``z``                ⁱẐᵢ          the joint axis (any unit vector, not only z)
===================  ===========  ===============================================

For a tree, "the child i+1" of Craig's chain becomes "every child c of i",
and "link i" of the outward iteration follows its parent p rather than i−1.
The lecture notes print several of these equations with wrong frames or
indices; the lines below are the corrected forms (reference/errata.md).

The same functions run on one state (floats), a batch (arrays of shape (N,)
per joint) and sympy symbols: see :mod:`course_dynamics.core.algebra`.

The iterations are written against a few named operations (:class:`~course_dynamics.core.operations.Operations`),
one for each place in (6.45)–(6.53) where the equations could be written
otherwise: the rotation into a child's frame and into a parent's, the cross
product, the acceleration of a point, the angular acceleration and the centre
of mass (6.48) uses, the inertial force (6.49), the inertia each term of (6.50)
multiplies and its gyroscopic term, the link's own moment, the child's force and
its moment arm in (6.51)–(6.52), the moment τ is read from (6.53), and the base
acceleration (:mod:`~course_dynamics.core.operations`); each link's equations take theirs from
:meth:`~course_dynamics.core.operations.Operations.at`, so that another set may differ on one link only.
:data:`~course_dynamics.core.operations.EXACT`, the default, is the chapter's; every other use of the recursion
(compiled programs, batches, symbols, the regressor, the native loop's steps) runs the exact set.

Each iteration's loop body is a function of its own (:func:`outward_link`, :func:`link_wrench`,
:func:`carried_wrench`, :func:`joint_torque`): one body's step, which the native loop traces once with the
body's numbers as inputs (:mod:`~course_dynamics.core.compiled.looped`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .algebra import Vec3, cross, dot
from .kinematics import JointTransforms, joint_transforms
from .model import Model
from .operations import EXACT, Operations
from .state import as_state, entries, layout_of




@dataclass(frozen=True)
class OutwardPass:
    """Result of the outward iteration: per-body kinematics and inertial loads.

    Each field is a list of n_bodies :class:`~course_dynamics.core.algebra.Vec3`, body i's in frame i.

    Parameters
    ----------
    omega : list of Vec3
        ⁱωᵢ, rad/s (6.45).
    omega_dot : list of Vec3
        ⁱω̇ᵢ, rad/s² (6.46).
    v_dot : list of Vec3
        ⁱv̇ᵢ, m/s² (6.47), with the −g base lift.
    v_dot_c : list of Vec3
        ⁱv̇_Cᵢ, m/s² (6.48).
    F : list of Vec3
        ⁱFᵢ, N (6.49).
    N : list of Vec3
        ⁱNᵢ, N·m (6.50).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("two_link")
    >>> X = joint_transforms(arm, [0.0, 0.5])
    >>> out = outward_iteration(arm, X, [1.0, 0.0], [0.0, 0.0], arm.gravity_v)
    >>> len(out.omega), [round(c, 6) for c in out.omega[1]]        # ²ω₂ = ²₁R ¹ω₁ + θ̇₂ ²Ẑ₂ (6.45)
    (2, [0.0, 0.0, 1.0])
    """

    omega: list
    omega_dot: list
    v_dot: list
    v_dot_c: list
    F: list
    N: list


@dataclass(frozen=True)
class InwardPass:
    """Result of the inward iteration: joint reactions and torques.

    Parameters
    ----------
    f : list of Vec3
        ⁱfᵢ, the force on link i from its parent, frame i, N (6.51).
    n : list of Vec3
        ⁱnᵢ, the moment on link i from its parent, frame i, N·m (6.52).
    tau : list
        τ = Sᵀ τ_bodies, N·m (N for a prismatic joint), one scalar per coordinate (per joint without mimic joints).
    tau_bodies : list
        τᵢ (6.53), one scalar per body: each joint's own torque, a mimic joint's included.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("two_link")
    >>> X = joint_transforms(arm, [0.0, 0.5])
    >>> back = inward_iteration(arm, X, outward_iteration(arm, X, [0.0, 0.0], [0.0, 0.0], arm.gravity_v))
    >>> [round(t, 6) for t in back.tau]                             # at rest: G
    [18.158634, 3.443634]
    """

    f: list
    n: list
    tau: list
    tau_bodies: list


def outward_link(model: Model, X: JointTransforms, i: int, parent: tuple, qd, qdd, gravity: Vec3,
                 op: Operations = EXACT) -> tuple:
    """Body i's step of the outward iteration, (6.45)–(6.50): its motion from its parent's.

    Parameters
    ----------
    model : Model
        The robot.
    X : JointTransforms
        The joint transforms at Θ.
    i : int
        The body.
    parent : tuple of Vec3
        The parent's ᵖωₚ, ᵖω̇ₚ and ᵖv̇ₚ (for the base: 0, 0 and −g).
    qd, qdd : scalar
        The body's θ̇ and θ̈ (S Θ̇ and S Θ̈ for a mimic joint), rad/s and rad/s² (m/s, m/s²).
    gravity : Vec3
        g in the base frame, m/s².
    op : Operations, optional
        The operations body i's equations are written with.

    Returns
    -------
    tuple of Vec3
        ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ, ⁱFᵢ and ⁱNᵢ.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("pendulum")
    >>> still = (Vec3(0, 0, 0), Vec3(0, 0, 0), -arm.gravity_v)
    >>> [round(c, 6) for c in outward_link(arm, joint_transforms(arm, [0.0]), 0, still, 2.0, 0.0, arm.gravity_v)[0]]
    [0.0, 2.0, 0.0]
    """
    body = model.bodies[i]
    z = body.axis_v
    omega_p, omega_dot_p, v_dot_p = parent
    R = op.into_child(X, i, "6.46")
    if body.is_prismatic:  # a prismatic joint adds no rotation ((6.33) in Craig, unnumbered in the notes)
        w = op.into_child(X, i, "6.45") @ omega_p
        w_dot = R @ omega_dot_p
    else:
        w = op.into_child(X, i, "6.45") @ omega_p + qd * z  # (6.45)
        w_dot = R @ omega_dot_p + op.cross(R @ omega_p, qd * z, "6.46") + qdd * z  # (6.46)
    # (6.47)
    v = op.into_child(X, i, "6.47") @ op.point_acceleration(v_dot_p, omega_dot_p, omega_p, X.P[i], "6.47")
    if body.is_prismatic:
        v = v + cross(2 * w, qd * z) + qdd * z  # (6.35)
    w_dot_c, P_c = op.link_angular_acceleration(w_dot, omega_dot_p, "6.48"), op.centre_of_mass(model, i, "6.48")
    v_c = op.point_acceleration(v, w_dot_c, w, P_c, "6.48")  # (6.48)
    F_i = op.inertial_force(model, X, i, v_c, gravity)  # (6.49)
    N_i = op.inertia(body) @ w_dot + op.gyroscopic(w, op.inertia(body, "ω × I ω"), "6.50")  # (6.50)
    return w, w_dot, v, v_c, F_i, N_i


def outward_iteration(model: Model, X: JointTransforms, theta_dot: list, theta_ddot: list, gravity: Vec3,
                      ops: Operations = EXACT) -> OutwardPass:
    """Link velocities, accelerations and inertial loads, base to tips.

    Parameters
    ----------
    model : Model
        The robot.
    X : JointTransforms
        The joint transforms at Θ (:func:`~course_dynamics.core.kinematics.joint_transforms`).
    theta_dot : list
        Θ̇, one scalar per coordinate (float, (N,) array or sympy expression), rad/s (m/s); a mimic joint's
        body moves at S Θ̇ (:meth:`~course_dynamics.core.model.Model.body_entries`).
    theta_ddot : list
        Θ̈, one scalar per coordinate, rad/s² (m/s²).
    gravity : Vec3
        g in the base frame, m/s².
    ops : Operations, optional
        The operations the equations are written with; :data:`~course_dynamics.core.operations.EXACT` by default.

    Returns
    -------
    OutwardPass
        ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ, ⁱFᵢ and ⁱNᵢ of every body.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("two_link")
    >>> X = joint_transforms(arm, [0.0, 0.5])
    >>> out = outward_iteration(arm, X, [0.0, 0.0], [0.0, 0.0], arm.gravity_v)
    >>> [round(c, 6) for c in out.v_dot[0]]                         # ⁰v̇₀ = −g: the base accelerates upward
    [0.0, 9.81, 0.0]
    """
    zero = Vec3(0, 0, 0)
    omega, omega_dot, v_dot, v_dot_c, F, N = [], [], [], [], [], []
    theta_dot, theta_ddot = model.body_entries(theta_dot, False), model.body_entries(theta_ddot, False)  # S Θ̇, S Θ̈
    for i, body in enumerate(model.bodies):
        p, op = body.parent, ops.at(i)
        parent = (zero, zero, op.base_acceleration(gravity)) if p < 0 else (omega[p], omega_dot[p], v_dot[p])
        w, w_dot, v, v_c, F_i, N_i = outward_link(model, X, i, parent, theta_dot[i], theta_ddot[i], gravity, op)
        omega.append(w)
        omega_dot.append(w_dot)
        v_dot.append(v)
        v_dot_c.append(v_c)
        F.append(F_i)
        N.append(N_i)
    return OutwardPass(omega, omega_dot, v_dot, v_dot_c, F, N)


def link_wrench(model: Model, i: int, out: OutwardPass, op: Operations = EXACT) -> tuple:
    """Link i's own part of (6.51) and (6.52): ⁱFᵢ, and ⁱNᵢ + ⁱP_Cᵢ × ⁱFᵢ (its children are added to them).

    Parameters
    ----------
    model : Model
        The robot.
    i : int
        The body.
    out : OutwardPass
        The outward iteration's result.
    op : Operations, optional
        The operations link i's equations are written with.

    Returns
    -------
    tuple of Vec3
        (f, n) before the children's: N and N·m.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("pendulum")
    >>> X = joint_transforms(arm, [0.0])
    >>> f, n = link_wrench(arm, 0, outward_iteration(arm, X, [0.0], [0.0], arm.gravity_v))
    >>> [round(c, 6) for c in f]                       # the weight held up: m g, N
    [0.0, 0.0, 9.81]
    """
    P_c = op.centre_of_mass(model, i, "6.52")
    return out.F[i], op.link_moment(model, i, out, "6.52") + op.cross(P_c, out.F[i], "6.52")  # (6.51), (6.52)


def carried_wrench(model: Model, X: JointTransforms, c: int, f_i: Vec3, n_i: Vec3, f_c: Vec3, n_c: Vec3,
                   op: Operations = EXACT) -> tuple:
    """(f, n) of child c's parent with c's force and moment carried in, (6.51) and (6.52).

    Parameters
    ----------
    model : Model
        The robot.
    X : JointTransforms
        The joint transforms at Θ.
    c : int
        The child body.
    f_i, n_i : Vec3
        The parent's force and moment so far, N and N·m.
    f_c, n_c : Vec3
        The child's ᶜf_c and ᶜn_c, N and N·m.
    op : Operations, optional
        The operations the parent's equations are written with.

    Returns
    -------
    tuple of Vec3
        The parent's (f, n) with the child's added.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("two_link")
    >>> X, zero, up = joint_transforms(arm, [0.0, 0.0]), Vec3(0, 0, 0), Vec3(0, 1, 0)
    >>> [list(v) for v in carried_wrench(arm, X, 1, zero, zero, up, zero)]   # ¹P₂ × f: the arm's moment
    [[0.0, 1.0, 0.0], [0.0, 0.0, 0.5]]
    """
    f_i = f_i + op.carried_force(model, c, op.into_parent(X, c, "6.51"), f_c, "6.51")  # (6.51)
    R = op.into_parent(X, c, "6.52")
    n_i = n_i + R @ n_c + op.moment_arm(X.P[c], R, f_c, "6.52")  # (6.52)
    return f_i, n_i


def joint_torque(model: Model, i: int, f: list, n: list, out: OutwardPass, op: Operations = EXACT):
    """τᵢ, read from the joint's moment (6.53), or its force for a prismatic joint (6.44).

    Parameters
    ----------
    model : Model
        The robot.
    i : int
        The body.
    f, n : list of Vec3
        The bodies' ⁱfᵢ and ⁱnᵢ (body i's complete).
    out : OutwardPass
        The outward iteration's result.
    op : Operations, optional
        The operations link i's equations are written with.

    Returns
    -------
    scalar
        τᵢ, N·m (N).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> arm = load_robot("pendulum")
    >>> round(joint_torque(arm, 0, [Vec3(0, 0, 0)], [Vec3(0, 2.5, 0)], None), 6)   # the moment about the axis y
    2.5
    """
    body = model.bodies[i]
    n_z = op.joint_moment(model, i, n, out, "6.53")
    return dot(f[i], body.axis_v) if body.is_prismatic else dot(n_z, body.axis_v)  # (6.44) / (6.53)


def inward_iteration(model: Model, X: JointTransforms, out: OutwardPass, ops: Operations = EXACT) -> InwardPass:
    """Joint forces, moments and torques, tips to base.

    Parameters
    ----------
    model : Model
        The robot.
    X : JointTransforms
        The joint transforms at Θ (:func:`~course_dynamics.core.kinematics.joint_transforms`).
    out : OutwardPass
        The outward iteration's result at the same state.
    ops : Operations, optional
        The operations the equations are written with; :data:`~course_dynamics.core.operations.EXACT` by default.

    Returns
    -------
    InwardPass
        ⁱfᵢ, ⁱnᵢ and τᵢ of every body.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("two_link")
    >>> X = joint_transforms(arm, [0.0, 0.5])
    >>> back = inward_iteration(arm, X, outward_iteration(arm, X, [1.0, 0.0], [0.0, 0.0], arm.gravity_v))
    >>> [round(t, 6) for t in back.tau], len(back.f)                # τᵢ = ⁱnᵢᵀ ⁱẐᵢ (6.53)
    ([18.158634, 3.539519], 2)
    """
    f, n, tau = [None] * model.n_bodies, [None] * model.n_bodies, [None] * model.n_bodies
    for i in reversed(range(model.n_bodies)):
        op = ops.at(i)
        f_i, n_i = link_wrench(model, i, out, op)  # (6.51), (6.52): the link's own part
        for c in model.children[i]:
            f_i, n_i = carried_wrench(model, X, c, f_i, n_i, f[c], n[c], op)  # (6.51), (6.52): each child's
        f[i], n[i] = f_i, n_i
        tau[i] = joint_torque(model, i, f, n, out, op)  # (6.53) / (6.44)
    return InwardPass(f, n, model.coordinate_entries(tau), tau)  # τ = Sᵀ τ_bodies (mimic joints)


def torque_entries(model: Model, X: JointTransforms, theta_dot: list, theta_ddot: list, gravity: Vec3) -> list:
    """τ as per-joint scalars, given transforms: the building block of M, V, G and C.

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("two_link")
    >>> X = joint_transforms(arm, [0.0, 0.5])
    >>> [round(t, 6) for t in torque_entries(arm, X, [0, 0], [1, 0], arm.gravity_v * 0)]   # column 1 of M
    [1.261033, 0.335517]
    """
    return inward_iteration(model, X, outward_iteration(model, X, theta_dot, theta_ddot, gravity)).tau


def inverse_dynamics(model: Model, q, qd, qdd) -> np.ndarray:
    """τ = M(Θ)Θ̈ + V(Θ, Θ̇) + G(Θ) by Newton–Euler.

    Parameters
    ----------
    model : Model
        The robot. Gravity is ``model.gravity`` (``model.with_gravity(g)`` changes it).
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint), joints in ``model.joint_names`` order; numpy object
        arrays of sympy expressions give symbolic torques.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : array_like, shape (n,) or (N, n)
        Joint accelerations Θ̈, rad/s² (m/s²).

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
    >>> arm = load_robot("pendulum")          # m = 1 kg at l = 1 m, θ = 0 hanging down
    >>> inverse_dynamics(arm, [0.5], [0.0], [0.0]).round(4)  # m g l sin θ
    array([4.7032])
    """
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    layout = layout_of(q, qd, qdd)
    X = joint_transforms(model, entries(q))
    tau = torque_entries(model, X, entries(qd), entries(qdd), model.gravity_v)
    return layout.assemble(tau, (model.n,))


@dataclass(frozen=True)
class LinkQuantities:
    """Every intermediate quantity of one Newton–Euler evaluation, per link.

    Vectors have shape (n_bodies, 3) for one state or (N, n_bodies, 3) for a batch (one row per body, a
    mimic joint's included; n_bodies = n without mimic joints); each is expressed in its own link's frame
    (Craig's ⁱ(·)ᵢ). ``tau`` has shape (n_bodies,) or (N, n_bodies): each joint's own τᵢ (6.53), before a
    mimic's is mapped onto its leader (:func:`inverse_dynamics` gives τ = Sᵀ τ_bodies).

    Parameters
    ----------
    joints : tuple of str
        The bodies' joints, in model order.
    omega : numpy.ndarray, shape (n_bodies, 3) or (N, n_bodies, 3)
        ⁱωᵢ, rad/s.
    omega_dot : numpy.ndarray, shape (n_bodies, 3) or (N, n_bodies, 3)
        ⁱω̇ᵢ, rad/s².
    v_dot : numpy.ndarray, shape (n_bodies, 3) or (N, n_bodies, 3)
        ⁱv̇ᵢ, m/s², with the −g base lift.
    v_dot_c : numpy.ndarray, shape (n_bodies, 3) or (N, n_bodies, 3)
        ⁱv̇_Cᵢ, m/s².
    F : numpy.ndarray, shape (n_bodies, 3) or (N, n_bodies, 3)
        ⁱFᵢ, N.
    N : numpy.ndarray, shape (n_bodies, 3) or (N, n_bodies, 3)
        ⁱNᵢ, N·m.
    f : numpy.ndarray, shape (n_bodies, 3) or (N, n_bodies, 3)
        ⁱfᵢ, N.
    n : numpy.ndarray, shape (n_bodies, 3) or (N, n_bodies, 3)
        ⁱnᵢ, N·m.
    tau : numpy.ndarray, shape (n_bodies,) or (N, n_bodies)
        τᵢ, N·m (N for a prismatic joint).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> links = newton_euler_links(load_robot("pendulum"), [0.5], [2.0], [0.0])
    >>> np.round(links.omega, 6), np.round(links.tau, 4)     # ¹ω₁ = θ̇₁ ¹Ẑ₁, the joint axis (the URDF's y)
    (array([[0., 2., 0.]]), array([4.7032]))
    """

    joints: tuple[str, ...]
    omega: np.ndarray
    omega_dot: np.ndarray
    v_dot: np.ndarray
    v_dot_c: np.ndarray
    F: np.ndarray
    N: np.ndarray
    f: np.ndarray
    n: np.ndarray
    tau: np.ndarray


def newton_euler_links(model: Model, q, qd, qdd, ops: Operations = EXACT) -> LinkQuantities:
    """The outward and inward iterations with every per-link quantity kept, run with the operations ``ops``.

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
    ops : Operations, optional
        The operations the equations are written with; :data:`~course_dynamics.core.operations.EXACT` by default.

    Returns
    -------
    LinkQuantities
        Every body's ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ, ⁱFᵢ, ⁱNᵢ, ⁱfᵢ, ⁱnᵢ and τᵢ.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> links = newton_euler_links(load_robot("two_link"), [0.0, 0.5], [1.0, 0.0], [0.0, 0.0])
    >>> links.omega.shape, links.joints, np.round(links.tau, 6)
    ((2, 3), ('theta1', 'theta2'), array([18.158634,  3.539519]))
    """
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    layout = layout_of(q, qd, qdd)
    X = joint_transforms(model, entries(q))
    out = outward_iteration(model, X, entries(qd), entries(qdd), model.gravity_v, ops)
    back = inward_iteration(model, X, out, ops)

    def per_link(vectors):
        return layout.assemble([tuple(v) for v in vectors], (model.n_bodies, 3))

    return LinkQuantities(
        joints=tuple(body.joint for body in model.bodies),
        omega=per_link(out.omega), omega_dot=per_link(out.omega_dot), v_dot=per_link(out.v_dot),
        v_dot_c=per_link(out.v_dot_c), F=per_link(out.F), N=per_link(out.N),
        f=per_link(back.f), n=per_link(back.n), tau=layout.assemble(back.tau_bodies, (model.n_bodies,)),
    )


__all__ = ["InwardPass", "LinkQuantities", "OutwardPass", "carried_wrench", "inverse_dynamics", "inward_iteration",
           "joint_torque", "link_wrench", "newton_euler_links", "outward_iteration", "outward_link"]
