"""What is wrong with an answer, in words that teach: a list of small checks over one record.

An :class:`~course_dynamics.grading.records.Answer` is one comparison: a student's values next to ours, state by
state (the grader's seeded states for τ, M, V, G or C; one "state" for a
notebook exercise's value), with what else the checks may read: the states, our
answers made with typical mistakes, V's (6.63) coefficients, τ's parts. Each
check is a small function (or frozen dataclass) of the record that returns a
:class:`~course_dynamics.grading.records.Finding` (a named mistake in Craig's terms, with its advice) or None.
:func:`diagnose` runs :data:`SCREENS` always, then :data:`CHECKS` when some
comparable state disagrees, in order; a *conclusive* finding (†) explains the
whole answer and ends the list:

=================================  ====================================================
check                              the answer …
=================================  ====================================================
not_defined †                      does not exist: no function, no τ to derive it from
raised_an_error, wrong_shape       is an exception, has the wrong shape,
not_finite                         holds NaN or inf (on some states)
returns_zeros †, opposite_sign †   (its own function) returns zeros (to round-off); agrees with −ours
                                   everywhere (and the mistakes that do too)
named_mistake †                    agrees with ours made with a mistake of ``mistakes``
derived_zeros †                    (derived from τ) is zero: τ leaves that part out
error_in_parts †                   (τ) its parts are right but for some, each a named mistake: τ's error is
                                   all there
other_parameters †                 is the right dynamics of another robot: the textbook's, another variant's, or
                                   the handout's with other inertial parameters (``numbers``)
constant_factor †                  ≈ k · ours for one k ≠ 1
transposed †, joints_swapped       agrees with ours transposed, or joints permuted;
closest_mistake                    less than 5 % from one mistaken answer and ten times nearer it than the right one
                                   (``mistakes.CLOSE``); else says no known mistake is that close
tau_parts, InPart(…)               (τ) which of its parts G, M, V are right; a check on one
wrong_entries                      which entries disagree
not_symmetric                      (M) differs from its transpose
not_christoffel                    (C) satisfies C Θ̇ = V, but is not Christoffel's
wrong_coefficients                 (V) its (6.63) coefficients of θ̇ⱼθ̇ₖ (Coriolis, Craig's B)
                                   and θ̇ⱼ² (centrifugal, C); V(Θ, 2Θ̇) = 4 V(Θ, Θ̇)
coriolis_without_factor_2          (V) every Coriolis coefficient is half of ours
=================================  ====================================================

:func:`~course_dynamics.grading.score.score` turns a record and its findings
into a :class:`~course_dynamics.grading.records.Diagnosis`, for the grader and the notebooks alike.

>>> answer = Answer.single([0.5, -2.0], [-1.0, 4.0], tolerance=1e-6)
>>> [finding.tags for finding in diagnose(answer)]
[('constant factor',)]
"""
from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from itertools import permutations

import numpy as np

from ..core.sampling import relative_error, term_scales
from .mistakes import MISTAKES, closest_mistake, described, matching_mistakes, named_mistake
from .numbers import other_parameters
from .records import TERM_NAMES, Answer, Diagnosis, Finding

SIGNATURES = {"tau": "tau(q, qd, qdd)", "M": "M(q)", "V": "V(q, qd)", "G": "G(q)", "C": "C(q, qd)"}
LISTED = 8  # wrong entries named one by one
CODES = re.compile(r"((?:\[[a-z0-9-]+\] )*)(.*)", re.S)  # the codes a finding starts with, and the rest


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
SIGN_ADVICE = {"tau": "check the direction of gravity, of the joint axes, and subtractions done the wrong way round",
               "G": "check the direction of gravity", "": "check the sign of each term, and subtractions done the "
               "wrong way round"}


def opposite_sign(answer: Answer) -> Finding | None:
    """−ours everywhere; where a named mistake gives the same answer (a negated G is gravity's sign), it is
    named too."""
    if not answer.agrees_with(-answer.expected):
        return None
    advice = SIGN_ADVICE.get(answer.term, "check the joint axes and subtractions done the wrong way round")
    returned = f"{answer.name} returned" if answer.name else "yours"
    found = matching_mistakes(answer)
    also = ("; the same answer comes from " + " or from ".join(f"[{c}] {MISTAKES[c].words}" for c in found)
            if found else "")
    return Finding(f"has the opposite sign everywhere ({returned} = −1 × the right value): {advice}{also}",
                   ("opposite sign", *found), conclusive=True)


#: The share of the term's scale, and of our value, below which every entry of an answer counts as zero (round-off).
ZERO = 1e-9


