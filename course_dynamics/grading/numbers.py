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

Only a real robot is named: every body of the fitted robot must be physical
(its mass above :data:`ROUND_OFF` of the robot's largest, its pseudo-inertia
positive semi-definite to :data:`ROUND_OFF` in the robot's scale, which holds
the triangle inequality). For one parameter the fitted robot is the handout's
with that one changed; for the combinations, some robot on the handout's
kinematics with those combinations must be physical (:func:`physical_robot`
searches the parameters the states do not determine). An answer no real
robot gives (a negative inertia, a mass of zero) is no question of numbers,
and nothing is said of them. A fitted value within :data:`ZERO_BELOW` of its
scale whose zero fits as well is shown as 0, never as round-off such as 1e-15.

A fit that is the handout's parameters times one number is left to
``constant_factor`` (a missing ½ looks the same), and where several single
parameters explain a term (V of point masses sees one product m₂l₁l₂), the
student's other terms (``Answer.related``) tell them apart: a parameter that
explains every one of them is named.
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
from ..tools.consistency import pseudo_inertia
from ..tools.variants import COURSE_STUDENT, robot_variant
from .records import TERM_NAMES, Answer, Finding

#: The relative error, on every state, within which a fitted robot's answer must agree with the student's for the
#: fit to count as exact (round-off, far below any grading tolerance).
FIT = 1e-9
#: A body is physical when its mass is above this share of the robot's largest and its pseudo-inertia J, in units
#: of that mass and the robot's length (J / m diag(ℓ, ℓ, ℓ, 1)²), has no eigenvalue below −this: round-off allowed.
ROUND_OFF = 1e-6
#: A fitted value whose size is below this share of its kind's scale (the robot's largest mass, its length, that
#: mass times the length squared), and whose zero fits the answer as well, is shown as 0.
ZERO_BELOW = 1e-4
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
    if np.linalg.norm(B) <= 1e-12 * np.linalg.norm(A):  # linear in it (a mass), to round-off
        return float(A @ r / (A @ A))
    roots = np.roots([2 * B @ B, 3 * A @ B, A @ A - 2 * B @ r, -A @ r])
    real = [float(x.real) for x in roots if abs(x.imag) <= 1e-9 * max(1.0, abs(x))]
    return min(real, key=lambda d: float(np.linalg.norm(A * d + B * d * d - r)))


def _show(x: float, zero: float = 0.0) -> str:
    """``x`` to four digits; 0 when its size is below ``zero`` (round-off)."""
    return "0" if abs(x) < zero else f"{x + 0.0:.4g}"


@dataclass(frozen=True)
class Scales:
    """The sizes a robot's parameters are measured in: its largest mass (kg) and its length (m).

    Parameters
    ----------
    mass : float
        The largest body mass, kg.
    length : float
        The largest distance of a joint or a centre of mass from its frame origin, m (1 m when none).
    """

    mass: float
    length: float

    @classmethod
    def of(cls, model: Model) -> "Scales":
        """The scales of ``model``.

        Parameters
        ----------
        model : Model
            The robot.

        Returns
        -------
        Scales
            Its largest mass and its length.
        """
        lengths = [float(np.linalg.norm(v)) for b in model.bodies for v in (b.P, b.p_com)]
        return cls(max(float(b.mass) for b in model.bodies), max(lengths, default=0.0) or 1.0)

    def unit(self, name: str) -> float:
        """The scale of a physical parameter named as ``_physical`` names them (m, centre of mass …, I_C,…).

        Parameters
        ----------
        name : str
            The parameter's name.

        Returns
        -------
        float
            kg, m or kg·m².
        """
        return self.mass if name == "m" else self.length if name.startswith("centre") else self.mass * self.length**2

    def normalised(self, J: np.ndarray) -> np.ndarray:
        """J / m diag(ℓ, ℓ, ℓ, 1)²: a pseudo-inertia in units of the robot's mass and length.

        Parameters
        ----------
        J : numpy.ndarray, shape (4, 4)
            A pseudo-inertia.

        Returns
        -------
        numpy.ndarray, shape (4, 4)
            It, dimensionless.
        """
        d = np.array([1 / self.length] * 3 + [1.0])
        return J * np.outer(d, d) / self.mass


def _real(p: np.ndarray, scales: Scales) -> bool:
    return bool(p[0] > ROUND_OFF * scales.mass
                and np.linalg.eigvalsh(scales.normalised(pseudo_inertia(p))).min() >= -ROUND_OFF)


