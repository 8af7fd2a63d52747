"""Craig's recursive Newton–Euler dynamics, eqs. (6.45)–(6.53); prismatic joints by (6.35) and (6.44).

Notation (every vector is expressed in the frame of the link it belongs to;
i is a body, p its parent, frames as in :mod:`course_dynamics.core.model`):

=================  ===========  ===============================================
code               Craig        meaning (unit)
=================  ===========  ===============================================
``R[i]``           ᵖᵢR          orientation of frame i in its parent at Θ
``P[i]``           ᵖPᵢ          origin of frame i in its parent at Θ (m)
``omega[i]``       ⁱωᵢ          angular velocity of link i (rad/s)
``omega_dot[i]``   ⁱω̇ᵢ          angular acceleration (rad/s²)
``v_dot[i]``       ⁱv̇ᵢ          linear acceleration of the origin of frame i (m/s²),
                                classical (not spatial), including the −g base lift
``v_dot_c[i]``     ⁱv̇_Cᵢ        linear acceleration of the centre of mass (m/s²)
``F[i]``, ``N[i]`` ⁱFᵢ, ⁱNᵢ     inertial force (N) and moment (N·m) at the COM
``f[i]``, ``n[i]`` ⁱfᵢ, ⁱnᵢ     force and moment exerted on link i by its parent
``tau[i]``         τᵢ           joint torque (N·m) or force (N, prismatic)
``z``              ⁱẐᵢ          the joint axis (any unit vector, not only z)
=================  ===========  ===============================================

For a tree, "the child i+1" of Craig's chain becomes "every child c of i",
and "link i" of the outward iteration follows its parent p rather than i−1.
The lecture notes print several of these equations with wrong frames or
indices; the lines below are the corrected forms (reference/errata.md).

The same functions run on one state (floats), a batch (arrays of shape (N,)
per joint) and sympy symbols: see :mod:`course_dynamics.core.algebra`.

A :class:`Slip` makes one of the mistakes students make, on purpose, in the
equations it names: the grader and the notebooks compare a wrong answer with
this recursion run with each slip (:func:`slips`), so that a mistake is named
by the one implementation with that one mistake made, not by a second copy.

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

import numpy as np

from .algebra import Mat3, Vec3, cross, dot, point_acceleration
from .inertia import parallel_axis
from .kinematics import JointTransforms, joint_transforms
from .model import Model
from .state import as_state, entries, layout_of


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
class Slip:
    """One mistake made on purpose: ``code`` (a key of :data:`SLIP_EQUATIONS`) in ``equations`` (numbers such as
    "6.47", or "base" for ⁰v̇₀). The empty slip :data:`EXACT` makes none.

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("pendulum")
    >>> round(float(newton_euler_links(arm, [0.5], [0.0], [0.0], Slip("gravity-sign", ("base",))).tau[0]), 4)
    -4.7032
    """

    code: str = ""
    equations: tuple[str, ...] = ()

    def __post_init__(self):
        if self.code and (self.code not in SLIP_EQUATIONS or not set(self.equations) <= set(SLIP_EQUATIONS[self.code])):
            raise ValueError(f"no slip '{self.code}' in {self.equations} (slips: {SLIP_EQUATIONS})")

    def made(self, code: str, equation: str) -> bool:
        """Whether this slip makes mistake ``code`` in ``equation``."""
        return code == self.code and equation in self.equations

    @property
    def where(self) -> str:
        """The equations in words: "(6.47) and (6.48)", "the outward iteration", …"""
        every = SLIP_EQUATIONS[self.code]
        if self.equations == ("base",):
            return "the base acceleration ⁰v̇₀"
        if len(every) > 1 and set(self.equations) == set(every):
            return "every equation where it appears, " + _listed(self.equations)
        return _listed(self.equations)


def _listed(equations) -> str:
    named = [f"({e})" for e in equations]
    return named[0] if len(named) == 1 else ", ".join(named[:-1]) + " and " + named[-1]


EXACT = Slip()


def slips() -> tuple[Slip, ...]:
    """Every slip the diagnosis tries: each mistake everywhere it can be made, in the outward or the inward
    iteration only, and in each equation alone.

    >>> [s.equations for s in slips() if s.code == "centripetal-missing"]
    [('6.47', '6.48'), ('6.47',), ('6.48',)]
    """
    made = []
    for code, every in SLIP_EQUATIONS.items():
        groups = [every] + [tuple(e for e in every if e in part) for part in (OUTWARD, INWARD)] + [(e,) for e in every]
        for group in groups:
            if group and Slip(code, group) not in made:
                made.append(Slip(code, group))
    return tuple(made)


def _rotation(X: JointTransforms, i: int, slip: Slip, equation: str):
    """ⁱₚR, the rotation from the parent's frame into frame i; its transpose ᵖᵢR where the slip says so."""
    return X.R[i] if slip.made("rotation-transposed", equation) else X.R_T[i]


