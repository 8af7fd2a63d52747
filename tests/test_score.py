"""course_dynamics/grading/score.py (and the checks of grading/diagnosis.py it runs): one record per answer.

Every wrong answer here is made by making the mistake in the dynamics — our own
recursion run on a robot with gravity flipped, masses doubled, angles in
degrees, Christoffel symbols summed the wrong way — never by editing our
numbers. The answers go through the harness's ``evaluate`` and are read back
by key, as in grading; each check is then called on the record directly, and
:func:`score` on the same record must report it.
"""
from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest
from submissions import closed_forms

from course_dynamics.core.dynamics import gravity_torques, mass_matrix, velocity_torques
from course_dynamics.core.lagrange import christoffel_symbols, coriolis_matrix
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.core.robots import load_robot
from course_dynamics.grading import diagnosis
from course_dynamics.grading.assignment import Assignment
from course_dynamics.grading.diagnosis import Answer
from course_dynamics.grading.grade import grade_class
from course_dynamics.grading.harness import evaluate
from course_dynamics.grading.plan import Answers, Call, expected_terms, make_plan, returned_terms
from course_dynamics.grading.score import score, score_outcome, term_answer
from course_dynamics.teaching.exercises import check, show_values, term_assignment

MODEL = load_robot("two_link")
FLIPPED = MODEL.with_gravity(-MODEL.gravity)  # gravity pointing up: G(Θ) pushes the arm down
HEAVY = dataclasses.replace(MODEL, bodies=tuple(dataclasses.replace(b, mass=2 * b.mass, I_com=2 * b.I_com)
                                                for b in MODEL.bodies))  # every mass and inertia counted twice


@pytest.fixture(scope="module")
def setting():
    assignment = Assignment(Path("score.toml"), "two_link", MODEL, {t: 1.0 for t in ("tau", "M", "V", "G", "C")},
                            samples=8, seed=11)
    plan = make_plan(assignment)
    return assignment, plan, expected_terms(assignment, plan)


def answer_of(setting, term: str, **functions) -> Answer:
    """The record of ``term`` for a student who wrote ``functions``, through the harness and the plan's keys."""
    assignment, plan, reference = setting
    outcome = evaluate(functions, plan.harness_functions())
    return term_answer(term, Answers.read(outcome, plan), plan, reference, assignment)


def tau_with(M=None, V=None, G=None):
    """τ = M Θ̈ + V + G (6.59) with any of its parts replaced by a student's."""
    M, V, G = (M or (lambda q: mass_matrix(MODEL, q))), (V or (lambda q, qd: velocity_torques(MODEL, q, qd))), \
        (G or (lambda q: gravity_torques(MODEL, q)))
    return lambda q, qd, qdd: M(q) @ qdd + V(q, qd) + G(q)


def christoffel_V_once(q, qd):
    """Σⱼ≤ₖ Γᵢⱼₖ θ̇ⱼθ̇ₖ: each pair j ≠ k summed once instead of twice (the Coriolis terms lose their 2)."""
    Gamma = christoffel_symbols(MODEL, q)
    return np.einsum("ijk,j,k->i", Gamma * np.triu(np.ones((MODEL.n, MODEL.n))), qd, qd)


def lagrange_C(q, qd, h=1e-6):
    """Cᵢⱼ = Σₖ ∂Mᵢⱼ/∂θₖ θ̇ₖ − ½ Σₖ ∂Mⱼₖ/∂θᵢ θ̇ₖ: C Θ̇ = V from (6.76), but not the Christoffel form."""
    dM = np.array([(mass_matrix(MODEL, q + h * e) - mass_matrix(MODEL, q - h * e)) / (2 * h) for e in np.eye(MODEL.n)])
    return np.einsum("kij,k->ij", dM, qd) - 0.5 * np.einsum("ijk,k->ij", dM, qd)


def found(check, answer) -> diagnosis.Finding:
    finding = check(answer)
    assert finding is not None, check
    return finding


# ---------------------------------------------------------------------------------------- score(): the record

