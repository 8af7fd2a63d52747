"""Three-vector algebra that works on floats, numpy batches and sympy symbols.

The Newton–Euler recursion is written once, on :class:`Vec3` and :class:`Mat3`,
whose components are *scalars* of any of these kinds:

============================  ==========================================
component type                use
============================  ==========================================
``float``                     one state (fastest: plain Python arithmetic)
``numpy.ndarray`` shape (N,)  a batch of N states, vectorised over N
``sympy.Expr``                symbolic derivations
:class:`Dual`                 exact derivatives (forward-mode), e.g. ∂M/∂Θ
``complex``                   complex-step derivatives (used by the tests)
============================  ==========================================

Notation: ``cross(a, b)`` is a × b, ``dot(a, b)`` is aᵀb, ``R @ v`` is the
rotation of v, ``R.T`` the transpose (so ``R.T @ v`` maps a vector from the
parent frame into the child frame when R = ᵖᵢR, the orientation of frame i
in its parent p).
"""
from __future__ import annotations

import cmath
import math

import numpy as np


class Vec3:
    """A column 3-vector with components x, y, z of any scalar kind.

    Vectors add, subtract, negate, scale by a scalar (on either side) and divide by one; ``x, y, z = v``
    unpacks them.

    Parameters
    ----------
    x, y, z : float, numpy.ndarray of shape (N,), sympy.Expr, Dual or complex
        The components (one state, a batch of N, a symbol, …), in the vector's own unit.

    Examples
    --------

    >>> v = Vec3(1.0, 2.0, 3.0)
    >>> 2 * v - Vec3.of([1.0, 0.0, 0.0])
    Vec3(1.0, 4.0, 6.0)
    """

    __slots__ = ("x", "y", "z")
    __array_ufunc__ = None  # numpy defers ``array * Vec3`` to Vec3.__rmul__

    def __init__(self, x, y, z):
        self.x = x
        self.y = y
        self.z = z

    @classmethod
    def of(cls, values) -> "Vec3":
        """Vec3 from a length-3 sequence (a numpy array becomes Python floats).

        Parameters
        ----------
        values : sequence or numpy.ndarray, shape (3,)
            The components.

        Returns
        -------
        Vec3
            The vector; Python floats for a numeric array (fast arithmetic), the entries as they are otherwise.

        Examples
        --------
        >>> Vec3.of(np.array([1.0, 2.0, 3.0]))
        Vec3(1.0, 2.0, 3.0)
        """
        if isinstance(values, np.ndarray) and values.dtype != object:
            values = values.tolist()
        return cls(values[0], values[1], values[2])

    def __add__(self, other: "Vec3") -> "Vec3":
        return Vec3(self.x + other.x, self.y + other.y, self.z + other.z)

    def __sub__(self, other: "Vec3") -> "Vec3":
        return Vec3(self.x - other.x, self.y - other.y, self.z - other.z)

    def __neg__(self) -> "Vec3":
        return Vec3(-self.x, -self.y, -self.z)

    def __mul__(self, s) -> "Vec3":
        return Vec3(self.x * s, self.y * s, self.z * s)

    def __rmul__(self, s) -> "Vec3":
        return Vec3(s * self.x, s * self.y, s * self.z)

    def __truediv__(self, s) -> "Vec3":
        return Vec3(self.x / s, self.y / s, self.z / s)

    def __iter__(self):
        return iter((self.x, self.y, self.z))

    def __repr__(self) -> str:
        return f"Vec3({self.x!r}, {self.y!r}, {self.z!r})"


def cross(a: Vec3, b: Vec3) -> Vec3:
    """a × b.

    Parameters
    ----------
    a : Vec3
        The left factor.
    b : Vec3
        The right factor.

    Returns
    -------
    Vec3
        The cross product a × b.

    Examples
    --------

    >>> cross(Vec3(1, 0, 0), Vec3(0, 1, 0))   # x × y = z
    Vec3(0, 0, 1)
    """
    return Vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x)