def _all_zero(answer: Answer) -> bool:
    return bool(answer.usable) and all(
        float(np.abs(answer.values[k]).max(initial=0.0)) <= ZERO * max(answer.scales[k],
                                                                        float(np.abs(answer.expected[k]).max()))
        for k in answer.usable)


def returns_zeros(answer: Answer) -> Finding | None:
    """The student's own function returned zeros on every state (to round-off, :data:`ZERO`): not written yet? A
    term derived from their τ is never said to be (:func:`derived_zeros`)."""
    if answer.source != "direct" or not _all_zero(answer):
        return None
    return Finding("returns zeros everywhere: not written yet?", ("zeros",), conclusive=True)


DERIVED_PARTS = {"G": "the gravity torques: is gravity in the base acceleration ⁰v̇₀ = −g (or in each Fᵢ)?",
                 "M": "the inertia terms: does Θ̈ reach (6.46) and (6.47)?",
                 "V": "the velocity terms: do Θ̇ and ω reach (6.45)–(6.48) and (6.50)?",
                 "C": "the velocity terms: do Θ̇ and ω reach (6.45)–(6.48) and (6.50)?"}


def derived_zeros(answer: Answer) -> Finding | None:
    """A term derived from the student's τ is zero on every state, and no named mistake explains it: their τ leaves
    that part out."""
    if answer.source == "direct" or answer.term not in DERIVED_PARTS or not _all_zero(answer):
        return None
    return Finding(f"{answer.label or answer.name}, derived from your τ ({answer.source}), is zero on every state: "
                   f"your τ leaves out {DERIVED_PARTS[answer.term]} (τ's own feedback names the mistake, where one "
                   "fits)", ("zero part",), conclusive=True)


def constant_factor(answer: Answer) -> Finding | None:
    ours, usable = answer.expected, answer.usable
    denominator = sum(float(np.sum(ours[k] * ours[k])) for k in usable)
    if sum(ours[k].size for k in usable) < 2 or denominator <= 0:  # one number is always some factor of another
        return None
    factor = sum(float(np.sum(answer.values[k] * ours[k])) for k in usable) / denominator
    loose = 10 * answer.tolerance
    if abs(factor) < 1e-6 or abs(factor - 1) <= loose or not answer.agrees_with(factor * ours, loose):
        return None
    way = "smaller" if factor < 1 else "larger"
    if abs(factor - 1) < 0.02:  # 9.8 for 9.81, a length rounded: not a missing ½ or 2
        return Finding(f"is the right answer times one constant, about {percent(abs(factor - 1))} {way} everywhere: a "
                       "constant rounded or typed differently (g = 9.8 for 9.81? a length or a mass)?",
                       ("constant factor",), conclusive=True)
    if abs(factor - 1) < 0.1:  # two digits of a factor this near 1 say little: the difference instead
        return Finding(f"is the right answer times one constant, about {percent(abs(factor - 1))} {way} everywhere: "
                       "a mass or a length different from your handout's?", ("constant factor",), conclusive=True)
    return Finding(f"is the right answer times a constant factor of about {significant(factor)}: a missing or extra "
                   "factor such as ½, 2, a mass or a length squared?", ("constant factor",), conclusive=True)


#: The most significant digits a number that relates a student's answer to ours is printed with, so that dividing
#: by it never makes a wrong answer pass.
SHOWN_DIGITS = 2


def significant(x: float, digits: int = SHOWN_DIGITS) -> str:
    """``x`` to at most ``digits`` significant digits (:data:`SHOWN_DIGITS`), as a factor is shown to a student.

    >>> significant(0.998981), significant(0.656), significant(2.0)
    ('1.0', '0.66', '2.0')

    Parameters
    ----------
    x : float
        The number.
    digits : int, optional
        The most significant digits shown.

    Returns
    -------
    str
        Its text.
    """
    return f"{float(x):#.{min(digits, SHOWN_DIGITS)}g}".rstrip(".")


