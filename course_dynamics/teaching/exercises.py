"""The notebooks' exercises and their checks: ``check("name")`` says right, wrong and why, or not done yet.

Each exercise of the notebook course has a name here, the data it gives the
student (:data:`GIVEN`) and a way to know the answer from the library. A check
cell calls :func:`check` with the exercise's name; it finds the student's
answer under that name in the notebook (or takes it as a second argument) and
returns a :class:`Verdict`, which the notebook shows:

* *not done yet* — the name is missing, or holds ``...`` or ``None``, or the
  function returns ``None`` or raises ``NotImplementedError``: never an
  exception, so a fresh student notebook runs top to bottom;
* *right*;
* *wrong*, with what is wrong: for a function of the robot (τ, M, V, G, C) the
  grader's own score and diagnosis (:func:`course_dynamics.grading.score.score_outcome`:
  sign, named mistakes, scale, swapped joints, wrong entries, wrong Coriolis or
  centrifugal coefficients, the worst state); for a number, a vector or a
  matrix (once, or a function's on random inputs) the same
  :func:`~course_dynamics.grading.score.score` on a single state: shape, sign,
  scale, wrong entries; for a formula (sympy) where it differs.

Under nbgrader's autograder (``NBGRADER_EXECUTION=autograde``) a wrong or
missing answer raises ``AssertionError`` with the same feedback, so check cells
can carry points.
"""
from __future__ import annotations

import inspect
import os
import reprlib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core import inertia
from ..core.algebra import Vec3, point_acceleration
from ..core.cartesian import cartesian_dynamics
from ..core.friction import Friction
from ..core.newton_euler import inverse_dynamics, newton_euler_links
from ..core.regressor import base_parameters, parameter_names, regressor
from ..core.robots import load_robot
from ..grading.assignment import Assignment
from ..grading.diagnosis import Answer
from ..grading.harness import FUNCTIONS, evaluate
from ..grading.plan import expected_terms, make_plan
from ..grading.score import score, score_outcome
from ..output.render import markdown_escape

MISSING = object()


@dataclass
class Verdict:
    """The outcome of a check: ``status`` is "right", "wrong" or "not done", ``lines`` the feedback."""

    name: str
    status: str
    lines: list[str] = field(default_factory=list)

    def __bool__(self) -> bool:
        return self.status == "right"

    def text(self) -> str:
        head = {"right": "✓ right", "wrong": "✗ not yet right", "not done": "… not done yet"}[self.status]
        return "\n".join([f"{self.name}: {head}"] + [f"  - {line}" for line in self.lines])

    __repr__ = text

    def _repr_markdown_(self) -> str:

        head = {"right": "✅ **right**", "wrong": "❌ **not yet right**", "not done": "⏳ **not done yet**"}[self.status]
        return "\n".join([f"`{self.name}`: {head}", ""] + [f"- {markdown_escape(line)}" for line in self.lines])


# ---------------------------------------------------------------------------------------- what the exercises give

def _given_6_15() -> dict:
    from scipy.spatial.transform import Rotation

    return {"Omega_B": np.array([0.2, -0.4, 0.9]), "Omega_B_dot": np.array([0.5, 0.1, -0.3]),
            "R_AB": Rotation.from_rotvec([0.3, 0.4, -0.2]).as_matrix(),
            "Omega_C_in_B": np.array([0.0, 0.0, 1.5]), "Omega_C_dot_in_B": np.array([0.0, 0.0, -0.7])}


GIVEN = {
    "omega_dot_C": _given_6_15,
    "principal_moments": lambda: {"I": np.array([[0.30, -0.05, 0.02], [-0.05, 0.25, 0.0], [0.02, 0.0, 0.40]])},
    "physical": lambda: {"tensors": [np.diag([0.1, 0.2, 0.25]), np.diag([0.1, 0.1, 0.3]),
                                     np.array([[0.2, 0.1, 0.0], [0.1, 0.2, 0.0], [0.0, 0.0, 0.3]])]},
    "v_dot_c1": lambda: {"q": np.array([0.3, -0.8]), "qd": np.array([1.1, 0.6]), "qdd": np.array([-0.4, 0.9])},
    "Mx_value": lambda: {"q": np.array([0.4, 0.9])},
    "tau_with_friction": lambda: {"q": np.array([0.3, 0.5]), "qd": np.array([1.0, -2.0]), "qdd": np.array([0.5, 0.2]),
                                  "viscous": np.array([0.2, 0.1]), "coulomb": np.array([0.5, 0.3])},
    "I_xy_corner": lambda: {"m": 2.0, "w": 0.3, "l": 0.5, "h": 0.1},
    "Y_mcx2": lambda: {"q": np.array([-0.7, 1.9]), "qd": np.array([1.3, -0.6]), "qdd": np.array([0.4, 2.1])},
}


