"""The records of scoring: one comparison (:class:`Answer`), what a check found (:class:`Finding`), an answer's
score (:class:`Diagnosis`). The checks that read them are in :mod:`~course_dynamics.grading.diagnosis` and
:mod:`~course_dynamics.grading.mistakes`.

>>> answer = Answer.single([0.5, -2.0], [-1.0, 4.0], tolerance=1e-6)
>>> answer.correct, answer.wrong
(False, (0,))
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..core.sampling import relative_error

# Plan, Expected and VelocityProbe (grading/plan.py) and Handout (grading/numbers.py) appear in annotations only,
# never evaluated: the plan imports the mistakes, which read these records.
TERM_NAMES = {"tau": "τ", "M": "M", "V": "V", "G": "G", "C": "C"}
VALUE_SCALE = 1e-12  # the floor of the relative error of a value that is no function of the robot


@dataclass(frozen=True, eq=False)  # holds arrays: compared by identity
class Answer:
    """One comparison, state by state, the record every check reads: ``expected`` (N, …) is ours, ``values`` per
    state the student's array or None where ``errors`` says why, ``scales`` per state the floor of the relative
    error (:func:`~course_dynamics.core.sampling.term_scales`). For a function of the robot, ``term`` and ``joints``
    name it and its rows, ``plan`` and ``reference`` give the states and all our answers, ``coefficients`` V probed
    at the diagnostic states, ``parts`` τ's gravity, inertia and velocity parts (each an Answer of its own).

    Parameters
    ----------
    expected : numpy.ndarray, shape (N, ...)
        Our value at each of the N states.
    values : tuple of (numpy.ndarray or None)
        The student's value at each state, None where it gave none.
    errors : tuple of (str or None)
        Per state, why there is no value (the error raised, or the status), None where there is one.
    scales : tuple of float
        Per state, the floor of the relative error.
    tolerance : float
        The relative error allowed per state.
    term : str
        The term compared (one of ``tau``, ``M``, ``V``, ``G``, ``C``), empty for a value of no robot.
    label : str
        What the answer is, in feedback (empty: the term's name).
    source : str
        How the value was had: ``"direct"``, ``"missing"`` or how it was derived from other terms.
    joints : tuple of str
        The robot's joint names, naming the rows.
    plan : Plan or None
        The calls the answer was asked, with their states.
    reference : Expected or None
        All our answers at those states.
    coefficients : VelocityProbe or None
        The student's V(Θ, Θ̇) probed at the diagnostic states.
    parts : collections.abc.Mapping of str to Answer
        τ's gravity, inertia and velocity parts, each an Answer of its own.
    reveal : bool
        Whether the feedback may show our values (not in a student's notebook).
    handout : Handout or None
        The student's robot and the robots they may have used instead (:mod:`~course_dynamics.grading.numbers`).
    related : collections.abc.Mapping of str to Answer
        The student's other graded terms, each an Answer of its own (what one term alone cannot tell, such as
        which parameter a factor of V is, they may).
    """

    expected: np.ndarray
    values: tuple
    errors: tuple
    scales: tuple
    tolerance: float
    term: str = ""
    label: str = ""
    source: str = "direct"
    joints: tuple[str, ...] = ()
    plan: Plan | None = None
    reference: Expected | None = None
    coefficients: VelocityProbe | None = None
    parts: Mapping[str, Answer] = field(default_factory=dict)
    reveal: bool = True  # whether the feedback may show our values (not in a student's notebook)
    handout: Handout | None = None
    related: Mapping[str, Answer] = field(default_factory=dict)

    @classmethod
    def single(cls, expected, value, tolerance: float, reveal: bool = True) -> Answer:
        """A value compared once (a notebook exercise's number, vector or matrix).

        Parameters
        ----------
        expected : array_like
            Our value.
        value : array_like
            The student's value.
        tolerance : float
            The relative error allowed.
        reveal : bool
            Whether the feedback may show our value.

        Returns
        -------
        Answer
            The comparison, one state long.
        """
        expected = np.asarray(expected, dtype=float)
        return cls(expected[None], (np.asarray(value, dtype=float),), (None,), (VALUE_SCALE,), tolerance, reveal=reveal)

    @property
    def name(self) -> str:
        """The term's symbol (τ, M, V, G, C), empty for a value of no robot."""
        return TERM_NAMES.get(self.term, "")

    @property
    def count(self) -> int:
        """The number of states compared."""
        return len(self.expected)

    @property
    def available(self) -> bool:
        """Whether the student gave the term at all (directly or derived)."""
        return self.source != "missing"

    @cached_property
    def usable(self) -> tuple[int, ...]:
        """The states with a finite value of the right shape."""
        shape = self.expected.shape[1:]
        return tuple(k for k, v in enumerate(self.values)
                     if v is not None and v.shape == shape and bool(np.all(np.isfinite(v))))

    @cached_property
    def relative_errors(self) -> dict[int, float]:
        """The relative error at each usable state, by state index."""
        return {k: relative_error(self.values[k], self.expected[k], self.scales[k]) for k in self.usable}

    @property
    def agreed(self) -> tuple[int, ...]:
        """The states whose value agrees within the tolerance."""
        return tuple(k for k, e in self.relative_errors.items() if e <= self.tolerance)

    @property
    def wrong(self) -> tuple[int, ...]:
        """The usable states whose value does not agree."""
        return tuple(k for k, e in self.relative_errors.items() if e > self.tolerance)

    @property
    def correct(self) -> bool:
        """Whether every state agrees."""
        return len(self.agreed) == self.count

    def agrees_with(self, candidates: np.ndarray, tolerance: float | None = None) -> bool:
        """Whether the value of every usable state agrees with ``candidates`` (N, …) there.

        Parameters
        ----------
        candidates : numpy.ndarray, shape (N, ...)
            A value at each state to compare with.
        tolerance : float or None
            The relative error allowed; the answer's own when None.

        Returns
        -------
        bool
            True when there is a usable state and all of them agree.
        """
        tolerance = self.tolerance if tolerance is None else tolerance
        return bool(self.usable) and all(relative_error(self.values[k], candidates[k], self.scales[k]) <= tolerance
                                         for k in self.usable)


@dataclass(frozen=True)
class Finding:
    """What a check found: the sentence read, the tags counted, and whether it explains everything (``conclusive``).

    Parameters
    ----------
    text : str
        The sentence the student reads.
    tags : tuple of str
        The tags the summary counts.
    conclusive : bool
        Whether it explains every disagreeing state.
    """

    text: str
    tags: tuple[str, ...]
    conclusive: bool = False


@dataclass(frozen=True)
class Diagnosis:
    """The score of one answer: its points, the states that agree, the findings that explain the rest, the worst
    state (what :func:`~course_dynamics.grading.score.score` returns).

    Parameters
    ----------
    term : str
        The term scored.
    points : float
        The points given.
    max_points : float
        The points the term is worth.
    agreeing : tuple of int
        The states that agree.
    total : int
        The number of states.
    source : str
        How the value was had: ``"direct"``, ``"missing"`` or how it was derived from other terms.
    tolerance : float
        The relative error allowed per state.
    findings : tuple of str
        The sentences that explain the disagreeing states.
    tags : tuple of str
        The tags of those findings.
    worst : str
        The worst state, as a sentence (empty when all agree).
    """

    term: str
    points: float
    max_points: float
    agreeing: tuple[int, ...]
    total: int
    source: str
    tolerance: float
    findings: tuple[str, ...] = ()
    tags: tuple[str, ...] = ()
    worst: str = ""

    @property
    def agreed(self) -> int:
        """The number of states that agree."""
        return len(self.agreeing)

    @property
    def correct(self) -> bool:
        """Whether there are states and all of them agree."""
        return self.total > 0 and self.agreed == self.total

    def text(self) -> str:
        """The feedback as plain text: a summary line, the findings, the worst state.

        Returns
        -------
        str
            The lines, joined by newlines.
        """
        how = "" if self.source in ("direct", "missing") else f" ({self.source})"
        lines = [f"{TERM_NAMES.get(self.term, 'the answer')}: {self.points:g} / {self.max_points:g} points{how}; "
                 f"agrees on {self.agreed} of {self.total} states"]
        lines += [f"- {finding}" for finding in self.findings]
        if self.worst:
            lines.append(f"- {self.worst}")
        return "\n".join(lines)


__all__ = ["Answer", "Diagnosis", "Finding"]
