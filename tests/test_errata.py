"""The lecture notes, checked equation by equation (reference/errata.md).

Each misprint has a test that evaluates the equation as printed and as
corrected at a concrete state: the corrected form agrees with Pinocchio (or
with exact differentiation), the printed one does not. Equations found correct
are checked here too where no other test covers them.
"""
from __future__ import annotations

import numpy as np
import pytest
import sympy
from course_dynamics_reference import TOLERANCE
from course_dynamics_reference.misprints import printed_outward_rotation, printed_worked_N1, serial_inward
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states

from course_dynamics import InputError, inverse_dynamics, load_robot, newton_euler_links, potential_energy, robot_path
from course_dynamics.core import lagrange
from course_dynamics.core.cartesian import cartesian_dynamics
from course_dynamics.core.kinematics import joint_transforms
from course_dynamics.core.state import entries

t = sympy.Symbol("t", real=True)


def rotation(axis, angle):
    """Rodrigues, sympy."""
    a = sympy.Matrix(axis) / sympy.sqrt(sum(x**2 for x in axis))
    K = sympy.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return sympy.eye(3) + sympy.sin(angle) * K + (1 - sympy.cos(angle)) * K * K


def moving_frame():
    """A frame {B} turning about a fixed oblique axis with θ(t) = 0.7 t + 0.4 t², and its Ω, Ω̇ in {A}."""
    axis = (1, 2, 2)
    theta = sympy.Rational(7, 10) * t + sympy.Rational(2, 5) * t**2
    R = rotation(axis, theta)
    unit = sympy.Matrix(axis) / 3
    return R, unit * theta.diff(t), unit * theta.diff(t, 2)


def at(expression, time=sympy.Rational(13, 10)):
    return np.array(sympy.Matrix(expression).subs(t, time).evalf(30), dtype=float).ravel()


def cross(a, b):
    return a.cross(b)


# ---------------------------------------------------------------- accelerations (6.1), (6.2), (6.10), (6.12), (6.13), (6.15)

def angular_velocity(R):
    """ᴬΩ from a rotation ᴬR(t): the axial vector of Ṙ Rᵀ."""
    skew = R.diff(t) * R.T
    return sympy.Matrix([skew[2, 1], skew[0, 2], skew[1, 0]])


def test_6_1_and_6_2_are_limits_of_difference_quotients():
    """(6.1) ᴮV̇_Q and (6.2) ᴬΩ̇_B: the limits of the difference quotients, at t = 1.3 s, are the exact derivatives
    (of a point's velocity quadratic in t, and of a frame turning about a fixed axis k̂ by θ(t) = t⁴/4 + t, whose
    ᴬΩ_B = k̂ θ̇ is checked against Ṙ Rᵀ)."""
    axis = sympy.Matrix([1, 2, 2]) / 3
    V = sympy.Matrix([1 + t, 2 * t**2, -(t**3)]).diff(t)  # ᴮV_Q of a point moving in {B}
    Omega = axis * (t**3 + 1)  # ᴬΩ_B
    np.testing.assert_allclose(at(angular_velocity(rotation((1, 2, 2), t**4 / 4 + t))), at(Omega), rtol=TOLERANCE)
    h, now = sympy.Symbol("h", positive=True), sympy.Rational(13, 10)
    for x in (V, Omega):
        quotient = (x.subs(t, now + h) - x.subs(t, now)) / h
        limit = quotient.applyfunc(lambda e: sympy.limit(e, h, 0))
        np.testing.assert_allclose(np.array(limit.evalf(30), dtype=float).ravel(), at(x.diff(t)), rtol=TOLERANCE)
        assert np.abs(np.array(quotient.subs(h, sympy.Rational(1, 10)).evalf(30), dtype=float).ravel()
                      - at(x.diff(t))).max() > 1e-3  # a finite step is not the limit


