"""The notebooks' exercises and their checks: ``check("name")`` says right, wrong and why, or not done yet.

Each exercise of the notebook course has a name here, the data it gives the
student (:data:`~course_dynamics.teaching.catalogue.GIVEN`) and a way to know the answer from the library. A check
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
missing answer raises ``AssertionError`` with the same feedback. Check cells carry
no points: they run in the student's own kernel, where they can be made to pass;
marks come from ``course-dynamics grade``.
"""
from __future__ import annotations

import copy
import inspect
import os
import re
import reprlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.newton_euler import newton_euler_links
from ..grading.assignment import Assignment
from ..grading.diagnosis import Answer, significant
from ..grading.harness import FUNCTIONS, evaluate
from ..grading.mistakes import MISTAKES
from ..grading.numbers import Handout
from ..grading.plan import expected_terms, make_plan
from ..grading.score import score, score_outcome
from ..grading.slips import slips
from ..output.render import markdown_escape
from ..tools.variants import COURSE_STUDENT, rng_for
from .catalogue import (RP_PARAMETERS, EXERCISES, Exercise, given, my_robot, rp_arm_equations, student, symbols,
                        use_student)
from .limits import CheckTimeout, time_limit
from .derivations import equation_problems, in_joint_symbols, time_functions

__all__ = ["Verdict", "check", "given", "hint", "my_robot", "show_values", "student", "symbols",
           "term_assignment", "time_functions", "use_student"]
MISSING = object()
BACKTICKS = re.compile(r"`([^`]*)`")
_REVEAL = {"values": False}


def show_values(on: bool = True) -> None:
    """Let the checks print the expected values (the instructor's solution mode); students' checks never do, and
    under nbgrader's autograder it stays off.

    Parameters
    ----------
    on : bool, optional
        Show them (True, the default) or not.
    """
    _REVEAL["values"] = bool(on) and os.environ.get("NBGRADER_EXECUTION") != "autograde"


def hint(name: str, level: int = 1) -> str:
    """Hint ``level`` (1, 2, …) of exercise ``name``: which idea, then which equation, then the method, last (never
    the answer itself).

    Parameters
    ----------
    name : str
        The exercise.
    level : int, optional
        The tier, from 1; a level past the last gives the last (the method), and one that is not a number
        gives the first.

    Returns
    -------
    str
        ``"hint 1 of 3: …"``, with how to ask for the next one.

    Raises
    ------
    KeyError
        If there is no exercise of that name.

    Examples
    --------
    >>> print(hint("k_pendulum", 3))
    hint 3 of 3: ½ m v², v its speed
    """
    if name not in EXERCISES:
        raise KeyError(f"no exercise named {name!r} (exercises: {', '.join(EXERCISES)})")
    hints = EXERCISES[name].hints
    try:
        level = max(1, min(int(level), len(hints)))
    except (TypeError, ValueError, OverflowError):
        level = 1
    if not hints:
        return f"{name} has no hints"
    more = f" — for more, hint({name!r}, {level + 1})" if level < len(hints) else ""
    return f"hint {level} of {len(hints)}: {hints[level - 1]}{more}"

def _whose(student: str) -> str:
    return "no student id: the course's own numbers" if student == COURSE_STUDENT else f"{student}'s numbers"


