"""Symbolic dynamics: the same recursions on sympy expressions, in Craig's notation.

The Newton–Euler and Lagrangian code run unchanged on sympy expressions (see
:mod:`course_dynamics.core.algebra`). This module prepares exact models and turns
their results into closed forms:

* :func:`rationalize` turns a model's floating-point numbers into sympy
  rationals (9.81 → 981/100, cos(π/2) round-off → 0);
* :func:`symbolic_model` also keeps chosen parameters as symbols named as in
  the notes (table below);
* :func:`joint_symbols` gives Θ, Θ̇, Θ̈ as symbols ``q_<joint>``,
  ``qd_<joint>``, ``qdd_<joint>``;
* :func:`derive` gives τ, M, V, G and Craig's B, C (6.63)–(6.65), simplified;
* :func:`canonical` is an exact normal form (to compare two derivations);
* :func:`numeric_functions` compiles closed forms into vectorised numpy code.

Parameter symbols (i is the 1-based joint number; a one-joint robot also takes
the names without the index, as the notes' pendulum ``m``, ``l``, ``g``):

==============  ==============================================================
name            stands for
==============  ==============================================================
``m<i>``        mass of body i
``I<ab><i>``    entry ab (xx, yy, zz, xy, xz, yz) of ᶜⁱIᵢ, the inertia about the COM
``l<i>``        the length of link i: the distance along a frame-i axis to the next
                joint's origin (or, for the last link, to its COM); it replaces that
                value wherever it is a coordinate of ⁱP_Cᵢ or of a child's ⁱP
``lc<i>``       l_{c_i}, the distance from joint i to the centre of mass of link i
                (the single coordinate of ⁱP_Cᵢ); it replaces ⁱP_Cᵢ alone, so a link
                whose mass is not at its tip keeps l<i> and lc<i> apart
``g``           the magnitude of gravity (its direction stays as in the model)
==============  ==============================================================

``decimals=N`` (``--decimal N`` on the command line) writes the model's numbers
as N-digit decimals instead of exact fractions: readable closed forms for
real robots, whose URDF numbers become long rationals otherwise.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, replace

import numpy as np

from ..base.errors import CourseDynamicsError
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

ROUND_OFF = 1e-12
INERTIA_ENTRIES = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
MAX_SYMBOLIC_JOINTS = 4  # beyond this, simplification takes far longer than a lecture
METHODS = ("newton-euler", "lagrange")


class SymbolError(CourseDynamicsError):
    """A symbol name that does not name a parameter of the robot, or a robot too large."""


def _sympy():
    import sympy

    return sympy


def _exact_number(value, tolerance: float = ROUND_OFF):
    sympy = _sympy()
    if isinstance(value, (float, np.floating, int, np.integer)):
        return sympy.nsimplify(float(value), rational=True, tolerance=tolerance)
    return value


def _exact(array, tolerance: float = ROUND_OFF) -> np.ndarray:
    out = np.empty(np.shape(array), dtype=object)
    for index, value in np.ndenumerate(np.asarray(array, dtype=object)):
        out[index] = _exact_number(value, tolerance)
    return out


def rationalize(model: Model, tolerance: float = ROUND_OFF) -> Model:
    """The same robot with every number an exact sympy rational (within ``tolerance``)."""
    bodies = tuple(
        replace(
            body, R0=_exact(body.R0, tolerance), P=_exact(body.P, tolerance), axis=_exact(body.axis, tolerance),
            mass=_exact_number(body.mass, tolerance), p_com=_exact(body.p_com, tolerance),
            I_com=_exact(body.I_com, tolerance),
        )
        for body in model.bodies
    )
    frames = tuple(replace(frame, R=_exact(frame.R, tolerance), P=_exact(frame.P, tolerance)) for frame in model.frames)
    return replace(model, bodies=bodies, frames=frames, gravity=_exact(model.gravity, tolerance))


def link_length(model: Model, i: int) -> float | None:
    """lᵢ (0-based i): the single non-zero coordinate of the first child's origin, else of the COM."""
    children = model.children[i]
    for vector in ([model.bodies[children[0]].P] if children else []) + [model.bodies[i].p_com]:
        nonzero = np.flatnonzero(np.abs(np.asarray(vector, dtype=float)) > ROUND_OFF)
        if len(nonzero) == 1:
            return abs(float(vector[nonzero[0]]))
        if len(nonzero) > 1:
            return None
    return None


def com_distance(body) -> float | None:
    """l_{c_i}: the single non-zero coordinate of ⁱP_Cᵢ (None if the COM is at the origin or off-axis)."""
    nonzero = np.flatnonzero(np.abs(np.asarray(body.p_com, dtype=float)) > ROUND_OFF)
    return abs(float(body.p_com[nonzero[0]])) if len(nonzero) == 1 else None