def test_6_2_is_the_angular_velocity_of_frame_B():
    """(6.2) prints ᴬΩ_Q, "ω_Q in frame {B}": the angular velocity belongs to the frame {B}, not to a point Q.

    One vector, ᴬΩ_B (from ᴬ_BṘ ᴬ_BRᵀ), gives every point fixed in {B} its velocity ᴬΩ_B × ᴬ_BR ᴮQ (origins
    coincide), whichever point it is; that is the vector (6.2) differentiates.
    """
    R, Omega, Omega_dot = moving_frame()
    np.testing.assert_allclose(at(angular_velocity(R)), at(Omega), rtol=TOLERANCE)
    for point in ([1, 0, 0], [0.3, -2, 0.5], [0, 0, 4]):
        Q = sympy.Matrix(point)
        np.testing.assert_allclose(at((R * Q).diff(t)), at(cross(Omega, R * Q)), rtol=TOLERANCE, atol=1e-14)
    one, other = (at(cross(Omega, R * sympy.Matrix(point))) for point in ([1, 0, 0], [0, 0, 4]))
    assert np.abs(one - other).max() > 0.1  # the points move differently, with the one ᴬΩ_B


def test_6_13_angular_velocities_add():
    """(6.13): ᴬΩ_C = ᴬΩ_B + ᴬ_BR ᴮΩ_C, with each angular velocity from its rotation, ṘRᵀ."""
    R_AB, Omega_B, _ = moving_frame()
    R_BC = rotation((0, 0, 1), 3 * t**2)  # {C} turns about ᴮẐ at 6t rad/s
    np.testing.assert_allclose(at(Omega_B + R_AB * sympy.Matrix([0, 0, 6 * t])), at(angular_velocity(R_AB * R_BC)),
                               rtol=TOLERANCE)


def test_6_10_printed_has_an_extra_coriolis_term():
    R, Omega, Omega_dot = moving_frame()
    Q = sympy.Matrix([1 + t, 2 * t**2, -t])  # ᴮQ(t), moving in {B}
    V, V_dot = Q.diff(t), Q.diff(t, 2)
    truth = at((R * Q).diff(t, 2))  # ᴬV̇_Q by exact differentiation, origins coincide
    correct = R * V_dot + 2 * cross(Omega, R * V) + cross(Omega_dot, R * Q) + cross(Omega, cross(Omega, R * Q))
    printed = cross(Omega, R * V) + 2 * cross(Omega, R * V) + R * V_dot + cross(Omega_dot, R * Q) + cross(Omega, cross(Omega, R * Q))
    np.testing.assert_allclose(at(correct), truth, rtol=1e-12)
    assert np.abs(at(printed) - truth).max() > 0.1


def test_6_12_fixed_point_is_correct():
    R, Omega, Omega_dot = moving_frame()
    Q = sympy.Matrix([1, -2, sympy.Rational(1, 2)])  # ᴮQ constant
    correct = cross(Omega_dot, R * Q) + cross(Omega, cross(Omega, R * Q))  # (6.12) with ᴬV̇_BORG = 0
    np.testing.assert_allclose(at(correct), at((R * Q).diff(t, 2)), rtol=1e-12)


def test_6_15_angular_acceleration_is_correct():
    R_AB, Omega_B, Omega_B_dot = moving_frame()
    R_BC = rotation((0, 0, 1), 3 * t**2)  # {C} turns about ᴮẐ
    Omega_C_in_B = sympy.Matrix([0, 0, 6 * t])
    R_AC = R_AB * R_BC
    skew = R_AC.diff(t) * R_AC.T  # [ᴬΩ_C]ₓ
    Omega_C = sympy.Matrix([skew[2, 1], skew[0, 2], skew[1, 0]])
    correct = Omega_B_dot + R_AB * Omega_C_in_B.diff(t) + cross(Omega_B, R_AB * Omega_C_in_B)  # (6.15)
    np.testing.assert_allclose(at(correct), at(Omega_C.diff(t)), rtol=1e-10)


# ---------------------------------------------------------------- inertia: example 6.1, 6.2, parallel axis

def box_integrals():
    x, y, z, w, l, h, rho = sympy.symbols("x y z w l h rho", positive=True)
    m = rho * w * l * h

    def integral(f):
        return sympy.simplify(sympy.integrate(f * rho, (x, 0, w), (y, 0, l), (z, 0, h)) / m)

    return x, y, z, w, l, h, integral


def test_example_6_1_is_correct():
    x, y, z, w, l, h, per_mass = box_integrals()
    assert sympy.simplify(per_mass(y**2 + z**2) - (l**2 + h**2) / 3) == 0  # Ixx = m/3 (l² + h²)
    assert sympy.simplify(per_mass(x * y) - w * l / 4) == 0  # Ixy = m/4 w l