def point_acceleration(v_dot: Vec3, omega_dot: Vec3, omega: Vec3, P: Vec3) -> Vec3:
    """v̇ + ω̇ × P + ω × (ω × P): acceleration of a point P fixed in a moving frame (6.12).

    Written out in components because it is the innermost step of the recursion.

    Parameters
    ----------
    v_dot : Vec3
        v̇, the linear acceleration of the moving frame's origin, m/s².
    omega_dot : Vec3
        ω̇, the frame's angular acceleration, rad/s².
    omega : Vec3
        ω, the frame's angular velocity, rad/s.
    P : Vec3
        The point's position from the frame's origin, m (all four in the same coordinates).

    Returns
    -------
    Vec3
        The point's acceleration, m/s², in those coordinates.

    Examples
    --------

    >>> # a point 1 m out on a frame spinning at 2 rad/s about z: centripetal −ω² r
    >>> point_acceleration(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 2.0), Vec3(1.0, 0, 0))
    Vec3(-4.0, 0.0, 0.0)
    """
    wx, wy, wz = omega.x, omega.y, omega.z
    px, py, pz = P.x, P.y, P.z
    # ω × P
    cx, cy, cz = wy * pz - wz * py, wz * px - wx * pz, wx * py - wy * px
    return Vec3(
        v_dot.x + (omega_dot.y * pz - omega_dot.z * py) + (wy * cz - wz * cy),
        v_dot.y + (omega_dot.z * px - omega_dot.x * pz) + (wz * cx - wx * cz),
        v_dot.z + (omega_dot.x * py - omega_dot.y * px) + (wx * cy - wy * cx),
    )


def dot(a: Vec3, b: Vec3):
    """aᵀ b.

    Parameters
    ----------
    a : Vec3
        The left factor.
    b : Vec3
        The right factor.

    Returns
    -------
    float, numpy.ndarray of shape (N,) or sympy.Expr
        The scalar product, of the components' kind.

    Examples
    --------

    >>> dot(Vec3(1, 2, 3), Vec3(4, 5, 6))
    32
    """
    return a.x * b.x + a.y * b.y + a.z * b.z


class Mat3:
    """A 3×3 matrix stored by rows; ``R @ v`` and ``R @ S`` are products.

    Iterating over it gives its rows.

    Parameters
    ----------
    rows : tuple of tuple
        ((a, b, c), (d, e, f), (g, h, i)), entries of any scalar kind (as :class:`Vec3`'s components); kept
        as the attribute ``rows``.

    Examples
    --------

    >>> R = Mat3.of(np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]))   # 90° about z
    >>> R @ Vec3(1.0, 0.0, 0.0)
    Vec3(0.0, 1.0, 0.0)
    >>> (R.T @ R).rows
    ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    """

    __slots__ = ("rows",)
    __array_ufunc__ = None

    def __init__(self, rows):
        self.rows = rows  # ((a, b, c), (d, e, f), (g, h, i))

    @classmethod
    def of(cls, matrix) -> "Mat3":
        """Mat3 from a 3×3 nested sequence or numpy array.

        Parameters
        ----------
        matrix : sequence or numpy.ndarray, shape (3, 3)
            The entries, by rows.

        Returns
        -------
        Mat3
            The matrix; Python floats for a numeric array, the entries as they are otherwise.

        Examples
        --------
        >>> Mat3.of(np.eye(3)).rows[0]
        (1.0, 0.0, 0.0)
        """
        if isinstance(matrix, np.ndarray) and matrix.dtype != object:
            matrix = matrix.tolist()
        return cls(tuple(tuple(row) for row in matrix))

    @property
    def T(self) -> "Mat3":
        """The transpose; ``R.T @ v`` maps a vector from the parent frame into the child frame when R = ᵖᵢR."""
        (a, b, c), (d, e, f), (g, h, i) = self.rows
        return Mat3(((a, d, g), (b, e, h), (c, f, i)))

    def __matmul__(self, other):
        (a, b, c), (d, e, f), (g, h, i) = self.rows
        if isinstance(other, Vec3):
            x, y, z = other.x, other.y, other.z
            return Vec3(a * x + b * y + c * z, d * x + e * y + f * z, g * x + h * y + i * z)
        cols = tuple(zip(*other.rows))
        return Mat3(tuple(tuple(r[0] * k[0] + r[1] * k[1] + r[2] * k[2] for k in cols) for r in self.rows))

    def __iter__(self):
        return iter(self.rows)


# ---------------------------------------------------------------------------
# Scalars: exact forward-mode derivatives and the trigonometric dispatch.