def test_a_right_answer_scores_every_state_and_says_nothing(setting):
    answer = answer_of(setting, "tau", tau=lambda q, qd, qdd: inverse_dynamics(MODEL, q, qd, qdd))
    result = score(answer, max_points=40)
    assert result.correct and result.points == 40 and result.agreeing == tuple(range(8))
    assert result.findings == result.tags == () and result.worst == ""


def test_partial_credit_counts_the_states_that_agree(setting):
    _, plan, _ = setting
    heavy_on_the_left = lambda q: gravity_torques(HEAVY if q[0] < 0 else MODEL, q)  # noqa: E731
    answer = answer_of(setting, "G", G=heavy_on_the_left)
    right = tuple(k for k in range(8) if plan.q[k, 0] >= 0)
    assert 0 < len(right) < 8
    result = score(answer, max_points=10)
    assert result.agreeing == right and result.points == round(10 * len(right) / 8, 2)
    assert score(answer, max_points=10, partial_credit="none").points == 0
    assert "worst state #" in result.worst and "expected G = " in result.worst


def test_the_derived_terms_are_the_librarys_terms(setting):
    """The deliberate second path: M, V, G, C taken out of a τ by differences agree with the library's own."""
    assignment, plan, reference = setting
    outcome = evaluate({"tau": lambda q, qd, qdd: inverse_dynamics(MODEL, q, qd, qdd)}, plan.harness_functions())
    for result in score_outcome(outcome, assignment, plan, reference):
        assert result.correct, result.text()
        assert result.source == ("direct" if result.term == "tau" else "derived from tau")


def test_every_call_is_read_back_by_its_key(setting):
    _, plan, _ = setting
    # Each answer echoes its arguments within the n × n values a term may have: Θ, then Θ̇ + 2 Θ̈ (or Θ̇).
    echo = {"tau": lambda q, qd, qdd: np.concatenate([q, qd + 2 * qdd]), "V": lambda q, qd: np.concatenate([q, qd])}
    answers = Answers.read(evaluate(echo, plan.harness_functions()), plan)
    unasked = plan.calls_of("M") + plan.calls_of("G") + plan.calls_of("C")
    assert len(answers.records) == len(plan.arguments) - len(unasked)
    for call, arguments in plan.arguments.items():
        if call.function in echo:
            q, *rates = (np.asarray(a) for a in arguments)
            expected = np.concatenate([q, rates[0] + 2 * rates[1] if len(rates) == 2 else rates[0]])
            assert answers.value(call).tolist() == expected.tolist(), call
    column = answers.value(Call("tau", "mass", 3, (1,)))  # τ(Θ₄, 0, e₂)
    assert column[:2].tolist() == plan.q[3].tolist() and column[2:].tolist() == [0.0, 2.0]


# ---------------------------------------------------------------------------------------- screens

def test_screens_name_what_could_not_be_compared(setting):
    nothing = answer_of(setting, "G")
    assert found(diagnosis.not_defined, nothing).text == "not defined: write G(q), or tau(q, qd, qdd) to derive it from"
    assert score(nothing).worst.startswith("to check yours, state #1: q = ")
    raising = answer_of(setting, "G", G=lambda q: gravity_torques(MODEL, q) if q[0] > 0 else {}["theta1"])
    assert found(diagnosis.raised_an_error, raising).text.startswith("raised an error on ")
    three = answer_of(setting, "G", G=lambda q: np.append(gravity_torques(MODEL, q), 0.0))
    shape = found(diagnosis.wrong_shape, three).text
    assert shape.startswith("returned 3 values, the robot has 2 joints (theta1, theta2)")
    nan = answer_of(setting, "G", G=lambda q: gravity_torques(MODEL, q) * float("nan"))
    assert "NaN or inf" in found(diagnosis.not_finite, nan).text
    assert all(score(a).points == 0 for a in (nothing, three, nan))


# ---------------------------------------------------------------------------------------- the named mistakes

