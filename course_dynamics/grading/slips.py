"""The slips students make in Newton–Euler, made on purpose by the one recursion.

A :class:`Slip` is a set of the operations :mod:`course_dynamics.core.newton_euler`
is written against (:class:`~course_dynamics.core.operations.Operations`) that
makes one mistake in the equations it names and is exact everywhere else. The
grader and the notebooks compare a wrong answer with the recursion run with each
slip (:func:`slips`), so that a mistake is named by the one implementation with
that one mistake made, not by a second copy of the algorithm.

========================  =============================  ================================
code                      the mistake                    equations it can be made in
========================  =============================  ================================
``gravity-missing``       ⁰v̇₀ = 0: gravity left out      ⁰v̇₀
``gravity-sign``          ⁰v̇₀ = +g, not −g               ⁰v̇₀
``rotation-transposed``   ᵖᵢR where ⁱₚR belongs          (6.45) (6.46) (6.47) (6.51) (6.52)
``rotation-identity``     a rotation read as the         (6.45) (6.46) (6.47) (6.51) (6.52)
                          identity (left out)
``cross-reversed``        b × a for a × b                (6.46) (6.47) (6.48) (6.50) (6.52)
``centripetal-missing``   ω × (ω × P) left out           (6.47) (6.48)
``gyroscopic-missing``    ω × ᶜI ω left out              (6.50)
``inertia-about-origin``  ⁱIᵢ about the frame origin,    (6.50)
                          not ᶜⁱIᵢ about the COM
``moment-arm-missing``    ⁱPᵢ₊₁ × ⁱfᵢ₊₁ left out          (6.52)
``first-moment-missing``  ⁱP_Cᵢ × ⁱFᵢ left out           (6.52)
``gravity-frame``         gravity added link by link     (6.49), ⁰v̇₀ = 0
                          with ⁰g not rotated into
                          frame i, or rotated by ⁰ᵢR
``com-wrong-link``        link i−1's ⁱ⁻¹P_Cᵢ₋₁ for        (6.48) (6.52)
                          ⁱP_Cᵢ (``Pc[i - 1]``)
``tau-wrong-moment``      τᵢ = ⁱNᵢᵀ Ẑᵢ, the inertial       (6.53)
                          moment (the notes' words at
                          (6.43)), or the child's nᵢ₊₁
``notes-6.48``            (6.48) as printed: the           (6.48)
                          parent's ω̇ᵢ, or ⁱ⁺¹Pᵢ₊₁ = 0
``notes-6.50``            (6.50) as printed: ⁱIᵢ about     (6.50)
                          the origin in ω × I ω only
``notes-6.51``            (6.51) as printed: ⁱIᵢ₊₁        (6.51)
                          ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁ + ⁱFᵢ, link
                          i+1's tensor (``I[i + 1]``)
``notes-6.52``            (6.52) as printed: ⁱNᵢ₊₁,       (6.52)
                          ⁱPᵢ × ⁱFᵢ, ⁱ⁺¹fᵢ₊₁ unrotated;
                          all three, or one of them
========================  =============================  ================================

A slip with ``variant`` (``gravity-frame``, ``tau-wrong-moment``, ``notes-6.48``,
``notes-6.52``) is made in one of the ways :data:`SLIP_VARIANTS` lists. The
``notes-…`` slips are the lecture notes' misprints (``reference/errata.md``)
copied into code: the notes' (6.45)–(6.47) print the rotation the wrong way
round, which is ``rotation-transposed`` in those equations; the worked
example's ¹F₁ = m₁ ¹v̇₁ and ¹N₁ are ``notes-6.48`` (ⁱ⁺¹Pᵢ₊₁ = 0) and
``notes-6.50`` on link 1; its ²v̇_C₂ with ¹ω̇₁ is ``notes-6.48`` with the
parent's ω̇ on link 2, and its ²v̇₂ = ²R² ¹v̇_C₁ is ``rotation-identity`` in
(6.47) on link 2. A slip with ``links`` is made in those links' equations only
(:meth:`Slip.at`), as a printed equation copied into one place is:
:func:`slips` makes the printed equations' slips (:data:`PER_LINK`) on each
link alone too.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..core.algebra import Mat3, Vec3, cross
from ..core.inertia import parallel_axis
from ..core.operations import EXACT, Operations

ZERO = Vec3(0, 0, 0)
#: The identity rotation, as ``rotation-identity`` reads a rotation.
IDENTITY = Mat3(((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)))

#: Each slip's code and the equations of chapter 6 it can be made in (``"base"`` for ⁰v̇₀), as the table above.
#: The simpler mistakes come first: where two slips give the same answers on a robot, the first is named
#: (:func:`~course_dynamics.grading.mistakes.mistaken_terms`).
SLIP_EQUATIONS = {
    "gravity-missing": ("base",),
    "gravity-sign": ("base",),
    "rotation-transposed": ("6.45", "6.46", "6.47", "6.51", "6.52"),
    "rotation-identity": ("6.45", "6.46", "6.47", "6.51", "6.52"),
    "cross-reversed": ("6.46", "6.47", "6.48", "6.50", "6.52"),
    "centripetal-missing": ("6.47", "6.48"),
    "gyroscopic-missing": ("6.50",),
    "inertia-about-origin": ("6.50",),
    "moment-arm-missing": ("6.52",),
    "first-moment-missing": ("6.52",),
    "gravity-frame": ("6.49",),
    "com-wrong-link": ("6.48", "6.52"),
    "tau-wrong-moment": ("6.53",),
    "notes-6.48": ("6.48",),
    "notes-6.50": ("6.50",),
    "notes-6.51": ("6.51",),
    "notes-6.52": ("6.52",),
}
#: The ways a slip with variants is made, code → variant → its words.
SLIP_VARIANTS = {
    "gravity-frame": {"unrotated": "⁰g used in frame i as it is, not rotated into it by ⁱ₀R = ⁰ᵢRᵀ",
                      "rotated": "⁰g rotated by ⁰ᵢR, not by its transpose ⁱ₀R"},
    "tau-wrong-moment": {"N": "τᵢ read from ⁱNᵢ, the inertial moment, not from ⁱnᵢ",
                   "child": "τᵢ read from the child's ⁱ⁺¹nᵢ₊₁, not from ⁱnᵢ"},
    "notes-6.48": {"origin": "with ⁱ⁺¹Pᵢ₊₁ = 0 for ⁱ⁺¹P_Cᵢ₊₁", "parent": "with the parent's ⁱω̇ᵢ for ⁱ⁺¹ω̇ᵢ₊₁"},
    "notes-6.52": {"": "all three misprints: ⁱNᵢ₊₁, ⁱPᵢ × ⁱFᵢ with ⁱPᵢ = 0, and ⁱ⁺¹R^{i+1} = 1",
                   "N": "one of its misprints: the child's ⁱ⁺¹Nᵢ₊₁ for ⁱNᵢ",
                   "PxF": "one of its misprints: ⁱPᵢ × ⁱFᵢ with Pᵢ the joint's offset (the code's P[i]) for "
                          "ⁱP_Cᵢ × ⁱFᵢ",
                   "identity": "one of its misprints: ⁱ⁺¹R^{i+1} = 1, the child's force unrotated in its moment"},
}
#: The slips of equations as the notes print them, which a student copies into one link's equations as readily as
#: into every link's (the worked example's are on one link): :func:`slips` makes these on each link alone too.
PER_LINK = ("rotation-identity", "notes-6.48", "notes-6.50", "notes-6.51", "notes-6.52")
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
    variant : str, optional
        How it is made, a key of :data:`SLIP_VARIANTS` for the code (for the codes that have variants).
    links : tuple of int, optional
        The bodies (0 for link 1) whose equations it is made in; every link's when empty.

    Raises
    ------
    ValueError
        If ``code`` is no slip, ``equations`` are not all equations it can be made in, ``variant`` is not one
        of the code's, or a link is negative.
    """

    code: str
    equations: tuple[str, ...]
    variant: str = ""
    links: tuple[int, ...] = ()

    def __post_init__(self):
        if self.code not in SLIP_EQUATIONS or not set(self.equations) <= set(SLIP_EQUATIONS[self.code]):
            raise ValueError(f"no slip '{self.code}' in {self.equations} (slips: {SLIP_EQUATIONS})")
        if self.variant not in SLIP_VARIANTS.get(self.code, {"": ""}):
            raise ValueError(f"slip '{self.code}' has no variant '{self.variant}' (variants: {SLIP_VARIANTS})")
        if any(i < 0 for i in self.links):
            raise ValueError(f"slip '{self.code}' on links {self.links}: bodies count from 0")

    def at(self, i: int) -> Operations:
        """The operations link i's equations are written with: this slip on its links, the chapter's elsewhere.

        Parameters
        ----------
        i : int
            The body.

        Returns
        -------
        Operations
            This slip, or :data:`~course_dynamics.core.operations.EXACT`.
        """
        return self if not self.links or i in self.links else EXACT

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
        how = f" ({SLIP_VARIANTS[self.code][self.variant]})" if self.code in SLIP_VARIANTS else ""
        links = "" if not self.links else " on link" + ("s " if len(self.links) > 1 else " ") + \
            _listed([str(i + 1) for i in self.links], "") + " only"
        if self.equations == ("base",):
            return "the base acceleration ⁰v̇₀"
        if len(every) > 1 and set(self.equations) == set(every):
            return "every equation where it appears, " + _listed(self.equations) + how + links
        return _listed(self.equations) + how + links

    # The operations, each with this slip's mistake where it is made.

    def into_child(self, X, i, equation):
        """ⁱₚR, the rotation from the parent's frame into frame i; with ``rotation-transposed``, ᵖᵢR; with
        ``rotation-identity``, the identity.

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
        if self.made("rotation-identity", equation):
            return IDENTITY
        return X.R[i] if self.made("rotation-transposed", equation) else X.R_T[i]

    def into_parent(self, X, c, equation):
        """The rotation from child c's frame into its parent's; with ``rotation-transposed``, its transpose; with
        ``rotation-identity``, the identity.

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
        if self.made("rotation-identity", equation):
            return IDENTITY
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
            return ZERO
        return super().gyroscopic(omega, I, equation)

    def moment_arm(self, P, R, f, equation):
        """ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁, the moment of a child's force about frame i's origin in (6.52); zero with
        ``moment-arm-missing``; with ``notes-6.52`` (all three misprints, or ``identity``) the force left in the
        child's frame (ⁱ⁺¹R^{i+1} read as the identity).

        Parameters
        ----------
        P : Vec3
            The child's origin ⁱPᵢ₊₁, m.
        R : Mat3
            ⁱᵢ₊₁R.
        f : Vec3
            The child's force ⁱ⁺¹fᵢ₊₁ in its own frame, N.
        equation : str
            The equation the moment is used in.

        Returns
        -------
        Vec3
            The moment, N·m.
        """
        if self.made("moment-arm-missing", equation):
            return ZERO
        if self.made("notes-6.52", equation) and self.variant in ("", "identity"):
            return cross(P, f)
        return super().moment_arm(P, R, f, equation)

    def inertia(self, body, term="I ω̇"):
        """ᶜI, the inertia tensor about the centre of mass; with ``inertia-about-origin``, ⁱI about the frame origin;
        with ``notes-6.50`` that one in the term ω × I ω only.

        Parameters
        ----------
        body : Body
            The link.
        term : str, optional
            The term of (6.50) that asks for it: ``"I ω̇"`` or ``"ω × I ω"``.

        Returns
        -------
        Mat3
            The inertia tensor in the body's frame, kg·m².
        """
        if self.made("inertia-about-origin", "6.50") or (self.made("notes-6.50", "6.50") and term == "ω × I ω"):
            return Mat3.of(parallel_axis(body.I_com, body.mass, body.p_com))
        return super().inertia(body, term)

    def base_acceleration(self, gravity):
        """⁰v̇₀ = −g; with ``gravity-sign``, +g; with ``gravity-missing`` (and ``gravity-frame``, which adds it link
        by link instead), 0.

        Parameters
        ----------
        gravity : Vec3
            The gravity vector g in the base frame, m/s².

        Returns
        -------
        Vec3
            The base's acceleration ⁰v̇₀, m/s².
        """
        if self.code == "gravity-frame" or self.made("gravity-missing", "base"):
            return ZERO  # gravity-frame adds it link by link instead (:meth:`inertial_force`)
        return gravity if self.made("gravity-sign", "base") else super().base_acceleration(gravity)

    def link_angular_acceleration(self, own, parent, equation):
        """ⁱ⁺¹ω̇ᵢ₊₁ in (6.48); with ``notes-6.48`` (variant ``parent``), the parent's ⁱω̇ᵢ as the notes print it.

        Parameters
        ----------
        own : Vec3
            ⁱ⁺¹ω̇ᵢ₊₁, rad/s².
        parent : Vec3
            ⁱω̇ᵢ, in the parent's frame, rad/s².
        equation : str
            The equation it is used in.

        Returns
        -------
        Vec3
            The angular acceleration used, rad/s².
        """
        return parent if self.made("notes-6.48", equation) and self.variant == "parent" else own

    def centre_of_mass(self, model, i, equation):
        """ⁱP_Cᵢ; with ``com-wrong-link`` link i−1's (``Pc[i - 1]``: link 1 takes the last link's); with
        ``notes-6.48`` (variant ``origin``) in (6.48), ``notes-6.52`` (all three misprints) and
        ``first-moment-missing`` in (6.52), the frame origin ⁱPᵢ = 0 the notes print; with ``notes-6.52``'s
        ``PxF``, the joint's offset ᵖPᵢ that a code's ``P[i]`` holds.

        Parameters
        ----------
        model : Model
            The robot.
        i : int
            The body.
        equation : str
            The equation it is used in.

        Returns
        -------
        Vec3
            The centre of mass used, m.
        """
        if self.made("com-wrong-link", equation):
            return model.bodies[i - 1].p_com_v
        if self.made("notes-6.52", equation) and self.variant == "PxF":
            return model.bodies[i].P_v
        printed_origin = (self.made("notes-6.48", equation) and self.variant == "origin") or (
            self.made("notes-6.52", equation) and not self.variant)
        if printed_origin or self.made("first-moment-missing", equation):
            return ZERO
        return super().centre_of_mass(model, i, equation)

    def inertial_force(self, model, X, i, v_dot_c, gravity):
        """ⁱFᵢ = mᵢ ⁱv̇_Cᵢ; with ``gravity-frame``, mᵢ (ⁱv̇_Cᵢ − g) with the base not lifted and g in the wrong frame.

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
            ⁰g, m/s².

        Returns
        -------
        Vec3
            ⁱFᵢ, N.
        """
        if not self.made("gravity-frame", "6.49"):
            return super().inertial_force(model, X, i, v_dot_c, gravity)
        g = gravity
        if self.variant == "rotated":
            R0, k = X.R[i], model.bodies[i].parent
            while k >= 0:  # ⁰ᵢR = ⁰₁R ¹₂R … ⁱ⁻¹ᵢR
                R0, k = X.R[k] @ R0, model.bodies[k].parent
            g = R0 @ gravity
        return model.bodies[i].mass_s * (v_dot_c - g)

    def link_moment(self, model, i, out, equation):
        """ⁱNᵢ in (6.52); with ``notes-6.52`` (all three misprints, or ``N``), the children's ⁱ⁺¹Nᵢ₊₁ as printed (in
        their own frames; none at the tip).

        Parameters
        ----------
        model : Model
            The robot.
        i : int
            The body.
        out : OutwardPass
            The outward iteration's result.
        equation : str
            The equation it is used in.

        Returns
        -------
        Vec3
            The moment used, N·m.
        """
        if self.made("notes-6.52", equation) and self.variant in ("", "N"):
            total = ZERO
            for c in model.children[i]:
                total = total + out.N[c]
            return total
        return super().link_moment(model, i, out, equation)

    def carried_force(self, model, c, R, f, equation):
        """ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁ in (6.51); with ``notes-6.51``, times the inertia tensor ⁱIᵢ₊₁ the notes print before it:
        link i+1's tensor as given, ᶜIᵢ₊₁ (a code's ``I[i + 1]``).

        Parameters
        ----------
        model : Model
            The robot.
        c : int
            The child body i+1.
        R : Mat3
            ⁱᵢ₊₁R.
        f : Vec3
            ⁱ⁺¹fᵢ₊₁, N.
        equation : str
            The equation it is used in.

        Returns
        -------
        Vec3
            The force added, as the slip has it.
        """
        if self.made("notes-6.51", equation):
            return model.bodies[c].I_com_m @ (R @ f)
        return super().carried_force(model, c, R, f, equation)

    def joint_moment(self, model, i, n, out, equation):
        """ⁱnᵢ, read for τᵢ (6.53); with ``tau-wrong-moment``, ⁱNᵢ (variant ``N``) or the child's ⁱ⁺¹nᵢ₊₁ (``child``).

        Parameters
        ----------
        model : Model
            The robot.
        i : int
            The body.
        n : list of Vec3
            ⁱnᵢ of the bodies done so far, N·m.
        out : OutwardPass
            The outward iteration's result.
        equation : str
            The equation it is used in.

        Returns
        -------
        Vec3
            The moment read, N·m.
        """
        if not self.made("tau-wrong-moment", equation):
            return super().joint_moment(model, i, n, out, equation)
        if self.variant == "N":
            return out.N[i]
        total = ZERO
        for c in model.children[i]:
            total = total + n[c]  # as stored, in the child's frame: n[i + 1] @ z
        return total