def _into_parent(X: JointTransforms, c: int, slip: Slip, equation: str):
    """ⁱ_cR, the rotation from child c's frame into its parent's; its transpose where the slip says so."""
    return X.R_T[c] if slip.made("rotation-transposed", equation) else X.R[c]


def _cross(a: Vec3, b: Vec3, slip: Slip, equation: str) -> Vec3:
    """a × b; b × a where the slip reverses it."""
    return cross(b, a) if slip.made("cross-reversed", equation) else cross(a, b)


def _point(v_dot: Vec3, omega_dot: Vec3, omega: Vec3, P: Vec3, slip: Slip, equation: str) -> Vec3:
    """(6.12), v̇ + ω̇ × P + ω × (ω × P), with the slip's reversed cross products or missing centripetal term."""
    if slip.made("centripetal-missing", equation):
        return v_dot + cross(omega_dot, P)
    if slip.made("cross-reversed", equation):
        return v_dot + cross(P, omega_dot) + cross(cross(P, omega), omega)
    return point_acceleration(v_dot, omega_dot, omega, P)


def _inertia(body, slip: Slip):
    """ᶜI, the inertia about the centre of mass; about the frame origin (parallel axis) where the slip says so."""
    if slip.made("inertia-about-origin", "6.50"):
        return Mat3.of(parallel_axis(body.I_com, body.mass, body.p_com))
    return body.I_com_m