def test_example_6_2_is_correct():
    x, y, z, w, l, h, per_mass = box_integrals()
    about_com = per_mass((x - w / 2) ** 2 + (y - l / 2) ** 2)
    assert sympy.simplify(about_com - (w**2 + l**2) / 12) == 0  # ᶜI_zz = m/12 (w² + l²)


def test_parallel_axis_product_of_inertia_sign():
    """ᴬI_xy = ᶜI_xy + m x_c y_c (with I_xy = ∫xy ρ dv); the notes print − m x_c y_c."""
    x, y, z, w, l, h, per_mass = box_integrals()
    I_xy_A = per_mass(x * y)  # about the corner: m w l / 4 (example 6.1)
    I_xy_C = per_mass((x - w / 2) * (y - l / 2))  # about the centre: 0
    x_c, y_c = w / 2, l / 2
    assert sympy.simplify(I_xy_A - (I_xy_C + x_c * y_c)) == 0  # corrected, per unit mass
    assert sympy.simplify(I_xy_A - (I_xy_C - x_c * y_c)) != 0  # as printed
    I_zz_A = per_mass(x**2 + y**2)
    I_zz_C = per_mass((x - w / 2) ** 2 + (y - l / 2) ** 2)
    assert sympy.simplify(I_zz_A - (I_zz_C + x_c**2 + y_c**2)) == 0  # ᴬI_zz = ᶜI_zz + m(x_c² + y_c²): correct


def test_example_6_1_I_xy_integrates_over_x_too():
    """Example 6.1 prints I_xy = ∫₀ʰ∫₀ˡ xy ρ dx dy dz: two integrals for three differentials. Without ∫₀ʷ over x
    the result still depends on x (and is a length short of kg·m²); the triple integral is m w l / 4."""
    x, y, z, w, l, h, rho = sympy.symbols("x y z w l h rho", positive=True)
    m = rho * w * l * h
    printed = sympy.integrate(x * y * rho, (y, 0, l), (z, 0, h))  # the limits l and h on y and z, as for I_xx
    assert x in printed.free_symbols
    assert sympy.simplify(sympy.integrate(x * y * rho, (x, 0, w), (y, 0, l), (z, 0, h)) - m * w * l / 4) == 0


def test_the_frame_at_the_centre_of_mass_is_C_not_A():
    """The notes print "The frame {A} has its origin at ᴬP_c = ½ [w l h]ᵀ"; that frame is {C}.

    In example 6.1's box, {A} has its origin at a corner (the integrals run from 0), and ᴬP_c = ½ (w, l, h) is
    not that origin. About the frame with its origin at ᴬP_c (axes parallel to {A}'s) the first moments vanish,
    and the tensor is the one the notes give next, ᶜI_zz = m/12 (w² + l²) and ᶜI_xy = 0; about {A}'s origin I_xy
    is m w l / 4, not 0.
    """
    x, y, z, w, l, h, per_mass = box_integrals()
    com = [per_mass(x), per_mass(y), per_mass(z)]
    assert [sympy.simplify(c - e) for c, e in zip(com, (w / 2, l / 2, h / 2))] == [0, 0, 0]  # ᴬP_c = ½ (w, l, h)
    assert all(sympy.simplify(c) != 0 for c in com)  # so the corner, {A}'s origin, is not at ᴬP_c
    about_c = [(x - w / 2), (y - l / 2), (z - h / 2)]  # coordinates in {C}
    assert [per_mass(c) for c in about_c] == [0, 0, 0]  # {C}'s origin is the centre of mass
    assert sympy.simplify(per_mass(about_c[0] * about_c[1])) == 0  # ᶜI_xy = 0
    assert sympy.simplify(per_mass(about_c[0] ** 2 + about_c[1] ** 2) - (w**2 + l**2) / 12) == 0  # ᶜI_zz
    assert sympy.simplify(per_mass(x * y)) != 0  # about {A}'s origin the product is m w l / 4


# ---------------------------------------------------------------- the Newton–Euler iterations (6.45)–(6.53)

@pytest.fixture(scope="module")
def panda():
    model = load_robot("panda")
    oracle = PinocchioOracle(robot_path("panda"), model.joint_names)
    q, qd, qdd = random_states(model, 1, seed=24)  # a state where link 1 spins off its axis enough to tell (6.50) apart
    return model, oracle, q[0], qd[0], qdd[0]