def given(name: str) -> dict:
    """The data exercise ``name`` gives (numbers the student works with)."""
    return GIVEN[name]()


def symbols(*names: str):
    """Positive real sympy symbols for parameters (m, l, g, …) and real ones for angles and rates."""
    import sympy

    real = ("theta", "theta_dot", "theta_ddot", "theta1", "theta2", "d2")
    made = [sympy.Symbol(n, real=True) if n in real else sympy.Symbol(n, positive=True) for n in names]
    return made[0] if len(made) == 1 else made


# ---------------------------------------------------------------------------------------- the answers


def _robot(name: str):

    return load_robot(name)


def _omega_dot_C():
    d = given("omega_dot_C")
    R = d["R_AB"]
    return d["Omega_B_dot"] + R @ d["Omega_C_dot_in_B"] + np.cross(d["Omega_B"], R @ d["Omega_C_in_B"])  # (6.15)


def _I_corner():
    m, w, l, h = symbols("m", "w", "l", "h")
    return inertia.parallel_axis(inertia.box(m, w, l, h), m, (w / 2, l / 2, h / 2))


def _v_dot_c1():

    d = given("v_dot_c1")
    return newton_euler_links(_robot("two_link"), d["q"], d["qd"], d["qdd"]).v_dot_c[0]


def _pendulum(kind: str):
    m, l, g, theta, theta_dot, theta_ddot = symbols("m", "l", "g", "theta", "theta_dot", "theta_ddot")
    import sympy

    return {"k": m * l**2 * theta_dot**2 / 2, "u": -m * g * l * sympy.cos(theta),
            "tau": m * l**2 * theta_ddot + m * g * l * sympy.sin(theta)}[kind]


def _J_tool():
    import sympy

    l1, l2, theta2 = symbols("l1", "l2", "theta2")
    return sympy.Matrix([[l1 * sympy.sin(theta2), 0], [l1 * sympy.cos(theta2) + l2, l2]])


def _Mx_value():

    q = given("Mx_value")["q"]
    return cartesian_dynamics(_robot("two_link"), q, np.zeros(2), "tool", expressed_in="frame", rows=["x", "y"]).Mx


def _tau_with_friction():

    d = given("tau_with_friction")
    friction = Friction(viscous=d["viscous"], coulomb=d["coulomb"])
    return inverse_dynamics(_robot("two_link"), d["q"], d["qd"], d["qdd"]) + friction.torques(d["qd"])  # (6.114)


def _I_xy_corner():
    d = given("I_xy_corner")
    return d["m"] * d["w"] * d["l"] / 4  # the parallel-axis theorem with +: example 6.1's ᴬI_xy


def _Y_mcx2():
    d = given("Y_mcx2")
    arm = _robot("two_link")
    return regressor(arm, d["q"], d["qd"], d["qdd"])[:, parameter_names(arm).index("mcx_2")]


def _euler(q, qd, qdd, dt):
    return q + qd * dt + 0.5 * qdd * dt**2, qd + qdd * dt  # (6.117), (6.116)


def _semi_implicit(q, qd, qdd, dt):
    qd_next = qd + qdd * dt
    return q + qd_next * dt, qd_next


@dataclass(frozen=True)
class Exercise:
    """How to check one exercise: ``kind`` is "term" (a robot function graded like the grader does),
    "function" (compared on random inputs with ``reference``), "value" or "formula"."""

    kind: str
    answer: Callable | None = None
    robot: str = "two_link"
    term: str = ""
    reference: Callable | None = None
    inputs: Callable | None = None
    tolerance: float = 1e-6
    variables: tuple[str, ...] = ()
    constant_in: tuple[str, ...] = ()  # a formula may differ by anything that does not depend on these
    hint: str = ""


def _random_vectors(count: int):
    return lambda rng: [rng.standard_normal(3) for _ in range(count)]


