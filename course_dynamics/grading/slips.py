"""The slips students make in Newton–Euler, made on purpose by the one recursion.

A :class:`Slip` is a set of the operations :mod:`course_dynamics.core.newton_euler`
is written against (:class:`~course_dynamics.core.newton_euler.Operations`) that
makes one mistake in the equations it names and is exact everywhere else. The
grader and the notebooks compare a wrong answer with the recursion run with each
slip (:func:`slips`), so that a mistake is named by the one implementation with
that one mistake made, not by a second copy of the algorithm.

========================  =============================  ================================
code                      the mistake                    equations it can be made in
========================  =============================  ================================
``rotation-transposed``   ᵖᵢR where ⁱₚR belongs          (6.45) (6.46) (6.47) (6.51) (6.52)
``cross-reversed``        b × a for a × b                (6.46) (6.47) (6.48) (6.50) (6.52)
``centripetal-missing``   ω × (ω × P) left out           (6.47) (6.48)
``gyroscopic-missing``    ω × ᶜI ω left out              (6.50)
``inertia-about-origin``  ⁱIᵢ about the frame origin,    (6.50)
                          not ᶜⁱIᵢ about the COM
``moment-arm-missing``    ⁱPᵢ₊₁ × ⁱfᵢ₊₁ left out          (6.52)
``gravity-sign``          ⁰v̇₀ = +g, not −g               ⁰v̇₀
========================  =============================  ================================
"""
from __future__ import annotations

from dataclasses import dataclass

from ..core.algebra import Mat3, Vec3, cross
from ..core.inertia import parallel_axis
from ..core.newton_euler import Operations

#: Each slip's code and the equations of chapter 6 it can be made in (``"base"`` for ⁰v̇₀), as the table above.
SLIP_EQUATIONS = {
    "rotation-transposed": ("6.45", "6.46", "6.47", "6.51", "6.52"),
    "cross-reversed": ("6.46", "6.47", "6.48", "6.50", "6.52"),
    "centripetal-missing": ("6.47", "6.48"),
    "gyroscopic-missing": ("6.50",),
    "inertia-about-origin": ("6.50",),
    "moment-arm-missing": ("6.52",),
    "gravity-sign": ("base",),
}
OUTWARD, INWARD = ("6.45", "6.46", "6.47", "6.48", "6.49", "6.50"), ("6.51", "6.52", "6.53")