def _listed(items, brackets: str = "()") -> str:
    named = [f"{brackets[:1]}{e}{brackets[1:]}" for e in items]
    return named[0] if len(named) == 1 else ", ".join(named[:-1]) + " and " + named[-1]


def slips(bodies: int = 1) -> tuple[Slip, ...]:
    """Every slip the diagnosis tries: each mistake everywhere it can be made, in the outward or the inward
    iteration only, and in each equation alone; on a robot of two or more bodies, the printed equations' slips
    (:data:`PER_LINK`) in each equation alone on each link alone too.

    >>> [s.equations for s in slips() if s.code == "centripetal-missing"]
    [('6.47', '6.48'), ('6.47',), ('6.48',)]
    >>> [(s.variant, s.links) for s in slips(2) if s.code == "notes-6.48"][-2:]
    [('origin', (1,)), ('parent', (1,))]

    Parameters
    ----------
    bodies : int, optional
        The robot's number of bodies.

    Returns
    -------
    tuple of Slip
        The slips, each once, the whole robot's before one link's.
    """
    made = []
    for code, every in SLIP_EQUATIONS.items():
        groups = [every] + [tuple(e for e in every if e in part) for part in (OUTWARD, INWARD)] + [(e,) for e in every]
        for group in groups:
            for variant in SLIP_VARIANTS.get(code, {"": ""}):
                if group and Slip(code, group, variant) not in made:
                    made.append(Slip(code, group, variant))
    if bodies > 1:
        for code in PER_LINK:
            for link in range(bodies):
                for equation in SLIP_EQUATIONS[code]:
                    made += [Slip(code, (equation,), variant, (link,)) for variant in SLIP_VARIANTS.get(code, {"": ""})]
    return tuple(made)


__all__ = ["IDENTITY", "PER_LINK", "SLIP_EQUATIONS", "SLIP_VARIANTS", "Slip", "slips"]
