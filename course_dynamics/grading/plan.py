"""What a submission is asked, what it should answer, and how its answers become terms.

:func:`make_plan` draws the seeded states and lists every call a student
function may be asked, each under a :class:`Call` key; :func:`expected_terms`
computes the right answers with our library; :class:`Answers` reads the
harness's records back by those keys, and :func:`returned_terms` turns them into
one value (or error) per state for every graded term, directly when the student
defines the term and derived from their ``tau`` otherwise:

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
V is quadratic in Θ̇ at all (:func:`returned_coefficients`).

The harness's own format stays positional (a list of argument lists per
function, answered in the same order); the keys live only on our side.

>>> from course_dynamics.core.robots import load_robot
>>> from pathlib import Path
>>> plan = make_plan(Assignment(Path("a.toml"), "two_link", load_robot("two_link"), {"G": 1.0}, samples=2))
>>> plan.calls_of("G")
[Call(function='G', purpose='state', state=0, detail=()), Call(function='G', purpose='state', state=1, detail=())]
>>> Call("tau", "mass", 1, (0,)) in plan.arguments  # τ(Θ₂, 0, e₁): the first column of M at the second state
True
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from itertools import combinations_with_replacement

import numpy as np

from ..core.dynamics import (
    coriolis_matrix,
    gravity_torques,
    mass_matrix,
    velocity_torques,
)
from ..core.lagrange import configuration_space_terms, velocity_pairs
from ..core.newton_euler import inverse_dynamics
from ..core.sampling import random_states
from .assignment import Assignment
from .mistakes import mistaken_terms

#: The central-difference step h of a C derived from the student's τ, rad (m for a prismatic joint).
STEP = 1e-5  # rad or m: central-difference step for a C derived from tau
DIAGNOSTIC_STATES = 3
FUNCTION_ARGUMENTS = {"tau": ("q", "qd", "qdd"), "M": ("q",), "V": ("q", "qd"), "G": ("q",), "C": ("q", "qd")}


@dataclass(frozen=True)
class Call:
    """The key of one call: ``function`` asked at state ``state`` for ``purpose``; ``detail`` tells apart the
    calls one purpose makes at one state.

    ================  ==============  ===============================================
    purpose           detail          arguments (those of ``tau``; ``V`` drops Θ̈)
    ================  ==============  ===============================================
    state             ()              the state itself (every function)
    gravity           ()              (Θ, 0, 0)
    velocity          ()              (Θ, Θ̇, 0)
    mass              (j,)            (Θ, 0, eⱼ)
    polar             (j, k), j ≤ k   (Θ, eⱼ + eₖ, 0), or eⱼ alone when j = k
    double            ()              (Θ, 2Θ̇, 0)
    shift gravity     (i, sign)       (Θ ± h eᵢ, 0, 0)
    shift momentum    (i, sign)       (Θ ± h eᵢ, 0, Θ̇)
    shift mass        (i, sign, j)    (Θ ± h eᵢ, 0, eⱼ)
    ================  ==============  ===============================================

    Parameters
    ----------
    function : str
        The student function called: ``tau``, ``M``, ``V``, ``G`` or ``C``.
    purpose : str
        What the call is for (the table).
    state : int
        The index of the state it is made at.
    detail : tuple
        What tells apart the calls one purpose makes at one state (the table).
    """

    function: str
    purpose: str
    state: int
    detail: tuple = ()


@dataclass
class Plan:
    """States (N, n) each, and every call to make with its arguments, by key, in the order they are made.

    Parameters
    ----------
    q : numpy.ndarray, shape (N, n)
        Joint positions Θ of the N states, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (N, n)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : numpy.ndarray, shape (N, n)
        Joint accelerations Θ̈, rad/s² (m/s²).
    terms : tuple of str
        The graded terms.
    arguments : dict of Call to list
        Every call's argument lists (plain lists of floats), in the order they are made.
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    terms: tuple[str, ...]
    arguments: dict[Call, list] = field(default_factory=dict)

    @property
    def n(self) -> int:
        """The robot's number of joints."""
        return self.q.shape[1]

    @property
    def diagnostic(self) -> range:
        """The indices of the diagnostic states (the first few states)."""
        return range(min(DIAGNOSTIC_STATES, len(self.q)))

    def add(self, call: Call, arguments: list) -> None:
        """Add a call and its arguments (made plain lists of floats, as the harness receives them).

        Parameters
        ----------
        call : Call
            The call's key.
        arguments : list of array_like
            Its arguments, in order.
        """
        self.arguments[call] = [np.asarray(a, dtype=float).tolist() for a in arguments]

    def calls_of(self, function: str) -> list[Call]:
        """The keys of ``function``'s calls, in the order the harness makes (and answers) them.

        Parameters
        ----------
        function : str
            A student function's name.

        Returns
        -------
        list of Call
            Its calls' keys.
        """
        return [call for call in self.arguments if call.function == function]

    def asks(self, function: str) -> bool:
        """Whether the plan calls ``function`` at all.

        Parameters
        ----------
        function : str
            A student function's name.

        Returns
        -------
        bool
            True when some call is to that function.
        """
        return any(call.function == function for call in self.arguments)

    def harness_functions(self) -> dict[str, list]:
        """The ``functions`` part of the harness's plan: per function, its argument lists in order.

        Returns
        -------
        dict of str to list
            Per function, the argument lists of its calls, in the order of :meth:`calls_of`.
        """
        functions: dict[str, list] = {}
        for call, arguments in self.arguments.items():
            functions.setdefault(call.function, []).append(arguments)
        return functions