def test_gravity_flipped_in_the_model(setting):
    G = answer_of(setting, "G", G=lambda q: gravity_torques(FLIPPED, q))
    named = found(diagnosis.named_mistake, G)  # −G: gravity's sign, or every moment reversed, G alone cannot tell
    assert named.text.startswith("[gravity-sign] [cross-reversed] matches the right answer computed with this slip: gravity with "
                                 "the wrong sign in the base acceleration ⁰v̇₀; or, equally, with this one: a cross product")
    sign = found(diagnosis.opposite_sign, G)  # what the student reads first: the plain fact, then the mistakes that fit
    assert sign.text.startswith("has the opposite sign everywhere (G returned = −1 × the right value): check the "
                                "direction of gravity; the same answer comes from [gravity-sign] gravity with the wrong sign or from "
                                "[cross-reversed] a cross product in the wrong order")
    assert score(G).tags == ("opposite sign", "gravity-sign", "cross-reversed")
    tau = answer_of(setting, "tau", tau=lambda q, qd, qdd: inverse_dynamics(FLIPPED, q, qd, qdd))
    assert diagnosis.opposite_sign(tau) is None
    finding = found(diagnosis.named_mistake, tau)
    assert finding.conclusive and finding.text.startswith(
        "[gravity-sign] matches the right answer computed with this slip: gravity with the wrong sign in the base acceleration ⁰v̇₀. "
        "In Craig's recursion")
    assert score(tau).tags == ("gravity-sign",)


@pytest.mark.parametrize("convert, variant", [(np.deg2rad, "read as"), (np.rad2deg, "turned into")])
def test_angles_in_degrees(setting, convert, variant):
    tau = answer_of(setting, "tau", tau=lambda q, qd, qdd: inverse_dynamics(MODEL, convert(q), qd, qdd))
    assert found(diagnosis.named_mistake, tau).text.startswith(
        f"[degrees] matches the right answer computed with this slip: the angles in degrees (positions {variant} degrees). ")
    assert score(tau).tags == ("degrees",)


def test_zeros_are_not_written_yet_rather_than_a_mistake(setting):
    V = answer_of(setting, "V", V=lambda q, qd: np.zeros(2))  # on the planar arm: the same as ω × (ω × P) left out
    assert score(V).findings == ("returns zeros everywhere: not written yet?",) and score(V).tags == ("zeros",)


def test_masses_counted_twice_are_a_constant_factor(setting):
    M = answer_of(setting, "M", M=lambda q: mass_matrix(HEAVY, q))
    assert "constant factor of about 2.0:" in found(diagnosis.constant_factor, M).text
    assert score(M).tags == ("constant factor",)


def test_christoffel_indices_exchanged_give_the_transpose(setting):
    C = answer_of(setting, "C", C=lambda q, qd: np.einsum("jik,k->ij", christoffel_symbols(MODEL, q), qd))
    assert found(diagnosis.transposed, C).text.startswith("is the transpose of the right matrix")
    assert score(C).tags == ("transposed",)


def test_torques_in_the_wrong_joint_order(setting):
    tau = answer_of(setting, "tau", tau=lambda q, qd, qdd: inverse_dynamics(MODEL, q, qd, qdd)[::-1])
    assert "wrong order (theta2, theta1 appear as theta1, theta2)" in found(diagnosis.joints_swapped, tau).text


def test_a_wrong_coupling_inertia_names_its_entries_and_symmetry(setting):
    def coupling_without_cosine(q):
        M = mass_matrix(MODEL, q).copy()
        M[0, 1] = M[1, 0] = M[1, 1]  # m₂l₂² only: the m₂l₁l₂c₂ of (6.60) left out
        return M

    def one_sided(q):
        M = coupling_without_cosine(q)
        M[1, 0] = mass_matrix(MODEL, q)[1, 0]
        return M

    M = answer_of(setting, "M", M=coupling_without_cosine)
    assert found(diagnosis.wrong_entries, M).text.startswith("entries M[1,2], M[2,1] are wrong (rows and columns")
    assert diagnosis.not_symmetric(M) is None
    assert "is not symmetric" in found(diagnosis.not_symmetric, answer_of(setting, "M", M=one_sided)).text
    tau = answer_of(setting, "tau", tau=tau_with(M=coupling_without_cosine))
    assert found(diagnosis.InPart("M", diagnosis.wrong_entries, "in τ's inertia part, "), tau).text.startswith(
        "in τ's inertia part, entries M[1,2], M[2,1] are wrong")
    assert "the inertia part M(Θ) (τ(Θ, 0, eⱼ) − G) is wrong" in found(diagnosis.tau_parts, tau).text