class Dual:
    """a + b·ε with ε² = 0: carries a value and its exact directional derivative.

    Duals add, subtract, negate and multiply (with each other and with plain scalars); :class:`Vec3` and
    :class:`Mat3` take them as components.

    Parameters
    ----------
    a : float or numpy.ndarray, shape (N,)
        The value.
    b : float or numpy.ndarray, shape (N,)
        Its derivative along the chosen direction.

    Examples
    --------

    >>> x = Dual(3.0, 1.0)   # x = 3 with dx = 1
    >>> x * x + 2 * x        # x² + 2x = 15, derivative 2x + 2 = 8
    Dual(15.0, 8.0)
    """

    __slots__ = ("a", "b")
    __array_ufunc__ = None

    def __init__(self, a, b):
        self.a = a
        self.b = b

    def __add__(self, o):
        if isinstance(o, Dual):
            return Dual(self.a + o.a, self.b + o.b)
        return Dual(self.a + o, self.b)

    __radd__ = __add__

    def __sub__(self, o):
        if isinstance(o, Dual):
            return Dual(self.a - o.a, self.b - o.b)
        return Dual(self.a - o, self.b)

    def __rsub__(self, o):
        return Dual(o - self.a, -self.b)

    def __neg__(self):
        return Dual(-self.a, -self.b)

    def __mul__(self, o):
        if isinstance(o, (Vec3, Mat3)):
            return NotImplemented  # scalar × vector: let Vec3.__rmul__ scale each component
        if isinstance(o, Dual):
            return Dual(self.a * o.a, self.a * o.b + self.b * o.a)
        return Dual(self.a * o, self.b * o)

    __rmul__ = __mul__

    def __repr__(self) -> str:
        return f"Dual({self.a!r}, {self.b!r})"


def cos_sin(angle):
    """(cos θ, sin θ) for an angle of any scalar kind.

    >>> cos_sin(0.0)
    (1.0, 0.0)
    >>> cos_sin(Dual(0.0, 1.0))   # derivatives: −sin 0, cos 0
    (Dual(1.0, -0.0), Dual(0.0, 1.0))
    """
    if isinstance(angle, float):
        return math.cos(angle), math.sin(angle)
    if isinstance(angle, Dual):
        c, s = cos_sin(angle.a)
        return Dual(c, -s * angle.b), Dual(s, c * angle.b)
    if isinstance(angle, np.ndarray):
        return np.cos(angle), np.sin(angle)
    if isinstance(angle, complex):
        return cmath.cos(angle), cmath.sin(angle)
    if isinstance(angle, int):
        return math.cos(angle), math.sin(angle)
    if hasattr(angle, "cos_sin"):  # a traced scalar (course_dynamics.core.compiled) records the call
        return angle.cos_sin()
    import sympy  # only symbolic use reaches here

    return sympy.cos(angle), sympy.sin(angle)


def rotation_from_parts(parts, c, s) -> Mat3:
    """R = K₀ + c·K_c + s·K_s, entry by entry, for precomputed constant parts.

    A rotation by θ about a fixed unit axis a, composed on the left with a
    constant R₀, is R₀ Rot(a, θ) = R₀ a aᵀ + cos θ · R₀ (1 − a aᵀ) + sin θ · R₀ [a]ₓ
    (Rodrigues). ``parts`` holds those three constant matrices as 3×3 nested
    tuples; products with exact zeros are skipped, which keeps symbolic output
    free of 0·sin θ clutter and saves work for coordinate axes.

    >>> from course_dynamics import load_robot
    >>> body = load_robot("rrr_arm").bodies[0]               # axis z, no fixed rotation
    >>> rotation_from_parts(body.rotation_parts, 0.0, 1.0).rows   # θ = 90°: cos θ = 0, sin θ = 1
    ((0.0, -1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    """
    K0, Kc, Ks = parts
    rows = []
    for r0, rc, rs in zip(K0, Kc, Ks):
        row = []
        for k0, kc, ks in zip(r0, rc, rs):
            value = k0
            if kc != 0:
                value = kc * c if value == 0 else value + kc * c
            if ks != 0:
                value = ks * s if (not isinstance(value, np.ndarray) and value == 0) else value + ks * s
            row.append(value)
        rows.append(tuple(row))
    return Mat3(tuple(rows))


__all__ = ["Dual", "Mat3", "Vec3", "cross", "dot", "point_acceleration"]