def test_6_45_to_6_47_rotation_is_inverted_in_print(panda):
    model, oracle, q, qd, qdd = panda
    reference = oracle.tau(q, qd, qdd)
    np.testing.assert_allclose(inverse_dynamics(model, q, qd, qdd), reference, rtol=1e-12, atol=1e-12)
    assert np.abs(printed_outward_rotation(model, q, qd, qdd) - reference).max() > 0.1


def test_6_48_com_acceleration(panda):
    """Printed: ω̇ᵢ × ⁱ⁺¹Pᵢ₊₁ + … with ⁱ⁺¹Pᵢ₊₁ = 0, i.e. the COM would move as the frame origin."""
    model, oracle, q, qd, qdd = panda
    ref = oracle.link_quantities(q, qd, qdd)
    links = newton_euler_links(model, q, qd, qdd)
    np.testing.assert_allclose(links.v_dot_c, ref["v_dot_c"], rtol=1e-10, atol=1e-10)
    printed = links.v_dot  # the printed right-hand side reduces to ⁱ⁺¹v̇ᵢ₊₁
    assert np.abs(printed - ref["v_dot_c"]).max() > 0.1


def test_6_50_euler_uses_the_com_inertia_twice(panda):
    """Printed: N = ᶜI ω̇ + ω × ⁱ⁺¹I ω, the second inertia about the frame origin instead of the COM."""
    model, oracle, q, qd, qdd = panda
    ref = oracle.link_quantities(q, qd, qdd)
    links = newton_euler_links(model, q, qd, qdd)
    np.testing.assert_allclose(links.N, ref["N"], rtol=1e-10, atol=1e-12)
    printed = []
    for body, w, w_dot in zip(model.bodies, links.omega, links.omega_dot):
        c = body.p_com
        I_origin = body.I_com + body.mass * (c @ c * np.eye(3) - np.outer(c, c))  # parallel axis
        printed.append(body.I_com @ w_dot + np.cross(w, I_origin @ w))
    assert np.abs(np.array(printed) - ref["N"]).max() > 1e-3


@pytest.mark.parametrize("variant", ["6.51", "6.52"])
def test_6_51_and_6_52_inward_iteration(variant):
    model = load_robot("ur5")  # a serial chain of revolute joints
    oracle = PinocchioOracle(robot_path("ur5"), model.joint_names)
    q, qd, qdd = (x[0] for x in random_states(model, 1, seed=5))
    links = newton_euler_links(model, q, qd, qdd)
    X = joint_transforms(model, entries(q))
    reference = oracle.tau(q, qd, qdd)
    np.testing.assert_allclose(serial_inward(model, links, X, "corrected"), reference, rtol=1e-12, atol=1e-12)
    assert np.abs(serial_inward(model, links, X, variant) - reference).max() > 0.1


# ---------------------------------------------------------------- the worked two-link example (section 6.7)

@pytest.fixture(scope="module")
def two_link_state():
    model = load_robot("two_link")
    oracle = PinocchioOracle(robot_path("two_link"), model.joint_names)
    q, qd, qdd = np.array([0.3, -0.8]), np.array([1.1, 0.6]), np.array([-0.4, 0.9])
    return model, oracle.link_quantities(q, qd, qdd), q, qd, qdd


def test_worked_example_v_dot_c1_y_component(two_link_state):
    """Printed ¹v̇_C1 = (−l1θ̇1² + g s1, l1θ̈1 + g s1, 0); the y component is l1θ̈1 + g c1."""
    model, ref, q, qd, qdd = two_link_state
    l1, g, s1, c1 = 0.5, 9.81, np.sin(q[0]), np.cos(q[0])
    correct = [-l1 * qd[0] ** 2 + g * s1, l1 * qdd[0] + g * c1, 0]
    printed = [-l1 * qd[0] ** 2 + g * s1, l1 * qdd[0] + g * s1, 0]
    np.testing.assert_allclose(ref["v_dot_c"][0], correct, atol=1e-12)
    assert abs(printed[1] - ref["v_dot_c"][0][1]) > 1.0


def test_worked_example_F1_uses_the_com_acceleration(two_link_state):
    """Printed ¹F₁ = m₁ ¹v̇₁; Newton's law (6.49) needs ¹v̇_C1."""
    model, ref, q, qd, qdd = two_link_state
    m1 = 2.0
    np.testing.assert_allclose(ref["F"][0], m1 * ref["v_dot_c"][0], atol=1e-12)
    assert np.abs(m1 * ref["v_dot"][0] - ref["F"][0]).max() > 0.1