def _pairs(n: int) -> list[tuple[int, int]]:
    """(j, k), j ≤ k: the unit (j = k) and paired (j < k) velocity directions."""
    return list(combinations_with_replacement(range(n), 2))


def _direction(n: int, j: int, k: int) -> np.ndarray:
    v = np.zeros(n)
    v[j] = v[k] = 1.0
    return v


def make_plan(assignment: Assignment) -> Plan:
    """The states and every call each student function may be asked (module docstring, :class:`Call`).

    Parameters
    ----------
    assignment : Assignment
        The assignment: its robot, samples, seed and graded terms.

    Returns
    -------
    Plan
        The seeded states and the calls (τ always, to derive the terms a student does not define).
    """
    model = assignment.robot
    q, qd, qdd = random_states(model, assignment.samples, assignment.seed)
    plan = Plan(q, qd, qdd, assignment.terms)
    n, zero, eye = model.n, np.zeros(model.n), np.eye(model.n)
    asked = {"tau", *assignment.terms}

    def ask(function, purpose, k, detail, arguments):
        if function in asked:
            plan.add(Call(function, purpose, k, detail), arguments)

    for k in range(len(q)):  # τ, and everything derived from it
        ask("tau", "state", k, (), [q[k], qd[k], qdd[k]])
        ask("tau", "gravity", k, (), [q[k], zero, zero])
        ask("tau", "velocity", k, (), [q[k], qd[k], zero])
        for j in range(n):
            ask("tau", "mass", k, (j,), [q[k], zero, eye[j]])
    for d in plan.diagnostic:
        for pair in _pairs(n):
            ask("tau", "polar", d, pair, [q[d], _direction(n, *pair), zero])
            ask("V", "polar", d, pair, [q[d], _direction(n, *pair)])
        ask("tau", "double", d, (), [q[d], 2 * qd[d], zero])
        ask("V", "double", d, (), [q[d], 2 * qd[d]])
    if "C" in asked:
        for k in range(len(q)):
            for i in range(n):
                for sign in (1, -1):
                    shifted = q[k] + sign * STEP * eye[i]
                    ask("tau", "shift gravity", k, (i, sign), [shifted, zero, zero])
                    ask("tau", "shift momentum", k, (i, sign), [shifted, zero, qd[k]])
                    for j in range(n):
                        ask("tau", "shift mass", k, (i, sign, j), [shifted, zero, eye[j]])
    for k in range(len(q)):
        ask("M", "state", k, (), [q[k]])
        ask("G", "state", k, (), [q[k]])
        ask("V", "state", k, (), [q[k], qd[k]])
        ask("C", "state", k, (), [q[k], qd[k]])
    return plan


@dataclass(frozen=True)
class Expected:
    """Our library's answers: every term (N, …), V's (6.63) coefficients at the diagnostic states, and
    the answers of typical mistakes: per term, (code, variant) → the answer made with that mistake
    (:func:`~course_dynamics.grading.mistakes.mistaken_terms`).

    Parameters
    ----------
    terms : dict of str to numpy.ndarray
        Our τ, M, V, G and C at the plan's N states: shape (N, n), or (N, n, n) for M and C.
    B : numpy.ndarray, shape (D, n, n(n-1)/2)
        Craig's B(Θ) of (6.63), the Coriolis coefficients, at the D diagnostic states.
    C_centrifugal : numpy.ndarray, shape (D, n, n)
        Craig's C(Θ) of (6.63), the centrifugal coefficients, at the diagnostic states.
    mistakes : dict
        Per term, a dict of (code, variant) to our answer made with that mistake, at the states.
    """

    terms: dict[str, np.ndarray]
    B: np.ndarray
    C_centrifugal: np.ndarray
    mistakes: dict[str, dict[tuple[str, str], np.ndarray]]


