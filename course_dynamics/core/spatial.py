"""Six-dimensional velocities, forces and inertias, all in the base frame: the language of the O(n²) algorithms.

The composite-rigid-body mass matrix (:mod:`course_dynamics.core.crba`) and the
Coriolis matrix (:mod:`course_dynamics.core.coriolis`) add up inertias of whole
subtrees of bodies. Written in one frame, the base frame, about its origin O,
those sums need no transforms at all; this module is that frame's algebra.
A 6-vector is a pair of :class:`~course_dynamics.core.algebra.Vec3` (angular part
first), so one state, a batch and sympy symbols all work, as everywhere else.

=================  ==========================================================
code               meaning (base frame, about the base origin O)
=================  ==========================================================
``(w, v)``         a motion: angular velocity ω and the velocity v of the body
                   point passing through O (rad/s, m/s)
``(n, f)``         a force: moment n about O and force f (N·m, N)
``s[j]``           joint j's motion for a unit rate: revolute (⁰Ẑⱼ, ⁰Pⱼ × ⁰Ẑⱼ),
                   prismatic (0, ⁰Ẑⱼ)
``Inertia``        a body's mass m, first moment h = m ⁰P_C (kg·m) and
                   rotational inertia about O, Ī = ⁰I_C + m([c]ᵀ[c]) (kg·m²);
                   acting on a motion: I(w, v) = (Ī w + h × v, m v − h × w)
``cross_motion``   (w₁, v₁) × (w₂, v₂) = (w₁ × w₂, w₁ × v₂ + v₁ × w₂)
``cross_force``    (w, v) ×* (n, f) = (w × n + v × f, w × f)
=================  ==========================================================
"""
from __future__ import annotations

from dataclasses import dataclass

from .algebra import Mat3, Vec3, cross, dot
from .joints import kind_of
from .kinematics import BasePlacements
from .model import Model


@dataclass(frozen=True)
class Inertia:
    """A rigid body's spatial inertia about the base origin: m, h = m c, Ī (rotational, about O).

    Two inertias add (``a + b``): the inertia of the two bodies moving as one.

    Parameters
    ----------
    m : float, numpy.ndarray of shape (N,) or sympy.Expr
        The mass, kg.
    h : Vec3
        The first moment m ⁰P_C, base coordinates, kg·m.
    I : Mat3
        The rotational inertia Ī about the base origin O, base axes, kg·m².

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import placement_entries
    >>> arm = load_robot("rrr_arm")
    >>> forearm = body_inertias(arm, placement_entries(arm, [0.0, 0.0, 0.0]))[2]
    >>> forearm.m, list(forearm.h)   # kg and m ⁰P_C, kg·m
    (1.0, [0.55, 0.0, 0.3])
    """

    m: object
    h: Vec3
    I: Mat3

    def __add__(self, other: "Inertia") -> "Inertia":
        rows = tuple(tuple(a + b for a, b in zip(r1, r2)) for r1, r2 in zip(self.I.rows, other.I.rows))
        return Inertia(self.m + other.m, self.h + other.h, Mat3(rows))

    def times(self, motion: tuple[Vec3, Vec3]) -> tuple[Vec3, Vec3]:
        """The force I (w, v) = (Ī w + h × v, m v − h × w), e.g. the momentum of a moving body.

        Parameters
        ----------
        motion : tuple of (Vec3, Vec3)
            (w, v): an angular velocity, rad/s, and the velocity of the body point at O, m/s.

        Returns
        -------
        tuple of (Vec3, Vec3)
            (n, f): a moment about O, N·m·s (or N·m for an acceleration), and a force, N·s (or N).
        """
        w, v = motion
        return self.I @ w + cross(self.h, v), self.m * v - cross(self.h, w)


