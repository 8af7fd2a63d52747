"""Mass distribution: inertia tensors of simple bodies, moving and turning them, and checking them.

The notes print this section's equations (the inertia tensor, the parallel-axis theorem) without
numbers; it is Craig's §6.3.

An inertia tensor is the 3×3 matrix ᴬI = ∭ (rᵀr 1 − r rᵀ) ρ dv about the origin
of a frame {A} (kg·m²). Its diagonal holds the moments of inertia
I_xx = ∭ (y² + z²) ρ dv, …; off the diagonal stand the *negated* products of
inertia, −I_xy with I_xy = ∭ x y ρ dv, as Craig writes the matrix. Every
function takes numbers or sympy symbols and returns a numpy array (object
dtype for symbols).

========================  ==========================================================
function                  gives
========================  ==========================================================
``box(m, a, b, c)``       a solid box with sides a, b, c along x, y, z, about its centre
``rod(m, length, axis)``  a thin rod along ``axis`` ("x", "y" or "z"), about its centre
``cylinder(m, r, h, …)``  a solid cylinder of radius r, height h along ``axis``
``sphere(m, r)``          a solid sphere
``point_mass()``          the zero tensor: a point mass has no inertia about its centre
``parallel_axis``         ᴬI = ᶜI + m (pᵀp 1 − p pᵀ): from the centre of mass to a
                          point at −p from it, i.e. ᴬP_C = p; in products of inertia
                          ᴬI_xy = ᶜI_xy + m x_c y_c (the notes print − here)
``rotate(I, R)``          the same tensor in rotated axes: ᴬI = ᴬ_BR ᴮI ᴬ_BRᵀ
``products_of_inertia``   (I_xy, I_xz, I_yz) from the matrix, with Craig's sign
``principal_axes(I)``     principal moments (ascending) and axes (columns)
``physical_problems(I)``  what makes a tensor impossible for a real body, if anything:
                          asymmetry, a negative moment, a broken triangle inequality
========================  ==========================================================

>>> box(12.0, 1.0, 2.0, 3.0).diagonal().tolist()     # m/12 (b² + c²), …
[13.0, 10.0, 5.0]
>>> float(parallel_axis(box(12.0, 1.0, 2.0, 3.0), 12.0, [0.5, 1.0, 1.5])[0, 1])   # −ᴬI_xy = −m x_c y_c
-6.0
"""
from __future__ import annotations

import numpy as np

AXES = {"x": 0, "y": 1, "z": 2}
#: The round-off allowed in the physical checks (:func:`physical_problems`), kg·m².
TOLERANCE = 1e-12


def _is_symbolic(*values) -> bool:
    return any(not isinstance(v, (int, float, np.integer, np.floating))
               for v in np.ravel(np.array(values, dtype=object)))


def _tensor(rows) -> np.ndarray:
    flat = [x for row in rows for x in row]
    return np.array(rows, dtype=object if _is_symbolic(*flat) else float)


def box(m, a, b, c) -> np.ndarray:
    """A solid box of mass m with sides a (x), b (y), c (z), about its centre: diag(m/12 (b² + c²), …).

    Parameters
    ----------
    m : float or sympy.Expr
        The mass, kg.
    a : float or sympy.Expr
        The side along x, m.
    b : float or sympy.Expr
        The side along y, m.
    c : float or sympy.Expr
        The side along z, m.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        ᶜI about the centre, box axes, kg·m²; of object dtype when an argument is a sympy expression.

    Examples
    --------
    >>> box(12.0, 1.0, 2.0, 3.0).diagonal().tolist()   # kg·m²
    [13.0, 10.0, 5.0]
    """
    return _tensor([[m * (b**2 + c**2) / 12, 0, 0], [0, m * (a**2 + c**2) / 12, 0], [0, 0, m * (a**2 + b**2) / 12]])