def physical(pi: np.ndarray, scales: Scales, skip=()) -> bool:
    """Whether every body of the ten-per-body parameters ``pi`` is a real body, to round-off (module docstring).

    Parameters
    ----------
    pi : numpy.ndarray, shape (10 n,)
        The regressor's parameters, body by body.
    scales : Scales
        The robot's scales.
    skip : collection of int, optional
        Bodies not held to it (those the handout itself gives no mass, such as a frame of no link).

    Returns
    -------
    bool
        True when every mass is above :data:`ROUND_OFF` of the robot's largest and every pseudo-inertia is
        positive semi-definite to :data:`ROUND_OFF`.
    """
    return all(_real(p, scales) for i, p in enumerate(np.reshape(pi, (-1, 10))) if i not in skip)


def unreal_bodies(pi: np.ndarray, scales: Scales) -> tuple[int, ...]:
    """The bodies of ``pi`` that are no real body (:func:`physical`): in a handout, a frame of no mass.

    Parameters
    ----------
    pi : numpy.ndarray, shape (10 n,)
        The regressor's parameters, body by body.
    scales : Scales
        The robot's scales.

    Returns
    -------
    tuple of int
        Those bodies.
    """
    return tuple(i for i, p in enumerate(np.reshape(pi, (-1, 10))) if not _real(p, scales))