def parameter_values(model: Model) -> dict[str, float]:
    """Every parameter symbol this robot has (non-zero ones), with its value from the URDF."""
    values = {}
    for i, body in enumerate(model.bodies, start=1):
        if body.mass != 0:
            values[f"m{i}"] = float(body.mass)
        for name, (a, b) in INERTIA_ENTRIES.items():
            if body.I_com[a, b] != 0:
                values[f"I{name}{i}"] = float(body.I_com[a, b])
        length = link_length(model, i - 1)
        if length:
            values[f"l{i}"] = length
        com = com_distance(body)
        if com:
            values[f"lc{i}"] = com
    gravity = float(np.linalg.norm(model.gravity))
    if gravity:
        values["g"] = gravity
    return values


def check_symbolic_size(model: Model) -> None:
    """SymbolError for robots with more joints than the symbolic path handles in reasonable time."""
    if model.n > MAX_SYMBOLIC_JOINTS:
        raise SymbolError(
            f"robot '{model.name}' has {model.n} joints; the symbolic path handles at most {MAX_SYMBOLIC_JOINTS} "
            "in reasonable time (use the numeric functions)"
        )


def _resolve(model: Model, name: str, known: dict) -> str:
    if name in known:
        return name
    if model.n == 1 and f"{name}1" in known:
        return f"{name}1"  # the pendulum's m, l
    raise SymbolError(f"unknown symbol '{name}' for robot '{model.name}'; known: {', '.join(sorted(known))}")


def symbolic_model(model: Model, symbols=()) -> tuple[Model, dict[str, object]]:
    """An exact model in which the named parameters are sympy symbols.

    Returns the model and {name: Symbol}. Unnamed parameters are exact
    rationals from the URDF. Raises :class:`SymbolError` for unknown names.
    """
    sympy = _sympy()
    exact = rationalize(model)
    table = {name: sympy.Symbol(name, positive=True) for name in symbols}
    known = parameter_values(model)
    resolved = {_resolve(model, name, known): symbol for name, symbol in table.items()}
    bodies, frames = list(exact.bodies), list(exact.frames)
    for i in range(model.n):
        number = i + 1
        body = bodies[i]
        changes = {}
        if f"m{number}" in resolved:
            changes["mass"] = resolved[f"m{number}"]
        inertia = body.I_com.copy()
        for name, (a, b) in INERTIA_ENTRIES.items():
            if f"I{name}{number}" in resolved:
                inertia[a, b] = inertia[b, a] = resolved[f"I{name}{number}"]
        changes["I_com"] = inertia
        if f"lc{number}" in resolved:
            changes["p_com"] = _substitute_length(body.p_com, _exact_number(com_distance(model.bodies[i])),
                                                  resolved[f"lc{number}"])
        if f"l{number}" in resolved:
            length = _exact_number(link_length(model, i))
            symbol = resolved[f"l{number}"]
            if f"lc{number}" not in resolved:
                changes["p_com"] = _substitute_length(body.p_com, length, symbol)
            for c in model.children[i]:
                bodies[c] = replace(bodies[c], P=_substitute_length(bodies[c].P, length, symbol))
            frames = [replace(frame, P=_substitute_length(frame.P, length, symbol)) if frame.body == i else frame
                      for frame in frames]  # frames fixed to link i, such as a tool frame at its tip
        bodies[i] = replace(body, **changes)  # body carries any P its parent's l substituted
    gravity = exact.gravity
    if "g" in resolved:
        magnitude = _exact_number(float(np.linalg.norm(model.gravity)))
        gravity = np.array([resolved["g"] * (component / magnitude) for component in exact.gravity], dtype=object)
    return replace(exact, bodies=tuple(bodies), frames=tuple(frames), gravity=gravity), table


def _substitute_length(vector: np.ndarray, length, symbol) -> np.ndarray:
    out = np.array(vector, dtype=object)
    for k, value in enumerate(out):
        if value == length:
            out[k] = symbol
        elif value == -length:
            out[k] = -symbol
    return out


SYMBOL_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def joint_symbols(model: Model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Θ, Θ̇, Θ̈) as object arrays of real sympy symbols q_<joint>, qd_<joint>, qdd_<joint>.

    Raises
    ------
    SymbolError
        For a joint name that is not an ASCII identifier: its symbols would print as text that
        reads back as another expression (``q_a-b`` is ``q_a − b``), or as code.
    """
    sympy = _sympy()
    for name in model.joint_names:
        if not SYMBOL_NAME.fullmatch(name):
            raise SymbolError(f"joint '{name}': symbolic results name symbols q_<joint>, so joint names must be ASCII "
                              "identifiers (letters, digits, _, not starting with a digit); rename the joint in the URDF")

    def symbols(prefix):
        return np.array([sympy.Symbol(f"{prefix}_{name}", real=True) for name in model.joint_names], dtype=object)

    return symbols("q"), symbols("qd"), symbols("qdd")


def canonical(expression, angles):
    """An exact normal form: trig expanded, sin²θ → 1 − cos²θ for every joint angle θ.

    Two expressions are equal as functions iff their canonical forms are
    identical, which is much faster to decide than ``simplify(a − b) == 0``.
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
    """A readable form for display: canonical, then sympy's trigonometric simplification."""
    sympy = _sympy()
    return sympy.factor_terms(sympy.trigsimp(canonical(expression, angles)))