@dataclass
class Verdict:
    """The outcome of a check: ``status`` is "right", "wrong" or "not done", ``lines`` the feedback.

    True when right; a notebook shows it as Markdown, a console as :meth:`text`.

    Parameters
    ----------
    name : str
        The exercise.
    status : str
        ``"right"``, ``"wrong"`` or ``"not done"``.
    lines : list of str, optional
        The feedback, one line each (Markdown: code names in backticks).
    numbers_of : str, optional
        The student whose robot and numbers it was checked on (empty when the exercise has none of its own).
    """

    name: str
    status: str
    lines: list[str] = field(default_factory=list)
    numbers_of: str = ""  # the student whose robot and numbers it was checked on

    def __bool__(self) -> bool:
        return self.status == "right"

    def text(self) -> str:
        """Plain text (a console, a log): code names in quotes instead of Markdown's backticks.

        Returns
        -------
        str
            The exercise's name and verdict, then each line of feedback, indented, after a dash.
        """
        head = {"right": "✓ right", "wrong": "✗ not yet right", "not done": "… not done yet"}[self.status]
        head += f" ({_whose(self.numbers_of)})" if self.numbers_of else ""
        plain = [BACKTICKS.sub(r"'\1'", line) for line in self.lines]
        return "\n".join([f"{self.name}: {head}"] + [f"  - {line}" for line in plain])

    __repr__ = text

    def _repr_markdown_(self) -> str:

        head = {"right": "✅ **right**", "wrong": "❌ **not yet right**", "not done": "⏳ **not done yet**"}[self.status]
        head += f" ({markdown_escape(_whose(self.numbers_of))})" if self.numbers_of else ""
        return "\n".join([f"`{self.name}`: {head}", ""] + [f"- {markdown_escape(line)}" for line in self.lines])


# ---------------------------------------------------------------------------------------- checking


KINDS = {"term": "it should be a function of numpy arrays returning a numpy array",
         "links": "it should be a function returning a dict of per-link lists",
         "equations": "it should be a list of sympy expressions",
         "function": "it should be a function of numpy arrays returning numbers",
         "value": "it should be a number, a list of numbers or a numpy array",
         "formula": "it should be a sympy expression (or a sympy Matrix) in the symbols given"}


CHECK_SECONDS = 60


def _a(noun: str) -> str:
    return ("an " if noun[:1].lower() in "aeiou" else "a ") + noun


def _not_done(value) -> bool:
    return value is MISSING or value is None or value is Ellipsis


def check(name: str, answer=MISSING) -> Verdict:
    """Check exercise ``name`` against the library (module docstring); the answer is looked up by name if not given.

    Parameters
    ----------
    name : str
        The exercise (a key of :data:`~course_dynamics.teaching.catalogue.EXERCISES`).
    answer : object, optional
        The answer (a function, a value, a sympy expression, a list of equations); by default the value of
        the name ``name`` in the caller's globals (the notebook's).

    Returns
    -------
    Verdict
        Right, wrong (and why), or not done yet. An answer that fails, or runs longer than 60 s, is a
        wrong verdict, never an exception.

    Raises
    ------
    KeyError
        If there is no exercise of that name.
    AssertionError
        Under nbgrader's autograder (``NBGRADER_EXECUTION=autograde``), for an answer that is not right, with
        the verdict's text.

    Examples
    --------
    >>> check("k_pendulum").status
    'not done'
    >>> m, l, theta_dot = symbols("m", "l", "theta_dot")
    >>> bool(check("k_pendulum", m * l**2 * theta_dot**2 / 2))
    True
    """
    if name not in EXERCISES:
        raise KeyError(f"no exercise named '{name}' (exercises: {', '.join(EXERCISES)})")
    if answer is MISSING:
        answer = inspect.currentframe().f_back.f_globals.get(name, MISSING)
    exercise = EXERCISES[name]
    if _not_done(answer):
        verdict = Verdict(name, "not done",
                          [f"write your answer as `{name}` in the cell above, then run this cell again"])
    else:
        kind = {"term": _check_term, "links": _check_links, "equations": _check_equations, "function": _check_function,
                "value": _check_value, "formula": _check_formula}[exercise.kind]
        try:
            with np.errstate(all="ignore"), time_limit(CHECK_SECONDS):
                verdict = kind(name, exercise, answer)
        except CheckTimeout:
            verdict = Verdict(name, "wrong", [f"took more than {CHECK_SECONDS} s to check: an endless loop, or an "
                                              "answer far larger than it should be?"])
        except KeyboardInterrupt:
            raise
        except BaseException as exc:  # an answer no check foresaw (sys.exit too): feedback, never a crash
            verdict = Verdict(name, "wrong", [f"could not check this answer ({type(exc).__name__}: "
                                              f"{reprlib.repr(str(exc))}): {KINDS[exercise.kind]}"])
        if exercise.kind in ("term", "links", "value"):
            verdict.numbers_of = student()
    if verdict.status == "wrong" and exercise.hints:
        verdict.lines.append(f"a hint, if you want one: hint({name!r}) (there are {len(exercise.hints)}, "
                             "the method step by step last)")
    if os.environ.get("NBGRADER_EXECUTION") == "autograde" and verdict.status != "right":
        raise AssertionError(verdict.text())
    return verdict