def test_worked_example_link2(two_link_state):
    """²v̇₂ = ²₁R ¹v̇_C1 (right, given the corrected ¹v̇_C1); ²v̇_C2 printed with ¹ω̇₁ for ²ω̇₂."""
    model, ref, q, qd, qdd = two_link_state
    c2, s2, l2 = np.cos(q[1]), np.sin(q[1]), 0.4
    R21 = np.array([[c2, s2, 0], [-s2, c2, 0], [0, 0, 1]])
    np.testing.assert_allclose(ref["v_dot"][1], R21 @ ref["v_dot_c"][0], atol=1e-12)
    P_c2 = np.array([l2, 0, 0])
    w2 = np.array([0, 0, qd[0] + qd[1]])
    correct = np.cross([0, 0, qdd[0] + qdd[1]], P_c2) + np.cross(w2, np.cross(w2, P_c2)) + ref["v_dot"][1]
    printed = np.cross([0, 0, qdd[0]], P_c2) + np.cross(w2, np.cross(w2, P_c2)) + ref["v_dot"][1]
    np.testing.assert_allclose(ref["v_dot_c"][1], correct, atol=1e-12)
    assert np.abs(printed - ref["v_dot_c"][1]).max() > 0.1


def test_worked_example_v_dot_1_rotates_from_frame_0(two_link_state):
    """Printed ¹v̇₁ = ¹R^i v̇_i: the index is 0, ¹₀R ⁰v̇₀, with ⁰v̇₀ = (0, g, 0) (gravity as an upward lift of the base);
    the matrix printed beside it is ¹₀R, which maps frame-0 vectors into frame 1 (its transpose would not do)."""
    model, ref, q, qd, qdd = two_link_state
    c1, s1, g = np.cos(q[0]), np.sin(q[0]), 9.81
    R10 = np.array([[c1, s1, 0], [-s1, c1, 0], [0, 0, 1]])  # as printed
    v0 = np.array([0.0, g, 0.0])  # ⁰v̇₀
    np.testing.assert_allclose(ref["v_dot"][0], R10 @ v0, rtol=TOLERANCE, atol=1e-12)
    assert np.abs(R10.T @ v0 - ref["v_dot"][0]).max() > 1.0


def test_worked_example_N1_uses_the_com_inertia(two_link_state, panda):
    """Printed ¹N₁ = ᶜⁱ⁺¹Iᵢ₊₁ ¹ω̇₁ + ω₁ × ⁱ⁺¹Iᵢ₊₁ ¹ω₁, read as (6.50) prints it (the second inertia about the frame
    origin); correct ᶜ¹I₁ ¹ω̇₁ + ¹ω₁ × ᶜ¹I₁ ¹ω₁. On the two-link arm both are 0 (point masses; and ¹ω₁ ∥ ¹Ẑ₁ while
    ¹I₁ ¹Ẑ₁ ∥ ¹Ẑ₁, as the arm is planar), so they are told apart on a link with a real inertia and its COM off
    the joint axis: the Panda's link 1."""
    arm, ref, q, qd, qdd = two_link_state
    printed = printed_worked_N1(arm.bodies[0], ref["omega"][0], ref["omega_dot"][0])
    np.testing.assert_allclose([printed, ref["N"][0]], 0, atol=1e-15)  # the two-link arm cannot tell them apart
    model, oracle, q, qd, qdd = panda
    first = oracle.link_quantities(q, qd, qdd)
    body, w, w_dot, N = model.bodies[0], first["omega"][0], first["omega_dot"][0], first["N"][0]
    np.testing.assert_allclose(body.I_com @ w_dot + np.cross(w, body.I_com @ w), N, rtol=TOLERANCE, atol=1e-15)
    assert np.abs(printed_worked_N1(body, w, w_dot) - N).max() > 1e-2 * np.abs(N).max()