@dataclass(frozen=True)
class Derivation:
    """Closed forms of one robot, joints in model order (sympy objects).

    ``tau`` (n,), ``M`` (n, n), ``V`` (n,), ``G`` (n,), ``B`` (n, n(n−1)/2) and
    ``C`` (n, n) with V = B [Θ̇Θ̇] + C [Θ̇²] (6.63); ``pairs`` are the (j, k) of [Θ̇Θ̇].
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
    """``expression`` with its fractions written as ``digits``-digit decimals (unchanged for None)."""
    if digits is None:
        return expression
    sympy = _sympy()
    expression = sympy.sympify(expression)
    return expression.xreplace({r: sympy.Float(r, digits) for r in expression.atoms(sympy.Rational) if not r.is_Integer})


def derive(model: Model, symbols=(), method: str = "newton-euler", simplify: bool = True,
           decimals: int | None = None) -> Derivation:
    """τ, M(Θ), V(Θ, Θ̇), G(Θ), B(Θ), C(Θ) in closed form, by Newton–Euler or Lagrange.

    ``symbols`` names parameters kept symbolic (module table); the rest are the
    URDF's numbers, made exact (or ``decimals``-digit decimals in the result).
    B and C are read off V as the coefficients of θ̇ⱼθ̇ₖ (j < k) and θ̇ⱼ² (6.63)–(6.65).
    """

    sympy = _sympy()
    check_symbolic_size(model)
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
    if decimals is not None and not (isinstance(decimals, int) and 1 <= decimals <= 30):
        raise SymbolError(f"decimals must be a whole number of digits from 1 to 30, got {decimals!r}")
    exact_form = (lambda e: tidy(e, q)) if simplify else (lambda e: canonical(e, q))

    def form(e):
        return decimal(exact_form(e), decimals)

    n = model.n
    V = [canonical(v, q) for v in V]
    pairs = velocity_pairs(n)
    B = [[form(sympy.expand(v).coeff(qd[j], 1).coeff(qd[k], 1)) for j, k in pairs] for v in V]
    C = [[form(sympy.expand(v).coeff(qd[j], 2)) for j in range(n)] for v in V]
    return Derivation(
        joints=model.joint_names, prismatic=tuple(b.is_prismatic for b in model.bodies), method=method, q=tuple(q), qd=tuple(qd), qdd=tuple(qdd), parameters=parameters,
        tau=[form(t) for t in tau], M=[[form(x) for x in row] for row in M], V=[form(v) for v in V],
        G=[form(x) for x in G], B=B, C=C, pairs=pairs,
    )


def numeric_functions(derivation: Derivation, parameter_values: dict | None = None):
    """Vectorised numpy functions from closed forms, with common subexpressions shared.

    Returns a dict of callables: ``M(q)`` → (n, n) or (N, n, n), ``V(q, qd)``,
    ``G(q)``, ``tau(q, qd, qdd)`` → (n,) or (N, n). Parameter symbols must be
    given numbers in ``parameter_values``.
    """
    sympy = _sympy()
    values = {derivation.parameters[k]: v for k, v in (parameter_values or {}).items()}
    missing = [name for name, symbol in derivation.parameters.items() if symbol not in values]
    if missing:
        raise SymbolError(f"give values for the parameter symbols {', '.join(missing)}")
    q, qd, qdd = (list(v) for v in (derivation.q, derivation.qd, derivation.qdd))

    def compile_(expressions, arguments, shape):
        exprs = [sympy.sympify(e).xreplace(values) for e in expressions]
        function = sympy.lambdify(arguments, exprs, modules="numpy", cse=True)

        def evaluate(*arrays):
            arrays = [np.asarray(a, dtype=float) for a in arrays]
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
    """Closed forms of (6.99) for one frame and task rows: J, M_x, V_x, G_x as sympy matrices."""

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
    """

    sympy = _sympy()
    check_symbolic_size(model)
    exact, parameters = symbolic_model(model, symbols)
    q, qd, _ = joint_symbols(model)
    indices = row_indices(rows)
    if len(indices) != model.n:
        raise SymbolError(f"the task has {len(indices)} rows but robot '{model.name}' has {model.n} joints: "
                          f"(6.99) needs a square Jacobian; choose {model.n} rows")
    J = sympy.Matrix(jacobian(exact, q, frame, expressed_in, indices))
    J_dot = sympy.Matrix(jacobian_dot(exact, q, qd, frame, expressed_in, indices))
    M, V, G = sympy.Matrix(mass_matrix(exact, q)), sympy.Matrix(velocity_torques(exact, q, qd)), sympy.Matrix(gravity_torques(exact, q))
    Mx, Vx, Gx = operational_space_terms(J.inv(), J_dot, M, V, G, sympy.Matrix(qd))

    def clean(matrix):
        return matrix.applyfunc(lambda e: decimal(sympy.factor_terms(sympy.simplify(e)), decimals))

    return CartesianDerivation(
        frame=frame, rows=tuple(ROW_NAMES[i] for i in indices), q=tuple(q), qd=tuple(qd), parameters=parameters,
        J=clean(J), Mx=clean(Mx), Vx=clean(Vx), Gx=clean(Gx),
    )
