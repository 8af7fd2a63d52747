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

# Plan, Expected and VelocityProbe (grading/plan.py) appear in annotations only, never evaluated: the plan imports
# the mistakes, which read these records.
TERM_NAMES = {"tau": "τ", "M": "M", "V": "V", "G": "G", "C": "C"}
VALUE_SCALE = 1e-12  # the floor of the relative error of a value that is no function of the robot


@dataclass(frozen=True, eq=False)  # holds arrays: compared by identity
class Answer:
    """One comparison, state by state, the record every check reads: ``expected`` (N, …) is ours, ``values`` per
    state the student's array or None where ``errors`` says why, ``scales`` per state the floor of the relative
    error (:func:`~course_dynamics.core.sampling.term_scales`). For a function of the robot, ``term`` and ``joints``
    name it and its rows, ``plan`` and ``reference`` give the states and all our answers, ``coefficients`` V probed
    at the diagnostic states, ``parts`` τ's gravity, inertia and velocity parts (each an Answer of its own)."""

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

    @classmethod
    def single(cls, expected, value, tolerance: float, reveal: bool = True) -> Answer:
        """A value compared once (a notebook exercise's number, vector or matrix)."""
        expected = np.asarray(expected, dtype=float)
        return cls(expected[None], (np.asarray(value, dtype=float),), (None,), (VALUE_SCALE,), tolerance, reveal=reveal)

    @property
    def name(self) -> str:
        return TERM_NAMES.get(self.term, "")

    @property
    def count(self) -> int:
        return len(self.expected)

    @property
    def available(self) -> bool:
        return self.source != "missing"

    @cached_property
    def usable(self) -> tuple[int, ...]:
        """The states with a finite value of the right shape."""
        shape = self.expected.shape[1:]
        return tuple(k for k, v in enumerate(self.values)
                     if v is not None and v.shape == shape and bool(np.all(np.isfinite(v))))

    @cached_property
    def relative_errors(self) -> dict[int, float]:
        return {k: relative_error(self.values[k], self.expected[k], self.scales[k]) for k in self.usable}

    @property
    def agreed(self) -> tuple[int, ...]:
        return tuple(k for k, e in self.relative_errors.items() if e <= self.tolerance)

    @property
    def wrong(self) -> tuple[int, ...]:
        return tuple(k for k, e in self.relative_errors.items() if e > self.tolerance)

    @property
    def correct(self) -> bool:
        return len(self.agreed) == self.count

    def agrees_with(self, candidates: np.ndarray, tolerance: float | None = None) -> bool:
        """Whether the value of every usable state agrees with ``candidates`` (N, …) there."""
        tolerance = self.tolerance if tolerance is None else tolerance
        return bool(self.usable) and all(relative_error(self.values[k], candidates[k], self.scales[k]) <= tolerance
                                         for k in self.usable)


@dataclass(frozen=True)
class Finding:
    """What a check found: the sentence read, the tags counted, and whether it explains everything (``conclusive``)."""

    text: str
    tags: tuple[str, ...]
    conclusive: bool = False


@dataclass(frozen=True)
class Diagnosis:
    """The score of one answer: its points, the states that agree, the findings that explain the rest, the worst
    state (what :func:`~course_dynamics.grading.score.score` returns)."""

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
        return len(self.agreeing)

    @property
    def correct(self) -> bool:
        return self.total > 0 and self.agreed == self.total

    def text(self) -> str:
        """The feedback as plain text: a summary line, the findings, the worst state."""
        how = "" if self.source in ("direct", "missing") else f" ({self.source})"
        lines = [f"{TERM_NAMES.get(self.term, 'the answer')}: {self.points:g} / {self.max_points:g} points{how}; "
                 f"agrees on {self.agreed} of {self.total} states"]
        lines += [f"- {finding}" for finding in self.findings]
        if self.worst:
            lines.append(f"- {self.worst}")
        return "\n".join(lines)
