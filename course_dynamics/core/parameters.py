"""The robot's parameters for the symbolic path: exact numbers, and the notes' symbols in their place.

The Newton–Euler and Lagrangian code run unchanged on sympy expressions (see
:mod:`course_dynamics.core.algebra`). This module prepares the models they run on;
:mod:`course_dynamics.core.symbolic` turns their results into closed forms.

* :func:`rationalize` turns a model's floating-point numbers into sympy
  rationals (9.81 → 981/100, cos(π/2) round-off → 0);
* :func:`symbolic_model` also keeps chosen parameters as symbols named as in
  the notes (table below);
* :func:`joint_symbols` gives Θ, Θ̇, Θ̈ as symbols ``q_<joint>``,
  ``qd_<joint>``, ``qdd_<joint>``;
* :func:`check_symbolic_size` refuses robots too large for the symbolic path.

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
"""
from __future__ import annotations

import re
from dataclasses import replace

import numpy as np

from ..base.errors import CourseDynamicsError
from .model import Model

ROUND_OFF = 1e-12
INERTIA_ENTRIES = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}
#: The most joints the symbolic path takes (beyond them, simplification takes far longer than a lecture).
MAX_SYMBOLIC_JOINTS = 4


class SymbolError(CourseDynamicsError):
    """A symbol name that does not name a parameter of the robot, or a robot too large.

    The message names the symbol and the robot and lists the symbols it has.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> symbolic_model(load_robot("pendulum"), ["mass"])
    Traceback (most recent call last):
    course_dynamics.core.parameters.SymbolError: unknown symbol 'mass' for robot 'pendulum'; known: g, l1, lc1, m1
    """


def _exact_number(value, tolerance: float = ROUND_OFF):
    import sympy

    if isinstance(value, (float, np.floating, int, np.integer)):
        return sympy.nsimplify(float(value), rational=True, tolerance=tolerance)
    return value


def _exact(array, tolerance: float = ROUND_OFF) -> np.ndarray:
    out = np.empty(np.shape(array), dtype=object)
    for index, value in np.ndenumerate(np.asarray(array, dtype=object)):
        out[index] = _exact_number(value, tolerance)
    return out


def rationalize(model: Model, tolerance: float = ROUND_OFF) -> Model:
    """The same robot with every number an exact sympy rational (within ``tolerance``).

    Parameters
    ----------
    model : Model
        The robot.
    tolerance : float, optional
        How far a rational may be from the float it replaces (1e-12 by default).

    Returns
    -------
    Model
        The robot with rational placements, masses, inertias and gravity (object arrays).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> exact = rationalize(load_robot("two_link"))
    >>> exact.gravity.tolist(), exact.bodies[0].R0.tolist()   # cos(π/2) round-off is exactly 0
    ([0, 0, -981/100], [[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    """
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
    """lᵢ (0-based i): the single non-zero coordinate of the first child's origin, else of the COM.

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> link_length(arm, 0), link_length(arm, 1)   # l₁ to joint 2, l₂ to the last COM, m
    (0.5, 0.4)
    """
    children = model.children[i]
    for vector in ([model.bodies[children[0]].P] if children else []) + [model.bodies[i].p_com]:
        nonzero = np.flatnonzero(np.abs(np.asarray(vector, dtype=float)) > ROUND_OFF)
        if len(nonzero) == 1:
            return abs(float(vector[nonzero[0]]))
        if len(nonzero) > 1:
            return None
    return None


def com_distance(body) -> float | None:
    """l_{c_i}: the single non-zero coordinate of ⁱP_Cᵢ (None if the COM is at the origin or off-axis).

    >>> from course_dynamics import load_robot
    >>> [round(com_distance(body), 6) for body in load_robot("rrr_arm").bodies]   # m
    [0.1, 0.2, 0.15]
    """
    nonzero = np.flatnonzero(np.abs(np.asarray(body.p_com, dtype=float)) > ROUND_OFF)
    return abs(float(body.p_com[nonzero[0]])) if len(nonzero) == 1 else None