@dataclass(frozen=True)
class Slip(Operations):
    """One mistake made on purpose: ``code`` (a key of :data:`SLIP_EQUATIONS`) in ``equations`` (numbers such as
    "6.47", or "base" for ⁰v̇₀); exact everywhere else.

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.newton_euler import newton_euler_links
    >>> arm = load_robot("pendulum")
    >>> round(float(newton_euler_links(arm, [0.5], [0.0], [0.0], Slip("gravity-sign", ("base",))).tau[0]), 4)
    -4.7032

    Parameters
    ----------
    code : str
        The mistake, a key of :data:`SLIP_EQUATIONS`.
    equations : tuple of str
        The equations it is made in, among those :data:`SLIP_EQUATIONS` gives the code.

    Raises
    ------
    ValueError
        If ``code`` is no slip, or ``equations`` are not all equations it can be made in.
    """

    code: str
    equations: tuple[str, ...]

    def __post_init__(self):
        if self.code not in SLIP_EQUATIONS or not set(self.equations) <= set(SLIP_EQUATIONS[self.code]):
            raise ValueError(f"no slip '{self.code}' in {self.equations} (slips: {SLIP_EQUATIONS})")

    def made(self, code: str, equation: str) -> bool:
        """Whether this slip makes mistake ``code`` in ``equation``.

        Parameters
        ----------
        code : str
            A slip's code.
        equation : str
            An equation's number, such as ``"6.47"``, or ``"base"``.

        Returns
        -------
        bool
            True when this is that slip and it is made in that equation.
        """
        return code == self.code and equation in self.equations

    @property
    def where(self) -> str:
        """The equations in words, such as "(6.47) and (6.48)" or "every equation where it appears, …"."""
        every = SLIP_EQUATIONS[self.code]
        if self.equations == ("base",):
            return "the base acceleration ⁰v̇₀"
        if len(every) > 1 and set(self.equations) == set(every):
            return "every equation where it appears, " + _listed(self.equations)
        return _listed(self.equations)

    # The operations, each with this slip's mistake where it is made.

    def into_child(self, X, i, equation):
        """ⁱₚR, the rotation from the parent's frame into frame i; with ``rotation-transposed``, ᵖᵢR.

        Parameters
        ----------
        X : JointTransforms
            The joints' transforms at Θ.
        i : int
            The frame.
        equation : str
            The equation the rotation is used in.

        Returns
        -------
        Mat3
            The rotation.
        """
        return X.R[i] if self.made("rotation-transposed", equation) else X.R_T[i]

    def into_parent(self, X, c, equation):
        """The rotation from child c's frame into its parent's; with ``rotation-transposed``, its transpose.

        Parameters
        ----------
        X : JointTransforms
            The joints' transforms at Θ.
        c : int
            The child's frame.
        equation : str
            The equation the rotation is used in.

        Returns
        -------
        Mat3
            The rotation.
        """
        return X.R_T[c] if self.made("rotation-transposed", equation) else X.R[c]

    def cross(self, a: Vec3, b: Vec3, equation: str) -> Vec3:
        """a × b; with ``cross-reversed``, b × a.

        Parameters
        ----------
        a, b : Vec3
            The factors.
        equation : str
            The equation the product is used in.

        Returns
        -------
        Vec3
            The product.
        """
        return cross(b, a) if self.made("cross-reversed", equation) else cross(a, b)

    def point_acceleration(self, v_dot, omega_dot, omega, P, equation):
        """v̇ + ω̇ × P + ω × (ω × P), the acceleration of a point P of a moving frame; with ``centripetal-missing``
        without ω × (ω × P), with ``cross-reversed`` with its products reversed.

        Parameters
        ----------
        v_dot : Vec3
            The frame origin's acceleration v̇, m/s².
        omega_dot : Vec3
            The frame's angular acceleration ω̇, rad/s².
        omega : Vec3
            The frame's angular velocity ω, rad/s.
        P : Vec3
            The point, in the frame, m.
        equation : str
            The equation the acceleration is used in.

        Returns
        -------
        Vec3
            The point's acceleration, m/s².
        """
        if self.made("centripetal-missing", equation):
            return v_dot + cross(omega_dot, P)
        if self.made("cross-reversed", equation):
            return v_dot + cross(P, omega_dot) + cross(cross(P, omega), omega)
        return super().point_acceleration(v_dot, omega_dot, omega, P, equation)

    def gyroscopic(self, omega, I, equation):
        """ω × ᶜI ω, the gyroscopic term of (6.50); zero with ``gyroscopic-missing``.

        Parameters
        ----------
        omega : Vec3
            The link's angular velocity ω, rad/s.
        I : Mat3
            Its inertia tensor ᶜI, kg·m².
        equation : str
            The equation the term is used in.

        Returns
        -------
        Vec3
            The term, N·m.
        """
        if self.made("gyroscopic-missing", equation):
            return Vec3(0, 0, 0)
        return super().gyroscopic(omega, I, equation)

    def moment_arm(self, P, f, equation):
        """ⁱPᵢ₊₁ × ⁱfᵢ₊₁, the moment of a child's force about frame i's origin in (6.52); zero with
        ``moment-arm-missing``.

        Parameters
        ----------
        P : Vec3
            The child's origin ⁱPᵢ₊₁, m.
        f : Vec3
            The child's force ⁱfᵢ₊₁, N.
        equation : str
            The equation the moment is used in.

        Returns
        -------
        Vec3
            The moment, N·m.
        """
        if self.made("moment-arm-missing", equation):
            return Vec3(0, 0, 0)
        return super().moment_arm(P, f, equation)

    def inertia(self, body):
        """ᶜI, the inertia tensor about the centre of mass; with ``inertia-about-origin``, ⁱI about the frame origin.

        Parameters
        ----------
        body : Body
            The link.

        Returns
        -------
        Mat3
            The inertia tensor in the body's frame, kg·m².
        """
        if self.made("inertia-about-origin", "6.50"):
            return Mat3.of(parallel_axis(body.I_com, body.mass, body.p_com))
        return super().inertia(body)

    def base_acceleration(self, gravity):
        """⁰v̇₀ = −g; with ``gravity-sign``, +g.

        Parameters
        ----------
        gravity : Vec3
            The gravity vector g in the base frame, m/s².

        Returns
        -------
        Vec3
            The base's acceleration ⁰v̇₀, m/s².
        """
        return gravity if self.made("gravity-sign", "base") else super().base_acceleration(gravity)


def _listed(equations) -> str:
    named = [f"({e})" for e in equations]
    return named[0] if len(named) == 1 else ", ".join(named[:-1]) + " and " + named[-1]


def slips() -> tuple[Slip, ...]:
    """Every slip the diagnosis tries: each mistake everywhere it can be made, in the outward or the inward
    iteration only, and in each equation alone.

    >>> [s.equations for s in slips() if s.code == "centripetal-missing"]
    [('6.47', '6.48'), ('6.47',), ('6.48',)]

    Returns
    -------
    tuple of Slip
        The slips, each once.
    """
    made = []
    for code, every in SLIP_EQUATIONS.items():
        groups = [every] + [tuple(e for e in every if e in part) for part in (OUTWARD, INWARD)] + [(e,) for e in every]
        for group in groups:
            if group and Slip(code, group) not in made:
                made.append(Slip(code, group))
    return tuple(made)


__all__ = ["SLIP_EQUATIONS", "Slip", "slips"]