def test_a_C_from_lagranges_equation_is_not_christoffels(setting):
    C = answer_of(setting, "C", C=lagrange_C)
    assert found(diagnosis.not_christoffel, C).text.startswith("satisfies C Θ̇ = V")
    assert "C not Christoffel" in score(C).tags


def test_coriolis_terms_summed_once_miss_their_factor_2(setting):
    V = answer_of(setting, "V", V=christoffel_V_once)
    assert "the Coriolis coefficient of θ̇1θ̇2 in τ1" in found(diagnosis.wrong_coefficients, V).text
    assert "Craig's B is 2Γᵢⱼₖ" in found(diagnosis.coriolis_without_factor_2, V).text
    assert diagnosis.coriolis_without_factor_2(answer_of(setting, "V", V=lambda q, qd: 2 * christoffel_V_once(q, qd))) \
        is None
    tau = answer_of(setting, "tau", tau=tau_with(V=christoffel_V_once))
    parts = found(diagnosis.tau_parts, tau)
    assert parts.text.endswith("the velocity part V = τ(Θ, Θ̇, 0) − G is wrong")
    assert parts.tags == ("wrong V part of tau",)
    in_part = found(diagnosis.InPart("V", diagnosis.coriolis_without_factor_2), tau)
    assert in_part.text.startswith("[coriolis-half] in τ's velocity part V, every Coriolis term")
    assert {"wrong V part of tau", "wrong Coriolis terms", "coriolis-half"} <= set(score(tau).tags)


def test_a_V_that_is_not_quadratic_in_the_rates(setting):
    V = answer_of(setting, "V", V=lambda q, qd: coriolis_matrix(MODEL, q, qd).sum(axis=1))  # C Θ̇ without its Θ̇
    assert found(diagnosis.wrong_coefficients, V).text.startswith("V is not quadratic in Θ̇")
    assert diagnosis.coriolis_without_factor_2(V) is None


# ---------------------------------------------------------------------------------------- values, and one diagnosis

def test_a_single_value_is_scored_by_the_same_checks():
    m, w, l, h = 2.0, 0.3, 0.5, 0.1
    p = np.array([w, l, h]) / 2  # the box's centre seen from its corner
    at_centre = m / 12 * np.diag([l**2 + h**2, w**2 + h**2, w**2 + l**2])  # (6.2)
    at_corner = at_centre + m * (p @ p * np.eye(3) - np.outer(p, p))  # parallel-axis theorem
    products_with_plus = at_centre + m * (p @ p * np.eye(3) + np.outer(p, p) - 2 * np.diag(p * p))  # the misprint
    result = score(Answer.single(at_corner, products_with_plus, 1e-6))
    assert result.findings == ("entries (1, 2), (1, 3), (2, 1), (2, 3), (3, 1), (3, 2) are wrong (numbered from 1); "
                               "the others are right",)
    assert result.tags == ("wrong entries",) and result.worst.startswith("expected [[")
    assert score(Answer.single(at_corner[0, 1], products_with_plus[0, 1], 1e-6)).tags == ("opposite sign",)
    moments = np.linalg.eigvalsh(at_corner)
    too_short = score(Answer.single(moments, moments[:2], 1e-6))
    assert too_short.findings == ("has shape (2,), the answer has shape (3,)",)


@pytest.mark.parametrize("exercise, change", [
    ("G_two_link", "\ng = -9.81\n"),
    ("tau_two_link", "\ndef V(q, qd):\n    h = m2 * l1 * l2 * np.sin(q[1])\n"
                     "    return np.array([-h * qd[1] ** 2 - h * qd[0] * qd[1], h * qd[0] ** 2])\n"),
])
def test_the_grader_and_the_notebook_give_one_diagnosis(tmp_path, exercise, change):
    """The same wrong code, graded in the sandbox and checked in a notebook's kernel: the same findings and state."""
    source = closed_forms(change)
    (tmp_path / "student.py").write_text(source)
    [graded] = grade_class(term_assignment(exercise), [tmp_path / "student.py"])
    namespace = {}
    exec(compile(source, str(tmp_path / "student.py"), "exec"), namespace)
    show_values(True)  # the instructor's view, which shows our values as the grader's pages do
    verdict = check(exercise, namespace[exercise.split("_")[0]])
    show_values(False)
    students = check(exercise, namespace[exercise.split("_")[0]])
    [result] = graded.diagnoses
    assert graded.status == "ok" and not result.correct and not verdict
    assert verdict.lines[1:-1] == [*result.findings, result.worst]
    assert verdict.lines[0] == f"agrees on {result.agreed} of {result.total} random states"
    assert len(students.lines) == len(verdict.lines) and not any("expected" in line for line in students.lines)


