"""Whose numbers: a wrong answer that is the right dynamics of another robot, and the parameters that differ.

The commonest wrong answer is right dynamics with the wrong numbers: another
student's robot, the textbook's, or the handout's with one mass typed wrong.
:func:`other_parameters` is the diagnosis check that finds them, for τ, M, V
and G, when the answer is wrong on every state:

1. *Robots a student is likely to have used* (lengths are not linear in
   anything, so these are compared whole): the course robot before it was
   varied (the textbook's and the worked examples' numbers), the variant a
   notebook without a student id gets, and, in a class graded per student,
   every other student's variant (:class:`Handout`). One that agrees with the
   answer on every state is named, without naming its student, with the
   numbers in which it differs from the handout.
2. *The handout's robot with other inertial parameters*: τ = Y(Θ, Θ̇, Θ̈) π is
   linear in the ten parameters of every link (:mod:`course_dynamics.core.regressor`),
   and so are M (Y with Θ̇ = 0, g = 0 and Θ̈ = eⱼ for column j), V (Y with
   Θ̈ = 0, g = 0) and G (Y with Θ̇ = Θ̈ = 0). π is fitted by least squares on the
   handout's kinematics over the graded states. The fit is *exact* when the
   fitted robot's answer agrees with the student's to :data:`FIT` relative on
   every state (round-off: a thousand times below the grader's 1e-6). Then one
   physical parameter of one link that explains it alone (a mass, a
   component of the centre of mass, an entry of the inertia tensor about it)
   is named with its value; otherwise the identifiable combinations (the base
   parameters of :func:`~course_dynamics.core.regressor.base_parameters`)
   that differ, and only those the states determine.

A fit that is the handout's parameters times one number is left to
``constant_factor`` (a missing ½ looks the same).
"""
from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..core.dynamics import gravity_torques, mass_matrix, velocity_torques
from ..core.inertia import parallel_axis
from ..core.model import Model
from ..core.newton_euler import inverse_dynamics
from ..core.parameters import parameter_values
from ..core.regressor import base_parameters, parameters, regressor
from ..core.robots import COURSE_ROBOTS, load_robot
from ..tools.variants import COURSE_STUDENT, robot_variant
from .records import Answer, Finding

#: The relative error, on every state, within which a fitted robot's answer must agree with the student's for the
#: fit to count as exact (round-off, far below any grading tolerance).
FIT = 1e-9
LISTED = 6  # differing numbers named one by one
TERMS = ("tau", "M", "V", "G")
TEXTBOOK = "the course robot's own numbers (the textbook's, before your robot was varied)"
NO_ID = "the numbers of a notebook without a student id (the course's default student)"
CLASSMATE = "another student's robot's numbers"
AXES = "xyz"


@dataclass(frozen=True)
class Handout:
    """The robot a student was given, and where the robots they may have used instead come from.

    Parameters
    ----------
    model : Model
        The student's robot: the handout's numbers.
    robot : str
        The course robot it is a variant of (empty: none, only the fit is tried).
    student : str
        The student's id (empty: unknown).
    classmates : tuple of str
        Other students' ids, whose variants of ``robot`` are tried (a class graded per student, with a roster);
        the student's own variant is never named, since it is the right answer.
    """

    model: Model
    robot: str = ""
    student: str = ""
    classmates: tuple[str, ...] = ()

    def others(self) -> Iterator[tuple[str, Model]]:
        """The robots a student is likely to have used instead of the handout, each with how it is named.

        Returns
        -------
        iterator of (str, Model)
            The course robot unvaried, the no-id notebook's variant, the classmates' variants (module docstring);
            each under the handout's gravity.
        """
        if self.robot not in COURSE_ROBOTS:
            return
        gravity = tuple(self.model.gravity.tolist())
        yield TEXTBOOK, _robot(self.robot, "", gravity)
        if self.student != COURSE_STUDENT:
            yield NO_ID, _robot(self.robot, COURSE_STUDENT, gravity)
        for other in self.classmates:
            if other not in (self.student, COURSE_STUDENT):
                yield CLASSMATE, _robot(self.robot, other, gravity)


@lru_cache(maxsize=4096)  # a roster's variants, built once per process, not once per wrong answer
def _robot(robot: str, student: str, gravity: tuple[float, ...]) -> Model:
    """The course robot (``student`` empty) or a student's variant of it, under ``gravity``."""
    model = robot_variant(robot, student).model if student else load_robot(robot)
    return model.with_gravity(np.array(gravity))


