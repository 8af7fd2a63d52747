"""What a submission is asked, what it should answer, and how its answers become terms.

:func:`make_plan` draws the seeded states and lists, per student function,
the argument lists to call it with; :func:`expected_terms` computes the right
answers with our library; :func:`returned_terms` turns the harness's records
into one value (or error) per state for every graded term, directly when the
student defines the term and derived from their ``tau`` otherwise:

=====  ==============================================================
term   derived from ``tau`` (the library's own recipe)
=====  ==============================================================
G      τ(Θ, 0, 0)
V      τ(Θ, Θ̇, 0) − G
M      column j is τ(Θ, 0, eⱼ) − G
C      ½(Ṁ + D − Dᵀ), Ṁ = Σₖ θ̇ₖ ∂M/∂θₖ, D[:, k] = ∂(M Θ̇)/∂θₖ, by central
       differences of the derived M and M Θ̇ (step :data:`STEP`)
=====  ==============================================================

The plan also asks V (or τ) at a few *diagnostic* states for unit and paired
unit velocities, which reads off the coefficients of the quadratic form
V = B(Θ)[Θ̇Θ̇] + C(Θ)[Θ̇²] of (6.63) one by one, and at 2Θ̇, which shows whether
V is quadratic in Θ̇ at all.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations_with_replacement

import numpy as np

from ..core.dynamics import (
    coriolis_matrix,
    gravity_torques,
    mass_matrix,
    velocity_torques,
)
from ..core.joints import kind_of
from ..core.lagrange import configuration_space_terms, velocity_pairs
from ..core.newton_euler import inverse_dynamics
from ..core.sampling import random_states
from .assignment import Assignment

STEP = 1e-5  # rad or m: central-difference step for a C derived from tau
DIAGNOSTIC_STATES = 3
FUNCTION_ARGUMENTS = {"tau": ("q", "qd", "qdd"), "M": ("q",), "V": ("q", "qd"), "G": ("q",), "C": ("q", "qd")}


@dataclass
class Plan:
    """States (N, n) each, and the calls per student function with named blocks of call indices."""

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    terms: tuple[str, ...]
    calls: dict[str, list] = field(default_factory=dict)
    blocks: dict[str, dict[str, list[int]]] = field(default_factory=dict)

    @property
    def n(self) -> int:
        return self.q.shape[1]

    @property
    def diagnostic(self) -> range:
        return range(min(DIAGNOSTIC_STATES, len(self.q)))

    def add(self, function: str, block: str, arguments: list) -> None:
        calls = self.calls.setdefault(function, [])
        self.blocks.setdefault(function, {}).setdefault(block, []).append(len(calls))
        calls.append([np.asarray(a, dtype=float).tolist() for a in arguments])

    def harness_functions(self) -> dict:
        """The ``functions`` part of the harness's plan."""
        return self.calls


def _pairs(n: int) -> list[tuple[int, int]]:
    """(j, k), j ≤ k: the unit (j = k) and paired (j < k) velocity directions."""
    return list(combinations_with_replacement(range(n), 2))


def _direction(n: int, j: int, k: int) -> np.ndarray:
    v = np.zeros(n)
    v[j] = v[k] = 1.0
    return v


def make_plan(assignment: Assignment) -> Plan:
    """The states and every call each student function may be asked (module docstring)."""
    model = assignment.robot
    q, qd, qdd = random_states(model, assignment.samples, assignment.seed)
    plan = Plan(q, qd, qdd, assignment.terms)
    n, zero, eye = model.n, np.zeros(model.n), np.eye(model.n)
    terms = set(assignment.terms)
    for k in range(len(q)):  # τ, and everything derived from it
        plan.add("tau", "state", [q[k], qd[k], qdd[k]])
        plan.add("tau", "gravity", [q[k], zero, zero])
        plan.add("tau", "velocity", [q[k], qd[k], zero])
        for j in range(n):
            plan.add("tau", "mass", [q[k], zero, eye[j]])
    for d in plan.diagnostic:
        for j, i in _pairs(n):
            plan.add("tau", "polar", [q[d], _direction(n, j, i), zero])
            plan.add("V", "polar", [q[d], _direction(n, j, i)])
        plan.add("tau", "double", [q[d], 2 * qd[d], zero])
        plan.add("V", "double", [q[d], 2 * qd[d]])
    if "C" in terms:
        for k in range(len(q)):
            for i in range(n):
                for sign in (1, -1):
                    shifted = q[k] + sign * STEP * eye[i]
                    plan.add("tau", "shift gravity", [shifted, zero, zero])
                    plan.add("tau", "shift momentum", [shifted, zero, qd[k]])
                    for j in range(n):
                        plan.add("tau", "shift mass", [shifted, zero, eye[j]])
    for k in range(len(q)):
        plan.add("M", "state", [q[k]])
        plan.add("G", "state", [q[k]])
        plan.add("V", "state", [q[k], qd[k]])
        plan.add("C", "state", [q[k], qd[k]])
    plan.calls = {name: calls for name, calls in plan.calls.items() if name == "tau" or name in terms}
    return plan