def test_returned_terms_read_a_direct_function_by_its_state_key(setting):
    _, plan, _ = setting
    answers = Answers.read(evaluate({"G": lambda q: q * 0 + 1.0}, plan.harness_functions()), plan)
    returned = returned_terms(answers, plan, "G")
    assert returned.source == "direct" and all(v.tolist() == [1.0, 1.0] for v in returned.values)
    assert returned_terms(answers, plan, "M").source == "missing"


# ---------------------------------------------------------------------------------------- messages that do not mislead
GRAVITY_FORGOTTEN = ("w, wd, vd = np.zeros(3), np.zeros(3), np.array([0.0, g, 0.0])",
                     "w, wd, vd = np.zeros(3), np.zeros(3), np.zeros(3)")
MISBRACKETED = ("np.cross(w, np.cross(w, P[i]))", "np.cross(np.cross(w, w), P[i])")  # ω × ω = 0: no centripetal term


def test_a_term_derived_from_the_student_s_tau_is_never_not_written_yet(tmp_path):
    """Only τ is written; M, V and G are derived from it. Gravity forgotten, τ read from ⁱNᵢ (zero on point
    masses) and a misbracketed ω × (ω × P) give derived terms that are zero: the feedback says where they come from
    and what τ leaves out, or names the mistake, and never asks whether they are written."""
    from submissions import NEWTON_EULER

    sources = {"gravity": NEWTON_EULER.replace(*GRAVITY_FORGOTTEN),
               "from_N": NEWTON_EULER.replace("out[i] = n @ z", "out[i] = np.zeros(3) @ z  # ⁱNᵢ = 0 here"),
               "bracket": NEWTON_EULER.replace(*MISBRACKETED).replace("np.cross(w, np.cross(w, Pc[i]))",
                                                                       "np.cross(np.cross(w, w), Pc[i])")}
    for name, source in sources.items():
        assert source != NEWTON_EULER
        (tmp_path / f"{name}.py").write_text(source)
    assignment = Assignment(tmp_path / "a.toml", "two_link", MODEL, {t: 1.0 for t in ("tau", "M", "V", "G")},
                            samples=8, seed=11)
    grades = {g.student: {d.term: d for d in g.diagnoses}
              for g in grade_class(assignment, [tmp_path / f"{n}.py" for n in sources])}
    for name, terms in grades.items():
        for term in ("M", "V", "G"):
            assert not any("not written yet" in f for f in terms[term].findings), (name, term, terms[term].findings)
    assert grades["from_N"]["tau"].findings == ("returns zeros everywhere: not written yet?",)  # τ itself: its own
    assert grades["from_N"]["M"].tags == ("zero part",)
    assert "your τ leaves out the gravity torques" in grades["gravity"]["G"].findings[0]
    assert grades["bracket"]["tau"].tags == ("centripetal-missing",)  # named on τ; V derived from it is zero
    assert grades["bracket"]["V"].tags == ("zero part",) and "τ's own feedback" in grades["bracket"]["V"].findings[0]


def test_a_zero_term_derived_from_tau_says_what_tau_leaves_out():
    """The spatial arm's τ without gravity: G derived from it is zero, which no named mistake gives there."""
    spatial = load_robot("spatial_arm")
    assignment = Assignment(Path("zero.toml"), "spatial_arm", spatial, {"G": 1.0}, samples=6, seed=2)
    plan = make_plan(assignment)
    weightless = spatial.with_gravity(np.zeros(3))
    outcome = evaluate({"tau": lambda q, qd, qdd: inverse_dynamics(weightless, q, qd, qdd)}, plan.harness_functions())
    [G] = score_outcome(outcome, assignment, plan, expected_terms(assignment, plan))
    assert G.tags == ("zero part",) and G.findings[0].startswith(
        "G, derived from your τ (derived from tau), is zero on every state: your τ leaves out the gravity torques")


