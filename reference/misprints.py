"""The lecture notes' misprints, each evaluated as printed and as corrected against an independent truth.

:func:`demonstrations` returns one :class:`Misprint` per entry of ``errata.md``
that has a numeric reading: the equation as the notes print it and as
corrected, both evaluated at a concrete state and compared with Pinocchio, with
exact differentiation, or with the exact integral. The printed forms are wrong
on purpose; they live here, beside the oracle, so that the errata notebook and
the tests show the same numbers and no notebook carries an algorithm.

:func:`steps` returns one :class:`Check` per equation that the notes print
correctly (or leave blank) but no other notebook shows: the equation evaluated
with Pinocchio's own quantities, or by exact differentiation, against the truth.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy

from course_dynamics import inverse_dynamics, load_robot, newton_euler_links, robot_path
from course_dynamics.core import lagrange
from course_dynamics.core.cartesian import cartesian_configuration_space_terms, cartesian_dynamics, jacobian
from course_dynamics.core.kinematics import joint_transforms
from course_dynamics.grading.slips import Slip
from course_dynamics.core.state import entries

from .pinocchio_oracle import PinocchioOracle
from .validate import random_states


@dataclass(frozen=True)
class Misprint:
    """One misprint: where, what is compared with what, and the largest error of each form."""

    where: str
    quantity: str
    truth: str
    printed_error: float
    corrected_error: float


@dataclass(frozen=True)
class Check:
    """One equation printed correctly (or left blank and read as ``errata.md`` says): its largest relative error."""

    where: str
    quantity: str
    truth: str
    error: float


def printed_outward_rotation(model, q, qd, qdd) -> np.ndarray:
    """τ with (6.45)–(6.47) as printed: ⁱR^{i+1} (frame i+1 in i) where ⁱ⁺¹ᵢR belongs — our recursion with that
    slip made (the slip a student makes, :class:`~course_dynamics.grading.slips.Slip`)."""
    links = newton_euler_links(model, q, qd, qdd, Slip("rotation-transposed", ("6.45", "6.46", "6.47")))
    return model.S.T @ np.asarray(links.tau)  # each joint's own τᵢ, a mimic's onto its leader


def serial_inward(model, links, X, variant: str) -> np.ndarray:
    """τ of a serial chain by the inward iteration, corrected or with the misprint of (6.51) or (6.52) switched on."""
    n = model.n_bodies
    f, m_ = [None] * n, [None] * n
    for i in reversed(range(n)):
        body = model.bodies[i]
        F, N = links.F[i], links.N[i]
        f_i, n_i = F.copy(), N + np.cross(body.p_com, F)
        if i + 1 < n:
            R = np.array(X.R[i + 1].rows, dtype=float)
            P = np.array(tuple(X.P[i + 1]), dtype=float)
            if variant == "6.51":  # ⁱfᵢ = ⁱIᵢ₊₁ ⁱR f + F: the stray inertia factor, link i+1's tensor as printed
                f_i = model.bodies[i + 1].I_com @ R @ f[i + 1] + F
            else:
                f_i = R @ f[i + 1] + F
            if variant == "6.52":  # N_{i+1}, ⁱPᵢ × Fᵢ (= 0) and ⁱ⁺¹R^{i+1} (= 1) as printed
                n_i = links.N[i + 1] + R @ m_[i + 1] + np.zeros(3) + np.cross(P, f[i + 1])
            else:
                n_i = n_i + R @ m_[i + 1] + np.cross(P, R @ f[i + 1])
        elif variant == "6.52":
            n_i = np.zeros(3) + np.zeros(3)  # Nₙ₊₁ = 0 and ⁿPₙ × Fₙ = 0 leave nothing
        f[i], m_[i] = f_i, n_i
    return np.array([n_i @ b.axis for n_i, b in zip(m_, model.bodies)])


def printed_worked_N1(body, omega, omega_dot) -> np.ndarray:
    """¹N₁ as the worked example prints it, ᶜⁱ⁺¹Iᵢ₊₁ ¹ω̇₁ + ω₁ × ⁱ⁺¹Iᵢ₊₁ ¹ω₁: the second inertia, without its C,
    about the origin of frame 1 (the parallel-axis theorem moves ᶜ¹I₁ there), as (6.50) prints it."""
    c = np.asarray(body.p_com, dtype=float)
    I_origin = body.I_com + body.mass * (c @ c * np.eye(3) - np.outer(c, c))
    return body.I_com @ omega_dot + np.cross(omega, I_origin @ omega)


def pinocchio_chain(oracle, q, qd, qdd) -> dict[str, np.ndarray]:
    """Pinocchio's own quantities of a serial chain, link by link in our joint order, none computed by course_dynamics.

    The per-link quantities of :meth:`PinocchioOracle.link_quantities` (each (n, 3), in the link's frame), and
    Pinocchio's placements: ``R_up`` (n, 3, 3) the orientation of frame i in frame i−1 (``liMi``), ``P_up`` (n, 3)
    the origin of frame i in frame i−1 (m), ``R_base`` (n, 3, 3) the orientation of frame i in the base, and
    ``p_com`` (n, 3) the centre of mass of link i in frame i (m).
    """
    chain = oracle.link_quantities(q, qd, qdd)  # runs rnea, which fills liMi
    ids = [oracle.model.getJointId(name) for name in oracle.joint_names]
    if [oracle.model.parents[j] for j in ids] != [0, *ids[:-1]]:
        raise ValueError("pinocchio_chain needs a serial chain, each joint the child of the one before")
    chain["R_up"] = np.array([oracle.data.liMi[j].rotation for j in ids])
    chain["P_up"] = np.array([oracle.data.liMi[j].translation for j in ids])
    chain["p_com"] = np.array([oracle.model.inertias[j].lever for j in ids])
    R_base = [chain["R_up"][0]]
    for R in chain["R_up"][1:]:
        R_base.append(R_base[-1] @ R)
    chain["R_base"] = np.array(R_base)
    return chain


def _parents(values, base=0.0) -> np.ndarray:
    """The value of each link's parent in a serial chain; link 1's parent is the base, with value ``base``
    (0: at rest; the identity for an orientation)."""
    values = np.asarray(values, dtype=float)
    return np.concatenate([np.broadcast_to(base, values.shape[1:])[None], values[:-1]])


def _children(values) -> np.ndarray:
    """The value of each link's child in a serial chain: nothing beyond the last link."""
    values = np.asarray(values, dtype=float)
    return np.concatenate([values[1:], np.zeros((1,) + values.shape[1:])])


def turning_frame():
    """A frame {B} turning about a fixed oblique axis of {A} by θ(t) = 0.7 t + 0.4 t², origins coincident, and a
    point moving in {B}: (t, ᴬ_BR, ᴬΩ_B, ᴬΩ̇_B, ᴮQ(t)) as exact sympy expressions, lengths in m."""
    t = sympy.Symbol("t", real=True)
    axis = sympy.Matrix([1, 2, 2]) / 3
    theta = sympy.Rational(7, 10) * t + sympy.Rational(2, 5) * t**2
    K = sympy.Matrix([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R = sympy.eye(3) + sympy.sin(theta) * K + (1 - sympy.cos(theta)) * K * K  # Rodrigues
    Q = sympy.Matrix([1 + t, 2 * t**2, -t])
    return t, R, axis * theta.diff(t), axis * theta.diff(t, 2), Q


def _at(t, expression, time=sympy.Rational(13, 10)) -> np.ndarray:
    return np.array(sympy.Matrix(expression).subs(t, time).evalf(30), dtype=float).ravel()


def _relative(value, truth) -> float:
    return float(np.abs(np.asarray(value) - np.asarray(truth)).max() / max(np.abs(np.asarray(truth)).max(), 1e-300))


def demonstrations() -> list[Misprint]:
    """Every numerically checkable misprint, printed and corrected, against its truth (module docstring)."""
    found = []

    ur5 = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), ur5.joint_names)
    q, qd, qdd = (x[0] for x in random_states(ur5, 1, seed=5))
    truth = oracle.tau(q, qd, qdd)
    found.append(Misprint("(6.45)–(6.47)", "UR5 joint torques τ", "Pinocchio's rnea",
                          _relative(printed_outward_rotation(ur5, q, qd, qdd), truth),
                          _relative(inverse_dynamics(ur5, q, qd, qdd), truth)))
    links = newton_euler_links(ur5, q, qd, qdd)
    X = joint_transforms(ur5, entries(q))
    reference = oracle.link_quantities(q, qd, qdd)
    found.append(Misprint("(6.48)", "UR5 COM accelerations ⁱv̇_Cᵢ", "Pinocchio's RNEA data",
                          _relative(links.v_dot, reference["v_dot_c"]), _relative(links.v_dot_c, reference["v_dot_c"])))
    printed_N = [b.I_com @ w_dot + np.cross(w, (b.I_com + b.mass * (b.p_com @ b.p_com * np.eye(3)
                                                                       - np.outer(b.p_com, b.p_com))) @ w)
                 for b, w, w_dot in zip(ur5.bodies, links.omega, links.omega_dot)]
    found.append(Misprint("(6.49, 6.50)", "UR5 inertial moments ⁱNᵢ", "Pinocchio's RNEA data",
                          _relative(printed_N, reference["N"]), _relative(links.N, reference["N"])))
    for variant in ("6.51", "6.52"):
        found.append(Misprint(f"({variant})", "UR5 joint torques τ", "Pinocchio's rnea",
                              _relative(serial_inward(ur5, links, X, variant), truth),
                              _relative(serial_inward(ur5, links, X, "corrected"), truth)))

    arm = load_robot("two_link")
    two_link = PinocchioOracle(robot_path("two_link"), arm.joint_names)
    q2, qd2, qdd2 = np.array([0.3, -0.8]), np.array([1.1, 0.6]), np.array([-0.4, 0.9])
    ref2 = two_link.link_quantities(q2, qd2, qdd2)
    l1, g, s1, c1 = 0.5, 9.81, np.sin(q2[0]), np.cos(q2[0])
    found.append(Misprint("worked example, ¹v̇_C₁", "two-link ¹v̇_C₁", "Pinocchio's RNEA data",
                          _relative([-l1 * qd2[0] ** 2 + g * s1, l1 * qdd2[0] + g * s1, 0], ref2["v_dot_c"][0]),
                          _relative([-l1 * qd2[0] ** 2 + g * s1, l1 * qdd2[0] + g * c1, 0], ref2["v_dot_c"][0])))
    found.append(Misprint("worked example, ¹F₁", "two-link ¹F₁", "Pinocchio's RNEA data",
                          _relative(2.0 * ref2["v_dot"][0], ref2["F"][0]),
                          _relative(2.0 * ref2["v_dot_c"][0], ref2["F"][0])))

    pendulum = load_robot("pendulum")
    swing = PinocchioOracle(robot_path("pendulum"), pendulum.joint_names).aba([0.7], [0.0], [0.0])[0]
    found.append(Misprint("pendulum, Lagrange's equation", "θ̈ released at θ = 0.7 rad", "Pinocchio's aba",
                          _relative(+9.81 * np.sin(0.7), swing), _relative(-9.81 * np.sin(0.7), swing)))

    q6 = np.array([0.4, 0.9])
    J_true = two_link.frame_jacobian(q6, "tool", "frame")[[0, 1]]
    s2, c2 = np.sin(q6[1]), np.cos(q6[1])
    found.append(Misprint("example 6.6, J(Θ)", "two-link ³J", "Pinocchio's frame Jacobian",
                          _relative([[0.5 * s2, 0], [0.5 * c2, 0.4]], J_true),
                          _relative(jacobian(arm, q6, "tool", expressed_in="frame", rows=["x", "y"]), J_true)))
    qd6, qdd6 = np.array([0.7, -1.2]), np.array([0.3, 0.5])
    terms = cartesian_dynamics(arm, q6, qd6, "tool", expressed_in="frame", rows=["x", "y"])
    x_ddot = terms.J @ qdd6 + terms.J_dot @ qd6
    tau6 = two_link.tau(q6, qd6, qdd6)
    Bx, Cx = cartesian_configuration_space_terms(arm, q6, "tool", expressed_in="frame", rows=["x", "y"])
    velocity = Bx @ [qd6[0] * qd6[1]] + Cx @ qd6**2  # B_x[Θ̇Θ̇] + C_x[Θ̇²], joint torques
    printed = terms.J.T @ two_link.M(q6) @ x_ddot + velocity + terms.Gx  # M for M_x, G_x for G
    corrected = terms.J.T @ terms.Mx @ x_ddot + velocity + two_link.G(q6)  # Craig's (6.105)
    found.append(Misprint("(6.105)", "two-link τ from a Cartesian acceleration", "Pinocchio's rnea",
                          _relative(printed, tau6), _relative(corrected, tau6)))

    m, w, l = 2.0, 0.3, 0.5  # example 6.1's product of inertia about the corner: m w l / 4 by the integral
    found.append(Misprint("parallel-axis theorem, products", "box ᴬI_xy about its corner", "the exact integral",
                          _relative(0.0 - m * (w / 2) * (l / 2), m * w * l / 4),
                          _relative(0.0 + m * (w / 2) * (l / 2), m * w * l / 4)))
    found.extend(second_reading())
    found.extend(frames_and_superscripts())
    return found


def second_reading() -> list[Misprint]:
    """The misprints with a numeric reading found on the second, line-by-line reading (errata.md)."""
    found = []

    ur5 = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), ur5.joint_names)
    q, qd, qdd = (x[0] for x in random_states(ur5, 1, seed=5))
    chain = pinocchio_chain(oracle, q, qd, qdd)
    R_into = chain["R_up"].transpose(0, 2, 1)  # ⁱ⁺¹ᵢR
    Z = np.array([b.axis for b in ur5.bodies])  # ⁱ⁺¹Ẑᵢ₊₁, each joint's axis in its own frame
    printed = [R @ w_dot + rate * z for R, w_dot, rate, z in zip(R_into, _parents(chain["omega_dot"]), qd, Z)]
    corrected = [R @ w + rate * z for R, w, rate, z in zip(R_into, _parents(chain["omega"]), qd, Z)]  # (5.45)
    found.append(Misprint("the (5.45) line of (6.32)'s derivation",
                          "UR5: both sides, ⁱ⁺¹ω̇ᵢ₊₁ as printed, ⁱ⁺¹ωᵢ₊₁ as corrected", "Pinocchio's RNEA data",
                          _relative(printed, chain["omega_dot"]), _relative(corrected, chain["omega"])))

    links = newton_euler_links(ur5, q, qd, qdd)
    truth = oracle.tau(q, qd, qdd)
    found.append(Misprint("(6.43), in words", "UR5 τᵢ as the Ẑ component of a moment", "Pinocchio's rnea",
                          _relative([N @ z for N, z in zip(links.N, Z)], truth),
                          _relative([n @ z for n, z in zip(links.n, Z)], truth)))

    t, R, Omega, _, Q = turning_frame()
    velocity = _at(t, (R * Q).diff(t))  # ᴬV_Q by exact differentiation
    found.append(Misprint("(6.5) restated before (6.34)", "ᴬV_Q of a point moving in a turning frame",
                          "exact differentiation",
                          _relative(_at(t, R * Q.diff(t, 2) + Omega.cross(R * Q)), velocity),
                          _relative(_at(t, R * Q.diff(t) + Omega.cross(R * Q)), velocity)))

    arm = load_robot("two_link")
    two_link = PinocchioOracle(robot_path("two_link"), arm.joint_names)
    q6, qd6 = np.array([0.4, 0.9]), np.array([0.7, -1.2])  # rad, rad/s: example 6.6's state
    B, C = lagrange.configuration_space_terms(arm, q6)
    products = np.array([qd6[j] * qd6[k] for j, k in lagrange.velocity_pairs(arm.n)])  # [Θ̇Θ̇] (6.64)
    Bx, Cx = cartesian_configuration_space_terms(arm, q6, "tool", expressed_in="frame", rows=["x", "y"])  # (6.105)
    V = two_link.V(q6, qd6)
    found.append(Misprint("(6.63) legend", "two-link velocity terms of (6.63)", "Pinocchio's nonLinearEffects − G",
                          _relative(Bx @ products + Cx @ qd6**2, V), _relative(B @ products + C @ qd6**2, V)))

    pendulum = load_robot("double_pendulum_continuous")
    swing = PinocchioOracle(robot_path("double_pendulum_continuous"), pendulum.joint_names)
    dt = 0.01  # s
    theta_ddot = swing.aba([2.0, 0.3], [0.0, 0.0], [0.0, 0.0])  # released from rest, rad/s²
    a, s, r = sympy.symbols("a s r", real=True)
    under_constant = sympy.integrate(sympy.integrate(a, (s, 0, r)), (r, 0, dt))  # the exact displacement, a Δt²/2
    exact = np.array([float(under_constant.subs(a, value)) for value in theta_ddot])
    found.append(Misprint("(6.117)", "double pendulum Θ(t + Δt) − Θ(t) from rest, Δt = 0.01 s",
                          "the exact integral of a constant Θ̈ (Pinocchio's aba)",
                          _relative(0.5 * theta_ddot * dt * dt**2, exact), _relative(0.5 * theta_ddot * dt**2, exact)))

    panda = load_robot("panda")
    franka = PinocchioOracle(robot_path("panda"), panda.joint_names)
    qp, qdp, qddp = (x[0] for x in random_states(panda, 1, seed=24))  # link 1 spinning off its axis enough
    first = newton_euler_links(panda, qp, qdp, qddp)
    N_1 = franka.link_quantities(qp, qdp, qddp)["N"][0]
    found.append(Misprint("worked example, ¹N₁", "Panda link 1: ¹N₁ by the worked example's formula",
                          "Pinocchio's RNEA data",
                          _relative(printed_worked_N1(panda.bodies[0], first.omega[0], first.omega_dot[0]), N_1),
                          _relative(first.N[0], N_1)))

    q2 = np.array([0.3, -0.8])  # rad: the worked example's state of the other two-link rows
    ref2 = two_link.link_quantities(q2, np.array([1.1, 0.6]), np.array([-0.4, 0.9]))
    c2, s2 = np.cos(q2[1]), np.sin(q2[1])
    R21 = np.array([[c2, s2, 0], [-s2, c2, 0], [0, 0, 1]])  # ²₁R as the notes print it
    found.append(Misprint("worked example, ²v̇₂", "two-link ²v̇₂ from ¹v̇_C₁", "Pinocchio's RNEA data",
                          _relative(np.eye(3) @ ref2["v_dot_c"][0], ref2["v_dot"][1]),  # ²R² = ²₂R, the identity
                          _relative(R21 @ ref2["v_dot_c"][0], ref2["v_dot"][1])))
    return found