@dataclass(frozen=True)
class Expected:
    """Our library's answers: every term (N, …), V's (6.63) coefficients at the diagnostic states, and
    the answers of typical mistakes (a dict of named alternatives per term)."""

    terms: dict[str, np.ndarray]
    B: np.ndarray
    C_centrifugal: np.ndarray
    mistakes: dict[str, dict[str, np.ndarray]]


def _all_terms(model, q, qd, qdd) -> dict[str, np.ndarray]:
    return dict(tau=inverse_dynamics(model, q, qd, qdd), M=mass_matrix(model, q), V=velocity_torques(model, q, qd),
                G=gravity_torques(model, q), C=coriolis_matrix(model, q, qd))


def expected_terms(assignment: Assignment, plan: Plan) -> Expected:
    """Every term by our library at the plan's states, with the answers of the mistakes the diagnosis names."""
    model = assignment.robot
    terms = _all_terms(model, plan.q, plan.qd, plan.qdd)
    d = list(plan.diagnostic)
    B, C = configuration_space_terms(model, plan.q[d])
    revolute = np.array([kind_of(b).rotates for b in model.bodies])
    mistakes: dict[str, dict[str, np.ndarray]] = {t: {} for t in terms}
    for label, factor in (("angles read as degrees", np.pi / 180), ("angles turned into degrees", 180 / np.pi)):
        scale = np.where(revolute, factor, 1.0)
        for what, (q, qd, qdd) in (("positions", (plan.q * scale, plan.qd, plan.qdd)),
                                   ("positions, velocities and accelerations",
                                    (plan.q * scale, plan.qd * scale, plan.qdd * scale))):
            for term, value in _all_terms(model, q, qd, qdd).items():
                mistakes[term][f"{label} ({what})"] = value
    mistakes["tau"]["gravity with the wrong sign"] = terms["tau"] - 2 * terms["G"]
    return Expected(terms=terms, B=B, C_centrifugal=C, mistakes=mistakes)


@dataclass
class Returned:
    """A student's answers for one term: per state a value (array) or an error message; how they were obtained."""

    values: list
    errors: list
    source: str  # "direct", "derived from tau", "missing"

    @property
    def available(self) -> bool:
        return self.source != "missing"


def _records(outcome: dict, function: str, plan: Plan, block: str) -> list:
    records = outcome.get("results", {}).get(function)
    if not isinstance(records, list):
        return []
    return [records[i] if i < len(records) and isinstance(records[i], dict) else {"error": "no answer"}
            for i in plan.blocks.get(function, {}).get(block, [])]


def _array(record):
    if "value" in record:
        try:
            return np.array(record["value"], dtype=float), None
        except (TypeError, ValueError):
            return None, "returned values that are not numbers"
    return None, str(record.get("error", "no answer"))


def _combine(records_list: list[list], combine, count: int) -> tuple[list, list]:
    """Per state, apply ``combine`` to the arrays of the records it needs; the first error wins."""
    values, errors = [], []
    for k in range(count):
        arrays = []
        error = None
        for records, indices in records_list:
            for i in indices(k):
                array, message = _array(records[i]) if i < len(records) else (None, "no answer")
                if message is not None and error is None:
                    error = message
                arrays.append(array)
        if error is not None:
            values.append(None)
            errors.append(error)
            continue
        try:
            values.append(combine(k, arrays))
            errors.append(None)
        except ValueError as exc:  # arrays of the wrong shape: say which
            values.append(None)
            errors.append(f"returned arrays that do not fit together ({exc})")
    return values, errors


