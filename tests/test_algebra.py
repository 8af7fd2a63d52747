"""course_dynamics/core/algebra.py: Vec3/Mat3 against numpy, dual numbers against exact derivatives, every scalar kind."""
from __future__ import annotations

import cmath
import math

import numpy as np
import pytest
import sympy
from helpers import AWKWARD
from scipy.spatial.transform import Rotation

from course_dynamics import load_urdf
from course_dynamics.core.algebra import (
    Dual,
    Mat3,
    Vec3,
    cos_sin,
    cross,
    dot,
    point_acceleration,
    rotation_from_parts,
)

rng = np.random.default_rng(0)


def as_array(v: Vec3) -> np.ndarray:
    return np.array(tuple(v), dtype=float)


def test_vector_operations_match_numpy():
    a, b = rng.standard_normal((2, 3))
    A, B = Vec3.of(a), Vec3.of(b)
    np.testing.assert_allclose(as_array(A + B), a + b)
    np.testing.assert_allclose(as_array(A - B), a - b)
    np.testing.assert_allclose(as_array(-A), -a)
    np.testing.assert_allclose(as_array(A * 2.5), a * 2.5)
    np.testing.assert_allclose(as_array(2.5 * A), a * 2.5)
    np.testing.assert_allclose(as_array(cross(A, B)), np.cross(a, b))
    assert dot(A, B) == pytest.approx(a @ b)


def test_matrix_products_match_numpy():
    R, S, v = rng.standard_normal((3, 3)), rng.standard_normal((3, 3)), rng.standard_normal(3)
    np.testing.assert_allclose(as_array(Mat3.of(R) @ Vec3.of(v)), R @ v)
    np.testing.assert_allclose(np.array((Mat3.of(R) @ Mat3.of(S)).rows), R @ S)
    np.testing.assert_allclose(np.array(Mat3.of(R).T.rows), R.T)


def test_point_acceleration_is_6_12():
    """v̇ + ω̇ × P + ω × (ω × P), written out in components in the library."""
    v_dot, w_dot, w, P = rng.standard_normal((4, 3))
    expected = v_dot + np.cross(w_dot, P) + np.cross(w, np.cross(w, P))
    np.testing.assert_allclose(as_array(point_acceleration(*(Vec3.of(x) for x in (v_dot, w_dot, w, P)))), expected)


def test_batches_run_through_the_same_operations():
    """Components that are (N,) arrays give the N results of the single-state operation."""
    a, b = rng.standard_normal((2, 3, 50))
    batch = cross(Vec3(*a), Vec3(*b))
    np.testing.assert_allclose(np.array(tuple(batch)), np.cross(a.T, b.T).T)
    scaled = np.full(50, 2.0) * Vec3(*a)  # numpy array × Vec3 defers to Vec3
    assert isinstance(scaled, Vec3)


def test_dual_numbers_carry_exact_derivatives():
    """d/dx of x·sin x + x² at x = 0.7 through the product rule and cos_sin's chain rule."""
    x = Dual(0.7, 1.0)
    c, s = cos_sin(x)
    f = x * s + x * x - 3 * x + 1
    assert f.a == pytest.approx(0.7 * math.sin(0.7) + 0.49 - 2.1 + 1)
    assert f.b == pytest.approx(math.sin(0.7) + 0.7 * math.cos(0.7) + 1.4 - 3, rel=1e-15)
    assert c.b == pytest.approx(-math.sin(0.7), rel=1e-15)
    assert (2 - x).b == -1 and (-x).a == -0.7


def test_cos_sin_dispatches_on_every_scalar_kind():
    assert cos_sin(0.3) == (math.cos(0.3), math.sin(0.3))
    assert cos_sin(1) == (math.cos(1), math.sin(1))
    assert cos_sin(0.3 + 1e-30j) == (cmath.cos(0.3 + 1e-30j), cmath.sin(0.3 + 1e-30j))
    angles = np.linspace(0, 1, 5)
    c, s = cos_sin(angles)
    np.testing.assert_array_equal(c, np.cos(angles))
    theta = sympy.Symbol("theta")
    assert cos_sin(theta) == (sympy.cos(theta), sympy.sin(theta))


def test_rotation_from_parts_is_rodrigues():
    """ᵖᵢR(θ) = R0 Rot(a, θ) for the oblique axes of the test robot, against SciPy's rotation vectors."""
    model = load_urdf(AWKWARD)
    for body in model.bodies:
        for theta in (-2.0, 0.0, 0.4, 3.0):
            R = np.array(rotation_from_parts(body.rotation_parts, math.cos(theta), math.sin(theta)).rows)
            expected = body.R0 @ Rotation.from_rotvec(body.axis * theta).as_matrix()
            np.testing.assert_allclose(R, expected, atol=1e-14)


def test_symbolic_rotation_has_no_zero_terms():
    """Exact zeros of the constant parts are skipped: a z-axis joint gives Rot(z, θ) with no 0·sin θ terms."""
    from course_dynamics import load_robot

    body = load_robot("two_link").bodies[1]  # R0 = identity, axis z
    theta = sympy.Symbol("theta")
    R = rotation_from_parts(body.rotation_parts, *cos_sin(theta))
    c, s = sympy.cos(theta), sympy.sin(theta)
    expected = ((c, -s, 0), (s, c, 0), (0, 0, 1))
    for row, expected_row in zip(R.rows, expected):
        for entry, value in zip(row, expected_row):
            assert sympy.simplify(sympy.sympify(entry - value)).is_zero
            assert sympy.sympify(entry).count_ops() <= sympy.sympify(value).count_ops() + 1  # 1.0·cos θ at most
