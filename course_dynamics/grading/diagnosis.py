"""What is wrong with an answer, in words that teach: a list of small checks over one record.

An :class:`Answer` is one comparison: a student's values next to ours, state by
state (the grader's seeded states for τ, M, V, G or C; one "state" for a
notebook exercise's value), with what else the checks may read: the states, our
answers made with typical mistakes, V's (6.63) coefficients, τ's parts. Each
check is a small function (or frozen dataclass) of the record that returns a
:class:`Finding` (a named mistake in Craig's terms, with its advice) or None.
:func:`diagnose` runs :data:`SCREENS` always, then :data:`CHECKS` when some
comparable state disagrees, in order; a *conclusive* finding (†) explains the
whole answer and ends the list:

============================  ====================================================
check                         the answer …
============================  ====================================================
not_defined †                 does not exist: no function, no τ to derive it from
raised_an_error, wrong_shape  is an exception, has the wrong shape,
not_finite                    holds NaN or inf (on some states)
opposite_sign †               agrees with −ours everywhere
named_mistake †               agrees with ours made with a mistake of ``mistakes``
constant_factor †             ≈ k · ours for one k ≠ 1
transposed †, joints_swapped  agrees with ours transposed, or joints permuted;
closest_mistake               much nearer one mistaken answer than the right one
tau_parts, InPart(…)          (τ) which of its parts G, M, V are right; a check on one
wrong_entries                 which entries disagree
not_symmetric                 (M) differs from its transpose
not_christoffel               (C) satisfies C Θ̇ = V, but is not Christoffel's
wrong_coefficients            (V) its (6.63) coefficients of θ̇ⱼθ̇ₖ (Coriolis, Craig's B)
                              and θ̇ⱼ² (centrifugal, C); V(Θ, 2Θ̇) = 4 V(Θ, Θ̇)
coriolis_without_factor_2     (V) every Coriolis coefficient is half of ours
============================  ====================================================

:func:`~course_dynamics.grading.score.score` turns a record and its findings
into a :class:`Diagnosis`, for the grader and the notebooks alike.

>>> answer = Answer.single([0.5, -2.0], [-1.0, 4.0], tolerance=1e-6)
>>> [finding.tags for finding in diagnose(answer)]
[('constant factor',)]
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from itertools import permutations

import numpy as np

from ..core.sampling import relative_error, term_scales
from .mistakes import MISTAKES
from .plan import Expected, Plan, VelocityProbe

TERM_NAMES = {"tau": "τ", "M": "M", "V": "V", "G": "G", "C": "C"}
SIGNATURES = {"tau": "tau(q, qd, qdd)", "M": "M(q)", "V": "V(q, qd)", "G": "G(q)", "C": "C(q, qd)"}
# the floor of the relative error of a value that is no function of the robot; wrong entries named one by one
VALUE_SCALE, LISTED = 1e-12, 8


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
                 f"agrees on {self.agreed} of {self.total} states (relative tolerance {self.tolerance:g})"]
        lines += [f"- {finding}" for finding in self.findings]
        if self.worst:
            lines.append(f"- {self.worst}")
        return "\n".join(lines)


# ---------------------------------------------------------------------------------------- screens: unusable states
def not_defined(answer: Answer) -> Finding | None:
    if answer.available:
        return None
    derive = "" if answer.term == "tau" else ", or tau(q, qd, qdd) to derive it from"
    return Finding(f"not defined: write {SIGNATURES[answer.term]}{derive}", ("not defined",), conclusive=True)


def raised_an_error(answer: Answer) -> Finding | None:
    errors = [(k, e) for k, e in enumerate(answer.errors) if e is not None]
    if not errors:
        return None
    (k, message), N = errors[0], answer.count
    every = "every state" if len(errors) == N else f"{len(errors)} of {N} states (first: state #{k + 1})"
    return Finding(f"raised an error on {every}: {message}", ("raised an error",))


def wrong_shape(answer: Answer) -> Finding | None:
    shape = answer.expected.shape[1:]
    got = next((v.shape for v in answer.values if v is not None and v.shape != shape), None)
    if got is None:
        return None
    if not answer.joints:
        return Finding(f"has shape {got}, the answer has shape {shape}", ("wrong shape",))
    n, joints, name = len(answer.joints), ", ".join(answer.joints), answer.name
    if len(shape) == 1:
        count = got[0] if len(got) == 1 else int(np.prod(got))
        what = f"returned {count} values" if len(got) == 1 else f"returned an array of shape {tuple(got)}"
        text = f"{what}, the robot has {n} joints ({joints}): {name} has one entry per joint, shape ({n},)"
    else:
        text = (f"returned an array of shape {tuple(got)}, {name} must be {n} × {n} (rows and columns in joint order "
                f"{joints})")
    return Finding(text, ("wrong shape",))


def not_finite(answer: Answer) -> Finding | None:
    shape = answer.expected.shape[1:]
    found = [k for k, v in enumerate(answer.values)
             if v is not None and v.shape == shape and not np.all(np.isfinite(v))]
    if not found:
        return None
    where = "contains NaN or inf:" if answer.count == 1 else \
        f"returned NaN or inf on {len(found)} of {answer.count} states (first: state #{found[0] + 1});"
    return Finding(f"{where} look for a division by zero or a square root of a negative number", ("NaN or inf",))


# ---------------------------------------------------------------------------------------- the whole answer explained
def opposite_sign(answer: Answer) -> Finding | None:
    if not answer.agrees_with(-answer.expected):
        return None
    if answer.term == "G":
        return Finding(f"[gravity-sign] has the opposite sign everywhere: {MISTAKES['gravity-sign'].advice}",
                       ("gravity-sign",), True)
    advice = "check the direction of gravity, of the joint axes, and subtractions done the wrong way round" \
        if answer.joints else "check the sign of each term, and subtractions done the wrong way round"
    returned = f"{answer.name} returned" if answer.name else "yours"
    return Finding(f"has the opposite sign everywhere ({returned} = −1 × the right value): {advice}",
                   ("opposite sign",), conclusive=True)


def named_mistake(answer: Answer) -> Finding | None:
    """Agrees with one of our answers made with a mistake (:mod:`~course_dynamics.grading.mistakes`)."""
    made = answer.reference.mistakes.get(answer.term, {}) if answer.reference is not None else {}
    for (code, variant), values in made.items():
        if answer.agrees_with(values):
            return Finding(f"[{code}] matches the right answer made with {MISTAKES[code].words}"
                           f"{' ' + variant if variant else ''}: {MISTAKES[code].advice}", (code,), conclusive=True)
    return None


def closest_mistake(answer: Answer) -> Finding | None:
    """Much nearer one of our mistaken answers than the right one, without agreeing: that mistake and another?"""
    made = answer.reference.mistakes.get(answer.term, {}) if answer.reference is not None else {}
    if not made or not answer.usable:
        return None

    def distance(candidates):
        return float(np.median([relative_error(answer.values[k], candidates[k], answer.scales[k])
                                for k in answer.usable]))

    right = distance(answer.expected)
    (code, variant), nearest = min(((key, distance(values)) for key, values in made.items()), key=lambda x: x[1])
    if nearest > min(0.1, right / 10):
        return None
    return Finding(f"closest to [{code}] {MISTAKES[code].words}{' ' + variant if variant else ''} (relative error "
                   f"{nearest:.1g} from that, {right:.1g} from the right answer): that mistake and another?",
                   (f"closest to {code}",))


def constant_factor(answer: Answer) -> Finding | None:
    ours, usable = answer.expected, answer.usable
    denominator = sum(float(np.sum(ours[k] * ours[k])) for k in usable)
    if sum(ours[k].size for k in usable) < 2 or denominator <= 0:  # one number is always some factor of another
        return None
    factor = sum(float(np.sum(answer.values[k] * ours[k])) for k in usable) / denominator
    loose = 10 * answer.tolerance
    if abs(factor) < 1e-6 or abs(factor - 1) <= loose or not answer.agrees_with(factor * ours, loose):
        return None
    return Finding(f"is the right answer times a constant factor {factor:.6g}: a missing or extra factor such as ½, 2, "
                   "a mass or a length squared?", ("constant factor",), conclusive=True)


def transposed(answer: Answer) -> Finding | None:
    ours = answer.expected
    if ours.ndim != 3 or ours.shape[1] != ours.shape[2] or not answer.agrees_with(np.swapaxes(ours, 1, 2)):
        return None
    advice = (f": row i of {answer.name} belongs to τᵢ and column j to the θ̇ⱼ or θ̈ⱼ it multiplies"
              if answer.joints else " (rows and columns exchanged)")
    return Finding(f"is the transpose of the right matrix{advice}", ("transposed",), conclusive=True)


def joints_swapped(answer: Answer) -> Finding | None:
    if not answer.joints:
        return None
    ours, n = answer.expected, answer.expected.shape[1]
    candidates = permutations(range(n)) if n <= 5 else (
        tuple(j if j not in (a, b) else (b if j == a else a) for j in range(n))
        for a in range(n) for b in range(a + 1, n))
    for p in map(list, candidates):
        if p == list(range(n)):
            continue
        # vectors: entries reordered; matrices: rows and columns, or rows only (a τ returned in the wrong order)
        moved = [ours[:, p]] if ours.ndim == 2 else [ours[:, p][:, :, p], ours[:, p]]
        if any(answer.agrees_with(m) for m in moved):
            names, joints = ", ".join(answer.joints[j] for j in p), ", ".join(answer.joints)
            return Finding(f"[joints-swapped] has its joints in the wrong order ({names} appear as {joints}): entries must follow the "
                           f"joint order {joints} that `course-dynamics info` prints", ("joints-swapped",), True)
    return None


# ---------------------------------------------------------------------------------------- details
def wrong_entries(answer: Answer) -> Finding | None:
    ours, bad = answer.expected, set()
    size = int(np.prod(ours.shape[1:], dtype=int))
    if size < 2:
        return None
    for k in answer.usable:
        error = np.abs(answer.values[k] - ours[k]) / max(float(np.abs(ours[k]).max()), answer.scales[k],
                                                         np.finfo(float).tiny)
        bad |= {tuple(int(i) for i in index) for index in np.argwhere(error > answer.tolerance)}
    if not bad or len(bad) == size:
        return None
    if answer.joints:
        names = [f"{answer.name}[{','.join(str(i + 1) for i in index)}]" for index in sorted(bad)]
        order = "rows and columns numbered" if ours.ndim == 3 else "numbered"
        where = f"{order} from 1 in joint order {', '.join(answer.joints)}"
    else:
        names = [str(index[0] + 1) if len(index) == 1 else str(tuple(i + 1 for i in index)) for index in sorted(bad)]
        where = "numbered from 1"
    more = f" (and {len(names) - LISTED} more)" if len(names) > LISTED else ""
    tag = f"wrong entries of {answer.term}" if answer.term else "wrong entries"
    return Finding(("entry {} is" if len(names) == 1 else "entries {} are").format(", ".join(names[:LISTED])) +
                   f"{more} wrong ({where}); the others are right", (tag,))


def not_symmetric(answer: Answer) -> Finding | None:
    if answer.term != "M" or not any(
            np.abs(answer.values[k] - answer.values[k].T).max() > answer.tolerance * max(answer.scales[k], 1e-300)
            for k in answer.usable):
        return None
    return Finding("is not symmetric: a mass matrix always is (Mᵢⱼ = Mⱼᵢ), since k = ½ Θ̇ᵀ M Θ̇ (6.71)",
                   ("M not symmetric",))


def not_christoffel(answer: Answer) -> Finding | None:
    if answer.term != "C" or answer.plan is None or answer.reference is None:
        return None
    plan, ours, usable = answer.plan, answer.reference.terms, set(answer.usable)
    product = tuple(v @ plan.qd[k] if k in usable else None for k, v in enumerate(answer.values))
    scales = tuple(term_scales(ours["M"][k], ours["G"][k], plan.qd[k], plan.qdd[k], np.zeros(3))["V"]
                   for k in range(answer.count))
    velocity = Answer(ours["V"], product, (None,) * answer.count, scales, answer.tolerance)
    if not velocity.agrees_with(velocity.expected):
        return None
    return Finding("satisfies C Θ̇ = V, but it is not the Christoffel-symbol form Cᵢⱼ = Σₖ Γᵢⱼₖ θ̇ₖ (the one with "
                   "Ṁ − 2C skew-symmetric) that the assignment asks for", ("C not Christoffel",))


def _quadratic(answer: Answer) -> bool:
    probe = answer.coefficients
    return all(np.abs(twice - 4 * once).max() <= answer.tolerance * max(4 * np.abs(once).max(), scale)
               for once, twice, scale in zip(probe.single, probe.doubled, probe.scales, strict=True))


def wrong_coefficients(answer: Answer) -> Finding | None:
    if answer.coefficients is None:
        return None
    label = answer.label or answer.name
    if not _quadratic(answer):
        return Finding(f"{label} is not quadratic in Θ̇: V(Θ, 2Θ̇) should be 4 V(Θ, Θ̇), because every velocity term is "
                       "a product of two joint rates (θ̇ⱼθ̇ₖ or θ̇ⱼ²)", ("V not quadratic",))
    wrong = {}
    for c in answer.coefficients.coefficients:
        if not c.right(answer.tolerance):
            wrong.setdefault((c.kind, c.i, c.j, c.k), c)  # the first diagnostic state that shows it
    if not wrong:
        return None
    described = []
    for c in [wrong[key] for key in sorted(wrong)][:6]:
        rates, matrix = (f"θ̇{c.j + 1}θ̇{c.k + 1}", "B") if c.kind == "Coriolis" else (f"θ̇{c.j + 1}²", "C")
        expected = f"expected {c.expected:.6g}, " if answer.reveal else ""
        described.append(f"the {c.kind} coefficient of {rates} in τ{c.i + 1} (Craig's {matrix}, (6.63)): {expected}"
                         f"returned {c.returned:.6g} at state #{c.state + 1}")
    more = f" (and {len(wrong) - 6} more)" if len(wrong) > 6 else ""
    return Finding(f"in {label} = B(Θ)[Θ̇Θ̇] + C(Θ)[Θ̇²], these coefficients are wrong: " + "; ".join(described) + more,
                   tuple(f"wrong {kind} terms" for kind in sorted({kind for kind, *_ in wrong})))


def coriolis_without_factor_2(answer: Answer) -> Finding | None:
    if answer.coefficients is None or not _quadratic(answer):
        return None
    found = answer.coefficients.coefficients
    coriolis = [c for c in found if c.kind == "Coriolis"]
    if not any(abs(c.expected) > answer.tolerance * c.scale for c in coriolis) or not all(
            c.right(answer.tolerance, 0.5 if c.kind == "Coriolis" else 1.0) for c in found):
        return None
    return Finding(f"[coriolis-half] in {answer.label or answer.name}, every Coriolis term θ̇ⱼθ̇ₖ (j ≠ k) has half its coefficient: "
                   "Σⱼₖ Γᵢⱼₖ θ̇ⱼθ̇ₖ holds each product twice, so Craig's B is 2Γᵢⱼₖ (6.63), as in the "
                   "two-link arm's −2 m₂l₁l₂s₂ θ̇₁θ̇₂ (6.61)", ("coriolis-half",))


PART_NAMES = {"G": "the gravity part G = τ(Θ, 0, 0)", "M": "the inertia part M(Θ) (τ(Θ, 0, eⱼ) − G)",
              "V": "the velocity part V = τ(Θ, Θ̇, 0) − G"}


def tau_parts(answer: Answer) -> Finding | None:
    """τ = M Θ̈ + V + G: which of its parts are right, from τ(Θ, 0, 0), τ(Θ, 0, eⱼ) and τ(Θ, Θ̇, 0)."""
    if not answer.parts:
        return None
    right = [key for key, part in answer.parts.items() if part.correct]
    wrong = [key for key, part in answer.parts.items() if not part.correct]
    summary = []
    for keys, verdict in ((right, "right"), (wrong, "wrong")):
        if keys:
            names = " and ".join(PART_NAMES[k] for k in keys)
            summary.append(f"{names} {'is' if len(keys) == 1 else 'are'} {verdict}")
    return Finding("; ".join(summary), tuple(f"wrong {k} part of tau" for k in wrong))


@dataclass(frozen=True)
class InPart:
    """``check`` run on one of τ's parts (when that part is wrong), its finding said to be about the part."""

    part: str
    check: Callable[[Answer], Finding | None]
    prefix: str = ""

    def __call__(self, answer: Answer) -> Finding | None:
        part = answer.parts.get(self.part)
        finding = self.check(part) if part is not None and part.wrong else None
        if finding is None:
            return None  # the code of a named mistake stays first
        code, _, text = finding.text.partition("] ") if finding.text.startswith("[") else ("", "", finding.text)
        return Finding((code + "] " if code else "") + self.prefix + text, finding.tags)


SCREENS = (not_defined, raised_an_error, wrong_shape, not_finite)
CHECKS = (
    opposite_sign, named_mistake, constant_factor, transposed, joints_swapped, closest_mistake,
    tau_parts, InPart("G", named_mistake, "in τ's gravity part, "), InPart("M", wrong_entries, "in τ's inertia part, "),
    InPart("V", wrong_coefficients),
    InPart("V", coriolis_without_factor_2),
    wrong_entries, not_symmetric, not_christoffel, wrong_coefficients, coriolis_without_factor_2,
)


def diagnose(answer: Answer, checks=CHECKS) -> list[Finding]:
    """The findings of :data:`SCREENS`, then, when some comparable state disagrees, of ``checks``: in order, up to
    the first conclusive one (module docstring)."""
    found = []
    for check in SCREENS + (tuple(checks) if answer.wrong else ()):
        finding = check(answer)
        if finding is not None:
            found.append(finding)
            if finding.conclusive:
                break
    return found