@dataclass(frozen=True)
class OutwardPass:
    """Result of the outward iteration: per-body kinematics and inertial loads.

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


def outward_iteration(model: Model, X: JointTransforms, theta_dot: list, theta_ddot: list, gravity: Vec3,
                      slip: Slip = EXACT) -> OutwardPass:
    """Link velocities, accelerations and inertial loads, base to tips (with ``slip``'s mistake, if any).

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("two_link")
    >>> X = joint_transforms(arm, [0.0, 0.5])
    >>> out = outward_iteration(arm, X, [0.0, 0.0], [0.0, 0.0], arm.gravity_v)
    >>> [round(c, 6) for c in out.v_dot[0]]                         # ⁰v̇₀ = −g: the base accelerates upward
    [0.0, 9.81, 0.0]
    """
    zero = Vec3(0, 0, 0)
    base_v_dot = gravity if slip.made("gravity-sign", "base") else -gravity  # ⁰v̇₀ = −g: gravity lifts the base
    omega, omega_dot, v_dot, v_dot_c, F, N = [], [], [], [], [], []
    for i, body in enumerate(model.bodies):
        p = body.parent
        omega_p, omega_dot_p, v_dot_p = (zero, zero, base_v_dot) if p < 0 else (omega[p], omega_dot[p], v_dot[p])
        P_i, z = X.P[i], body.axis_v
        qd, qdd = theta_dot[i], theta_ddot[i]
        R_45, R_46, R_47 = (_rotation(X, i, slip, e) for e in ("6.45", "6.46", "6.47"))  # ⁱₚR
        v_dot_i = R_47 @ _point(v_dot_p, omega_dot_p, omega_p, P_i, slip, "6.47")  # (6.47)
        omega_in_i = R_45 @ omega_p  # ⁱₚR ᵖωₚ
        omega_in_46 = omega_in_i if R_46 is R_45 else R_46 @ omega_p
        if body.is_prismatic:
            w = omega_in_i  # a prismatic joint adds no rotation (unnumbered in the notes; (6.33) in Craig)
            w_dot = R_46 @ omega_dot_p
            v_dot_i = v_dot_i + cross(2 * w, qd * z) + qdd * z  # (6.35)
        else:
            w = omega_in_i + qd * z  # (6.45)
            w_dot = R_46 @ omega_dot_p + _cross(omega_in_46, qd * z, slip, "6.46") + qdd * z  # (6.46)
        v_dot_com = _point(v_dot_i, w_dot, w, body.p_com_v, slip, "6.48")  # (6.48)
        I = _inertia(body, slip)
        omega.append(w)
        omega_dot.append(w_dot)
        v_dot.append(v_dot_i)
        v_dot_c.append(v_dot_com)
        F.append(body.mass_s * v_dot_com)  # (6.49)
        gyroscopic = zero if slip.made("gyroscopic-missing", "6.50") else _cross(w, I @ w, slip, "6.50")
        N.append(I @ w_dot + gyroscopic)  # (6.50)
    return OutwardPass(omega, omega_dot, v_dot, v_dot_c, F, N)


def inward_iteration(model: Model, X: JointTransforms, out: OutwardPass, slip: Slip = EXACT) -> InwardPass:
    """Joint forces, moments and torques, tips to base (with ``slip``'s mistake, if any).

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("two_link")
    >>> X = joint_transforms(arm, [0.0, 0.5])
    >>> back = inward_iteration(arm, X, outward_iteration(arm, X, [1.0, 0.0], [0.0, 0.0], arm.gravity_v))
    >>> [round(t, 6) for t in back.tau], len(back.f)                # τᵢ = ⁱnᵢᵀ ⁱẐᵢ (6.53)
    ([18.158634, 3.539519], 2)
    """
    n_bodies, zero = model.n, Vec3(0, 0, 0)
    f, n, tau = [None] * n_bodies, [None] * n_bodies, [None] * n_bodies
    for i in reversed(range(n_bodies)):
        body = model.bodies[i]
        f_i = out.F[i]  # (6.51), children added below
        n_i = out.N[i] + _cross(body.p_com_v, out.F[i], slip, "6.52")  # (6.52), children added below
        for c in model.children[i]:
            R_51, R_52 = _into_parent(X, c, slip, "6.51"), _into_parent(X, c, slip, "6.52")  # ⁱ_cR
            f_c = R_51 @ f[c]  # ⁱ_cR ᶜf_c
            f_i = f_i + f_c  # (6.51)
            f_c = f_c if R_52 is R_51 else R_52 @ f[c]
            arm = zero if slip.made("moment-arm-missing", "6.52") else _cross(X.P[c], f_c, slip, "6.52")
            n_i = n_i + R_52 @ n[c] + arm  # (6.52)
        f[i], n[i] = f_i, n_i
        tau[i] = dot(f_i, body.axis_v) if body.is_prismatic else dot(n_i, body.axis_v)  # (6.44) / (6.53)
    return InwardPass(f, n, tau)


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
    q, qd, qdd : array_like, shape (n,) or (N, n)
        Θ (rad or m), Θ̇ (rad/s or m/s), Θ̈ (rad/s² or m/s²), joints in
        ``model.joint_names`` order; numpy object arrays of sympy expressions
        give symbolic torques. Gravity is ``model.gravity`` (``model.with_gravity(g)`` changes it).

    Returns
    -------
    tau : ndarray, shape (n,) or (N, n)
        Joint torques (N·m) and prismatic forces (N).

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

    Vectors have shape (n, 3) for one state or (N, n, 3) for a batch; each is
    expressed in its own link's frame (Craig's ⁱ(·)ᵢ). ``tau`` has shape (n,)
    or (N, n).

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


def newton_euler_links(model: Model, q, qd, qdd, slip: Slip = EXACT) -> LinkQuantities:
    """The outward and inward iterations with every per-link quantity kept (with ``slip``'s mistake, if any).

    >>> from course_dynamics import load_robot
    >>> links = newton_euler_links(load_robot("two_link"), [0.0, 0.5], [1.0, 0.0], [0.0, 0.0])
    >>> links.omega.shape, links.joints, np.round(links.tau, 6)
    ((2, 3), ('theta1', 'theta2'), array([18.158634,  3.539519]))
    """
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    layout = layout_of(q, qd, qdd)
    X = joint_transforms(model, entries(q))
    out = outward_iteration(model, X, entries(qd), entries(qdd), model.gravity_v, slip)
    back = inward_iteration(model, X, out, slip)

    def per_link(vectors):
        return layout.assemble([tuple(v) for v in vectors], (model.n, 3))

    return LinkQuantities(
        joints=model.joint_names,
        omega=per_link(out.omega), omega_dot=per_link(out.omega_dot), v_dot=per_link(out.v_dot),
        v_dot_c=per_link(out.v_dot_c), F=per_link(out.F), N=per_link(out.N),
        f=per_link(back.f), n=per_link(back.n), tau=layout.assemble(back.tau, (model.n,)),
    )