def rod(m, length, axis: str = "x") -> np.ndarray:
    """A thin rod along ``axis``, about its centre: m l²/12 about the two other axes, 0 about its own.

    Parameters
    ----------
    m : float or sympy.Expr
        The mass, kg.
    length : float or sympy.Expr
        The rod's length l, m.
    axis : {"x", "y", "z"}, optional
        The rod's axis.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        ᶜI about the centre, kg·m²; of object dtype when an argument is a sympy expression.

    Examples
    --------
    >>> rod(3.0, 2.0, "z").diagonal().tolist()   # m l²/12 across, 0 along the rod
    [1.0, 1.0, 0.0]
    """
    moments = [m * length**2 / 12] * 3
    moments[AXES[axis]] = 0
    return _tensor([[moments[0], 0, 0], [0, moments[1], 0], [0, 0, moments[2]]])


def cylinder(m, r, h, axis: str = "z") -> np.ndarray:
    """A solid cylinder of radius r and height h along ``axis``: m r²/2 about it, m (3r² + h²)/12 across.

    Parameters
    ----------
    m : float or sympy.Expr
        The mass, kg.
    r : float or sympy.Expr
        The radius, m.
    h : float or sympy.Expr
        The height, m.
    axis : {"x", "y", "z"}, optional
        The cylinder's axis.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        ᶜI about the centre, kg·m²; of object dtype when an argument is a sympy expression.

    Examples
    --------
    >>> cylinder(2.0, 1.0, 3.0).diagonal().tolist()   # axis z
    [2.0, 2.0, 1.0]
    """
    moments = [m * (3 * r**2 + h**2) / 12] * 3
    moments[AXES[axis]] = m * r**2 / 2
    return _tensor([[moments[0], 0, 0], [0, moments[1], 0], [0, 0, moments[2]]])


def sphere(m, r) -> np.ndarray:
    """A solid sphere: 2/5 m r² about every axis through its centre.

    Parameters
    ----------
    m : float or sympy.Expr
        The mass, kg.
    r : float or sympy.Expr
        The radius, m.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        ᶜI about the centre, kg·m²; of object dtype when an argument is a sympy expression.

    Examples
    --------
    >>> sphere(5.0, 1.0).diagonal().tolist()
    [2.0, 2.0, 2.0]
    """
    moment = 2 * m * r**2 / 5
    return _tensor([[moment, 0, 0], [0, moment, 0], [0, 0, moment]])


def point_mass() -> np.ndarray:
    """A point mass: no inertia about its own centre (Craig's two-link arm, section 6.7).

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        The zero tensor, kg·m².

    Examples
    --------
    >>> parallel_axis(point_mass(), 2.0, [0.5, 0.0, 0.0]).diagonal().tolist()   # m₁ at l₁: m₁l₁² about y and z
    [0.0, 0.5, 0.5]
    """
    return np.zeros((3, 3))


def parallel_axis(I_c, m, p) -> np.ndarray:
    """ᴬI = ᶜI + m (pᵀp 1 − p pᵀ) (6.25): the tensor about a point {A} for which ᴬP_C = p (the COM's position).

    Parameters
    ----------
    I_c : array_like, shape (3, 3)
        ᶜI, the tensor about the centre of mass, kg·m².
    m : float or sympy.Expr
        The mass, kg.
    p : array_like, shape (3,)
        ᴬP_C, the centre of mass seen from the point {A}, in the tensor's axes, m.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        ᴬI about {A}, the same axes, kg·m²; of object dtype when an argument is a sympy expression.

    Examples
    --------
    >>> import sympy
    >>> m, l = sympy.symbols("m l", positive=True)
    >>> parallel_axis(rod(m, l), m, [l / 2, 0, 0])[2, 2]   # a rod about its end: m l²/12 + m l²/4
    l**2*m/3
    """
    x, y, z = p
    shift = [[y**2 + z**2, -x * y, -x * z], [-x * y, x**2 + z**2, -y * z], [-x * z, -y * z, x**2 + y**2]]
    I_c = np.asarray(I_c)
    return _tensor([[I_c[i, j] + m * shift[i][j] for j in range(3)] for i in range(3)])