def _all_terms(model, q, qd, qdd) -> dict[str, np.ndarray]:
    # Deliberately the recursions as written, not the evaluator's choice: a grade rests on these answers, so they
    # come from the code a student reads, the same code whose mistaken variants (mistakes.py) they are told apart
    # from, whatever the cache holds; and a class's few states take milliseconds interpreted (docs: Compiled models).
    return dict(tau=inverse_dynamics(model, q, qd, qdd), M=mass_matrix(model, q), V=velocity_torques(model, q, qd),
                G=gravity_torques(model, q), C=coriolis_matrix(model, q, qd))


def expected_terms(assignment: Assignment, plan: Plan) -> Expected:
    """Every term by our library at the plan's states, with the answers of the mistakes the diagnosis names.

    Parameters
    ----------
    assignment : Assignment
        The assignment: its robot.
    plan : Plan
        The states.

    Returns
    -------
    Expected
        Our answers.
    """
    model = assignment.robot
    terms = _all_terms(model, plan.q, plan.qd, plan.qdd)
    d = list(plan.diagnostic)
    B, C = configuration_space_terms(model, plan.q[d])
    mistakes = {"C": {}, **mistaken_terms(model, plan.q, plan.qd, plan.qdd)}
    return Expected(terms=terms, B=B, C_centrifugal=C, mistakes=mistakes)


class Unanswered(Exception):
    """A call the student's function did not answer with numbers; the message says what it did instead."""


@dataclass(frozen=True)
class Answers:
    """A submission's answers by :class:`Call` key: which functions it defines and the record of each call.

    Parameters
    ----------
    defined : frozenset of str
        The functions the submission defines.
    records : dict
        Per :class:`Call`, the harness's record of it: a dict with ``value`` or ``error``.
    """

    defined: frozenset
    records: dict

    @classmethod
    def read(cls, outcome: dict, plan: Plan) -> Answers:
        """The harness's outcome (``defined``, ``results``: per function one record per call, in the order asked).

        Parameters
        ----------
        outcome : dict
            The harness's outcome; a list of records shorter than the calls leaves the rest unanswered.
        plan : Plan
            The calls the records answer.

        Returns
        -------
        Answers
            The records by call.
        """
        results = outcome.get("results", {})
        records = {}
        for function in FUNCTION_ARGUMENTS:
            answered = results.get(function)
            if isinstance(answered, list):
                records.update(zip(plan.calls_of(function), answered, strict=False))  # short lists: "no answer"
        return cls(frozenset(outcome.get("defined", ())), records)

    def value(self, call: Call) -> np.ndarray:
        """The array the student answered ``call`` with; :class:`Unanswered` when there is none.

        Parameters
        ----------
        call : Call
            The call.

        Returns
        -------
        numpy.ndarray
            The value returned.

        Raises
        ------
        Unanswered
            If the call has no record, raised an error, or returned values that are not numbers.
        """
        record = self.records.get(call)
        if not isinstance(record, dict):
            raise Unanswered("no answer")
        if "value" not in record:
            raise Unanswered(str(record.get("error", "no answer")))
        try:
            return np.array(record["value"], dtype=float)
        except (TypeError, ValueError):
            raise Unanswered("returned values that are not numbers") from None


@dataclass
class Returned:
    """A student's answers for one term: per state a value (array) or an error message; how they were obtained.

    Parameters
    ----------
    values : list of (numpy.ndarray or None)
        Per state, the value, None where there is none.
    errors : list of (str or None)
        Per state, why there is no value, None where there is one.
    source : str
        ``"direct"``, ``"derived from tau"`` or ``"missing"``.
    """

    values: list
    errors: list
    source: str  # "direct", "derived from tau", "missing"

    @property
    def available(self) -> bool:
        """Whether the term was had at all (directly or derived)."""
        return self.source != "missing"


def _per_state(count: int, recipe: Callable[[int], np.ndarray]) -> tuple[list, list]:
    """Per state k, ``recipe(k)``, or what stopped it: the first unanswered call, or arrays that do not fit."""
    values, errors = [], []
    for k in range(count):
        try:
            values.append(recipe(k))
            errors.append(None)
        except Unanswered as exc:
            values.append(None)
            errors.append(str(exc))
        except ValueError as exc:  # arrays of the wrong shape: say which
            values.append(None)
            errors.append(f"returned arrays that do not fit together ({exc})")
    return values, errors


