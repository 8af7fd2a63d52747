"""Symbolic dynamics: the closed forms of the same recursions run on sympy expressions, in Craig's notation.

The Newton–Euler and Lagrangian code run unchanged on sympy expressions (see
:mod:`course_dynamics.core.algebra`), here on the exact models of
:mod:`course_dynamics.core.parameters`, whose table names the parameter symbols
(m1, l1, Izz1, g, …). This module turns their results into closed forms:

* :func:`derive` gives τ, M, V, G and Craig's B, C (6.63)–(6.65), simplified;
* :func:`derive_cartesian` gives J, M_x, V_x, G_x of (6.99);
* :func:`canonical` is an exact normal form (to compare two derivations);
* :func:`numeric_functions` compiles closed forms into vectorised numpy code.

``decimals=N`` (``--decimal N`` on the command line) writes the model's numbers
as N-digit decimals instead of exact fractions: readable closed forms for
real robots, whose URDF numbers become long rationals otherwise.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import StateError
from . import lagrange
from .cartesian import (
    ROW_NAMES,
    jacobian,
    jacobian_dot,
    operational_space_terms,
    row_indices,
)
from .dynamics import (
    gravity_torques,
    mass_matrix,
    mass_matrix_by_unit_accelerations,
    velocity_torques,
)
from .lagrange import velocity_pairs
from .model import Model
from .newton_euler import inverse_dynamics
from .parameters import SymbolError, check_symbolic_size, joint_symbols, parameter_values, symbolic_model

#: The most digits ``decimals`` may ask for (:func:`check_decimals`).
MAX_DECIMALS = 30
#: The two formulations :func:`derive` runs, Newton–Euler (the default) and Lagrange.
METHODS = ("newton-euler", "lagrange")


def _sympy():
    import sympy

    return sympy


def canonical(expression, angles):
    """An exact normal form: trig expanded, sin²θ → 1 − cos²θ for every joint angle θ.

    Two expressions are equal as functions iff their canonical forms are
    identical, which is much faster to decide than ``simplify(a − b) == 0``.

    Parameters
    ----------
    expression : sympy.Expr or number
        The expression.
    angles : sequence of sympy.Symbol
        The joint angles θ whose sines and cosines are reduced.

    Returns
    -------
    sympy.Expr
        Its canonical form.

    Examples
    --------

    >>> import sympy
    >>> q1 = sympy.Symbol("q1", real=True)
    >>> canonical(sympy.sin(q1)**2 + sympy.cos(q1)**2, [q1]), canonical(sympy.sin(2 * q1), [q1])
    (1, 2*sin(q1)*cos(q1))
    """
    sympy = _sympy()
    expression = sympy.expand(sympy.expand_trig(sympy.sympify(expression)))
    replacements, back, ideal, generators = {}, {}, [], []
    for angle in angles:
        c, s = sympy.Dummy("c"), sympy.Dummy("s")
        replacements[sympy.cos(angle)], replacements[sympy.sin(angle)] = c, s
        back[c], back[s] = sympy.cos(angle), sympy.sin(angle)
        ideal.append(s**2 + c**2 - 1)
        generators += [s, c]
    polynomial = sympy.expand(expression.xreplace(replacements))
    if polynomial.free_symbols & set(generators):
        polynomial = sympy.reduced(polynomial, ideal, *generators, order="lex")[1]
    return sympy.expand(polynomial.xreplace(back))


def tidy(expression, angles):
    """A readable form for display: canonical, then sympy's trigonometric simplification.

    Parameters
    ----------
    expression : sympy.Expr or number
        The expression.
    angles : sequence of sympy.Symbol
        The joint angles θ whose sines and cosines are reduced.

    Returns
    -------
    sympy.Expr
        The simplified expression, common factors taken out.

    Examples
    --------

    >>> import sympy
    >>> q1, l = sympy.Symbol("q1", real=True), sympy.Symbol("l")
    >>> tidy(l * sympy.sin(q1)**2 + l * sympy.cos(q1)**2 + 2 * l, [q1])
    3*l
    """
    sympy = _sympy()
    return sympy.factor_terms(sympy.trigsimp(canonical(expression, angles)))


@dataclass(frozen=True)
class Derivation:
    """Closed forms of one robot, joints in model order (sympy objects).

    ``tau`` (n,), ``M`` (n, n), ``V`` (n,), ``G`` (n,), ``B`` (n, n(n−1)/2) and
    ``C`` (n, n) with V = B [Θ̇Θ̇] + C [Θ̇²] (6.63); ``pairs`` are the (j, k) of [Θ̇Θ̇].

    Parameters
    ----------
    joints : tuple of str
        The joints, in model order.
    prismatic : tuple of bool
        Whether each joint is prismatic.
    method : str
        The formulation used (:data:`METHODS`).
    q : tuple of sympy.Symbol
        Θ's symbols, ``q_<joint>``.
    qd : tuple of sympy.Symbol
        Θ̇'s symbols, ``qd_<joint>``.
    qdd : tuple of sympy.Symbol
        Θ̈'s symbols, ``qdd_<joint>``.
    parameters : dict
        Each parameter kept symbolic, by name → its ``sympy.Symbol``.
    tau : list, length n
        τ, N·m (N for a prismatic joint).
    M : list of list, n × n
        M(Θ), kg·m² (kg).
    V : list, length n
        V(Θ, Θ̇), N·m (N).
    G : list, length n
        G(Θ), N·m (N).
    B : list of list, n × n(n−1)/2
        Craig's Coriolis coefficients B(Θ) of (6.63).
    C : list of list, n × n
        Craig's centrifugal coefficients C(Θ) of (6.63).
    pairs : list of tuple of (int, int)
        The (j, k), j < k, of B's columns (:func:`~course_dynamics.core.lagrange.velocity_pairs`).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> d = derive(load_robot("two_link"), ["m2", "l1", "l2"])
    >>> d.pairs, d.B   # Craig (6.63): V = B [θ̇₁θ̇₂] + C [θ̇₁², θ̇₂²]
    ([(0, 1)], [[-2*l1*l2*m2*sin(q_theta2)], [0]])
    """

    joints: tuple[str, ...]
    prismatic: tuple[bool, ...]
    method: str
    q: tuple
    qd: tuple
    qdd: tuple
    parameters: dict
    tau: list
    M: list
    V: list
    G: list
    B: list
    C: list
    pairs: list


def decimal(expression, digits: int | None):
    """``expression`` with its fractions written as ``digits``-digit decimals (unchanged for None).

    Parameters
    ----------
    expression : sympy.Expr or number
        The expression.
    digits : int or None
        Significant digits; None leaves the expression as it is.

    Returns
    -------
    sympy.Expr
        The expression with every non-integer rational a ``sympy.Float``.

    Examples
    --------

    >>> import sympy
    >>> x = sympy.Symbol("x")
    >>> decimal(sympy.Rational(981, 100) * x + sympy.Rational(1, 3), 3), decimal(x / 3, None)
    (9.81*x + 0.333, x/3)
    """
    if digits is None:
        return expression
    sympy = _sympy()
    expression = sympy.sympify(expression)
    return expression.xreplace({r: sympy.Float(r, digits)
                                for r in expression.atoms(sympy.Rational) if not r.is_Integer})


def check_decimals(decimals) -> None:
    """SymbolError unless ``decimals`` is None or a whole number of digits from 1 to :data:`MAX_DECIMALS`.

    The one check of the ``decimals`` argument, for every symbolic result that takes it (derivations, traces).

    Parameters
    ----------
    decimals : int or None
        The number of digits asked for.

    Raises
    ------
    SymbolError
        If ``decimals`` is neither None nor an int from 1 to :data:`MAX_DECIMALS`.

    Examples
    --------

    >>> check_decimals(4), check_decimals(None)
    (None, None)
    >>> check_decimals(0)
    Traceback (most recent call last):
    course_dynamics.core.parameters.SymbolError: decimals must be a whole number of digits from 1 to 30, got 0
    """
    if decimals is not None and not (isinstance(decimals, int) and 1 <= decimals <= MAX_DECIMALS):
        raise SymbolError(f"decimals must be a whole number of digits from 1 to {MAX_DECIMALS}, got {decimals!r}")


def derive(model: Model, symbols=(), method: str = "newton-euler", simplify: bool = True,
           decimals: int | None = None) -> Derivation:
    """τ, M(Θ), V(Θ, Θ̇), G(Θ), B(Θ), C(Θ) in closed form, by Newton–Euler or Lagrange.

    ``symbols`` names parameters kept symbolic (module table); the rest are the
    URDF's numbers, made exact (or ``decimals``-digit decimals in the result).
    B and C are read off V as the coefficients of θ̇ⱼθ̇ₖ (j < k) and θ̇ⱼ² (6.63)–(6.65).

    Parameters
    ----------
    model : Model
        The robot.
    symbols : iterable of str, optional
        The parameters kept as symbols (the table of :mod:`course_dynamics.core.parameters`: ``m1``, ``l1``,
        ``Izz1``, ``g``, …); the rest are the URDF's numbers, made exact. By default, none.
    method : {"newton-euler", "lagrange"}, optional
        The formulation (:data:`METHODS`).
    simplify : bool, optional
        Simplify each entry for display (the default); ``False`` keeps the canonical form, which is faster.
    decimals : int, optional
        Write the model's numbers as ``decimals``-digit decimals (1 to :data:`MAX_DECIMALS`); exact fractions
        by default.

    Returns
    -------
    Derivation
        τ, M, V, G, B and C, with the symbols they are in.

    Raises
    ------
    SymbolError
        If the robot has too many joints (:data:`~course_dynamics.core.parameters.MAX_SYMBOLIC_JOINTS`), a
        symbol is no parameter of it, a joint name is no identifier, or ``method`` or ``decimals`` is not one
        taken.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> d = derive(load_robot("pendulum"), ["m", "l", "g"])
    >>> d.tau, d.M
    ([l*m*(g*sin(q_theta) + l*qdd_theta)], [[l**2*m]])
    """

    sympy = _sympy()
    check_symbolic_size(model)
    check_decimals(decimals)
    if method not in METHODS:
        raise SymbolError(f"unknown method '{method}' ({' or '.join(METHODS)})")
    exact, parameters = symbolic_model(model, symbols)
    q, qd, qdd = joint_symbols(model)
    if method == "newton-euler":
        tau, M = inverse_dynamics(exact, q, qd, qdd), mass_matrix_by_unit_accelerations(exact, q)
        V, G = velocity_torques(exact, q, qd), gravity_torques(exact, q)
    else:
        tau, M = lagrange.inverse_dynamics(exact, q, qd, qdd), lagrange.mass_matrix(exact, q)
        V, G = lagrange.velocity_torques(exact, q, qd), lagrange.gravity_torques(exact, q)
    exact_form = (lambda e: tidy(e, q)) if simplify else (lambda e: canonical(e, q))

    def form(e):
        return decimal(exact_form(e), decimals)

    n = model.n
    V = [canonical(v, q) for v in V]
    pairs = velocity_pairs(n)
    B = [[form(sympy.expand(v).coeff(qd[j], 1).coeff(qd[k], 1)) for j, k in pairs] for v in V]
    C = [[form(sympy.expand(v).coeff(qd[j], 2)) for j in range(n)] for v in V]
    return Derivation(
        joints=model.joint_names, prismatic=tuple(b.is_prismatic for b in model.coordinate_bodies), method=method,
        q=tuple(q), qd=tuple(qd), qdd=tuple(qdd), parameters=parameters,
        tau=[form(t) for t in tau], M=[[form(x) for x in row] for row in M], V=[form(v) for v in V],
        G=[form(x) for x in G], B=B, C=C, pairs=pairs,
    )


def numeric_functions(derivation: Derivation, parameter_values: dict | None = None):
    """Vectorised numpy functions from closed forms, with common subexpressions shared.

    Returns a dict of callables: ``M(q)`` → (n, n) or (N, n, n), ``V(q, qd)``,
    ``G(q)``, ``tau(q, qd, qdd)`` → (n,) or (N, n). Parameter symbols must be
    given numbers in ``parameter_values``.

    Parameters
    ----------
    derivation : Derivation
        The closed forms (:func:`derive`).
    parameter_values : dict, optional
        A number for each parameter kept symbolic, by name (kg, m, kg·m², m/s²).

    Returns
    -------
    dict of str to callable
        ``"M"``, ``"V"``, ``"G"`` and ``"tau"``; each takes arrays of shape (n,) or (N, n), rad, rad/s, rad/s²
        (m, m/s, m/s²), and returns kg·m² or N·m (kg or N for a prismatic joint).

    Raises
    ------
    SymbolError
        If a parameter symbol of ``derivation`` is given no value, a name it does not have, or a value that is not
        a finite number.
    StateError
        From a returned function: if an array is not finite, or its last axis is not the n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> functions = numeric_functions(derive(load_robot("pendulum"), ["m"]), {"m": 1.0})
    >>> functions["G"](np.array([0.5])).round(4), functions["G"](np.zeros((3, 1))).shape   # N·m; a batch
    (array([4.7032]), (3, 1))
    """
    sympy = _sympy()
    given = dict(parameter_values or {})
    unknown = sorted(str(k) for k in given if k not in derivation.parameters)
    if unknown:
        raise SymbolError(f"unknown parameter symbols {', '.join(unknown)} (known: "
                          f"{', '.join(derivation.parameters) or 'none'})")
    for name, value in given.items():
        if isinstance(value, bool) or not isinstance(value, (int, float, np.number)) or not np.isfinite(value):
            raise SymbolError(f"parameter {name} must be a finite number, got {value!r}")
    values = {derivation.parameters[k]: v for k, v in given.items()}
    missing = [name for name, symbol in derivation.parameters.items() if symbol not in values]
    if missing:
        raise SymbolError(f"give values for the parameter symbols {', '.join(missing)}")
    q, qd, qdd = (list(v) for v in (derivation.q, derivation.qd, derivation.qdd))

    def compile_(expressions, arguments, shape):
        exprs = [sympy.sympify(e).xreplace(values) for e in expressions]
        function = sympy.lambdify(arguments, exprs, modules="numpy", cse=True)

        def evaluate(*arrays):
            arrays = [np.asarray(a, dtype=float) for a in arrays]
            if any(a.ndim == 0 or a.shape[-1] != len(q) for a in arrays):
                raise StateError(f"each argument needs shape ({len(q)},) or (N, {len(q)}): "
                                 f"got {', '.join(str(a.shape) for a in arrays)}")
            if not all(np.isfinite(a).all() for a in arrays):
                raise StateError("the state holds a value that is not finite (nan or inf)")
            columns = [a[..., j] for a in arrays for j in range(a.shape[-1])]
            batch = np.broadcast_shapes(*(a.shape[:-1] for a in arrays))
            out = [np.broadcast_to(np.asarray(v, dtype=float), batch) for v in function(*columns)]
            return np.stack(out, axis=-1).reshape(batch + shape)

        return evaluate

    n = len(q)
    return {
        "M": compile_([x for row in derivation.M for x in row], q, (n, n)),
        "V": compile_(derivation.V, q + qd, (n,)),
        "G": compile_(derivation.G, q, (n,)),
        "tau": compile_(derivation.tau, q + qd + qdd, (n,)),
    }


@dataclass(frozen=True)
class CartesianDerivation:
    """Closed forms of (6.99) for one frame and task rows: J, M_x, V_x, G_x as sympy matrices.

    Parameters
    ----------
    frame : str
        The URDF link whose origin is the task point.
    rows : tuple of str
        The task rows (:data:`~course_dynamics.core.cartesian.ROW_NAMES`).
    q : tuple of sympy.Symbol
        Θ's symbols.
    qd : tuple of sympy.Symbol
        Θ̇'s symbols.
    parameters : dict
        Each parameter kept symbolic, by name → its ``sympy.Symbol``.
    J : sympy.Matrix
        J(Θ), n × n.
    Mx : sympy.Matrix
        M_x(Θ), n × n.
    Vx : sympy.Matrix
        V_x(Θ, Θ̇), n × 1.
    Gx : sympy.Matrix
        G_x(Θ), n × 1.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> c = derive_cartesian(load_robot("rp_arm"), "link2", rows=["x", "y"], expressed_in="frame")
    >>> print(c.rows, c.J)   # the RP arm in its slider's frame: ∂(x, y)/∂(θ₁, d₂)
    ('x', 'y') Matrix([[0, 1], [q_d2, 0]])
    """

    frame: str
    rows: tuple[str, ...]
    q: tuple
    qd: tuple
    parameters: dict
    J: object
    Mx: object
    Vx: object
    Gx: object


def derive_cartesian(model: Model, frame: str, rows=None, expressed_in: str = "base", symbols=(),
                     decimals: int | None = None) -> CartesianDerivation:
    """M_x = J⁻ᵀ M J⁻¹, V_x = J⁻ᵀ (V − M J⁻¹ J̇ Θ̇), G_x = J⁻ᵀ G (6.99) in closed form.

    The same Jacobian and dynamics functions as the numeric path, on symbols; the
    selected task rows must make J square. For the two-link arm in its tool frame
    this is Craig's example 6.6.

    Parameters
    ----------
    model : Model
        The robot.
    frame : str
        A URDF link: the frame whose origin is the task point.
    rows : sequence of int or str, optional
        The task rows (:data:`~course_dynamics.core.cartesian.ROW_NAMES`), n of them; all six by default.
    expressed_in : {"base", "frame"}, optional
        The coordinates of J.
    symbols : iterable of str, optional
        The parameters kept as symbols (the table of :mod:`course_dynamics.core.parameters`: ``m1``, ``l1``,
        ``Izz1``, ``g``, …); the rest are the URDF's numbers, made exact. By default, none.
    decimals : int, optional
        Write the model's numbers as ``decimals``-digit decimals (1 to :data:`MAX_DECIMALS`); exact fractions
        by default.

    Returns
    -------
    CartesianDerivation
        J, M_x, V_x and G_x in closed form.

    Raises
    ------
    SymbolError
        If the rows do not make J square, the robot has too many joints, a symbol is no parameter of it, or
        ``decimals`` is not one taken.
    ModelError
        If the robot has no link ``frame``.
    InputError
        If ``expressed_in`` or a row is unknown.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> c = derive_cartesian(load_robot("rp_arm"), "link2", rows=["x", "y"], expressed_in="frame", symbols=["m2"])
    >>> print(c.Mx)   # m₂ along the slider; across it m₂ + (inertia about joint 1 = 1/4 kg·m²)/d₂²
    Matrix([[m2, 0], [0, m2 + 1/(4*q_d2**2)]])
    """

    sympy = _sympy()
    check_symbolic_size(model)
    check_decimals(decimals)
    exact, parameters = symbolic_model(model, symbols)
    q, qd, _ = joint_symbols(model)
    indices = row_indices(rows)
    if len(indices) != model.n:
        raise SymbolError(f"the task has {len(indices)} rows but robot '{model.name}' has {model.n} joints: "
                          f"(6.99) needs a square Jacobian; choose {model.n} rows")
    J = sympy.Matrix(jacobian(exact, q, frame, expressed_in, indices))
    J_dot = sympy.Matrix(jacobian_dot(exact, q, qd, frame, expressed_in, indices))
    M, V, G = (sympy.Matrix(mass_matrix(exact, q)), sympy.Matrix(velocity_torques(exact, q, qd)),
               sympy.Matrix(gravity_torques(exact, q)))
    Mx, Vx, Gx = operational_space_terms(J.inv(), J_dot, M, V, G, sympy.Matrix(qd))

    def clean(matrix):
        return matrix.applyfunc(lambda e: decimal(sympy.factor_terms(sympy.simplify(e)), decimals))

    return CartesianDerivation(
        frame=frame, rows=tuple(ROW_NAMES[i] for i in indices), q=tuple(q), qd=tuple(qd), parameters=parameters,
        J=clean(J), Mx=clean(Mx), Vx=clean(Vx), Gx=clean(Gx),
    )


__all__ = ["CartesianDerivation", "Derivation", "MAX_DECIMALS", "METHODS", "canonical", "check_decimals", "decimal",
           "derive", "derive_cartesian", "numeric_functions", "tidy"]