def percent(x: float) -> str:
    """A small relative difference as a percentage to one significant digit, such as "0.1 %".

    Parameters
    ----------
    x : float
        The difference, relative (0.001 is 0.1 %).

    Returns
    -------
    str
        Its text.
    """
    return f"{100 * float(x):.1g} %"


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
            return Finding(f"[joints-swapped] has its joints in the wrong order ({names} appear as {joints}): "
                           "entries must follow the "
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
        return Finding(f"{label} is not quadratic in Θ̇: V(Θ, 2Θ̇) should be 4 V(Θ, Θ̇), "
                       "because every velocity term is "
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
    return Finding(f"[coriolis-half] in {answer.label or answer.name}, "
                   "every Coriolis term θ̇ⱼθ̇ₖ (j ≠ k) has half its coefficient: "
                   "Σⱼₖ Γᵢⱼₖ θ̇ⱼθ̇ₖ holds each product twice, so Craig's B is 2Γᵢⱼₖ (6.63), as in the "
                   "two-link arm's −2 m₂l₁l₂s₂ θ̇₁θ̇₂ (6.61)", ("coriolis-half",))


PART_NAMES = {"G": "the gravity part G = τ(Θ, 0, 0)", "M": "the inertia part M(Θ) (τ(Θ, 0, eⱼ) − G)",
              "V": "the velocity part V = τ(Θ, Θ̇, 0) − G"}


def error_in_parts(answer: Answer) -> Finding | None:
    """τ's parts (G, M, V derived from it) are right but for some, and each of those is a named mistake, and τ is
    M Θ̈ + V + G of its parts: τ's error is all in those parts (G alone with sin and cos exchanged), never "that
    mistake and another"."""
    if not answer.parts or answer.plan is None or not answer.usable:
        return None
    wrong = {key: part for key, part in answer.parts.items() if not part.correct}
    found = {key: matching_mistakes(part) for key, part in wrong.items()}
    if not wrong or not all(found.values()) or any(len(p.usable) < p.count for p in answer.parts.values()):
        return None
    G, M, V = (answer.parts[key] for key in ("G", "M", "V"))
    assembled = np.stack([M.values[k] @ answer.plan.qdd[k] + V.values[k] + G.values[k] for k in range(answer.count)])
    if not answer.agrees_with(assembled, min(answer.tolerance, 1e-9)):
        return None  # τ is not M Θ̈ + V + G of its own parts: something else is wrong too
    right = [PART_NAMES[key] for key in answer.parts if key not in wrong]
    where = " and ".join(f"{PART_NAMES[key]} ({TERM_NAMES[key]}): {described(found[key])}" for key in wrong)
    advice = " ".join(dict.fromkeys(MISTAKES[c].advice.rstrip(".") + "." for codes in found.values() for c in codes))
    rest = f"; {' and '.join(right)} {'is' if len(right) == 1 else 'are'} right" if right else ""
    codes = tuple(dict.fromkeys(c for codes in found.values() for c in codes))
    return Finding(f"{' '.join(f'[{c}]' for c in codes)} τ's error is all in {where}{rest}. {advice}", codes, True)


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
        codes, text = CODES.match(finding.text).groups()
        return Finding(codes + self.prefix + text, finding.tags)


#: The checks :func:`diagnose` always runs, for what makes a state unusable (no function, an error, a wrong
#: shape, NaN or inf).
SCREENS = (not_defined, raised_an_error, wrong_shape, not_finite)
#: The checks :func:`diagnose` runs by default when some comparable state disagrees, in order (module docstring).
CHECKS = (
    returns_zeros, opposite_sign, named_mistake, derived_zeros, error_in_parts, other_parameters, constant_factor,
    transposed,
    joints_swapped, closest_mistake,
    tau_parts, InPart("G", named_mistake, "in τ's gravity part, "), InPart("M", wrong_entries, "in τ's inertia part, "),
    InPart("V", coriolis_without_factor_2),  # a named mistake first, then what is wrong where
    InPart("V", wrong_coefficients),
    coriolis_without_factor_2, wrong_entries, not_symmetric, not_christoffel, wrong_coefficients,
)


def diagnose(answer: Answer, checks=CHECKS) -> list[Finding]:
    """The findings of :data:`SCREENS`, then, when some comparable state disagrees, of ``checks``: in order, up to
    the first conclusive one (module docstring).

    Parameters
    ----------
    answer : Answer
        The comparison to explain.
    checks : iterable of callable
        The checks run after :data:`SCREENS` when some state disagrees, each taking the answer and returning a
        :class:`~course_dynamics.grading.records.Finding` or None.

    Returns
    -------
    list of Finding
        What the checks found, in order.
    """
    found = []
    for check in SCREENS + (tuple(checks) if answer.wrong else ()):
        finding = check(answer)
        if finding is not None:
            found.append(finding)
            if finding.conclusive:
                break
    return found


__all__ = ["CHECKS", "SCREENS", "SHOWN_DIGITS", "ZERO", "Answer", "Diagnosis", "Finding", "diagnose", "percent",
           "significant"]