def _try(function, *arguments):
    """(value, None), or (None, "not done") for a placeholder, or (None, error text)."""
    try:
        value = function(*arguments)
    except NotImplementedError:
        return None, "not done"
    except (KeyboardInterrupt, CheckTimeout):
        raise
    except BaseException as exc:  # the student's code failed (sys.exit too): feedback, not a crash of the notebook
        return None, f"{type(exc).__name__}: {exc}"
    return (None, "not done") if _not_done(value) else (value, None)


def term_assignment(name: str) -> Assignment:
    """The assignment term exercise ``name`` is checked under, as the grader would grade it: one point for its
    term, on 12 states seeded by the student and the exercise, on the student's robot.

    Parameters
    ----------
    name : str
        A ``"term"`` exercise (``"tau_two_link"``, ``"M_two_link"``, …).

    Returns
    -------
    Assignment
        The assignment (:class:`~course_dynamics.grading.assignment.Assignment`).

    Raises
    ------
    KeyError
        If there is no exercise of that name.
    """
    exercise = EXERCISES[name]
    seed = int(rng_for(student(), name).integers(2**31))
    return Assignment(source=Path(name), robot_argument=exercise.robot, robot=my_robot(exercise.robot).model,
                      points={exercise.term: 1.0}, samples=12, seed=seed, tolerance=exercise.tolerance, states="shared")


def _check_term(name: str, exercise: Exercise, function) -> Verdict:
    """A function of the robot (τ, M, V, G or C), scored exactly as the grader scores it."""
    if not callable(function):
        return Verdict(name, "wrong", [f"`{name}` should be a function, it is {_a(type(function).__name__)}"])
    assignment = term_assignment(name)
    plan = make_plan(assignment)
    calls = plan.harness_functions()
    _, problem = _try(function, *(np.array(a) for a in calls[exercise.term if exercise.term in calls else "tau"][0]))
    if problem == "not done":
        return Verdict(name, "not done", [f"`{name}` does not return anything yet: write its body"])
    outcome = evaluate({exercise.term: function}, {k: v for k, v in calls.items() if k in FUNCTIONS},
                       getattr(getattr(function, "__code__", None), "co_filename", "<your answer>"))
    handout = Handout(assignment.robot, exercise.robot, student())  # the robots they may have used instead
    [result] = score_outcome(outcome, assignment, plan, expected_terms(assignment, plan), _REVEAL["values"], handout)
    if result.correct:
        return Verdict(name, "right", [f"agrees with course_dynamics on all {result.total} random states"])
    return Verdict(name, "wrong", [f"agrees on {result.agreed} of {result.total} random states", *result.findings]
                   + ([result.worst] if result.worst else []))


LINK_QUANTITIES = {"omega": "ⁱωᵢ (6.45)", "omega_dot": "ⁱω̇ᵢ (6.46)", "v_dot": "ⁱv̇ᵢ (6.47)",
                   "v_dot_c": "ⁱv̇_Cᵢ (6.48)", "F": "ⁱFᵢ (6.49)", "N": "ⁱNᵢ (6.50)", "f": "ⁱfᵢ (6.51)",
                   "n": "ⁱnᵢ (6.52)", "tau": "τᵢ (6.53)"}


