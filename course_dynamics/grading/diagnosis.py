"""Scoring one term and saying what is wrong with it, in words that teach.

:func:`diagnose` compares a student's answers for one term (τ, M, V, G or C)
with ours, state by state, and when they disagree looks for the mistakes
students make, in this order:

==========================  =================================================
finding                     test (over every state where the answer is usable)
==========================  =================================================
not defined, exceptions     the harness's error records
wrong shape or length       the array's shape against (n,) or (n, n)
NaN or inf                  non-finite entries
opposite sign               −answer agrees
a named mistake             the answer agrees with ours under that mistake:
                            angles in degrees, gravity with the wrong sign
constant factor             answer ≈ k · ours for one k ≠ 1
joints swapped              answer agrees after permuting joints
wrong entries (M, C)        which (i, j) disagree; symmetry of M
wrong coefficients (V, τ)   the coefficients of θ̇ⱼθ̇ₖ (Coriolis, Craig's B)
                            and θ̇ⱼ² (centrifugal, Craig's C) of (6.63), read
                            off at unit velocities; V(Θ, 2Θ̇) = 4 V(Θ, Θ̇)
parts of τ                  τ's gravity, inertia and velocity parts separately
C Θ̇ = V, not Christoffel    for a C that is not the Christoffel form
==========================  =================================================

Every finding names the worst state with the expected and returned values.
The same function serves the grader and the notebooks' exercise checks.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import permutations

import numpy as np

from ..core.sampling import relative_error, term_scales
from .plan import Expected, Plan, Returned, coefficient_names

DERIVED_C_TOLERANCE = 1e-7  # central differences reach about 1e-8
TERM_NAMES = {"tau": "τ", "M": "M", "V": "V", "G": "G", "C": "C"}
SIGNATURES = {"tau": "tau(q, qd, qdd)", "M": "M(q)", "V": "V(q, qd)", "G": "G(q)", "C": "C(q, qd)"}
MISTAKE_ADVICE = {
    "angles read as degrees": "your code treats the joint angles as degrees (e.g. np.deg2rad(q) or "
                              "degree-based trigonometry), but every input is in radians",
    "angles turned into degrees": "your code turns the joint angles into degrees before using them "
                                  "(e.g. np.rad2deg), but numpy's trigonometry takes radians",
    "gravity with the wrong sign": "gravity enters with the wrong sign: in Craig's recursion the base "
                                   "accelerates upward, ⁰v̇₀ = −g, so G(Θ) holds the arm up against gravity",
}


@dataclass
class Diagnosis:
    """The grade of one term, with the findings that explain it."""

    term: str
    points: float
    max_points: float
    agreed: int
    total: int
    source: str
    tolerance: float
    findings: list[str] = field(default_factory=list)
    tags: list[str] = field(default_factory=list)
    worst: str = ""

    @property
    def correct(self) -> bool:
        return self.total > 0 and self.agreed == self.total

    def text(self) -> str:
        """The feedback as plain text: a summary line, the findings, the worst state."""
        how = "" if self.source in ("direct", "missing") else f" ({self.source})"
        lines = [f"{TERM_NAMES[self.term]}: {self.points:g} / {self.max_points:g} points{how}; "
                 f"agrees on {self.agreed} of {self.total} states (relative tolerance {self.tolerance:g})"]
        lines += [f"- {finding}" for finding in self.findings]
        if self.worst:
            lines.append(f"- {self.worst}")
        return "\n".join(lines)


def _fmt(x) -> str:
    array = np.asarray(x, dtype=float)
    if array.ndim == 0:
        return f"{float(array):.6g}"
    return "[" + ", ".join(_fmt(v) for v in array) + "]"


def _joint_list(joints) -> str:
    return ", ".join(joints)


def _state_text(plan: Plan, term: str, k: int) -> str:
    parts = [f"q = {_fmt(plan.q[k])}"]
    if term in ("tau", "V", "C"):
        parts.append(f"qd = {_fmt(plan.qd[k])}")
    if term == "tau":
        parts.append(f"qdd = {_fmt(plan.qdd[k])}")
    return ", ".join(parts)


def diagnose(term: str, plan: Plan, expected: Expected, returned: Returned, max_points: float, tolerance: float,
             joints, gravity, partial_credit: str = "states", coefficients=None, parts: dict | None = None) -> Diagnosis:
    """Score ``term`` and explain what is wrong (module docstring).

    ``coefficients`` is :func:`~course_dynamics.grading.plan.returned_coefficients`'s answer (for V and τ);
    ``parts`` maps "G", "M", "V" to the student's :class:`Returned` parts of τ (for τ).
    """
    N = len(plan.q)
    if returned.source == "derived from tau" and term == "C":
        tolerance = max(tolerance, DERIVED_C_TOLERANCE)
    result = Diagnosis(term, 0.0, max_points, 0, N, returned.source, tolerance)
    ours = expected.terms[term]
    if not returned.available:
        result.findings.append(f"not defined: write {SIGNATURES[term]}"
                               + ("" if term == "tau" else ", or tau(q, qd, qdd) to derive it from"))
        result.tags.append("not defined")
        result.worst = f"to check yours, state #1: {_state_text(plan, term, 0)}; expected {TERM_NAMES[term]} = {_fmt(ours[0])}"
        return result
    shape = ours.shape[1:]
    scales = [term_scales(expected.terms["M"][k], expected.terms["G"][k], plan.qd[k], plan.qdd[k], gravity)[term]
              for k in range(N)]
    usable, errors, wrong_shape, non_finite = [], [], [], []
    for k, (value, error) in enumerate(zip(returned.values, returned.errors)):
        if error is not None:
            errors.append((k, error))
        elif value.shape != shape:
            wrong_shape.append((k, value.shape))
        elif not np.all(np.isfinite(value)):
            non_finite.append(k)
        else:
            usable.append(k)
    if errors:
        k, message = errors[0]
        every = "every state" if len(errors) == N else f"{len(errors)} of {N} states (first: state #{k + 1})"
        result.findings.append(f"raised an error on {every}: {message}")
        result.tags.append("raised an error")
    if wrong_shape:
        k, got = wrong_shape[0]
        result.findings.append(_shape_advice(term, got, shape, joints))
        result.tags.append("wrong shape")
    if non_finite:
        result.findings.append(f"returned NaN or inf on {len(non_finite)} of {N} states (first: state #{non_finite[0] + 1}); "
                               "look for a division by zero or a square root of a negative number")
        result.tags.append("NaN or inf")
    errors_by_state = {k: relative_error(returned.values[k], ours[k], scales[k]) for k in usable}
    agreed = [k for k, e in errors_by_state.items() if e <= tolerance]
    result.agreed = len(agreed)
    if partial_credit == "states":
        result.points = round(max_points * len(agreed) / N, 2)
    else:
        result.points = max_points if len(agreed) == N else 0.0
    if len(agreed) == N:
        return result
    wrong = [k for k in usable if k not in set(agreed)]
    if wrong:
        _explain(result, term, plan, expected, returned, usable, scales, tolerance, joints, gravity, coefficients, parts)
        k = max(wrong, key=lambda i: errors_by_state[i])
        answer = f"{_fmt(returned.values[k])} (relative error {errors_by_state[k]:.2g})"
    elif non_finite:
        k = non_finite[0]
        answer = _fmt(returned.values[k])
    elif wrong_shape:
        k = wrong_shape[0][0]
        answer = f"{_fmt(returned.values[k])} (shape {tuple(returned.values[k].shape)})"
    else:
        k, answer = errors[0][0], f"an error: {errors[0][1]}"
    result.worst = f"worst state #{k + 1}: {_state_text(plan, term, k)}; expected {TERM_NAMES[term]} = {_fmt(ours[k])}, " \
                   f"returned {answer}"
    return result


def _shape_advice(term: str, got: tuple, shape: tuple, joints) -> str:
    n = len(joints)
    if len(shape) == 1:
        count = got[0] if len(got) == 1 else int(np.prod(got))
        what = f"returned {count} values" if len(got) == 1 else f"returned an array of shape {tuple(got)}"
        return (f"{what}, the robot has {n} joints ({_joint_list(joints)}): {TERM_NAMES[term]} has one entry per "
                f"joint, shape ({n},)")
    return (f"returned an array of shape {tuple(got)}, {TERM_NAMES[term]} must be {n} × {n} (rows and columns in joint "
            f"order {_joint_list(joints)})")


def _agrees_everywhere(values: list, candidates: np.ndarray, usable: list, scales: list, tolerance: float) -> bool:
    return bool(usable) and all(relative_error(values[k], candidates[k], scales[k]) <= tolerance for k in usable)


def _explain(result, term, plan, expected, returned, usable, scales, tolerance, joints, gravity, coefficients,
             parts) -> None:
    ours = expected.terms[term]
    values = returned.values
    if _agrees_everywhere(values, -ours, usable, scales, tolerance):
        result.findings.append(f"has the opposite sign everywhere ({TERM_NAMES[term]} returned = −1 × the right value): "
                               + ("gravity enters with the wrong sign (Craig lifts the base, ⁰v̇₀ = −g)" if term == "G" else
                                  "check the direction of gravity, of the joint axes, and subtractions done the wrong way round"))
        result.tags.append("opposite sign")
        return
    for label, alternative in expected.mistakes.get(term, {}).items():
        if _agrees_everywhere(values, alternative, usable, scales, tolerance):
            key = next(k for k in MISTAKE_ADVICE if label.startswith(k))
            result.findings.append(f"matches the right answer with {label}: {MISTAKE_ADVICE[key]}")
            result.tags.append(key)
            return
    numerator = sum(float(np.sum(values[k] * ours[k])) for k in usable)
    denominator = sum(float(np.sum(ours[k] * ours[k])) for k in usable)
    if denominator > 0:
        factor = numerator / denominator
        if abs(factor - 1) > 10 * tolerance and _agrees_everywhere(values, factor * ours, usable, scales, 10 * tolerance):
            result.findings.append(f"is the right answer times a constant factor {factor:.6g}: a missing or extra factor "
                                   "such as ½, 2, a mass or a length squared?")
            result.tags.append("constant factor")
            return
    swapped = _permutation(values, ours, usable, scales, tolerance, term)
    if swapped is not None:
        names = [joints[j] for j in swapped]
        result.findings.append(f"has its joints in the wrong order ({', '.join(names)} appear as "
                               f"{', '.join(joints)}): entries must follow the joint order {_joint_list(joints)} "
                               "that `course-dynamics info` prints")
        result.tags.append("joints swapped")
        return
    if term in ("M", "C"):
        _wrong_entries(result, term, values, ours, usable, scales, tolerance, joints)
        if term == "C":
            V = expected.terms["V"]
            if _agrees_everywhere([None if v is None else v @ qd for v, qd in zip(values, plan.qd)], V, usable,
                                  [term_scales(expected.terms["M"][k], expected.terms["G"][k], plan.qd[k], plan.qdd[k],
                                               np.zeros(3))["V"] for k in range(len(plan.q))], tolerance):
                result.findings.append("satisfies C Θ̇ = V, but it is not the Christoffel-symbol form "
                                       "Cᵢⱼ = Σₖ Γᵢⱼₖ θ̇ₖ (the one with Ṁ − 2C skew-symmetric) that the assignment asks for")
                result.tags.append("C not Christoffel")
    if term == "V":
        _coefficient_findings(result, plan, expected, coefficients, tolerance, joints, "V")
    if term == "tau" and parts:
        _tau_parts(result, plan, expected, parts, coefficients, tolerance, joints, gravity)
    if not result.tags:
        result.tags.append("wrong values")


def _permutation(values, ours, usable, scales, tolerance, term):
    n = ours.shape[1]
    candidates = permutations(range(n)) if n <= 5 else (
        tuple(j if j not in (a, b) else (b if j == a else a) for j in range(n)) for a in range(n) for b in range(a + 1, n))
    for p in candidates:
        p = list(p)
        if p == list(range(n)):
            continue
        # vectors: entries reordered; matrices: rows and columns, or rows only (a τ returned in the wrong order)
        moved = [ours[:, p]] if ours.ndim == 2 else [ours[:, p][:, :, p], ours[:, p]]
        if any(_agrees_everywhere(values, m, usable, scales, tolerance) for m in moved):
            return p
    return None


def _wrong_entries(result, term, values, ours, usable, scales, tolerance, joints) -> None:
    n = ours.shape[1]
    bad = set()
    for k in usable:
        error = np.abs(values[k] - ours[k]) / max(float(np.abs(ours[k]).max()), scales[k], np.finfo(float).tiny)
        bad |= {(i, j) for i, j in zip(*np.nonzero(error > tolerance))}
    if bad and len(bad) < n * n:
        names = ", ".join(f"{TERM_NAMES[term]}[{i + 1},{j + 1}]" for i, j in sorted(bad))
        result.findings.append(f"entries {names} are wrong (rows and columns numbered from 1 in joint order "
                               f"{_joint_list(joints)}); the others are right")
        result.tags.append(f"wrong entries of {term}")
    if term == "M":
        asymmetric = [k for k in usable if np.abs(values[k] - values[k].T).max() > tolerance * max(scales[k], 1e-300)]
        if asymmetric:
            result.findings.append("is not symmetric: a mass matrix always is (Mᵢⱼ = Mⱼᵢ), since k = ½ Θ̇ᵀ M Θ̇ (6.71)")
            result.tags.append("M not symmetric")


def _coefficient_findings(result, plan, expected, coefficients, tolerance, joints, label: str) -> None:
    """Which (6.63) coefficients of V are wrong, read off at unit and paired unit velocities."""
    if coefficients is None:
        return
    per_state, _ = coefficients
    n = plan.n
    coriolis, centrifugal = coefficient_names(n)
    order = {pair: index for index, pair in enumerate(sorted(set(coriolis + centrifugal)))}
    wrong, not_quadratic = {}, False
    for d, (polar, doubled, single) in enumerate(per_state):
        scale = max(float(np.abs(expected.B[d]).max(initial=0)), float(np.abs(expected.C_centrifugal[d]).max()), 1e-12)
        if np.abs(doubled - 4 * single).max() > max(tolerance * 4 * np.abs(single).max(), tolerance * scale):
            not_quadratic = True
        for i in range(n):
            for j, k in coriolis:
                got = polar[order[(j, k)]][i] - polar[order[(j, j)]][i] - polar[order[(k, k)]][i]
                want = expected.B[d][i][coriolis.index((j, k))]
                if abs(got - want) > tolerance * scale:
                    wrong.setdefault(("Coriolis", i, j, k), (d, want, got))
            for j, _ in centrifugal:
                got, want = polar[order[(j, j)]][i], expected.C_centrifugal[d][i][j]
                if abs(got - want) > tolerance * scale:
                    wrong.setdefault(("centrifugal", i, j, j), (d, want, got))
    if not_quadratic:
        result.findings.append(f"{label} is not quadratic in Θ̇: V(Θ, 2Θ̇) should be 4 V(Θ, Θ̇), because every velocity "
                               "term is a product of two joint rates (θ̇ⱼθ̇ₖ or θ̇ⱼ²)")
        result.tags.append("V not quadratic")
        return
    if not wrong:
        return
    described = []
    for (kind, i, j, k), (d, want, got) in sorted(wrong.items())[:6]:
        rates = f"θ̇{j + 1}θ̇{k + 1}" if kind == "Coriolis" else f"θ̇{j + 1}²"
        matrix = "B" if kind == "Coriolis" else "C"
        described.append(f"the {kind} coefficient of {rates} in τ{i + 1} (Craig's {matrix}, (6.63)): expected "
                         f"{want:.6g}, returned {got:.6g} at state #{d + 1}")
    more = f" (and {len(wrong) - 6} more)" if len(wrong) > 6 else ""
    kinds = sorted({kind for kind, *_ in wrong})
    result.findings.append(f"in {label} = B(Θ)[Θ̇Θ̇] + C(Θ)[Θ̇²], these coefficients are wrong: " + "; ".join(described) + more)
    result.tags += [f"wrong {kind} terms" for kind in kinds]


def _tau_parts(result, plan, expected, parts, coefficients, tolerance, joints, gravity) -> None:
    """τ = M Θ̈ + V + G: which of its parts are right, from τ(Θ, 0, 0), τ(Θ, 0, eⱼ) and τ(Θ, Θ̇, 0)."""
    N = len(plan.q)
    right, wrong = [], []
    names = {"G": "the gravity part G = τ(Θ, 0, 0)", "M": "the inertia part M(Θ) (τ(Θ, 0, eⱼ) − G)",
             "V": "the velocity part V = τ(Θ, Θ̇, 0) − G"}
    for key in ("G", "M", "V"):
        returned = parts.get(key)
        if returned is None:
            continue
        ours = expected.terms[key]
        scales = [term_scales(expected.terms["M"][k], expected.terms["G"][k], plan.qd[k], plan.qdd[k], gravity)[key]
                  for k in range(N)]
        usable = [k for k in range(N) if returned.errors[k] is None and returned.values[k].shape == ours.shape[1:]]
        (right if _agrees_everywhere(returned.values, ours, usable, scales, tolerance) and len(usable) == N
         else wrong).append(key)
        if key == "M" and key in wrong:
            sub = Diagnosis("M", 0, 0, 0, N, "", tolerance)
            _wrong_entries(sub, "M", returned.values, ours, usable, scales, tolerance, joints)
            result.findings += [f"in τ's inertia part, {f}" for f in sub.findings]
        if key == "V" and key in wrong:
            _coefficient_findings(result, plan, expected, coefficients, tolerance, joints, "τ's velocity part V")
    if right or wrong:
        summary = []
        if right:
            summary.append(" and ".join(names[k] for k in right) + (" is right" if len(right) == 1 else " are right"))
        if wrong:
            summary.append(" and ".join(names[k] for k in wrong) + (" is wrong" if len(wrong) == 1 else " are wrong"))
        result.findings.insert(0, "; ".join(summary))
        result.tags += [f"wrong {k} part of tau" for k in wrong]