def _term(model: Model, term: str, plan) -> np.ndarray:
    if term == "tau":
        return inverse_dynamics(model, plan.q, plan.qd, plan.qdd)
    if term == "M":
        return mass_matrix(model, plan.q)
    return velocity_torques(model, plan.q, plan.qd) if term == "V" else gravity_torques(model, plan.q)


def term_regressor(model: Model, term: str, plan) -> np.ndarray:
    """The term's regressor at the plan's states: term = Y π, shape (N, …, 10 n) (module docstring).

    Parameters
    ----------
    model : Model
        The robot whose kinematics (and gravity) the term is linear in the parameters of.
    term : str
        ``tau``, ``M``, ``V`` or ``G``.
    plan : Plan
        The states (``q``, ``qd``, ``qdd``, each (N, n)).

    Returns
    -------
    numpy.ndarray, shape (N, n, 10 n), or (N, n, n, 10 n) for M
        Y, so that the term at state k is ``Y[k] @ π``.
    """
    still = model.with_gravity(np.zeros(3))
    zero = np.zeros_like(plan.q)
    if term == "tau":
        return regressor(model, plan.q, plan.qd, plan.qdd)
    if term == "V":
        return regressor(still, plan.q, plan.qd, zero)
    if term == "G":
        return regressor(model, plan.q, zero, zero)
    columns = []
    for j in range(model.n):
        unit = zero.copy()
        unit[:, j] = 1.0
        columns.append(regressor(still, plan.q, zero, unit))
    return np.stack(columns, axis=2)  # column j of M is τ(Θ, 0, eⱼ) without gravity


def _body_pi(mass: float, c: np.ndarray, I_com: np.ndarray) -> np.ndarray:
    """A body's ten parameters from its mass, centre of mass and inertia about it (regressor's order)."""
    I_o = parallel_axis(I_com, mass, c)
    return np.array([mass, *(mass * c)] + [I_o[a, b] for a, b in ((0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2))])


def _physical(model: Model) -> Iterator[tuple[int, str, str, float, np.ndarray, np.ndarray]]:
    """Per link and physical parameter: (link, name, unit, handout value, dπ/dδ, ½ d²π/dδ²), π's change being a
    polynomial of degree ≤ 2 in the change δ of that one parameter (the others held)."""
    for i, body in enumerate(model.bodies):
        m, c, I = float(body.mass), np.asarray(body.p_com, float), np.asarray(body.I_com, float)
        changes = [("m", "kg", m, lambda d: (m + d, c, I))]
        for a in range(3):
            changes.append((f"centre of mass {AXES[a]}", "m", c[a], lambda d, a=a: (m, c + d * np.eye(3)[a], I)))
        for a, b in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)):
            unit = np.zeros((3, 3))
            unit[a, b] = unit[b, a] = 1.0
            changes.append((f"I_C,{AXES[a]}{AXES[b]}", "kg·m²", I[a, b], lambda d, u=unit: (m, c, I + d * u)))
        for name, unit_text, value, changed in changes:
            at = {d: _body_pi(*changed(d)) for d in (-1.0, 0.0, 1.0)}
            first, second = (at[1.0] - at[-1.0]) / 2, (at[1.0] + at[-1.0]) / 2 - at[0.0]
            dpi, half = np.zeros(10 * model.n), np.zeros(10 * model.n)
            dpi[10 * i:10 * i + 10], half[10 * i:10 * i + 10] = first, second
            yield i, name, unit_text, value, dpi, half


def _one_parameter(A: np.ndarray, B: np.ndarray, r: np.ndarray) -> float:
    """The δ that minimises ‖A δ + B δ² − r‖ (the roots of its derivative, a cubic)."""
    if not B.any():
        return float(A @ r / (A @ A))
    roots = np.roots([2 * B @ B, 3 * A @ B, A @ A - 2 * B @ r, -A @ r])
    real = [float(x.real) for x in roots if abs(x.imag) <= 1e-9 * max(1.0, abs(x))]
    return min(real, key=lambda d: float(np.linalg.norm(A * d + B * d * d - r)))


def _show(x: float) -> str:
    return f"{x + 0.0:.4g}"


def _unit(name: str) -> str:
    return " kg·m²" if name.startswith("I") else " kg" if name.startswith("m") else " m/s²" if name == "g" else " m"