def motion_axes(model: Model, placements: BasePlacements) -> list[tuple[Vec3, Vec3]]:
    """s[j] for every joint: the body's motion for a unit joint rate, in base coordinates.

    Parameters
    ----------
    model : Model
        The robot.
    placements : BasePlacements
        Every body's placement in the base frame, as ``kinematics.placement_entries`` gives it.

    Returns
    -------
    list of tuple of (Vec3, Vec3)
        n motions (angular, linear): revolute (⁰Ẑⱼ, ⁰Pⱼ × ⁰Ẑⱼ), prismatic (0, ⁰Ẑⱼ).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import placement_entries
    >>> arm = load_robot("rrr_arm")
    >>> motion_axes(arm, placement_entries(arm, [0.0, 0.0, 0.0]))[1]   # joint 2: about y through (0, 0, 0.3)
    (Vec3(0.0, 1.0, 0.0), Vec3(-0.3, 0.0, 0.0))
    """
    return [motion_axis(body, R, P) for body, R, P in zip(model.bodies, placements.R, placements.P)]


def motion_axis(body, R: Mat3, P: Vec3) -> tuple[Vec3, Vec3]:
    """One joint's unit motion s in base coordinates, from its body's placement.

    Parameters
    ----------
    body : Body
        The body the joint moves.
    R : Mat3
        ⁰ᵢR, the body's orientation in the base.
    P : Vec3
        ⁰Pᵢ, its origin in the base, m.

    Returns
    -------
    tuple of (Vec3, Vec3)
        (angular, linear): revolute (⁰Ẑⱼ, ⁰Pⱼ × ⁰Ẑⱼ), prismatic (0, ⁰Ẑⱼ).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.algebra import Mat3, Vec3
    >>> body = load_robot("pendulum").bodies[0]
    >>> motion_axis(body, Mat3(((1, 0, 0), (0, 1, 0), (0, 0, 1))), Vec3(0.0, 0.0, 0.0))
    (Vec3(0.0, 1.0, 0.0), Vec3(0.0, 0.0, 0.0))
    """
    z = R @ body.axis_v  # ⁰Ẑⱼ
    return kind_of(body).motion(z, P)


def body_inertias(model: Model, placements: BasePlacements) -> list[Inertia]:
    """Every body's spatial inertia about the base origin, from its mass, ⁰P_C and ᶜI rotated to the base.

    Parameters
    ----------
    model : Model
        The robot.
    placements : BasePlacements
        Every body's placement in the base frame, as ``kinematics.placement_entries`` gives it.

    Returns
    -------
    list of Inertia
        n spatial inertias, one per body.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import placement_entries
    >>> arm = load_robot("pendulum")
    >>> body_inertias(arm, placement_entries(arm, [0.0]))[0].I.rows   # m l² about x and y through the pivot
    ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 0.0))
    """
    return [body_inertia(body, R, c) for body, R, c in zip(model.bodies, placements.R, placements.P_com)]


def body_inertia(body, R: Mat3, c: Vec3) -> Inertia:
    """One body's spatial inertia about the base origin, from its placement.

    Parameters
    ----------
    body : Body
        The body: its mass and ᶜI.
    R : Mat3
        ⁰ᵢR, its orientation in the base.
    c : Vec3
        ⁰P_Cᵢ, its centre of mass in the base, m.

    Returns
    -------
    Inertia
        (m, h = m ⁰P_Cᵢ, Ī about the base origin).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.algebra import Mat3, Vec3
    >>> unit = Mat3(((1, 0, 0), (0, 1, 0), (0, 0, 1)))
    >>> point = body_inertia(load_robot("pendulum").bodies[0], unit, Vec3(1.0, 0.0, 0.0))
    >>> point.m, point.I.rows[2][2]          # m l² about the axis through O, kg·m²
    (1.0, 1.0)
    """
    m = body.mass_s
    I_c = R @ body.I_com_m @ R.T  # ⁰I_C: inertia about the COM, base axes
    cc = dot(c, c)
    shift = ((cc - c.x * c.x, -c.x * c.y, -c.x * c.z),
             (-c.y * c.x, cc - c.y * c.y, -c.y * c.z),
             (-c.z * c.x, -c.z * c.y, cc - c.z * c.z))  # [c]ᵀ[c]: parallel-axis theorem to O
    rows = tuple(tuple(a + m * b for a, b in zip(r1, r2)) for r1, r2 in zip(I_c.rows, shift))
    return Inertia(m, m * c, Mat3(rows))