def returned_terms(outcome: dict, plan: Plan, term: str) -> Returned:
    """The student's ``term`` per state: from their function of that name, else derived from their tau."""
    defined = set(outcome.get("defined", ()))
    N, n = len(plan.q), plan.n
    if term in defined:
        records = _records(outcome, term, plan, "state")
        values, errors = _combine([(records, lambda k: [k])], lambda k, a: a[0], N)
        return Returned(values, errors, "direct")
    if "tau" not in defined:
        return Returned([None] * N, ["not defined"] * N, "missing")
    tau = {block: _records(outcome, "tau", plan, block) for block in plan.blocks.get("tau", {})}
    if term == "tau":
        values, errors = _combine([(tau["state"], lambda k: [k])], lambda k, a: a[0], N)
    elif term == "G":
        values, errors = _combine([(tau["gravity"], lambda k: [k])], lambda k, a: a[0], N)
    elif term == "V":
        values, errors = _combine([(tau["velocity"], lambda k: [k]), (tau["gravity"], lambda k: [k])],
                                  lambda k, a: a[0] - a[1], N)
    elif term == "M":
        values, errors = _combine([(tau["mass"], lambda k: range(k * n, (k + 1) * n)), (tau["gravity"], lambda k: [k])],
                                  lambda k, a: np.column_stack([a[j] - a[n] for j in range(n)]), N)
    else:
        values, errors = _combine([(tau["shift gravity"], lambda k: range(2 * n * k, 2 * n * (k + 1))),
                                   (tau["shift momentum"], lambda k: range(2 * n * k, 2 * n * (k + 1))),
                                   (tau["shift mass"], lambda k: range(2 * n * n * k, 2 * n * n * (k + 1)))],
                                  lambda k, a: _christoffel_from_shifts(a, n, plan.qd[k]), N)
    return Returned(values, errors, "derived from tau")


def _christoffel_from_shifts(arrays: list, n: int, qd: np.ndarray) -> np.ndarray:
    """C = ½(Ṁ + D − Dᵀ) from τ at Θ ± h eᵢ: gravity (2n), M Θ̇ + G (2n), M columns + G (2n·n), in plan order."""
    gravity, momentum, mass = arrays[: 2 * n], arrays[2 * n: 4 * n], arrays[4 * n:]
    M_shift, Mqd_shift = [], []
    for s in range(2 * n):  # s = 2i (+h) and 2i + 1 (−h)
        M_shift.append(np.column_stack([mass[s * n + j] - gravity[s] for j in range(n)]))
        Mqd_shift.append(momentum[s] - gravity[s])
    dM = [(M_shift[2 * i] - M_shift[2 * i + 1]) / (2 * STEP) for i in range(n)]
    D = np.column_stack([(Mqd_shift[2 * i] - Mqd_shift[2 * i + 1]) / (2 * STEP) for i in range(n)])
    M_dot = sum(qd[i] * dM[i] for i in range(n))
    return (M_dot + D - D.T) / 2


def returned_coefficients(outcome: dict, plan: Plan) -> tuple[list, str] | None:
    """The student's V at the diagnostic states for unit and paired velocities, and at 2Θ̇.

    Returns ([(V at each pair direction, V(q, 2Θ̇), V(q, Θ̇)) per diagnostic state], source) or None
    when V cannot be evaluated (an error on any of these calls).
    """
    defined = set(outcome.get("defined", ()))
    pairs = _pairs(plan.n)
    per_state = []
    if "V" in defined and "V" in plan.calls:
        polar, double, state = (_records(outcome, "V", plan, b) for b in ("polar", "double", "state"))
        source, offset = "direct", None
    elif "tau" in defined:
        polar, double, state = (_records(outcome, "tau", plan, b) for b in ("polar", "double", "velocity"))
        gravity = _records(outcome, "tau", plan, "gravity")
        source = "derived from tau"
    else:
        return None
    for d in plan.diagnostic:
        arrays = []
        for record in polar[d * len(pairs):(d + 1) * len(pairs)] + [double[d], state[d]] + (
                [gravity[d]] if source != "direct" else []):
            array, error = _array(record)
            if error is not None or array is None or array.shape != (plan.n,):
                return None
            arrays.append(array)
        if source != "direct":
            offset = arrays.pop()
            arrays = [a - offset for a in arrays]
        per_state.append((arrays[: len(pairs)], arrays[-2], arrays[-1]))
    return per_state, source


def coefficient_names(n: int) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """The (j, k) of the Coriolis terms θ̇ⱼθ̇ₖ (j < k, Craig's B) and the centrifugal θ̇ⱼ² (Craig's C)."""
    return velocity_pairs(n), [(j, j) for j in range(n)]