def _gravity(answers: Answers, k: int, shift: tuple = ()) -> np.ndarray:
    return answers.value(Call("tau", "shift gravity" if shift else "gravity", k, shift))


def _mass(answers: Answers, n: int, k: int, shift: tuple = ()) -> np.ndarray:
    G = _gravity(answers, k, shift)
    purpose = "shift mass" if shift else "mass"
    return np.column_stack([answers.value(Call("tau", purpose, k, (*shift, j))) - G for j in range(n)])


def _christoffel(answers: Answers, plan: Plan, k: int) -> np.ndarray:
    """C = ½(Ṁ + D − Dᵀ) from τ at Θ ± h eᵢ: M(Θ ± h eᵢ) and M(Θ ± h eᵢ) Θ̇, then central differences."""
    n = plan.n
    M, momentum = {}, {}
    for i in range(n):
        for sign in (1, -1):
            M[i, sign] = _mass(answers, n, k, (i, sign))
            momentum[i, sign] = answers.value(Call("tau", "shift momentum", k, (i, sign))) \
                - _gravity(answers, k, (i, sign))
    dM = [(M[i, 1] - M[i, -1]) / (2 * STEP) for i in range(n)]
    D = np.column_stack([(momentum[i, 1] - momentum[i, -1]) / (2 * STEP) for i in range(n)])
    M_dot = sum(plan.qd[k][i] * dM[i] for i in range(n))
    return (M_dot + D - D.T) / 2


def returned_terms(answers: Answers, plan: Plan, term: str, from_tau: bool = False) -> Returned:
    """The student's ``term`` per state: from their function of that name, else (or with ``from_tau``) derived from
    their tau.

    The derivation is a deliberate second path, not a copy of the library: student code is opaque, so the
    only way to see the M, V, G (and C) inside a student's τ is to call τ with the inputs that isolate each
    (module docstring) and take differences, as :func:`~course_dynamics.core.dynamics.mass_matrix` and its
    siblings do with our own τ. It also lets a student who writes only τ be graded on every term.

    Parameters
    ----------
    answers : Answers
        The submission's answers.
    plan : Plan
        The calls asked.
    term : str
        The term: ``tau``, ``M``, ``V``, ``G`` or ``C``.
    from_tau : bool
        Derive the term from τ even when the student defines it.

    Returns
    -------
    Returned
        Per state a value or an error, and the source.
    """
    N, n = len(plan.q), plan.n
    if term in answers.defined and plan.asks(term) and not from_tau:
        values, errors = _per_state(N, lambda k: answers.value(Call(term, "state", k)))
        return Returned(values, errors, "direct")
    if "tau" not in answers.defined:
        return Returned([None] * N, ["not defined"] * N, "missing")
    recipes = {
        "tau": lambda k: answers.value(Call("tau", "state", k)),
        "G": lambda k: _gravity(answers, k),
        "V": lambda k: answers.value(Call("tau", "velocity", k)) - _gravity(answers, k),
        "M": lambda k: _mass(answers, n, k),
        "C": lambda k: _christoffel(answers, plan, k),
    }
    values, errors = _per_state(N, recipes[term])
    return Returned(values, errors, "derived from tau")


@dataclass(frozen=True)
class Coefficient:
    """One coefficient of V = B(Θ)[Θ̇Θ̇] + C(Θ)[Θ̇²] (6.63) at diagnostic state ``state``: of θ̇ⱼθ̇ₖ (``kind``
    "Coriolis", Craig's B) or θ̇ⱼ² ("centrifugal", Craig's C) in τᵢ; ours, the student's, and the size of ours.

    Parameters
    ----------
    kind : str
        ``"Coriolis"`` or ``"centrifugal"``.
    i : int
        The joint whose torque τᵢ the coefficient is in.
    j, k : int
        The joints of the velocity product θ̇ⱼθ̇ₖ (j = k for a centrifugal one).
    state : int
        The diagnostic state's index.
    expected : float
        Our coefficient (τᵢ per θ̇ⱼθ̇ₖ or θ̇ⱼ²: kg·m² when the joints are revolute).
    returned : float
        The student's, in the same unit.
    scale : float
        The size of our coefficients at that state, what the tolerance is relative to.
    """

    kind: str
    i: int
    j: int
    k: int
    state: int
    expected: float
    returned: float
    scale: float

    def right(self, tolerance: float, factor: float = 1.0) -> bool:
        """Whether the student's is ``factor`` × ours.

        Parameters
        ----------
        tolerance : float
            The error allowed, relative to ``scale``.
        factor : float
            The multiple of ours it is compared with.

        Returns
        -------
        bool
            True when it agrees.
        """
        return abs(self.returned - factor * self.expected) <= tolerance * self.scale


