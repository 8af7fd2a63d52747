"""Scoring a student's answer against ours: one mechanism, one record, for the grader and the notebooks alike.

:func:`score` is the one comparison. It takes an
:class:`~course_dynamics.grading.records.Answer` (the student's values next to
ours, state by state) and returns its
:class:`~course_dynamics.grading.records.Diagnosis`: the points, the states
that agree, the findings of :func:`~course_dynamics.grading.diagnosis.diagnose`
and the worst state.

:func:`score_outcome` wires a submission's functions of the robot into it: the
harness's outcome, read back by key (:class:`~course_dynamics.grading.plan.Answers`),
becomes one Answer per graded term (:func:`term_answer`: read directly or
derived from the student's τ, with τ's parts and V's (6.63) coefficients),
and each is scored. ``grade`` calls it on what came back from the sandbox, the
notebooks' term exercises on what :func:`~course_dynamics.grading.harness.evaluate`
returned in the student's kernel, and their value exercises call :func:`score`
on one :meth:`~course_dynamics.grading.records.Answer.single`: the same
answer gets the same diagnosis everywhere.

>>> graded = score(Answer.single([1.0, -2.0], [-1.0, 2.0], tolerance=1e-6), max_points=5)
>>> graded.points, graded.tags, graded.worst
(0.0, ('opposite sign',), 'expected [1, -2], got [-1, 2] (relative error 2)')
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..core.sampling import term_scales
from .assignment import Assignment
from .diagnosis import Answer, Diagnosis, diagnose
from .numbers import Handout
from .plan import Answers, Expected, Plan, returned_coefficients, returned_terms

DERIVED_C_TOLERANCE = 1e-7  # central differences reach about 1e-8
PARTS = ("G", "M", "V")  # τ's parts, each derived from the student's τ
PART_LABELS = {"V": "τ's velocity part V"}


def score(answer: Answer, max_points: float = 1.0, partial_credit: str = "states") -> Diagnosis:
    """``answer``'s points, agreeing states, findings and worst state (module docstring).

    ``partial_credit`` "states" gives ``max_points`` × the fraction of states that agree, "none" all or nothing.

    Parameters
    ----------
    answer : Answer
        The student's values next to ours.
    max_points : float
        The points the answer is worth.
    partial_credit : str
        ``"states"`` or ``"none"``.

    Returns
    -------
    Diagnosis
        The points (rounded to 0.01), the agreeing states, the findings and their tags, the worst state.

    Raises
    ------
    ValueError
        If ``partial_credit`` is neither ``"states"`` nor ``"none"``, or the answer has no states (a caller's
        mistake: an assignment's file is checked when it is read).
    """
    agreeing, N = answer.agreed, answer.count
    if partial_credit not in ("states", "none") or N == 0:
        raise ValueError(f"score: partial_credit {partial_credit!r} on {N} states")
    if partial_credit == "states":
        points = round(max_points * len(agreeing) / N, 2)
    else:
        points = max_points if len(agreeing) == N else 0.0
    found = [] if answer.correct else diagnose(answer)
    tags = tuple(tag for finding in found for tag in finding.tags)
    if answer.wrong and not tags:
        tags = ("wrong values",)
    return Diagnosis(answer.term, points, max_points, agreeing, N, answer.source, answer.tolerance,
                     tuple(finding.text for finding in found), tags, "" if answer.correct else _worst(answer))


def _fmt(x, floor: float | None = None) -> str:
    """Numbers to 6 digits; in an array, entries below 1e-12 of its largest are round-off and show as 0."""
    array = np.asarray(x, dtype=float)
    if floor is None:
        floor = 1e-12 * float(np.max(np.abs(array), initial=0.0)) if np.all(np.isfinite(array)) else 0.0
    if array.ndim == 0:
        return "0" if abs(float(array)) < floor else f"{float(array):.6g}"
    return "[" + ", ".join(_fmt(v, floor) for v in array) + "]"


def _state_text(plan: Plan, term: str, k: int) -> str:
    parts = [f"q = {_fmt(plan.q[k])}"]
    if term in ("tau", "V", "C"):
        parts.append(f"qd = {_fmt(plan.qd[k])}")
    if term == "tau":
        parts.append(f"qdd = {_fmt(plan.qdd[k])}")
    return ", ".join(parts)


def _worst(answer: Answer) -> str:
    """The state that shows the mistake best, with our value and the student's."""
    ours, values, name = answer.expected, answer.values, answer.name
    if not answer.available:
        state = _state_text(answer.plan, answer.term, 0)
        return f"to check yours, state #1: {state}; expected {name} = {_fmt(ours[0])}" if answer.reveal else ""
    shape = ours.shape[1:]
    unusable = [k for k, v in enumerate(values) if v is not None and k not in answer.usable]
    non_finite = [k for k in unusable if values[k].shape == shape]
    if answer.wrong:
        k = max(answer.wrong, key=lambda i: answer.relative_errors[i])
        returned = f"{_fmt(values[k])} (relative error {answer.relative_errors[k]:.2g})"
    elif non_finite:
        k = non_finite[0]
        returned = _fmt(values[k])
    elif unusable:
        k = unusable[0]
        returned = f"{_fmt(values[k])} (shape {tuple(values[k].shape)})"
    else:
        k = next(i for i, e in enumerate(answer.errors) if e is not None)
        returned = f"an error: {answer.errors[k]}"
    if answer.plan is None:  # a single value: in a student's view its error would tell the answer, so none is shown
        return f"expected {_fmt(ours[k])}, got {returned}" if answer.reveal else ""
    expected = f"expected {name} = {_fmt(ours[k])}, " if answer.reveal else ""
    return f"worst state #{k + 1}: {_state_text(answer.plan, answer.term, k)}; {expected}returned {returned}"


def scales_at(plan: Plan, reference: Expected, term: str, gravity) -> tuple[float, ...]:
    """The floor of ``term``'s relative error at each of the plan's states, from our M and G."""
    return tuple(term_scales(reference.terms["M"][k], reference.terms["G"][k], plan.qd[k], plan.qdd[k], gravity)[term]
                 for k in range(len(plan.q)))


def term_answer(term: str, answers: Answers, plan: Plan, reference: Expected, assignment: Assignment,
                from_tau: bool = False, reveal: bool = True, handout: Handout | None = None) -> Answer:
    """The student's ``term`` next to ours: from their function of that name, else (or with ``from_tau``) derived
    from their τ; τ comes with its parts G, M, V (derived from it), V with its (6.63) coefficients.

    Parameters
    ----------
    term : str
        The term: one of ``tau``, ``M``, ``V``, ``G``, ``C``.
    answers : Answers
        The submission's answers, by call.
    plan : Plan
        The calls asked, with their states.
    reference : Expected
        Our answers at those states.
    assignment : Assignment
        The assignment: the robot and the tolerance.
    from_tau : bool
        Derive the term from the student's τ even when they define a function of that name.
    reveal : bool
        Whether the feedback may show our values.
    handout : Handout or None
        The student's robot and the robots they may have used instead; the assignment's robot alone when None.

    Returns
    -------
    Answer
        The comparison (a C derived from τ held to a tolerance of at least 1e-7).
    """
    returned = returned_terms(answers, plan, term, from_tau)
    tolerance = assignment.tolerance
    if returned.source == "derived from tau" and term == "C":
        tolerance = max(tolerance, DERIVED_C_TOLERANCE)
    model = assignment.robot
    if handout is None:  # in a class graded per student, the roster's robots are the ones a student may have used
        roster = getattr(assignment, "roster", None) if assignment.variant == "per-student" else None
        handout = Handout(model, assignment.robot_argument, classmates=tuple(roster or ()))
    parts = {}
    if term == "tau" and returned.available and not from_tau:
        parts = {key: term_answer(key, answers, plan, reference, assignment, True, reveal, handout) for key in PARTS}
    return Answer(reference.terms[term], tuple(returned.values), tuple(returned.errors),
                  scales_at(plan, reference, term, model.gravity), tolerance, term=term,
                  label=PART_LABELS.get(term, "") if from_tau else "", source=returned.source,
                  joints=tuple(model.joint_names), plan=plan, reference=reference,
                  coefficients=returned_coefficients(answers, plan, reference, from_tau) if term == "V" else None,
                  parts=parts, reveal=reveal, handout=handout)


def score_outcome(outcome: dict, assignment: Assignment, plan: Plan, reference: Expected,
                  reveal: bool = True, handout: Handout | None = None) -> list[Diagnosis]:
    """Every graded term of ``outcome`` (the harness's ``defined`` and ``results``) scored, in the assignment's order:
    what ``grade`` and the notebooks' term exercises both call (``reveal`` False: the feedback shows none of our
    values, as in a student's notebook).

    Parameters
    ----------
    outcome : dict
        The harness's outcome: ``defined`` (the functions the submission defines) and ``results`` (per function,
        one record per call, in the order asked).
    assignment : Assignment
        The assignment: terms, points, tolerance, partial credit.
    plan : Plan
        The calls asked, with their states.
    reference : Expected
        Our answers at those states.
    reveal : bool
        Whether the feedback may show our values.
    handout : Handout or None
        The student's robot and the robots they may have used instead (:mod:`~course_dynamics.grading.numbers`);
        the assignment's robot alone when None.

    Returns
    -------
    list of Diagnosis
        One per graded term, in the assignment's order.
    """
    answers = Answers.read(outcome, plan)
    made = {term: term_answer(term, answers, plan, reference, assignment, reveal=reveal, handout=handout)
            for term in assignment.terms}
    # each answer sees the others: what one term alone cannot tell (which parameter a factor of V is), they may
    return [score(replace(made[term], related={t: a for t, a in made.items() if t != term}), assignment.points[term],
                  assignment.partial_credit) for term in assignment.terms]


__all__ = ["score", "score_outcome", "term_answer"]