def frames_and_superscripts() -> list[Misprint]:
    """The misprints of a frame, an index or a superscript that change a number: (6.34)'s {A} = {i+1}, the
    prismatic remark after (6.32), (6.69)'s Iᵢ without its C, (6.73)'s P_Cᵢ without its ⁰ (errata.md)."""
    found = []

    ur5 = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), ur5.joint_names)
    q, qd, qdd = (x[0] for x in random_states(ur5, 1, seed=5))
    c = pinocchio_chain(oracle, q, qd, qdd)
    Z = np.array([b.axis for b in ur5.bodies])  # each joint's axis in its own frame
    printed, corrected = [], []
    for k in range(1, ur5.n):  # links 2 … n: a link's parent is a link, whose ⁱv̇ᵢ Pinocchio gives
        R_AB, Q = c["R_up"][k].T, c["P_up"][k]  # ⁱ⁺¹ᵢR; ᴮQ = ⁱPᵢ₊₁, the origin of {i+1} (fixed in {i})
        Omega, Omega_dot = -qd[k] * Z[k], -qdd[k] * Z[k]  # {B} = {i} turning relative to {A} = {i+1}
        RQ = R_AB @ Q
        V_dot_Borg = -(np.cross(Omega_dot, RQ) + np.cross(Omega, np.cross(Omega, RQ)))  # {i}'s origin, −ᴬ_BR ᴮQ
        printed.append(V_dot_Borg + np.cross(Omega_dot, RQ) + np.cross(Omega, np.cross(Omega, RQ)))  # (6.12)
        w, w_dot, v_dot = c["omega"][k - 1], c["omega_dot"][k - 1], c["v_dot"][k - 1]
        corrected.append(R_AB @ (v_dot + np.cross(w_dot, Q) + np.cross(w, np.cross(w, Q))))  # (6.34), {A} = {0}
    found.append(Misprint("setting {A} = {i+1} before (6.34)", "UR5 ⁱ⁺¹v̇ᵢ₊₁ by (6.12), links 2–6",
                          "Pinocchio's RNEA data", _relative(printed, c["v_dot"][1:]),
                          _relative(corrected, c["v_dot"][1:])))

    rp = load_robot("rp_arm")  # joint 2 is prismatic
    slider = PinocchioOracle(robot_path("rp_arm"), rp.joint_names)
    c2 = pinocchio_chain(slider, np.array([0.6, 0.45]), np.array([1.3, -0.7]), np.array([-0.5, 0.8]))
    R21 = c2["R_up"][1].T
    found.append(Misprint("the prismatic remark after (6.32)", "RP arm ²ω₂, ²ω̇₂ (prismatic joint 2)",
                          "Pinocchio's RNEA data",
                          _relative([np.zeros(3), R21 @ c2["omega_dot"][0]], [c2["omega"][1], c2["omega_dot"][1]]),
                          _relative([R21 @ c2["omega"][0], R21 @ c2["omega_dot"][0]],
                                    [c2["omega"][1], c2["omega_dot"][1]])))

    oracle.link_quantities(q, qd, qdd)  # fills Pinocchio's velocities and placements at this state
    ids = [oracle.model.getJointId(name) for name in oracle.joint_names]
    k_printed = k_corrected = 0.0
    for j in ids:
        body, v = oracle.model.inertias[j], oracle.data.v[j]
        lever, w = body.lever, v.angular
        v_c = v.linear + np.cross(w, lever)  # v_Cᵢ, in frame i's axes
        I_origin = body.inertia + body.mass * (lever @ lever * np.eye(3) - np.outer(lever, lever))  # ⁱIᵢ, no C
        k_printed += 0.5 * body.mass * v_c @ v_c + 0.5 * w @ I_origin @ w  # (6.69) as printed
        k_corrected += 0.5 * body.mass * v_c @ v_c + 0.5 * w @ body.inertia @ w  # (6.69) with ᶜⁱIᵢ
    energy = oracle.kinetic_energy(q, qd)
    found.append(Misprint("(6.69)", "UR5 kinetic energy k", "Pinocchio's computeKineticEnergy",
                          _relative(k_printed, energy), _relative(k_corrected, energy)))

    g = np.array([0.0, 0.0, -9.81])  # ⁰g, m/s²
    q_other = random_states(ur5, 2, seed=73)[0][1]

    def u(at, in_base: bool) -> float:  # (6.73) with u_ref = 0, P_Cᵢ in the base (⁰P_Cᵢ) or in frame i (ⁱP_Cᵢ)
        oracle.frame_placement(at, ur5.bodies[0].name)  # Pinocchio's forward kinematics fills its oMi
        levers = [oracle.data.oMi[j].act(oracle.model.inertias[j].lever) if in_base
                  else oracle.model.inertias[j].lever for j in ids]
        return sum(-oracle.model.inertias[j].mass * g @ P for j, P in zip(ids, levers))

    rise = oracle.potential_energy(q_other) - oracle.potential_energy(q)  # u_ref cancels in a difference
    found.append(Misprint("(6.73)", "UR5 potential energy u(Θ₂) − u(Θ₁)", "Pinocchio's computePotentialEnergy",
                          _relative(u(q_other, False) - u(q, False), rise),
                          _relative(u(q_other, True) - u(q, True), rise)))
    return found