def test_worked_example_v_dot_2_as_printed(two_link_state):
    """Printed ²v̇₂ = ²R² v̇_C₁: ²₂R is the identity, which leaves ¹v̇_C₁ in frame 1's axes, and the vector printed
    with it carries ¹v̇_C₁'s misprinted g s₁; ²₁R ¹v̇_C₁ (the COM of link 1 is the origin of frame 2) is right."""
    model, ref, q, qd, qdd = two_link_state
    c2, s2, l1, g = np.cos(q[1]), np.sin(q[1]), 0.5, 9.81
    R21 = np.array([[c2, s2, 0], [-s2, c2, 0], [0, 0, 1]])
    np.testing.assert_allclose(R21 @ ref["v_dot_c"][0], ref["v_dot"][1], rtol=TOLERANCE)  # corrected
    assert np.abs(np.eye(3) @ ref["v_dot_c"][0] - ref["v_dot"][1]).max() > 1.0  # ²R² as printed
    printed_vector = R21 @ [-l1 * qd[0] ** 2 + g * np.sin(q[0]), l1 * qdd[0] + g * np.sin(q[0]), 0]
    assert np.abs(printed_vector - ref["v_dot"][1]).max() > 1.0


# ---------------------------------------------------------------- structure (6.63)–(6.65) and Lagrange

def test_6_65_centrifugal_vector():
    """[Θ̇²] = (θ̇1², θ̇2², …, θ̇n²); the notes print θ̇1² twice."""
    model = load_robot("rrr_arm")
    q, qd = np.array([0.3, -0.6, 1.1]), np.array([0.9, -1.3, 0.4])
    B, C = lagrange.configuration_space_terms(model, q)
    coriolis = B @ np.array([qd[j] * qd[k] for j, k in lagrange.velocity_pairs(3)])
    V = lagrange.velocity_torques(model, q, qd)
    np.testing.assert_allclose(coriolis + C @ qd**2, V, rtol=1e-12, atol=1e-14)
    printed = np.array([qd[0] ** 2, qd[0] ** 2, qd[2] ** 2])
    assert np.abs(coriolis + C @ printed - V).max() > 1e-3
    assert B.shape == (3, 3)  # n(n−1)/2 products; for the two-link arm B is 2 × 1 times the scalar θ̇1θ̇2


def test_two_link_split_shapes():
    B, C = lagrange.configuration_space_terms(load_robot("two_link"), [0.3, 0.5])
    assert B.shape == (2, 1) and C.shape == (2, 2)  # printed: a 2 × 1 B times a 2-vector [θ̇1θ̇2; θ̇1θ̇2]


def test_pendulum_lagrange_equation_sign():
    """Printed: m l² ω̇ − m g l sin θ = 0; with ∂L/∂θ = −m g l sin θ it is m l² θ̈ + m g l sin θ = 0."""
    model = load_robot("pendulum")
    oracle = PinocchioOracle(robot_path("pendulum"), model.joint_names)
    m, l, g, theta = 1.0, 1.0, 9.81, 0.7
    free_fall = oracle.aba([theta], [0.0], [0.0])[0]
    np.testing.assert_allclose(free_fall, -g / l * np.sin(theta), rtol=1e-12)  # corrected
    assert abs(free_fall - (+g / l * np.sin(theta))) > 1.0  # as printed
    assert np.isclose(m * l**2 * free_fall + m * g * l * np.sin(theta), 0.0, atol=1e-12)


def test_example_6_5_steps_are_correct():
    """k₁, k₂, u₁, u₂ and the Lagrange terms of example 6.5 against our symbolic Lagrangian path."""
    from course_dynamics.core.kinematics import potential_energy
    from course_dynamics.core.parameters import joint_symbols, symbolic_model

    model, p = symbolic_model(load_robot("rp_arm"), ("m1", "m2", "l1", "Izz1", "Izz2", "g"))
    q, qd, _ = joint_symbols(model)
    m1, m2, l1, Izz1, Izz2, g = (p[k] for k in ("m1", "m2", "l1", "Izz1", "Izz2", "g"))
    (t1, d2), (td1, dd2) = q, qd
    k = lagrange.link_kinetic_energies(model, q, qd)
    assert sympy.simplify(k[0] - (m1 * l1**2 * td1**2 / 2 + Izz1 * td1**2 / 2)) == 0
    assert sympy.simplify(k[1] - (m2 * (d2**2 * td1**2 + dd2**2) / 2 + Izz2 * td1**2 / 2)) == 0
    u = potential_energy(model, q)[()]  # a 0-d object array holds the expression
    d2_max = sympy.Symbol("d2max")
    u_notes = m1 * l1 * g * sympy.sin(t1) + m1 * l1 * g + m2 * d2 * g * sympy.sin(t1) + m2 * d2_max * g
    assert sympy.diff(sympy.simplify(u - u_notes), t1) == 0 and sympy.diff(sympy.simplify(u - u_notes), d2) == 0  # equal up to u_ref
    K = sum(k)
    assert sympy.simplify(sympy.diff(K, td1) - (m1 * l1**2 + Izz1 + Izz2 + m2 * d2**2) * td1) == 0
    assert sympy.simplify(sympy.diff(K, d2) - m2 * d2 * td1**2) == 0
    assert sympy.simplify(sympy.diff(u, t1) - g * (m1 * l1 + m2 * d2) * sympy.cos(t1)) == 0
    assert sympy.simplify(sympy.diff(u, d2) - g * m2 * sympy.sin(t1)) == 0