def _check_links(name: str, exercise: Exercise, function) -> Verdict:
    """Both iterations link by link: ``function(q, qd, qdd)`` returns a dict of :data:`LINK_QUANTITIES`, each a list
    of one 3-vector per link (τ: one number per joint), in the link's own frame. The first wrong quantity, in the
    order the iterations compute them, is named, with the slip of the recursion that explains it, if one does."""
    if not callable(function):
        return Verdict(name, "wrong", [f"`{name}` should be a function, it is {_a(type(function).__name__)}"])
    state, model = given(name), my_robot(exercise.robot).model
    returned, problem = _try(function, *copy.deepcopy([state["q"], state["qd"], state["qdd"]]))
    if problem is not None:
        return Verdict(name, "not done" if problem == "not done" else "wrong",
                       [f"`{name}` does not return anything yet: write its body" if problem == "not done"
                        else f"raised {problem}"])
    if not isinstance(returned, dict):
        return Verdict(name, "wrong", [f"should return a dict with the keys {', '.join(LINK_QUANTITIES)}"])
    ours, lines = newton_euler_links(model, state["q"], state["qd"], state["qdd"]), []
    for key, words in LINK_QUANTITIES.items():
        if key not in returned:
            lines.append(f"{words} is missing (key '{key}')")
            continue
        expected = getattr(ours, key)
        try:
            theirs = np.asarray(returned[key], dtype=float)
        except (TypeError, ValueError):
            theirs = None
        if theirs is None or theirs.shape != expected.shape:
            each = "one number per joint" if expected.ndim == 1 else "one 3-vector per link, link 1 first"
            lines.append(f"{words} (key '{key}') should be {each}: shape {expected.shape}, not "
                         f"{'numbers' if theirs is None else theirs.shape}")
            break
        wrong = [i + 1 for i in range(model.n) if _value_problems(expected[i], theirs[i], exercise.tolerance)]
        if wrong:
            right = [f"link {i}" for i in range(1, model.n + 1) if i not in wrong]
            lines.append(f"{words} is wrong for link {', '.join(map(str, wrong))}"
                         + (f" (right for {', '.join(right)})" if right else "") + "; what comes before it is right")
            slip, everything = _explaining_slip(model, state, returned, key, exercise.tolerance)
            if slip is not None:
                how = "it matches" if everything else f"{LINK_QUANTITIES[key].split()[0]} matches"
                more = "" if everything else " (the later quantities do not: that mistake and another?)"
                lines.append(f"[{slip.code}] {how} {MISTAKES[slip.code].words} in {slip.where}{more}. "
                             f"{MISTAKES[slip.code].advice}.")
            break
    return Verdict(name, "wrong" if lines else "right",
                   lines or [f"every quantity of both iterations agrees, link by link, at your state"])


def _check_equations(name: str, exercise: Exercise, answer) -> Verdict:
    """Equations of motion derived by hand (sympy, θ(t) and its derivatives, or the joint symbols), term by term."""
    import sympy  # heavy: only the derivation exercises use it

    expected, joints, _, _ = rp_arm_equations()
    rows = list(answer) if isinstance(answer, (list, tuple, sympy.MatrixBase)) else None
    if rows is None or len(rows) != len(expected):
        return Verdict(name, "wrong", [f"should be a list of {len(expected)} expressions, τ₁ first"])
    try:
        lines = equation_problems(rows, expected, joints, symbols(*RP_PARAMETERS), symbols("g"))
    except (sympy.SympifyError, TypeError, ValueError, AttributeError):
        return Verdict(name, "wrong", ["each entry should be a sympy expression"])
    return Verdict(name, "wrong" if lines else "right", lines or ["equals example 6.5's equations of motion"])


def _explaining_slip(model, state, returned: dict, first_wrong: str, tolerance: float):
    """The slip of the recursion that explains the student's quantities: one that matches every quantity they
    returned if there is one, else one that matches the first wrong quantity; the fewest equations first."""
    def matches(slip, key):
        ours = np.asarray(getattr(made[slip], key), dtype=float)
        try:
            theirs = np.asarray(returned[key], dtype=float)
        except (KeyError, TypeError, ValueError):
            return False
        return theirs.shape == ours.shape and np.allclose(theirs, ours, rtol=tolerance,
                                                          atol=tolerance * max(1.0, float(np.abs(ours).max())))

    made = {slip: newton_euler_links(model, state["q"], state["qd"], state["qdd"], slip) for slip in slips()}
    ordered = sorted(made, key=lambda slip: len(slip.equations))
    whole = [slip for slip in ordered if all(matches(slip, key) for key in LINK_QUANTITIES if key in returned)]
    first = [slip for slip in ordered if matches(slip, first_wrong)]
    return ((whole or first or [None])[0], bool(whole))