EXERCISES: dict[str, Exercise] = {
    "point_acceleration": Exercise(
        "function", reference=lambda v, wd, w, p: np.array(tuple(point_acceleration(*(Vec3.of(x) for x in (v, wd, w, p))))),
        inputs=_random_vectors(4), hint="(6.12) with ᴬ_BR = 1: v̇ + ω̇ × P + ω × (ω × P)"),
    "omega_dot_C": Exercise("value", _omega_dot_C, hint="(6.15): ᴬΩ̇_C = ᴬΩ̇_B + ᴬ_BR ᴮΩ̇_C + ᴬΩ_B × ᴬ_BR ᴮΩ_C"),
    "I_corner": Exercise("formula", _I_corner, variables=("m", "w", "l", "h"),
                         hint="the box about its centre (6.2), moved to the corner by the parallel-axis theorem"),
    "principal_moments": Exercise("value", lambda: np.linalg.eigvalsh(given("principal_moments")["I"]),
                                  hint="the eigenvalues of the tensor, smallest first"),
    "physical": Exercise("value", lambda: np.array([not inertia.physical_problems(t) for t in given("physical")["tensors"]]),
                         hint="symmetric, no negative principal moment, and I₁ + I₂ ≥ I₃"),
    "tau_two_link": Exercise("term", term="tau", hint="the outward iteration (6.45)–(6.50), then the inward (6.51)–(6.53)"),
    "tau_spatial_arm": Exercise("term", robot="spatial_arm", term="tau",
                                hint="the outward iteration (6.45)–(6.50), then the inward (6.51)–(6.53)"),
    "v_dot_c1": Exercise("value", _v_dot_c1, hint="(6.48) for link 1: ¹ω̇₁ × ¹P_C₁ + ¹ω₁ × (¹ω₁ × ¹P_C₁) + ¹v̇₁"),
    "M_two_link": Exercise("term", term="M", hint="(6.60)"),
    "V_two_link": Exercise("term", term="V", hint="(6.61)"),
    "G_two_link": Exercise("term", term="G", hint="(6.62)"),
    "k_pendulum": Exercise("formula", lambda: _pendulum("k"), variables=("m", "l", "g", "theta", "theta_dot"),
                           hint="(6.69) for a point mass at distance l: ½ m v², v = l θ̇"),
    "u_pendulum": Exercise("formula", lambda: _pendulum("u"), variables=("m", "l", "g", "theta", "theta_dot"),
                           constant_in=("theta",), hint="(6.73): −m gᵀ P_C; θ = 0 hangs straight down"),
    "tau_pendulum": Exercise("formula", lambda: _pendulum("tau"),
                             variables=("m", "l", "g", "theta", "theta_dot", "theta_ddot"),
                             hint="(6.76): d/dt ∂L/∂θ̇ − ∂L/∂θ = τ with L = k − u"),
    "J_tool": Exercise("formula", _J_tool, variables=("l1", "l2", "theta2"),
                       hint="the velocity of the tip in frame {3}, per unit θ̇₁ and θ̇₂ (Craig (5.66))"),
    "Mx_value": Exercise("value", _Mx_value, hint="(6.99): M_x = J⁻ᵀ M J⁻¹ with J the ³J of example 6.6"),
    "friction_torque": Exercise(
        "function", reference=lambda qd, v, c: c * np.sign(qd) + v * qd,
        inputs=lambda rng: [rng.standard_normal(3), rng.uniform(0, 1, 3), rng.uniform(0, 1, 3)],
        hint="(6.112): c sgn(θ̇) + v θ̇"),
    "tau_with_friction": Exercise("value", _tau_with_friction, hint="(6.114): τ = M Θ̈ + V + G + F(Θ̇)"),
    "euler_step": Exercise("function", reference=_euler, inputs=lambda rng: [*rng.standard_normal((3, 2)), 0.01],
                           hint="(6.116) for Θ̇, (6.117) for Θ"),
    "semi_implicit_step": Exercise("function", reference=_semi_implicit,
                                   inputs=lambda rng: [*rng.standard_normal((3, 2)), 0.01],
                                   hint="the new Θ̇ first, then Θ with the new Θ̇"),
    "I_xy_corner": Exercise("value", _I_xy_corner, hint="ᴬI_xy = ᶜI_xy + m x_c y_c (the notes print −)"),
    "inward_force": Exercise(
        "function", reference=lambda R, f_next, F: R @ f_next + F,
        inputs=lambda rng: [np.linalg.qr(rng.standard_normal((3, 3)))[0], rng.standard_normal(3), rng.standard_normal(3)],
        hint="(6.51) corrected: ⁱfᵢ = ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁ + ⁱFᵢ"),
    "Y_mcx2": Exercise("value", _Y_mcx2, hint="∂τ/∂(m₂l₂): the terms of (6.60)–(6.62) in m₂l₂, divided by m₂l₂"),
    "base_two_link": Exercise(
        "function", reference=lambda pi: base_parameters(_robot("two_link")).values(pi),
        inputs=lambda rng: [rng.standard_normal(20)],
        hint="for τ, link 2's mass is a point mass of link 1 at joint 2, (l₁, 0, 0): what does it add to h₁ and I_zz,₁?"),
}