def test_6_75_and_6_77_give_the_rp_arms_torques():
    """L = k − u (6.75), and d/dt ∂L/∂Θ̇ − ∂L/∂Θ = τ (6.77) with d/dt by the chain rule, on the RP arm's exact
    energies; its second form, d/dt ∂k/∂Θ̇ − ∂k/∂Θ + ∂u/∂Θ, is the same. Both against Pinocchio's rnea."""
    from course_dynamics.core.parameters import joint_symbols, rationalize

    model = rationalize(load_robot("rp_arm"))
    q, qd, qdd = joint_symbols(model)
    k, u = sum(lagrange.link_kinetic_energies(model, q, qd)), potential_energy(model, q)[()]

    def d_dt(e):
        return sum(sympy.diff(e, x) * x_dot for x, x_dot in zip([*q, *qd], [*qd, *qdd]))

    L = k - u  # (6.75)
    by_L = [d_dt(sympy.diff(L, qd[j])) - sympy.diff(L, q[j]) for j in range(model.n)]  # (6.77)
    by_k_u = [d_dt(sympy.diff(k, qd[j])) - sympy.diff(k, q[j]) + sympy.diff(u, q[j]) for j in range(model.n)]
    state = np.array([0.6, 0.45]), np.array([1.3, -0.7]), np.array([-0.5, 0.8])  # rad, m and their rates
    values = dict(zip([*q, *qd, *qdd], np.concatenate(state)))
    truth = PinocchioOracle(robot_path("rp_arm"), model.joint_names).tau(*state)
    for tau in (by_L, by_k_u):
        np.testing.assert_allclose([float(e.subs(values)) for e in tau], truth, rtol=TOLERANCE)


# ---------------------------------------------------------------- Cartesian space, example 6.6, (6.105)

@pytest.fixture(scope="module")
def example_6_6():
    model = load_robot("two_link")
    q, qd, qdd = np.array([0.4, 0.9]), np.array([0.7, -1.2]), np.array([0.3, 0.5])
    return model, q, qd, qdd, cartesian_dynamics(model, q, qd, "tool", expressed_in="frame", rows=["x", "y"])


def test_example_6_6_jacobian(example_6_6):
    """Printed J = [[l1 s2, 0], [l1 c2, l2]]; Craig's ³J (5.66) has l1 c2 + l2. The printed J⁻¹ and J̇ are right."""
    model, q, qd, qdd, terms = example_6_6
    l1, l2, s2, c2 = 0.5, 0.4, np.sin(q[1]), np.cos(q[1])
    printed = np.array([[l1 * s2, 0], [l1 * c2, l2]])
    correct = np.array([[l1 * s2, 0], [l1 * c2 + l2, l2]])
    np.testing.assert_allclose(terms.J, correct, atol=1e-12)
    assert np.abs(printed - terms.J).max() > 0.3
    J_inv_printed = np.array([[l2, 0], [-l1 * c2 - l2, l1 * s2]]) / (l1 * l2 * s2)
    np.testing.assert_allclose(J_inv_printed @ correct, np.eye(2), atol=1e-12)
    J_dot_printed = np.array([[l1 * c2 * qd[1], 0], [-l1 * s2 * qd[1], 0]])
    np.testing.assert_allclose(terms.J_dot, J_dot_printed, atol=1e-12)