def _value_problems(expected, value, tolerance: float) -> list[str]:
    """What is wrong with a value, as :func:`~course_dynamics.grading.score.score` finds it; [] when it is right."""
    if any(x is Ellipsis for x in np.ravel(np.asarray(value, dtype=object))):
        return ["still holds ... (the placeholder): put your numbers in its place"]
    if (np.iscomplexobj(np.asarray(value))
            or any(isinstance(x, complex) for x in np.ravel(np.asarray(value, dtype=object)))):
        return ["holds complex numbers: every quantity here is real (a square root of a negative number?)"]
    try:
        theirs = np.asarray(value).astype(float)
    except (TypeError, ValueError):
        return [f"expected numbers, got {reprlib.repr(value)}"]
    result = score(Answer.single(expected, theirs, tolerance, _REVEAL["values"]))
    if result.correct:
        return []
    said = [*result.findings] + ([result.worst] if result.worst else [])
    return said or ["is not the right value: every entry differs from it"]


def _show(array) -> str:
    return np.array2string(np.asarray(array), precision=6, separator=", ").replace("\n", "")


def _check_value(name: str, exercise: Exercise, answer) -> Verdict:
    expected = exercise.answer()
    problems = _value_problems(expected, answer, exercise.tolerance)
    if problems and np.asarray(expected).dtype == bool:  # for yes-or-no answers, which entries are wrong is the answer
        problems = ["not all of them are right: check each one again"]
    if problems and exercise.slipped is not None:  # the one recursion, with each slip a student makes
        for slip in sorted(slips(), key=lambda slip: len(slip.equations)):
            if _agrees(exercise.slipped(slip), answer, exercise.tolerance):
                return Verdict(name, "wrong", [f"[{slip.code}] it matches {MISTAKES[slip.code].words} in {slip.where}. "
                                               f"{MISTAKES[slip.code].advice}."])
    return Verdict(name, "wrong" if problems else "right", problems or ["equals course_dynamics' value"])


def _check_function(name: str, exercise: Exercise, function) -> Verdict:
    if not callable(function):
        return Verdict(name, "wrong", [f"`{name}` should be a function, it is {_a(type(function).__name__)}"])
    rng = rng_for(student(), name)
    for trial in range(20):
        arguments = exercise.inputs(rng)
        # before, and on copies: an answer may change its inputs
        expected = exercise.reference(*copy.deepcopy(arguments))
        value, problem = _try(function, *copy.deepcopy(arguments))
        if problem == "not done":
            return Verdict(name, "not done", [f"`{name}` does not return anything yet: write its body"])
        if problem is not None:
            return Verdict(name, "wrong", [f"raised {problem}"])
        if isinstance(expected, tuple):
            if not isinstance(value, (tuple, list)) or len(value) != len(expected):
                return Verdict(name, "wrong",
                               [f"should return {len(expected)} values, returned {type(value).__name__}"])
            problems = [f"value {k + 1}: {p}" for k, (e, v) in enumerate(zip(expected, value))
                        for p in _value_problems(e, v, exercise.tolerance)]
        else:
            problems = _value_problems(expected, value, exercise.tolerance)
        if problems:
            shown = ", ".join(_show(a) for a in arguments)
            named = [f"[{code}] it matches {words}" for code, made, words in exercise.mistakes
                     if _agrees(made(*copy.deepcopy(arguments)), value, exercise.tolerance)]
            return Verdict(name, "wrong", [f"for the inputs {shown}:"] + (named[:1] or problems))
    return Verdict(name, "right", ["agrees with course_dynamics on 20 random inputs"])


def _agrees(expected, value, tolerance: float) -> bool:
    if isinstance(expected, tuple):
        return isinstance(value, (tuple, list)) and len(value) == len(expected) and all(
            _agrees(e, v, tolerance) for e, v in zip(expected, value))
    return not _value_problems(expected, value, tolerance)


