"""Joint kinds: what each kind of joint does to its body, in one place.

Kinematics (the joint transform), the spatial algorithms (a joint's unit motion)
and point Jacobians ask the kind of the body's joint (:func:`kind_of`) instead of branching on the
type themselves, so a new kind of joint is one class here and its tests. (The
Newton–Euler recursion keeps its own visible revolute/prismatic branch: there
it is Craig's text, (6.45)–(6.50) against (6.35), (6.53) against (6.44).)

==============  =====  ==============================  ===================  ========================
kind            q      ᵖᵢR(q), ᵖPᵢ(q)                  unit motion s        point Jacobian column
==============  =====  ==============================  ===================  ========================
``revolute``    θ rad  R₀ Rot(Ẑ, θ), P                 (Ẑ, Pⱼ × Ẑ)          (Ẑ × (p − Pⱼ), Ẑ)
``continuous``  θ rad  as revolute, without limits     as revolute          as revolute
``prismatic``   d m    R₀, P + d R₀Ẑ                   (0, Ẑ)               (Ẑ, 0)
==============  =====  ==============================  ===================  ========================

R₀ and P are the joint's fixed placement in its parent (the URDF ``<origin>``), Ẑ its
unit axis; s is (angular, linear) in base coordinates about the base origin, Ẑ and
Pⱼ there too (:mod:`course_dynamics.core.spatial`).

>>> KINDS["prismatic"].symbol, KINDS["continuous"].rotates
('d', True)
"""
from __future__ import annotations

from .algebra import Mat3, Vec3, cos_sin, cross, rotation_from_parts

ZERO = Vec3(0, 0, 0)


class Revolute:
    """Turns its body by θ about its axis (rad): the kind of a ``revolute`` and of a ``continuous`` joint.

    Attributes
    ----------
    name : str
        ``"revolute"``.
    symbol : str
        ``"θ"``, the joint variable's symbol.
    latex : str
        The symbol in LaTeX, ``\\theta``.
    rotates : bool
        ``True``: the joint turns its body.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> R, P = Revolute.transform(load_robot("two_link").bodies[1], 0.0)
    >>> list(P)   # the joint's origin in its parent, m
    [0.5, 0.0, 0.0]
    """

    name, symbol, latex, rotates = "revolute", "θ", r"\theta", True

    @staticmethod
    def transform(body, q) -> tuple[Mat3, Vec3]:
        """ᵖᵢR(θ) by Rodrigues' formula on the body's precomputed parts, and the fixed ᵖPᵢ.

        Parameters
        ----------
        body : Body
            The body the joint moves.
        q : float, numpy.ndarray of shape (N,) or sympy.Expr
            The joint's position, θ, rad.

        Returns
        -------
        tuple of (Mat3, Vec3)
            ᵖᵢR, the body's orientation in its parent, and ᵖPᵢ, its origin there (m).
        """
        return rotation_from_parts(body.rotation_parts, *cos_sin(q)), body.P_v

    @staticmethod
    def motion(z: Vec3, P: Vec3) -> tuple[Vec3, Vec3]:
        """(ω, v) of the body for θ̇ = 1: a rotation about the axis through Pⱼ.

        Parameters
        ----------
        z : Vec3
            The joint's unit axis Ẑ, base coordinates.
        P : Vec3
            The joint's origin Pⱼ, base coordinates, m.

        Returns
        -------
        tuple of (Vec3, Vec3)
            (Ẑ, Pⱼ × Ẑ): the angular velocity, rad/s, and the velocity of the point at the base origin, m/s.
        """
        return z, cross(P, z)

    @staticmethod
    def point_column(z: Vec3, point: Vec3, P: Vec3) -> tuple[Vec3, Vec3]:
        """(∂v/∂θ̇, ∂ω/∂θ̇) of a point carried by the joint.

        Parameters
        ----------
        z : Vec3
            The joint's unit axis Ẑ, base coordinates.
        point : Vec3
            The point p, base coordinates, m.
        P : Vec3
            The joint's origin Pⱼ, base coordinates, m.

        Returns
        -------
        tuple of (Vec3, Vec3)
            (Ẑ × (p − Pⱼ), Ẑ): the point's linear velocity, m/s, and the angular velocity, rad/s, per rad/s.
        """
        return cross(z, point - P), z


class Prismatic:
    """Slides its body by d along its axis (m): the kind of a ``prismatic`` joint.

    Attributes
    ----------
    name : str
        ``"prismatic"``.
    symbol : str
        ``"d"``, the joint variable's symbol.
    latex : str
        The symbol in LaTeX, ``d``.
    rotates : bool
        ``False``: the joint slides its body.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> R, P = Prismatic.transform(load_robot("rp_arm").bodies[1], 0.2)   # d₂ = 0.2 m along the axis
    >>> [round(x, 3) for x in P]
    [0.2, 0.0, 0.0]
    """

    name, symbol, latex, rotates = "prismatic", "d", "d", False

    @staticmethod
    def transform(body, q) -> tuple[Mat3, Vec3]:
        """The fixed ᵖᵢR, and ᵖPᵢ moved by d along the axis.

        Parameters
        ----------
        body : Body
            The body the joint moves.
        q : float, numpy.ndarray of shape (N,) or sympy.Expr
            The joint's position, d, m.

        Returns
        -------
        tuple of (Mat3, Vec3)
            ᵖᵢR, the body's orientation in its parent, and ᵖPᵢ, its origin there (m).
        """
        return body.R0_m, body.P_v + q * body.R0_axis_v

    @staticmethod
    def motion(z: Vec3, P: Vec3) -> tuple[Vec3, Vec3]:
        """(ω, v) of the body for ḋ = 1: a translation along the axis.

        Parameters
        ----------
        z : Vec3
            The joint's unit axis Ẑ, base coordinates.
        P : Vec3
            The joint's origin Pⱼ, base coordinates, m.

        Returns
        -------
        tuple of (Vec3, Vec3)
            (0, Ẑ): no angular velocity, and the velocity Ẑ, m/s.
        """
        return ZERO, z

    @staticmethod
    def point_column(z: Vec3, point: Vec3, P: Vec3) -> tuple[Vec3, Vec3]:
        """(∂v/∂ḋ, ∂ω/∂ḋ) of a point carried by the joint.

        Parameters
        ----------
        z : Vec3
            The joint's unit axis Ẑ, base coordinates.
        point : Vec3
            The point p, base coordinates, m.
        P : Vec3
            The joint's origin Pⱼ, base coordinates, m.

        Returns
        -------
        tuple of (Vec3, Vec3)
            (Ẑ, 0): the point's linear velocity per m/s, and no angular velocity.
        """
        return z, ZERO


#: The kind of each URDF joint type the dynamics takes, by type name. ``revolute`` and ``continuous`` are
#: :class:`Revolute`, ``prismatic`` is :class:`Prismatic`.
KINDS: dict[str, type] = {"revolute": Revolute, "continuous": Revolute, "prismatic": Prismatic}


def kind_of(body) -> type:
    """The :data:`KINDS` entry of a body's joint.

    Parameters
    ----------
    body : Body
        The body; its ``joint_type`` names the kind.

    Returns
    -------
    type
        :class:`Revolute` or :class:`Prismatic`.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> [kind_of(body).name for body in load_robot("rp_arm").bodies]
    ['revolute', 'prismatic']
    """
    return KINDS[body.joint_type]


__all__ = ["KINDS", "Prismatic", "Revolute", "kind_of"]
