"""The operations the Newton–Euler iterations are written against, exactly as the chapter has them.

:mod:`~course_dynamics.core.newton_euler` writes (6.45)–(6.53) against these, one for each place where the
equations could be written otherwise: the rotation into a child's frame and into a parent's, the cross
product, the acceleration of a point, the angular acceleration and the centre of mass (6.48) uses, the
inertial force (6.49), the inertia each term of (6.50) multiplies and its gyroscopic term, the link's own
moment, the child's force and its moment arm in (6.51)–(6.52), the moment τ is read from (6.53), and the base
acceleration. :data:`EXACT` is the chapter's; a subclass that overrides some of them is another way of writing
the chapter (the grader's slips are such subclasses, :mod:`~course_dynamics.grading.slips`).

===================  =====================================================================
name                 what
===================  =====================================================================
:class:`Operations`  the operations, each taking the number of the equation that asks for it
:data:`EXACT`        the chapter's own set, what every use of the recursion runs by default
===================  =====================================================================
"""
from __future__ import annotations

from .algebra import Mat3, Vec3, cross, point_acceleration
from .kinematics import JointTransforms
from .model import Body, Model


class Operations:
    """The operations the iterations are written against, exactly as the chapter has them.

    Each takes the number of the equation that asks for it (such as "6.47"), so that
    another set of operations may differ in one equation and not in another.
    A subclass that overrides some of them is another way of writing the chapter
    (the grader's slips are such subclasses).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.newton_euler import newton_euler_links
    >>> arm = load_robot("pendulum")
    >>> round(float(newton_euler_links(arm, [0.5], [0.0], [0.0], EXACT).tau[0]), 4)
    4.7032
    """

    def into_child(self, X: JointTransforms, i: int, equation: str):
        """ⁱₚR, the rotation from the parent's frame into frame i.

        Parameters
        ----------
        X : JointTransforms
            The joint transforms at Θ (:func:`~course_dynamics.core.kinematics.joint_transforms`).
        i : int
            The body.
        equation : str
            The equation that asks for it, such as ``"6.47"``.

        Returns
        -------
        Mat3
            ⁱₚR.
        """
        return X.R_T[i]

    def into_parent(self, X: JointTransforms, c: int, equation: str):
        """ⁱ_cR, the rotation from child c's frame into its parent's.

        Parameters
        ----------
        X : JointTransforms
            The joint transforms at Θ (:func:`~course_dynamics.core.kinematics.joint_transforms`).
        c : int
            The child body.
        equation : str
            The equation that asks for it, such as ``"6.47"``.

        Returns
        -------
        Mat3
            ⁱ_cR, i being c's parent.
        """
        return X.R[c]

    def cross(self, a: Vec3, b: Vec3, equation: str) -> Vec3:
        """a × b.

        Parameters
        ----------
        a : Vec3
            The left factor.
        b : Vec3
            The right factor.
        equation : str
            The equation that asks for it, such as ``"6.47"``.

        Returns
        -------
        Vec3
            The cross product.
        """
        return cross(a, b)

    def point_acceleration(self, v_dot: Vec3, omega_dot: Vec3, omega: Vec3, P: Vec3, equation: str) -> Vec3:
        """v̇ + ω̇ × P + ω × (ω × P), the acceleration of a point P of a moving frame (as in (6.47), (6.48)).

        Parameters
        ----------
        v_dot : Vec3
            The frame origin's linear acceleration, m/s².
        omega_dot : Vec3
            The frame's angular acceleration, rad/s².
        omega : Vec3
            The frame's angular velocity, rad/s.
        P : Vec3
            The point, from the frame's origin, m.
        equation : str
            The equation that asks for it, such as ``"6.47"``.

        Returns
        -------
        Vec3
            The point's acceleration, m/s².
        """
        return point_acceleration(v_dot, omega_dot, omega, P)

    def link_angular_acceleration(self, own: Vec3, parent: Vec3, equation: str) -> Vec3:
        """The link's own angular acceleration ⁱ⁺¹ω̇ᵢ₊₁ where an equation asks for it (as (6.48) does); its parent's
        ⁱω̇ᵢ is given so that another set of operations may take that one instead.

        Parameters
        ----------
        own : Vec3
            ⁱ⁺¹ω̇ᵢ₊₁, rad/s².
        parent : Vec3
            ⁱω̇ᵢ, the parent's, in the parent's frame, rad/s² (zero for the base).
        equation : str
            The equation that asks for it, such as ``"6.48"``.

        Returns
        -------
        Vec3
            ``own``.
        """
        return own

    def centre_of_mass(self, model: Model, i: int, equation: str) -> Vec3:
        """ⁱP_Cᵢ, link i's centre of mass in frame i, where (6.48) and (6.52) use it.

        Parameters
        ----------
        model : Model
            The robot.
        i : int
            The body.
        equation : str
            The equation that asks for it, such as ``"6.48"``.

        Returns
        -------
        Vec3
            ⁱP_Cᵢ, m.
        """
        return model.bodies[i].p_com_v

    def inertial_force(self, model: Model, X: JointTransforms, i: int, v_dot_c: Vec3, gravity: Vec3) -> Vec3:
        """ⁱFᵢ = mᵢ ⁱv̇_Cᵢ (6.49): gravity is already in ⁱv̇_Cᵢ, lifted once at the base (:meth:`base_acceleration`).

        Parameters
        ----------
        model : Model
            The robot.
        X : JointTransforms
            The joint transforms at Θ.
        i : int
            The body.
        v_dot_c : Vec3
            ⁱv̇_Cᵢ, m/s².
        gravity : Vec3
            g in the base frame, m/s² (unused here: another set of operations may add it link by link).

        Returns
        -------
        Vec3
            ⁱFᵢ, N.
        """
        return model.bodies[i].mass_s * v_dot_c

    def gyroscopic(self, omega: Vec3, I: Mat3, equation: str) -> Vec3:
        """ω × ᶜI ω, the gyroscopic term of (6.50).

        Parameters
        ----------
        omega : Vec3
            ⁱωᵢ, rad/s.
        I : Mat3
            ᶜI, kg·m².
        equation : str
            The equation that asks for it, such as ``"6.47"``.

        Returns
        -------
        Vec3
            The gyroscopic moment, N·m.
        """
        return self.cross(omega, I @ omega, equation)

    def link_moment(self, model: Model, i: int, out: "OutwardPass", equation: str) -> Vec3:
        """ⁱNᵢ, link i's own inertial moment, where (6.52) adds it.

        Parameters
        ----------
        model : Model
            The robot.
        i : int
            The body.
        out : OutwardPass
            The outward iteration's result.
        equation : str
            The equation that asks for it, ``"6.52"``.

        Returns
        -------
        Vec3
            ⁱNᵢ, N·m.
        """
        return out.N[i]

    def carried_force(self, model: Model, c: int, R: Mat3, f: Vec3, equation: str) -> Vec3:
        """ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁, a child's force carried into frame i, as (6.51) adds it.

        Parameters
        ----------
        model : Model
            The robot.
        c : int
            The child body i+1 whose force is carried.
        R : Mat3
            ⁱᵢ₊₁R, from :meth:`into_parent`.
        f : Vec3
            ⁱ⁺¹fᵢ₊₁, in the child's frame, N.
        equation : str
            The equation that asks for it, ``"6.51"``.

        Returns
        -------
        Vec3
            ⁱfᵢ₊₁, N.
        """
        return R @ f

    def moment_arm(self, P: Vec3, R: Mat3, f: Vec3, equation: str) -> Vec3:
        """ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁, the moment of a child's force about frame i's origin in (6.52).

        Parameters
        ----------
        P : Vec3
            ⁱPᵢ₊₁, the child's origin in frame i, m.
        R : Mat3
            ⁱᵢ₊₁R, from :meth:`into_parent`.
        f : Vec3
            ⁱ⁺¹fᵢ₊₁, the child's force in its own frame, N.
        equation : str
            The equation that asks for it, such as ``"6.52"``.

        Returns
        -------
        Vec3
            The moment, N·m.
        """
        return self.cross(P, R @ f, equation)

    def joint_moment(self, model: Model, i: int, n: list, out: "OutwardPass", equation: str) -> Vec3:
        """ⁱnᵢ, the moment whose component along the joint axis is τᵢ (6.53).

        Parameters
        ----------
        model : Model
            The robot.
        i : int
            The body.
        n : list of Vec3
            ⁱnᵢ of every body done so far (link i's and its descendants'), N·m.
        out : OutwardPass
            The outward iteration's result.
        equation : str
            The equation that asks for it, ``"6.53"``.

        Returns
        -------
        Vec3
            ⁱnᵢ, N·m.
        """
        return n[i]

    def inertia(self, body: Body, term: str = "I ω̇") -> Mat3:
        """ᶜI, the inertia tensor about the centre of mass, in the body's frame (kg·m²), as each term of (6.50)
        multiplies it.

        Parameters
        ----------
        body : Body
            The body.
        term : str, optional
            The term of (6.50) that asks for it: ``"I ω̇"`` or ``"ω × I ω"``.

        Returns
        -------
        Mat3
            ᶜI, kg·m².
        """
        return body.I_com_m

    def at(self, i: int) -> "Operations":
        """The operations link i's equations are written with: these, for every link (another set may differ on
        some links only, as a slip copied into one link's equations does).

        Parameters
        ----------
        i : int
            The body whose equations the iteration is writing.

        Returns
        -------
        Operations
            This set.
        """
        return self

    def base_acceleration(self, gravity: Vec3) -> Vec3:
        """⁰v̇₀ = −g: gravity enters once, as an upward acceleration of the base.

        Parameters
        ----------
        gravity : Vec3
            g in the base frame, m/s².

        Returns
        -------
        Vec3
            ⁰v̇₀, m/s².
        """
        return -gravity


#: The chapter's operations, the default of every iteration.
#: The chapter's operations, what every use of the recursion runs by default.
EXACT = Operations()


__all__ = ["EXACT", "Operations"]