def _check_formula(name: str, exercise: Exercise, answer) -> Verdict:
    import sympy

    expected = exercise.answer()
    expected = sympy.Matrix(expected) if isinstance(expected, (np.ndarray, list)) else expected
    matrix_like = (np.ndarray, list, tuple, sympy.MatrixBase, sympy.NDimArray)
    try:
        answer = sympy.Matrix(answer) if isinstance(expected, sympy.MatrixBase) and isinstance(answer, matrix_like) \
            else sympy.sympify(answer)
        expected = sympy.Matrix(expected) if isinstance(answer, sympy.MatrixBase) else sympy.sympify(expected)
    except (sympy.SympifyError, TypeError, ValueError):
        return Verdict(name, "wrong", [f"expected a sympy expression, got {type(answer).__name__}"])
    if isinstance(expected, sympy.MatrixBase) != isinstance(answer, sympy.MatrixBase):
        return Verdict(name, "wrong", [
            f"should be a {'matrix' if isinstance(expected, sympy.MatrixBase) else 'single expression'}"
            f", of shape {getattr(expected, 'shape', '()')}"])
    if isinstance(expected, sympy.MatrixBase) and expected.shape != getattr(answer, "shape", None):
        return Verdict(name, "wrong",
                       [f"has shape {getattr(answer, 'shape', 'none')}, the answer has {expected.shape}"])
    if exercise.time_functions:  # θ(t), θ̇(t), θ̈(t) written by the chain rule: the symbols θ, θ_dot, θ_ddot
        answer = in_joint_symbols(answer, {f: symbols(f, f + "_dot", f + "_ddot") for f in exercise.time_functions})
    variables = symbols(*exercise.variables)
    variables = variables if isinstance(variables, list) else [variables]
    named = {str(v): v for v in variables}  # a student's own Symbol("m") is read by its name
    answer = answer.xreplace({x: named[str(x)] for x in answer.free_symbols if str(x) in named})
    stray = sorted(str(s) for s in answer.free_symbols if s not in set(variables))
    if stray:
        return Verdict(name, "wrong", [f"uses symbols {', '.join(stray)}; use the ones given: "
                                       f"{', '.join(map(str, variables))} "
                                       "(from course_dynamics.teaching.exercises.symbols)"])
    difference = answer - expected
    if exercise.constant_in:
        difference = sympy.Matrix([difference]) if not isinstance(difference, sympy.MatrixBase) else difference
        difference = difference.jacobian(symbols(*exercise.constant_in) if len(exercise.constant_in) > 1
                                         else [symbols(*exercise.constant_in)])
    if sympy.simplify(difference) == (sympy.zeros(*difference.shape) if hasattr(difference, "shape") else 0):
        return Verdict(name, "right",
                       ["equals the closed form" + (" (up to a constant)" if exercise.constant_in else "")])
    for code, made, words in exercise.mistakes:
        if sympy.simplify(answer - made()) == (sympy.zeros(*expected.shape) if hasattr(expected, "shape") else 0):
            return Verdict(name, "wrong", [f"[{code}] it matches {words}"])
    problems = []
    if isinstance(expected, sympy.MatrixBase):
        wrong = [(i + 1, j + 1) for i in range(expected.rows) for j in range(expected.cols)
                 if sympy.simplify(answer[i, j] - expected[i, j]) != 0]
        if len(wrong) < expected.rows * expected.cols:
            are = "entry {} is" if len(wrong) == 1 else "entries {} are"
            problems.append(f"{are.format(', '.join(map(str, wrong)))} wrong (numbered from 1); the others are right")
    elif expected != 0:
        ratio = sympy.simplify(answer / expected)
        if ratio.is_number:
            shown = ratio if ratio.is_Rational else significant(float(ratio))  # never digits to divide by
            problems.append("has the opposite sign" if ratio == -1 else "is zero" if ratio == 0
                            else f"is the right expression times {shown}")
    rng = np.random.default_rng(1)
    point = {v: float(rng.uniform(0.5, 1.5)) for v in variables}
    value = np.array(sympy.N(answer.subs(point)), dtype=float)
    right = np.array(sympy.N(expected.subs(point)), dtype=float)
    shown = ", ".join(f"{k} = {v:.3f}" for k, v in point.items())
    right = f", the right one {_show(right)}" if _REVEAL["values"] else ""
    return Verdict(name, "wrong", problems + [f"at {shown}: yours gives {_show(value)}{right}"])