def steps() -> list[Check]:
    """The equations no other notebook shows, each evaluated against its truth (module docstring)."""
    found = []

    t, R, Omega, Omega_dot, Q = turning_frame()
    V = Q.diff(t)  # ᴮV_Q
    truth = _at(t, (R * Q).diff(t, 2))  # ᴬV̇_Q by exact differentiation
    by_6_7 = (R * V).diff(t) + Omega_dot.cross(R * Q) + Omega.cross((R * Q).diff(t))
    by_6_8 = (R * V.diff(t) + Omega.cross(R * V)) + Omega_dot.cross(R * Q) + Omega.cross(R * V + Omega.cross(R * Q))
    found.append(Check("(6.7)", "ᴬV̇_Q of a point moving in a turning frame", "exact differentiation",
                       _relative(_at(t, by_6_7), truth)))
    found.append(Check("(6.8)", "ᴬV̇_Q of a point moving in a turning frame", "exact differentiation",
                       _relative(_at(t, by_6_8), truth)))

    ur5 = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), ur5.joint_names)
    q, qd, qdd = (x[0] for x in random_states(ur5, 1, seed=5))
    c = pinocchio_chain(oracle, q, qd, qdd)
    R_into = c["R_up"].transpose(0, 2, 1)  # ⁱ⁺¹ᵢR
    R_base = _parents(c["R_base"], np.eye(3))  # ⁰ᵢR, the parent's orientation in the base
    Z = np.array([b.axis for b in ur5.bodies])  # ⁱ⁺¹Ẑᵢ₊₁
    w, w_dot = _parents(c["omega"]), _parents(c["omega_dot"])  # ⁱωᵢ, ⁱω̇ᵢ of each link's parent
    by_6_15_prime = []  # (6.15) with {A} = {0}, {B} = {i}, {C} = {i+1}: ᴮΩ_C = θ̇ᵢ₊₁ ⁱẐᵢ₊₁, ᴮΩ̇_C = θ̈ᵢ₊₁ ⁱẐᵢ₊₁
    for R0, R_up, wi, wi_dot, rate, accel, z in zip(R_base, c["R_up"], w, w_dot, qd, qdd, Z):
        z_in_i = R_up @ z  # ⁱẐᵢ₊₁
        by_6_15_prime.append(R0 @ wi_dot + R0 @ (accel * z_in_i) + np.cross(R0 @ wi, R0 @ (rate * z_in_i)))  # (6.15')
    found.append(Check("(6.15')", "UR5 angular accelerations in the base, ⁰ω̇ᵢ₊₁", "Pinocchio's RNEA data",
                       _relative(by_6_15_prime, np.einsum("kij,kj->ki", c["R_base"], c["omega_dot"]))))
    by_6_15_second = [Ri @ wi_dot + accel * z + np.cross(Ri @ wi, rate * z)  # (6.15''): (6.15') in frame i+1's axes
                      for Ri, wi, wi_dot, rate, accel, z in zip(R_into, w, w_dot, qd, qdd, Z)]
    found.append(Check("(6.15'')", "UR5 angular accelerations ⁱ⁺¹ω̇ᵢ₊₁", "Pinocchio's RNEA data",
                       _relative(by_6_15_second, c["omega_dot"])))
    by_6_31 = [Ri @ wi + rate * z for Ri, wi, rate, z in zip(R_into, w, qd, Z)]  # (6.31), read as (5.45)
    found.append(Check("(6.31)", "UR5 angular velocities ⁱ⁺¹ωᵢ₊₁", "Pinocchio's RNEA data",
                       _relative(by_6_31, c["omega"])))
    R_child, P_child = _children(c["R_up"]), _children(c["P_up"])  # ⁱᵢ₊₁R, ⁱPᵢ₊₁ (nothing beyond the tip)
    f_next = np.einsum("kij,kj->ki", R_child, _children(c["f"]))  # ⁱfᵢ₊₁ = ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁
    n_next = np.einsum("kij,kj->ki", R_child, _children(c["n"]))
    by_6_38 = c["f"] - f_next  # (6.38)
    found.append(Check("(6.38)", "UR5 inertial forces ⁱFᵢ", "Pinocchio's RNEA data", _relative(by_6_38, c["F"])))
    by_6_39 = (c["n"] - n_next + np.cross(np.zeros(3) - c["p_com"], c["f"])  # (6.39), with ⁱPᵢ = 0
               - np.cross(P_child - c["p_com"], f_next))
    found.append(Check("(6.39)", "UR5 inertial moments ⁱNᵢ", "Pinocchio's RNEA data", _relative(by_6_39, c["N"])))

    rp = load_robot("rp_arm")  # joint 2 is prismatic
    slider = PinocchioOracle(robot_path("rp_arm"), rp.joint_names)
    q2, qd2, qdd2 = np.array([0.6, 0.45]), np.array([1.3, -0.7]), np.array([-0.5, 0.8])  # rad, m and their rates
    c2 = pinocchio_chain(slider, q2, qd2, qdd2)
    z2, R21, P12 = rp.bodies[1].axis, c2["R_up"][1].T, c2["P_up"][1]  # ²Ẑ₂, ²₁R, ¹P₂
    w1, w1_dot, v1_dot = c2["omega"][0], c2["omega_dot"][0], c2["v_dot"][0]
    by_6_35 = (R21 @ (v1_dot + np.cross(w1_dot, P12) + np.cross(w1, np.cross(w1, P12)))
               + 2 * np.cross(c2["omega"][1], qd2[1] * z2) + qdd2[1] * z2)  # (6.35)
    found.append(Check("(6.35)", "RP arm ²v̇₂ (prismatic joint 2)", "Pinocchio's RNEA data",
                       _relative(by_6_35, c2["v_dot"][1])))
    found.append(Check("(6.44)", "RP arm τ₂ (a force, N)", "Pinocchio's rnea",
                       _relative(c2["f"][1] @ z2, slider.tau(q2, qd2, qdd2)[1])))  # (6.44)
    return found