def parameter_values(model: Model) -> dict[str, float]:
    """Every parameter symbol this robot has (non-zero ones), with its value from the URDF.

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    dict of str to float
        Symbol name (module table) → value: kg for ``m<i>``, kg·m² for ``I<ab><i>``, m for ``l<i>`` and
        ``lc<i>``, m/s² for ``g``.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> parameter_values(load_robot("pendulum"))
    {'m1': 1.0, 'l1': 1.0, 'lc1': 1.0, 'g': 9.81}
    """
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
    """SymbolError for robots with more joints than the symbolic path handles in reasonable time.

    Parameters
    ----------
    model : Model
        The robot.

    Raises
    ------
    SymbolError
        If the robot has more than :data:`MAX_SYMBOLIC_JOINTS` joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> check_symbolic_size(load_robot("rrr_arm"))   # 3 joints: fine
    >>> check_symbolic_size(load_robot("ur5"))
    Traceback (most recent call last):
    course_dynamics.core.parameters.SymbolError: robot 'ur5' has 6 joints; the symbolic path handles at most 4 in
    reasonable time (use the numeric functions)
    """
    if model.n > MAX_SYMBOLIC_JOINTS:
        raise SymbolError(
            f"robot '{model.name}' has {model.n} joints; the symbolic path handles at most {MAX_SYMBOLIC_JOINTS} "
            "in reasonable time (use the numeric functions)"
        )


def _resolve(model: Model, name: str, known: dict) -> str:
    if name in known:
        return name
    if model.n_bodies == 1 and f"{name}1" in known:
        return f"{name}1"  # the pendulum's m, l
    raise SymbolError(f"unknown symbol '{name}' for robot '{model.name}'; known: {', '.join(sorted(known))}")


def symbolic_model(model: Model, symbols=()) -> tuple[Model, dict[str, object]]:
    """An exact model in which the named parameters are sympy symbols.

    Returns the model and {name: Symbol}. Unnamed parameters are exact
    rationals from the URDF. Raises :class:`SymbolError` for unknown names.

    Parameters
    ----------
    model : Model
        The robot.
    symbols : iterable of str, optional
        The parameters kept as symbols, named as in the module table (``m1``, ``l2``, ``Izz1``, ``g``; a
        one-joint robot also takes ``m``, ``l``, …); none by default.

    Returns
    -------
    tuple of (Model, dict)
        The exact model, and each name given → its positive ``sympy.Symbol``.

    Raises
    ------
    SymbolError
        If a name is no parameter of the robot (the message lists those it has).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> exact, symbols = symbolic_model(load_robot("pendulum"), ["m", "l"])
    >>> exact.bodies[0].mass, exact.bodies[0].p_com.tolist(), exact.gravity.tolist()
    (m, [0, 0, -l], [0, 0, -981/100])
    """
    import sympy

    exact = rationalize(model)
    table = {name: sympy.Symbol(name, positive=True) for name in symbols}
    known = parameter_values(model)
    resolved = {_resolve(model, name, known): symbol for name, symbol in table.items()}
    bodies, frames = list(exact.bodies), list(exact.frames)
    for i in range(model.n_bodies):
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
    """(Θ, Θ̇, Θ̈) as object arrays of real sympy symbols ``q_<joint>``, ``qd_<joint>``, ``qdd_<joint>``.

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    tuple of (numpy.ndarray, numpy.ndarray, numpy.ndarray), each of shape (n,)
        Θ, Θ̇ and Θ̈, object arrays of ``sympy.Symbol``.

    Raises
    ------
    SymbolError
        For a joint name that is not an ASCII identifier: its symbols would print as text that
        reads back as another expression (``q_a-b`` is ``q_a − b``), or as code.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> q, qd, qdd = joint_symbols(load_robot("two_link"))
    >>> q.tolist(), qdd.tolist()
    ([q_theta1, q_theta2], [qdd_theta1, qdd_theta2])
    """
    import sympy

    for name in model.joint_names:
        if not SYMBOL_NAME.fullmatch(name):
            raise SymbolError(f"joint '{name}': symbolic results name symbols q_<joint>, so joint names must be ASCII "
                              "identifiers (letters, digits, _, not starting with a digit); "
                              "rename the joint in the URDF")

    def symbols(prefix):
        return np.array([sympy.Symbol(f"{prefix}_{name}", real=True) for name in model.joint_names], dtype=object)

    return symbols("q"), symbols("qd"), symbols("qdd")


__all__ = ["MAX_SYMBOLIC_JOINTS", "SymbolError", "check_symbolic_size", "joint_symbols", "parameter_values",
           "rationalize", "symbolic_model"]