# ---------------------------------------------------------------------------------------- checking


def _not_done(value) -> bool:
    return value is MISSING or value is None or value is Ellipsis


def check(name: str, answer=MISSING) -> Verdict:
    """Check exercise ``name`` against the library (module docstring); the answer is looked up by name if not given."""
    if name not in EXERCISES:
        raise KeyError(f"no exercise named '{name}' (exercises: {', '.join(EXERCISES)})")
    if answer is MISSING:
        answer = inspect.currentframe().f_back.f_globals.get(name, MISSING)
    exercise = EXERCISES[name]
    if _not_done(answer):
        verdict = Verdict(name, "not done", [f"write your answer as `{name}` in the cell above, then run this cell again"])
    else:
        verdict = {"term": _check_term, "function": _check_function, "value": _check_value,
                   "formula": _check_formula}[exercise.kind](name, exercise, answer)
    if verdict.status == "wrong" and exercise.hint:
        verdict.lines.append(f"hint: {exercise.hint}")
    if os.environ.get("NBGRADER_EXECUTION") == "autograde" and verdict.status != "right":
        raise AssertionError(verdict.text())
    return verdict


def _try(function, *arguments):
    """(value, None), or (None, "not done") for a placeholder, or (None, error text)."""
    try:
        value = function(*arguments)
    except NotImplementedError:
        return None, "not done"
    except Exception as exc:  # the student's code failed: feedback, not a crash of the notebook
        return None, f"{type(exc).__name__}: {exc}"
    return (None, "not done") if _not_done(value) else (value, None)


def term_assignment(name: str) -> Assignment:
    """The assignment term exercise ``name`` is checked under, as the grader would grade it: one point for its
    term, on 12 states seeded by the exercise's name."""
    exercise = EXERCISES[name]
    return Assignment(source=Path(name), robot_argument=exercise.robot, robot=_robot(exercise.robot),
                      points={exercise.term: 1.0}, samples=12, seed=sum(map(ord, name)), tolerance=exercise.tolerance)


def _check_term(name: str, exercise: Exercise, function) -> Verdict:
    """A function of the robot (τ, M, V, G or C), scored exactly as the grader scores it."""
    if not callable(function):
        return Verdict(name, "wrong", [f"`{name}` should be a function, it is a {type(function).__name__}"])
    assignment = term_assignment(name)
    plan = make_plan(assignment)
    calls = plan.harness_functions()
    _, problem = _try(function, *(np.array(a) for a in calls[exercise.term if exercise.term in calls else "tau"][0]))
    if problem == "not done":
        return Verdict(name, "not done", [f"`{name}` does not return anything yet: write its body"])
    outcome = evaluate({exercise.term: function}, {k: v for k, v in calls.items() if k in FUNCTIONS},
                       function.__code__.co_filename)
    [result] = score_outcome(outcome, assignment, plan, expected_terms(assignment, plan))
    if result.correct:
        return Verdict(name, "right", [f"agrees with course_dynamics on all {result.total} random states"])
    return Verdict(name, "wrong", [f"agrees on {result.agreed} of {result.total} random states", *result.findings]
                   + ([result.worst] if result.worst else []))


def _value_problems(expected, value, tolerance: float) -> list[str]:
    """What is wrong with a value, as :func:`~course_dynamics.grading.score.score` finds it; [] when it is right."""
    try:
        theirs = np.asarray(value).astype(float)
    except (TypeError, ValueError):
        return [f"expected numbers, got {reprlib.repr(value)}"]
    result = score(Answer.single(expected, theirs, tolerance))
    return [] if result.correct else [*result.findings, result.worst]


def _show(array) -> str:
    return np.array2string(np.asarray(array), precision=6, separator=", ").replace("\n", "")