def test_6_105_has_M_x_and_the_joint_space_gravity(example_6_6):
    """Printed τ = Jᵀ M Ẍ + B_x[Θ̇Θ̇] + C_x[Θ̇²] + G_x; Craig's (6.105) is τ = Jᵀ M_x Ẍ + B_x[Θ̇Θ̇] + C_x[Θ̇²] + G, with
    B_x, C_x joint torques (B_x[Θ̇Θ̇] + C_x[Θ̇²] = Jᵀ V_x) and G = Jᵀ G_x; it equals (6.104),
    τ = Jᵀ (M_x Ẍ + V_x + G_x).
    Each printed slip alone (M for M_x, G_x for G) is refused."""
    from course_dynamics import gravity_torques, mass_matrix
    from course_dynamics.core.cartesian import cartesian_configuration_space_terms

    model, q, qd, qdd, terms = example_6_6
    tau = inverse_dynamics(model, q, qd, qdd)
    x_ddot = terms.J @ qdd + terms.J_dot @ qd  # (6.97)
    np.testing.assert_allclose(terms.joint_torques(x_ddot), tau, rtol=1e-10)  # (6.104)
    Bx, Cx = cartesian_configuration_space_terms(model, q, "tool", expressed_in="frame", rows=["x", "y"])
    velocity = Bx @ [qd[0] * qd[1]] + Cx @ qd**2
    np.testing.assert_allclose(velocity, terms.J.T @ terms.Vx, rtol=1e-10)
    M, G = mass_matrix(model, q), gravity_torques(model, q)
    np.testing.assert_allclose(terms.J.T @ terms.Mx @ x_ddot + velocity + G, tau, rtol=1e-10)  # (6.105), corrected
    scale = np.abs(tau).max()  # N·m
    assert np.abs(terms.J.T @ M @ x_ddot + velocity + terms.Gx - tau).max() > 0.1 * scale  # as printed
    assert np.abs(terms.J.T @ M @ x_ddot + velocity + G - tau).max() > 1e-2 * scale  # M where M_x belongs
    assert np.abs(terms.J.T @ terms.Mx @ x_ddot + velocity + terms.Gx - tau).max() > 0.1 * scale  # G_x for G


# ---------------------------------------------------------------- simulation (6.115)

def test_6_115_solves_the_joint_space_equation_with_friction(panda):
    """The notes derive (6.115) "from (6.104)"; it solves (6.59) with friction added, τ = M Θ̈ + V + G + F (Craig's
    (6.114)). Θ̈ = M⁻¹ [τ − V − G − F] with Pinocchio's M, V, G is Pinocchio's aba on τ − F, on the Panda, whose
    eight coordinates leave (6.104) undefined: no task of at most six rows gives it a square J to invert in (6.99)."""
    from course_dynamics.core.forward_dynamics import forward_dynamics
    from course_dynamics.core.friction import Friction

    model, oracle, q, qd, qdd = panda
    friction = Friction(viscous=np.full(model.n, 0.3), coulomb=np.full(model.n, 0.2))  # N·m·s/rad, N·m
    tau = oracle.tau(q, qd, qdd) + friction.torques(qd)
    by_6_115 = np.linalg.solve(oracle.M(q), tau - oracle.V(q, qd) - oracle.G(q) - friction.torques(qd))
    truth = oracle.aba(q, qd, tau - friction.torques(qd))
    np.testing.assert_allclose(by_6_115, truth, rtol=TOLERANCE, atol=TOLERANCE * np.abs(truth).max())
    np.testing.assert_allclose(forward_dynamics(model, q, qd, tau, friction), truth, rtol=TOLERANCE,
                               atol=TOLERANCE * np.abs(truth).max())
    with pytest.raises(InputError, match="needs a square Jacobian"):
        cartesian_dynamics(model, q, qd, "panda_hand")


def test_errata_document_names_existing_tests():
    """Every test reference/errata.md cites exists, so the document cannot drift from the suite."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    text = (root / "reference" / "errata.md").read_text()
    cited = re.findall(r"`(?:(tests/\w+\.py)::)?(test_\w+)(?:\[[^\]]*\])?`", text)
    assert len(cited) >= 30
    sources = {path: path.read_text() for path in (root / "tests").glob("test_*.py")}
    for file, name in cited:
        where = [root / file] if file else list(sources)
        assert any(f"def {name}(" in sources[path] for path in where), f"errata.md cites missing {file}::{name}"