def test_closest_to_a_mistake_only_within_its_stated_closeness(setting):
    """A V far too small is near every small mistaken V (degrees make V tiny) in absolute terms: no "closest to",
    since closeness is measured against the mistaken answer's own size (mistakes.CLOSE)."""
    from course_dynamics.grading.mistakes import CLOSE, closest_mistake

    V = answer_of(setting, "V", V=lambda q, qd: 0.01 * (1.2 + np.cos(q[0])) * velocity_torques(MODEL, q, qd))
    finding = closest_mistake(V)
    assert CLOSE == 0.05 and not finding.text.startswith("closest to")
    assert finding.text.startswith("no mistake the grader names is within 5% of it") and finding.tags == ()
    assert not any("closest to" in f for f in score(V).findings)
    near = answer_of(setting, "tau", tau=lambda q, qd, qdd: 1.001 * inverse_dynamics(FLIPPED, q, qd, qdd)
                     + 1e-4 * np.sin(q))  # [gravity-sign] and a little more
    assert closest_mistake(near).text.startswith("closest to [gravity-sign]")


@pytest.mark.parametrize("factor", [0.998981, 0.656, 1.0537])
def test_a_factor_is_never_shown_to_more_than_two_significant_digits(setting, factor):
    """Dividing by the factor printed must not make the answer pass: in the grader, the notebook and a formula."""
    M = answer_of(setting, "M", M=lambda q: factor * mass_matrix(MODEL, q))
    [finding] = score(M).findings
    shown = re.search(r"about (\d+(?:\.\d+)?)( %)?", finding).group(1)
    assert len(re.sub(r"^0\.0*|\.", "", shown).rstrip("0") or "0") <= 2, finding
    printed = float(shown)
    k = 1 + printed / 100 * (1 if factor > 1 else -1) if "%" in finding else printed
    fixed = answer_of(setting, "M", M=lambda q: factor * mass_matrix(MODEL, q) / k)
    assert not fixed.correct  # the printed number is too rough to divide by
    from submissions import CLOSED_FORMS
    namespace = {}
    exec(compile(CLOSED_FORMS, "student.py", "exec"), namespace)
    from course_dynamics.teaching.exercises import my_robot
    from course_dynamics.core.dynamics import mass_matrix as ours
    arm = my_robot("two_link").model
    verdict = check("M_two_link", lambda q: factor * ours(arm, q))
    assert str(factor) not in verdict.text() and f"{factor:.3g}" not in verdict.text()


def test_a_formula_s_factor_is_shown_to_two_digits_too():
    from course_dynamics.teaching.exercises import symbols

    m, l, theta_dot = symbols("m", "l", "theta_dot")
    verdict = check("k_pendulum", 0.998981 * m * l**2 * theta_dot**2 / 2)
    assert "times 1.0" in verdict.text() and "0.998981" not in verdict.text() and "0.999" not in verdict.text()


def test_a_mistake_is_closest_only_below_the_limit_and_never_printed_at_it(setting):
    """"closest to" holds a relative error below CLOSE, and the number shown beside "less than 5%" is below it:
    0.0496 would print as 0.05 to one or two digits, so it is shown with three; 0.04999 is not shown at all."""
    from course_dynamics.grading.mistakes import CLOSE, _below

    assert (_below(0.03, CLOSE), _below(0.0496, CLOSE), _below(0.049996, CLOSE)) == ("0.03", "0.0496", None)
    near = answer_of(setting, "tau", tau=lambda q, qd, qdd: 1.001 * inverse_dynamics(FLIPPED, q, qd, qdd)
                     + 1e-4 * np.sin(q))
    finding = next(f for f in score(near).findings if f.startswith("closest to"))
    shown = float(finding.split("(relative error ")[1].split(" ")[0])
    assert shown < CLOSE and "less than 5%" in finding and "within" not in finding