def physical_robot(Y: np.ndarray, pi: np.ndarray, scales: Scales, skip=(), rounds: int = 200) -> bool:
    """Whether some real robot has the answers Y π: π moved in what Y does not see (its null space) until every
    body is physical, by cutting planes (each round an LP over the moves and the least eigenvalue t).

    Parameters
    ----------
    Y : numpy.ndarray, shape (K, 10 n)
        The stacked regressor of the answer's states.
    pi : numpy.ndarray, shape (10 n,)
        A fit, Y π = the answer.
    scales : Scales
        The robot's scales.
    skip : collection of int, optional
        Bodies not held to it (:func:`physical`).
    rounds : int, optional
        The most LPs solved; undecided after them counts as no.

    Returns
    -------
    bool
        True when a π' with Y π' = Y π has every body physical (:func:`physical`).
    """
    from scipy.optimize import linprog

    if physical(pi, scales, skip):
        return True
    unit = np.tile([scales.mass] + [scales.mass * scales.length] * 3 + [scales.mass * scales.length**2] * 6,
                   len(pi) // 10)
    _, sigma, Vt = np.linalg.svd(Y * unit, full_matrices=True)
    rank = int(np.sum(sigma > 1e-10 * sigma[0])) if sigma.size else 0
    null = (Vt[rank:].T * unit[:, None])  # moves of π that change no answer, one per column, each of unit size
    if null.shape[1] == 0:
        return False
    bodies = [i for i in range(len(pi) // 10) if i not in skip]

    def J(i: int, x: np.ndarray) -> np.ndarray:
        return scales.normalised(pseudo_inertia(x[10 * i:10 * i + 10]))

    cuts = [(i, v) for i in bodies for v in np.eye(4)]
    for _ in range(rounds):
        # maximise t: vᵀ J_i(π + N b) v ≥ t for every cut, m_i ≥ ROUND_OFF, |b| ≤ 100 scale units, t ≤ 1
        rows, bounds = [], []
        for i, v in cuts:
            rows.append(([-(v @ J(i, column) @ v) for column in null.T] + [1.0], v @ J(i, pi) @ v))
        for i in bodies:
            rows.append(([-column[10 * i] / scales.mass for column in null.T] + [0.0],
                         pi[10 * i] / scales.mass - 2 * ROUND_OFF))
        A, b = np.array([r[0] for r in rows]), np.array([r[1] for r in rows])
        bounds = [(-100.0, 100.0)] * null.shape[1] + [(None, 1.0)]
        c = np.zeros(null.shape[1] + 1)
        c[-1] = -1.0
        solved = linprog(c, A_ub=A, b_ub=b, bounds=bounds, method="highs")
        if solved.status != 0 or -solved.fun < -ROUND_OFF:
            return False  # no move makes every body physical, even against these cuts alone
        moved = pi + null @ solved.x[:-1]
        if physical(moved, scales, skip):
            return True
        for i in bodies:
            values, vectors = np.linalg.eigh(J(i, moved))
            if values[0] < -ROUND_OFF:
                cuts.append((i, vectors[:, 0]))
    return False


def _unit(name: str) -> str:
    return " kg·m²" if name.startswith("I") else " kg" if name.startswith("m") else " m/s²" if name == "g" else " m"


def _differences(handout: Model, other: Model) -> str:
    """The named parameters in which ``other`` differs from the handout, as a student reads them."""
    ours, theirs = parameter_values(handout), parameter_values(other)
    said = [f"{name} = {_show(theirs[name])}{_unit(name)} where your handout has {_show(ours[name])}{_unit(name)}"
            for name in ours if name in theirs and not np.isclose(ours[name], theirs[name], rtol=1e-9, atol=0)]
    more = f" (and {len(said) - LISTED} more)" if len(said) > LISTED else ""
    return "; ".join(said[:LISTED]) + more if said else "their numbers differ from your handout's"


def _base_differences(model: Model, Y: np.ndarray, pi0: np.ndarray, pi: np.ndarray, term: str) -> tuple[str, bool]:
    """The base parameters whose values differ between π₀ and π, among those the stacked Y determines, and whether
    one of them is 0 on the handout (a combination its geometry does not have)."""
    base = base_parameters(model)
    rows = base.describe().splitlines()
    projector = np.linalg.pinv(Y) @ Y
    said, hidden, new = [], 0, False
    for row, line in zip(base.beta, rows):
        ours, theirs = float(row @ pi0), float(row @ pi)
        floor = 1e-9 * max(1.0, np.abs(pi0).max())  # round-off, far below any parameter of a robot
        if np.isclose(ours, theirs, rtol=1e-6, atol=floor):
            continue
        if np.linalg.norm(row - row @ projector) > 1e-6 * np.linalg.norm(row):
            hidden += 1  # this combination is not determined by this term on these states
            continue
        said.append(f"{line.split(' = ', 1)[1]} = {_show(theirs, floor)} where your handout's numbers give "
                    f"{_show(ours, floor)}")
        new = new or abs(ours) < floor
    if not said:
        return "", False
    return ("; ".join(said[:LISTED]) + (f" (and {len(said) - LISTED} more)" if len(said) > LISTED else "")
            + (" (what else differs, these states of your term cannot tell)" if hidden else "")), new


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

    def agrees(change: np.ndarray, which: Answer = answer, Y_which: np.ndarray = Y_all) -> bool:
        fitted = np.einsum("...p,p->...", Y_which, pi0 + change)
        return which.agrees_with(fitted, min(FIT, which.tolerance))

    if not agrees(delta):
        return None
    scales = Scales.of(model)
    skip = unreal_bodies(pi0, scales)
    y0 = Y @ pi0
    k = float(y @ y0 / (y0 @ y0)) if y0.any() else 0.0
    factor = bool(np.allclose(y, k * y0, rtol=0, atol=FIT * np.abs(y0).max()))
    found = []
    for i, name, unit, value, dpi, half in _physical(model):
        A, B = Y @ dpi, Y @ half
        if not A.any() and not B.any():
            continue
        d = _one_parameter(A, B, r)
        if abs(value + d) < ZERO_BELOW * scales.unit(name) and agrees(dpi * -value + half * value * value):
            d = -value  # round-off about a zero that fits as well: the value is 0
        change = dpi * d + half * d * d
        if agrees(change) and physical(pi0 + change, scales, skip):
            found.append((f"link {i + 1} has {name} = {_show(value + d)} {unit} where the handout has "
                          f"{_show(value)} {unit}", change))
    if factor or len(found) > 1:
        # the student's other terms tell the candidates apart: the one that explains every wrong one of them
        others = [(a, term_regressor(model, t, a.plan)) for t, a in answer.related.items()
                  if t in TERMS and a.wrong and a.plan is not None and len(a.usable) == a.count]
        confirmed = [(text, change) for text, change in found
                     if others and all(agrees(change, a, Y_a) for a, Y_a in others)]
        if len(confirmed) == 1:
            names = [TERM_NAMES[a.term] for a, _ in others]
            also = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
            return Finding(f"your dynamics are right; your {confirmed[0][0]} (as your {also} show"
                           f"{'s' if len(others) == 1 else ''})", tags, True)
        if factor:
            return None  # the handout's parameters times one number: constant_factor says it
    if len(found) == 1:
        return Finding(f"your dynamics are right; your {found[0][0]}", tags, True)
    if found:
        return Finding("your dynamics are right, with other inertial parameters that these states cannot pin to one: "
                       "either your " + ", or your ".join(text for text, _ in found), tags, True)
    if not physical_robot(Y, pi0 + delta, scales, skip):
        return None  # no real robot gives this answer: not a question of numbers
    combinations, new = _base_differences(model, Y, pi0, pi0 + delta, term)
    if not combinations:
        return None
    check = ("Your handout's numbers make some of these 0, which no mass or length typed differently changes: "
             "look for a component of a vector written in the wrong place (a sin for a cos, an x for a y)" if new else
             "Check the masses and lengths you typed (a link length enters these combinations too)")
    return Finding("your dynamics are right, with other numbers: on your handout's joint geometry, these "
                   f"combinations of masses, centres of mass (a mass times a length) and inertias differ from your "
                   f"handout's: {combinations}. {check}", tags, True)


__all__ = ["FIT", "ROUND_OFF", "ZERO_BELOW", "Handout", "Scales", "other_parameters", "physical", "physical_robot",
           "term_regressor", "unreal_bodies"]
