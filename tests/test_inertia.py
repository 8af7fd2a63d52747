"""course_dynamics/core/inertia.py: the simple bodies against exact integrals and Pinocchio, examples 6.1 and 6.2, the checks."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import sympy
from scipy.spatial.transform import Rotation

from course_dynamics.core.inertia import (
    box,
    cylinder,
    parallel_axis,
    physical_problems,
    point_mass,
    principal_axes,
    products_of_inertia,
    rod,
    rotate,
    sphere,
)

x, y, z, r, phi, theta = sympy.symbols("x y z r phi theta", real=True)
m, a, b, c, w, l, h, R = sympy.symbols("m a b c w l h R", positive=True)


def test_box_is_the_integral_over_its_volume():
    rho = m / (a * b * c)
    limits = [(x, -a / 2, a / 2), (y, -b / 2, b / 2), (z, -c / 2, c / 2)]
    exact = [[sympy.integrate((y**2 + z**2) * rho, *limits), -sympy.integrate(x * y * rho, *limits), 0],
             [0, sympy.integrate((x**2 + z**2) * rho, *limits), 0], [0, 0, sympy.integrate((x**2 + y**2) * rho, *limits)]]
    ours = box(m, a, b, c)
    for i in range(3):
        assert sympy.simplify(ours[i, i] - exact[i][i]) == 0
    assert sympy.simplify(ours[0, 1] - exact[0][1]) == 0


def test_cylinder_and_sphere_are_their_integrals():
    rho_c = m / (sympy.pi * R**2 * h)
    cyl = [(r, 0, R), (phi, 0, 2 * sympy.pi), (z, -h / 2, h / 2)]
    I_zz = sympy.integrate(r**2 * rho_c * r, *cyl)
    I_xx = sympy.integrate(((r * sympy.sin(phi)) ** 2 + z**2) * rho_c * r, *cyl)
    ours = cylinder(m, R, h)
    assert sympy.simplify(ours[2, 2] - I_zz) == 0 and sympy.simplify(ours[0, 0] - I_xx) == 0
    rho_s = m / (sympy.Rational(4, 3) * sympy.pi * R**3)
    ball = [(r, 0, R), (theta, 0, sympy.pi), (phi, 0, 2 * sympy.pi)]
    I_sphere = sympy.integrate(r**2 * sympy.sin(theta) ** 2 * rho_s * r**2 * sympy.sin(theta), *ball)
    assert sympy.simplify(sphere(m, R)[0, 0] - I_sphere) == 0


@pytest.mark.parametrize("ours, theirs", [
    (box(2.0, 1.0, 2.0, 3.0), pin.Inertia.FromBox(2.0, 1.0, 2.0, 3.0).inertia),
    (cylinder(2.0, 0.5, 3.0), pin.Inertia.FromCylinder(2.0, 0.5, 3.0).inertia),
    (sphere(2.0, 0.5), pin.Inertia.FromSphere(2.0, 0.5).inertia),
])
def test_simple_bodies_agree_with_pinocchio(ours, theirs):
    np.testing.assert_allclose(ours, theirs, rtol=1e-14, atol=0)


def test_rod_and_point_mass():
    np.testing.assert_allclose(rod(3.0, 2.0, "y"), np.diag([1.0, 0.0, 1.0]))
    assert not point_mass().any()
    np.testing.assert_allclose(cylinder(1.0, 1.0, 0.0, "x"), np.diag([0.5, 0.25, 0.25]))


def test_examples_6_1_and_6_2():
    """A box of sides w (x), l (y), h (z): about its corner (6.1), ᴬI_xx = m/3 (l² + h²), ᴬI_xy = m w l / 4;
    about its centre (6.2), ᶜI_zz = m/12 (w² + l²), ᶜI_xy = 0."""
    centre = box(m, w, l, h)
    corner = parallel_axis(centre, m, (w / 2, l / 2, h / 2))
    assert sympy.simplify(corner[0, 0] - m / 3 * (l**2 + h**2)) == 0
    I_xy, I_xz, I_yz = products_of_inertia(corner)
    assert sympy.simplify(I_xy - m * w * l / 4) == 0 and sympy.simplify(I_yz - m * l * h / 4) == 0
    assert sympy.simplify(centre[2, 2] - m / 12 * (w**2 + l**2)) == 0 and products_of_inertia(centre)[0] == 0


def test_rotation_keeps_the_principal_moments():
    I = parallel_axis(box(2.0, 0.3, 0.5, 0.7), 2.0, [0.1, -0.2, 0.3])
    turn = Rotation.from_rotvec([0.3, -1.1, 0.4]).as_matrix()
    turned = rotate(I, turn)
    np.testing.assert_allclose(np.linalg.eigvalsh(turned), np.linalg.eigvalsh(I), rtol=1e-13)
    moments, axes = principal_axes(turned)
    np.testing.assert_allclose(axes.T @ turned @ axes, np.diag(moments), atol=1e-13)
    symbolic = rotate(box(m, a, b, c), turn)
    np.testing.assert_allclose(np.array(sympy.Matrix(symbolic).subs({m: 2, a: 0.3, b: 0.5, c: 0.7}), dtype=float),
                               rotate(box(2.0, 0.3, 0.5, 0.7), turn), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("tensor, problem", [
    (np.diag([1.0, 1.0, 1.0]), None),
    (np.zeros((3, 3)), None),
    (np.diag([0.01, 0.01, 0.05]), "breaks the triangle inequality (principal moments 0.01 + 0.01 < 0.05)"),
    (np.diag([-0.1, 1.0, 1.0]), "not positive semi-definite"),
    (np.array([[1.0, 0.2, 0], [0.1, 1.0, 0], [0, 0, 1.0]]), "not symmetric"),
])
def test_physical_problems(tensor, problem):
    found = physical_problems(tensor)
    if problem is None:
        assert found == []
    else:
        assert any(problem in p for p in found), found