def cross_motion(a: tuple[Vec3, Vec3], b: tuple[Vec3, Vec3]) -> tuple[Vec3, Vec3]:
    """(w₁, v₁) × (w₂, v₂): how motion b changes when carried by motion a.

    Parameters
    ----------
    a : tuple of (Vec3, Vec3)
        The carrying motion (w₁, v₁), rad/s and m/s.
    b : tuple of (Vec3, Vec3)
        The carried motion (w₂, v₂).

    Returns
    -------
    tuple of (Vec3, Vec3)
        (w₁ × w₂, w₁ × v₂ + v₁ × w₂).

    Examples
    --------

    >>> from course_dynamics.core.algebra import Vec3
    >>> spin, slide = (Vec3(0, 0, 1), Vec3(0, 0, 0)), (Vec3(0, 0, 0), Vec3(1, 0, 0))
    >>> cross_motion(spin, slide)   # a slide along x, carried by a spin about z, turns towards y
    (Vec3(0, 0, 0), Vec3(0, 1, 0))
    """
    (w1, v1), (w2, v2) = a, b
    return cross(w1, w2), cross(w1, v2) + cross(v1, w2)


def cross_force(a: tuple[Vec3, Vec3], f: tuple[Vec3, Vec3]) -> tuple[Vec3, Vec3]:
    """(w, v) ``×*`` (n, f): how force f changes when carried by motion a.

    Parameters
    ----------
    a : tuple of (Vec3, Vec3)
        The carrying motion (w, v), rad/s and m/s.
    f : tuple of (Vec3, Vec3)
        The force (n, f): a moment about O, N·m, and a force, N.

    Returns
    -------
    tuple of (Vec3, Vec3)
        (w × n + v × f, w × f).

    Examples
    --------

    >>> from course_dynamics.core.algebra import Vec3
    >>> spin, push = (Vec3(0, 0, 1), Vec3(0, 0, 0)), (Vec3(0, 0, 0), Vec3(1, 0, 0))
    >>> cross_force(spin, push)
    (Vec3(0, 0, 0), Vec3(0, 1, 0))
    """
    (w, v), (n, f_lin) = a, f
    return cross(w, n) + cross(v, f_lin), cross(w, f_lin)


def power(s: tuple[Vec3, Vec3], f: tuple[Vec3, Vec3]):
    """sᵀ f = w·n + v·f: the work rate of force f along motion s (a generalized force for a joint axis).

    Parameters
    ----------
    s : tuple of (Vec3, Vec3)
        A motion (w, v), rad/s and m/s (or a joint's unit motion).
    f : tuple of (Vec3, Vec3)
        A force (n, f), N·m and N.

    Returns
    -------
    float, numpy.ndarray of shape (N,) or sympy.Expr
        w·n + v·f: W (or, for a unit motion, the joint torque, N·m, or force, N).

    Examples
    --------

    >>> from course_dynamics.core.algebra import Vec3
    >>> power((Vec3(0, 0, 1), Vec3(0, 0, 0)), (Vec3(0, 0, 2.5), Vec3(1, 0, 0)))   # a moment of 2.5 N·m about z
    2.5
    """
    return dot(s[0], f[0]) + dot(s[1], f[1])


def add(a: tuple[Vec3, Vec3], b: tuple[Vec3, Vec3]) -> tuple[Vec3, Vec3]:
    """a + b, part by part: the sum of two motions or of two forces.

    Parameters
    ----------
    a : tuple of (Vec3, Vec3)
        A motion or a force.
    b : tuple of (Vec3, Vec3)
        Another of the same.

    Returns
    -------
    tuple of (Vec3, Vec3)
        (a₀ + b₀, a₁ + b₁).

    Examples
    --------

    >>> from course_dynamics.core.algebra import Vec3
    >>> add((Vec3(1, 0, 0), Vec3(0, 0, 0)), (Vec3(0, 1, 0), Vec3(0, 0, 2)))
    (Vec3(1, 1, 0), Vec3(0, 0, 2))
    """
    return a[0] + b[0], a[1] + b[1]


__all__ = ["Inertia", "add", "body_inertias", "cross_force", "cross_motion", "motion_axes", "power"]