def _differences(handout: Model, other: Model) -> str:
    """The named parameters in which ``other`` differs from the handout, as a student reads them."""
    ours, theirs = parameter_values(handout), parameter_values(other)
    said = [f"{name} = {_show(theirs[name])}{_unit(name)} where your handout has {_show(ours[name])}{_unit(name)}"
            for name in ours if name in theirs and not np.isclose(ours[name], theirs[name], rtol=1e-9, atol=0)]
    more = f" (and {len(said) - LISTED} more)" if len(said) > LISTED else ""
    return "; ".join(said[:LISTED]) + more if said else "their numbers differ from your handout's"


def _base_differences(model: Model, Y: np.ndarray, pi0: np.ndarray, pi: np.ndarray, term: str) -> str:
    """The base parameters whose values differ between π₀ and π, among those the stacked Y determines."""
    base = base_parameters(model)
    rows = base.describe().splitlines()
    projector = np.linalg.pinv(Y) @ Y
    said, hidden = [], 0
    for row, line in zip(base.beta, rows):
        ours, theirs = float(row @ pi0), float(row @ pi)
        if np.isclose(ours, theirs, rtol=1e-6, atol=1e-9 * max(1.0, np.abs(pi0).max())):
            continue
        if np.linalg.norm(row - row @ projector) > 1e-6 * np.linalg.norm(row):
            hidden += 1  # this combination is not determined by this term on these states
            continue
        said.append(f"{line.split(' = ', 1)[1]} = {_show(theirs)} where your handout's numbers give {_show(ours)}")
    if not said:
        return ""
    return ("; ".join(said[:LISTED]) + (f" (and {len(said) - LISTED} more)" if len(said) > LISTED else "")
            + (" (what else differs, these states of your term cannot tell)" if hidden else ""))


def other_parameters(answer: Answer) -> Finding | None:
    """The answer is wrong on every state but the right dynamics of another robot: that robot's numbers, or the
    handout's parameters that differ (module docstring).

    Parameters
    ----------
    answer : Answer
        A term (τ, M, V or G) of a robot, with its plan and handout.

    Returns
    -------
    Finding or None
        Conclusive, tagged "other numbers"; None when no other robot and no exact fit explains the answer, or the
        fit is the handout's parameters times one number.
    """
    handout, plan = answer.handout, answer.plan
    if handout is None or plan is None or answer.term not in TERMS or answer.agreed or not answer.usable:
        return None
    model, term = handout.model, answer.term
    tags = ("other numbers",)
    for label, other in handout.others():
        theirs = _term(other, term, plan)
        if not answer.agrees_with(theirs, FIT) or np.allclose(theirs, answer.expected, rtol=1e-12, atol=0):
            continue
        return Finding(f"your dynamics are right, but these are {label}: {_differences(model, other)}", tags, True)
    usable = list(answer.usable)
    Y_all = term_regressor(model, term, plan)
    Y = Y_all[usable].reshape(-1, Y_all.shape[-1])
    y = np.concatenate([answer.values[k].ravel() for k in usable])
    pi0 = parameters(model).astype(float)
    r = y - Y @ pi0
    delta = np.linalg.lstsq(Y, r, rcond=None)[0]

    def agrees(change: np.ndarray) -> bool:
        fitted = np.einsum("...p,p->...", Y_all, pi0 + change)
        return answer.agrees_with(fitted, min(FIT, answer.tolerance))

    if not agrees(delta):
        return None
    y0 = Y @ pi0
    k = float(y @ y0 / (y0 @ y0)) if y0.any() else 0.0
    if np.allclose(y, k * y0, rtol=0, atol=FIT * np.abs(y0).max()):
        return None  # the handout's parameters times one number: constant_factor says it
    found = []
    for i, name, unit, value, dpi, half in _physical(model):
        A, B = Y @ dpi, Y @ half
        if not A.any() and not B.any():
            continue
        d = _one_parameter(A, B, r)
        if agrees(dpi * d + half * d * d):
            found.append(f"link {i + 1} has {name} = {_show(value + d)} {unit} where the handout has "
                         f"{_show(value)} {unit}")
    if len(found) == 1:
        return Finding(f"your dynamics are right; your {found[0]}", tags, True)
    if found:
        return Finding("your dynamics are right, with other inertial parameters that these states cannot pin to one: "
                       "either your " + ", or your ".join(found), tags, True)
    combinations = _base_differences(model, Y, pi0, pi0 + delta, term)
    if not combinations:
        return None
    return Finding("your dynamics are right, with other numbers: on your handout's joint geometry, these "
                   f"combinations of masses, centres of mass (a mass times a length) and inertias differ from your "
                   f"handout's: {combinations}. Check the masses and lengths you typed (a link length enters these "
                   "combinations too)", tags, True)


__all__ = ["FIT", "Handout", "other_parameters", "term_regressor"]