@dataclass(frozen=True)
class VelocityProbe:
    """The student's V read off at the diagnostic states: every (6.63) coefficient, and per state V at Θ̇
    (``single``) and at 2Θ̇ (``doubled``) with the size of our coefficients there (``scales``).

    Parameters
    ----------
    coefficients : tuple of Coefficient
        Every coefficient at every diagnostic state.
    single : tuple of numpy.ndarray
        Per diagnostic state, the student's V(Θ, Θ̇), shape (n,), N·m (N for a prismatic joint).
    doubled : tuple of numpy.ndarray
        Per diagnostic state, V(Θ, 2Θ̇), shape (n,).
    scales : tuple of float
        Per diagnostic state, the size of our coefficients.
    """

    coefficients: tuple[Coefficient, ...]
    single: tuple[np.ndarray, ...]
    doubled: tuple[np.ndarray, ...]
    scales: tuple[float, ...]


def returned_coefficients(answers: Answers, plan: Plan, expected: Expected,
                          from_tau: bool = False) -> VelocityProbe | None:
    """The student's V probed at the diagnostic states (module docstring): V at eⱼ gives the centrifugal
    coefficients of θ̇ⱼ², V at eⱼ + eₖ minus those the Coriolis coefficient of θ̇ⱼθ̇ₖ. From their V when they
    define it (and it is graded) unless ``from_tau``, else from their τ minus its G; None when any of these
    calls has no answer of shape (n,).

    Parameters
    ----------
    answers : Answers
        The submission's answers.
    plan : Plan
        The calls asked.
    expected : Expected
        Our coefficients.
    from_tau : bool
        Probe τ minus its G even when the student defines V.

    Returns
    -------
    VelocityProbe or None
        The probe; None when the student defines neither V nor τ, or a call has no answer of shape (n,).
    """
    direct = "V" in answers.defined and plan.asks("V") and not from_tau
    if not direct and "tau" not in answers.defined:
        return None
    coriolis, centrifugal = coefficient_names(plan.n)
    found, single, doubled, scales = [], [], [], []
    for d in plan.diagnostic:
        try:
            V, twice, once = _probe(answers, plan, d, direct)
        except Unanswered:
            return None
        B, C = expected.B[d], expected.C_centrifugal[d]
        scale = max(float(np.abs(B).max(initial=0)), float(np.abs(C).max()), 1e-12)
        for i in range(plan.n):
            found += [Coefficient("Coriolis", i, j, k, d, B[i][index], V[j, k][i] - V[j, j][i] - V[k, k][i], scale)
                      for index, (j, k) in enumerate(coriolis)]
            found += [Coefficient("centrifugal", i, j, j, d, C[i][j], V[j, j][i], scale) for j, _ in centrifugal]
        single.append(once)
        doubled.append(twice)
        scales.append(scale)
    return VelocityProbe(tuple(found), tuple(single), tuple(doubled), tuple(scales))


def _probe(answers: Answers, plan: Plan, d: int, direct: bool) -> tuple[dict, np.ndarray, np.ndarray]:
    """V at state d for each unit and paired unit velocity (keyed (j, k), j ≤ k), at 2Θ̇ and at Θ̇."""
    function, single = ("V", "state") if direct else ("tau", "velocity")

    def vector(call: Call) -> np.ndarray:
        value = answers.value(call)
        if value.shape != (plan.n,):
            raise Unanswered("not one value per joint")
        return value

    offset = 0.0 if direct else vector(Call("tau", "gravity", d))

    def at(purpose: str, detail: tuple = ()) -> np.ndarray:
        return vector(Call(function, purpose, d, detail)) - offset

    return {pair: at("polar", pair) for pair in _pairs(plan.n)}, at("double"), at(single)


def coefficient_names(n: int) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """The (j, k) of the Coriolis terms θ̇ⱼθ̇ₖ (j < k, Craig's B) and the centrifugal θ̇ⱼ² (Craig's C)."""
    return velocity_pairs(n), [(j, j) for j in range(n)]


__all__ = ["STEP", "Answers", "Call", "Coefficient", "Expected", "Plan", "Returned", "Unanswered", "VelocityProbe",
           "expected_terms", "make_plan", "returned_coefficients", "returned_terms"]