def rotate(I, R) -> np.ndarray:
    """ᴬI = R ᴮI Rᵀ for R = ᴬ_BR: the same body's tensor in the axes of {A}.

    Parameters
    ----------
    I : array_like, shape (3, 3)
        ᴮI, the tensor in the axes of {B}, kg·m².
    R : array_like, shape (3, 3)
        ᴬ_BR, the orientation of {B} in {A}.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        ᴬI, the same tensor in the axes of {A}, kg·m²; of object dtype when an argument is a sympy expression.

    Examples
    --------
    >>> R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])   # 90° about z
    >>> rotate(box(12.0, 1.0, 2.0, 3.0), R).diagonal().tolist()               # the x and y moments swap
    [10.0, 13.0, 5.0]
    """
    I, R = np.asarray(I), np.asarray(R)
    if I.dtype == object or R.dtype == object:
        import sympy

        return np.array(sympy.Matrix(R) * sympy.Matrix(I) * sympy.Matrix(R).T, dtype=object)
    return R @ I @ R.T


def products_of_inertia(I) -> tuple:
    """(I_xy, I_xz, I_yz) = (−I[0,1], −I[0,2], −I[1,2]): Craig's products of inertia from the matrix.

    Parameters
    ----------
    I : array_like, shape (3, 3)
        An inertia tensor, kg·m².

    Returns
    -------
    tuple
        (I_xy, I_xz, I_yz), kg·m²: floats or sympy expressions, as the tensor's entries.

    Examples
    --------
    >>> I = parallel_axis(box(12.0, 1.0, 2.0, 3.0), 12.0, [0.5, 1.0, 1.5])
    >>> [float(x) for x in products_of_inertia(I)]   # m x_c y_c, m x_c z_c, m y_c z_c
    [6.0, 9.0, 18.0]
    """
    I = np.asarray(I)
    return -I[0, 1], -I[0, 2], -I[1, 2]


def principal_axes(I) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (ascending, kg·m²) and the unit axes (as columns) of a numeric tensor.

    Parameters
    ----------
    I : array_like, shape (3, 3)
        A numeric, symmetric inertia tensor, kg·m².

    Returns
    -------
    tuple of (numpy.ndarray, numpy.ndarray)
        The principal moments, shape (3,), ascending, kg·m², and the unit principal axes as the columns of
        a (3, 3) array.

    Examples
    --------
    >>> moments, axes = principal_axes(np.diag([3.0, 1.0, 2.0]))
    >>> moments.tolist(), np.abs(axes[:, 0]).tolist()   # the smallest moment is about y
    ([1.0, 2.0, 3.0], [0.0, 1.0, 0.0])
    """
    moments, axes = np.linalg.eigh(np.asarray(I, dtype=float))
    return moments, axes


def physical_problems(I, tolerance: float = TOLERANCE) -> list[str]:
    """Why a numeric tensor cannot belong to a real body: [] if it can.

    It must be symmetric, positive semi-definite (no negative principal moment)
    and obey the triangle inequality of its principal moments, I₁ + I₂ ≥ I₃
    (a body is no thinner than a flat plate). Zero is allowed: a point mass.

    Parameters
    ----------
    I : array_like, shape (3, 3)
        A numeric inertia tensor, kg·m².
    tolerance : float, optional
        The round-off allowed, kg·m² (relative to the largest moment, when that is over 1 kg·m²).

    Returns
    -------
    list of str
        One phrase per problem ("tensor is not symmetric (…)", "breaks the triangle inequality (…)");
        empty when the tensor is physical.

    Examples
    --------
    >>> physical_problems(box(12.0, 1.0, 2.0, 3.0))
    []
    >>> physical_problems(np.diag([1.0, 1.0, 3.0]))
    ['breaks the triangle inequality (principal moments 1 + 1 < 3)']
    """
    I = np.asarray(I, dtype=float)
    if not np.allclose(I, I.T, rtol=0, atol=tolerance):
        return [f"tensor is not symmetric (I[0,1] = {I[0, 1]:g}, I[1,0] = {I[1, 0]:g})"]
    moments = np.linalg.eigvalsh(I)
    scale = max(float(np.abs(moments).max()), 1.0) * tolerance
    problems = []
    if moments[0] < -scale:
        problems.append("tensor is not positive semi-definite "
                        f"(principal moments {', '.join(f'{x:g}' for x in moments)})")
    a, b, c = moments
    if a + b < c - scale:
        problems.append(f"breaks the triangle inequality (principal moments {a:g} + {b:g} < {c:g})")
    return problems


__all__ = ["TOLERANCE", "box", "cylinder", "parallel_axis", "physical_problems", "point_mass", "principal_axes",
           "products_of_inertia", "rod", "rotate", "sphere"]
