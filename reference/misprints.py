"""The lecture notes' misprints, each evaluated as printed and as corrected against an independent truth.

:func:`demonstrations` returns one :class:`Misprint` per entry of ``errata.md``
that has a numeric reading: the equation as the notes print it and as
corrected, both evaluated at a concrete state and compared with Pinocchio, with
exact differentiation, or with the exact integral. The printed forms are wrong
on purpose; they live here, beside the oracle, so that the errata notebook and
the tests show the same numbers and no notebook carries an algorithm.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from course_dynamics import inverse_dynamics, load_robot, newton_euler_links, robot_path
from course_dynamics.core.algebra import Vec3
from course_dynamics.core.cartesian import cartesian_dynamics, jacobian
from course_dynamics.core.kinematics import JointTransforms, joint_transforms
from course_dynamics.core.newton_euler import inward_iteration, outward_iteration
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


def printed_outward_rotation(model, q, qd, qdd) -> np.ndarray:
    """τ with (6.45)–(6.47) as printed: ⁱR^{i+1} (frame i+1 in i) where ⁱ⁺¹ᵢR belongs."""
    X = joint_transforms(model, entries(np.asarray(q, dtype=float)))
    X_printed = JointTransforms(R=X.R, R_T=X.R, P=X.P)
    out = outward_iteration(model, X_printed, entries(np.asarray(qd, dtype=float)), entries(np.asarray(qdd, dtype=float)),
                            Vec3.of(model.gravity))
    return np.array(inward_iteration(model, X, out).tau)


def serial_inward(model, links, X, variant: str) -> np.ndarray:
    """τ of a serial chain by the inward iteration, corrected or with the misprint of (6.51) or (6.52) switched on."""
    n = model.n
    f, m_ = [None] * n, [None] * n
    for i in reversed(range(n)):
        body = model.bodies[i]
        F, N = links.F[i], links.N[i]
        f_i, n_i = F.copy(), N + np.cross(body.p_com, F)
        if i + 1 < n:
            R = np.array(X.R[i + 1].rows, dtype=float)
            P = np.array(tuple(X.P[i + 1]), dtype=float)
            if variant == "6.51":  # ⁱfᵢ = ⁱI ⁱR f + F: the stray inertia factor
                f_i = body.I_com @ R @ f[i + 1] + F
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
                          _relative(2.0 * ref2["v_dot"][0], ref2["F"][0]), _relative(2.0 * ref2["v_dot_c"][0], ref2["F"][0])))

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
    printed = terms.J.T @ two_link.M(q6) @ x_ddot + terms.Vx + terms.Gx
    found.append(Misprint("(6.105)", "two-link τ from a Cartesian acceleration", "Pinocchio's rnea",
                          _relative(printed, tau6), _relative(terms.joint_torques(x_ddot), tau6)))

    m, w, l = 2.0, 0.3, 0.5  # example 6.1's product of inertia about the corner: m w l / 4 by the integral
    found.append(Misprint("parallel-axis theorem, products", "box ᴬI_xy about its corner", "the exact integral",
                          _relative(0.0 - m * (w / 2) * (l / 2), m * w * l / 4), _relative(0.0 + m * (w / 2) * (l / 2), m * w * l / 4)))
    return found