def _check_value(name: str, exercise: Exercise, answer) -> Verdict:
    problems = _value_problems(exercise.answer(), answer, exercise.tolerance)
    return Verdict(name, "wrong" if problems else "right", problems or ["equals course_dynamics' value"])


def _check_function(name: str, exercise: Exercise, function) -> Verdict:
    if not callable(function):
        return Verdict(name, "wrong", [f"`{name}` should be a function, it is a {type(function).__name__}"])
    rng = np.random.default_rng(sum(map(ord, name)))
    for trial in range(20):
        arguments = exercise.inputs(rng)
        value, problem = _try(function, *arguments)
        if problem == "not done":
            return Verdict(name, "not done", [f"`{name}` does not return anything yet: write its body"])
        if problem is not None:
            return Verdict(name, "wrong", [f"raised {problem}"])
        expected = exercise.reference(*arguments)
        if isinstance(expected, tuple):
            if not isinstance(value, (tuple, list)) or len(value) != len(expected):
                return Verdict(name, "wrong", [f"should return {len(expected)} values, returned {type(value).__name__}"])
            problems = [f"value {k + 1}: {p}" for k, (e, v) in enumerate(zip(expected, value))
                        for p in _value_problems(e, v, exercise.tolerance)]
        else:
            problems = _value_problems(expected, value, exercise.tolerance)
        if problems:
            shown = ", ".join(_show(a) for a in arguments)
            return Verdict(name, "wrong", [f"for the inputs {shown}:"] + problems)
    return Verdict(name, "right", ["agrees with course_dynamics on 20 random inputs"])


def _check_formula(name: str, exercise: Exercise, answer) -> Verdict:
    import sympy

    expected = exercise.answer()
    try:
        answer = sympy.Matrix(answer) if isinstance(expected, sympy.MatrixBase) or isinstance(answer, np.ndarray) \
            else sympy.sympify(answer)
        expected = sympy.Matrix(expected) if isinstance(answer, sympy.MatrixBase) else sympy.sympify(expected)
    except (sympy.SympifyError, TypeError, ValueError):
        return Verdict(name, "wrong", [f"expected a sympy expression, got {type(answer).__name__}"])
    if isinstance(expected, sympy.MatrixBase) and expected.shape != getattr(answer, "shape", None):
        return Verdict(name, "wrong", [f"has shape {getattr(answer, 'shape', 'none')}, the answer has {expected.shape}"])
    variables = symbols(*exercise.variables)
    variables = variables if isinstance(variables, list) else [variables]
    stray = sorted(str(s) for s in answer.free_symbols if s not in set(variables))
    if stray:
        return Verdict(name, "wrong", [f"uses symbols {', '.join(stray)}; use the ones given: "
                                       f"{', '.join(map(str, variables))} (from course_dynamics.teaching.exercises.symbols)"])
    difference = answer - expected
    if exercise.constant_in:
        difference = sympy.Matrix([difference]) if not isinstance(difference, sympy.MatrixBase) else difference
        difference = difference.jacobian(symbols(*exercise.constant_in) if len(exercise.constant_in) > 1
                                         else [symbols(*exercise.constant_in)])
    if sympy.simplify(difference) == (sympy.zeros(*difference.shape) if hasattr(difference, "shape") else 0):
        return Verdict(name, "right", ["equals the closed form" + (" (up to a constant)" if exercise.constant_in else "")])
    problems = []
    if isinstance(expected, sympy.MatrixBase):
        wrong = [(i + 1, j + 1) for i in range(expected.rows) for j in range(expected.cols)
                 if sympy.simplify(answer[i, j] - expected[i, j]) != 0]
        if len(wrong) < expected.rows * expected.cols:
            problems.append(f"entries {', '.join(map(str, wrong))} are wrong (numbered from 1); the others are right")
    elif expected != 0:
        ratio = sympy.simplify(answer / expected)
        if ratio.is_number:
            problems.append("has the opposite sign" if ratio == -1 else f"is the right expression times {ratio}")
    rng = np.random.default_rng(1)
    point = {v: float(rng.uniform(0.5, 1.5)) for v in variables}
    value = np.array(sympy.N(answer.subs(point)), dtype=float)
    right = np.array(sympy.N(expected.subs(point)), dtype=float)
    shown = ", ".join(f"{k} = {v:.3f}" for k, v in point.items())
    return Verdict(name, "wrong", problems + [f"at {shown}: yours gives {_show(value)}, the right one {_show(right)}"])
