"""course_dynamics/grading/numbers.py: right dynamics with the wrong numbers is named, with the numbers.

The wrong answers are students' files: the two-link arm's closed forms (6.60)–(6.62) and the spatial arm's
Newton–Euler recursion (tests/submissions.py) with another robot's numbers typed in, graded in the sandbox and
checked in the notebook, as a student hands them in.
"""
from __future__ import annotations

import re

import numpy as np
import pytest
from submissions import CLOSED_FORMS, spatial_newton_euler

from course_dynamics.core.regressor import parameters
from course_dynamics.core.robots import load_robot
from course_dynamics.grading.assignment import Assignment
from course_dynamics.grading.grade import grade_class
from course_dynamics.grading.numbers import _body_pi
from course_dynamics.teaching.exercises import check, my_robot
from course_dynamics.tools.variants import robot_variant

ARM = load_robot("two_link")
NUMBERS = "m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 9.81"
TERMS = ("tau", "M", "V", "G")


def with_numbers(m1, m2, l1, l2, g=9.81) -> str:
    return CLOSED_FORMS.replace(NUMBERS, f"m1, m2, l1, l2, g = {m1}, {m2}, {l1}, {l2}, {g}")


def of(parameters) -> str:
    return with_numbers(*(parameters[k] for k in ("m1", "m2", "l1", "l2", "g")))


def notebook(source: str, name: str):
    namespace = {}
    exec(compile(source, "student.py", "exec"), namespace)
    return check(name, namespace[name.split("_")[0]])


def test_the_parameters_of_a_body_are_the_regressor_s():
    """The ten parameters of (m, P_C, ᶜI) that the fit moves are the regressor's π (a second path, tied here)."""
    model = load_robot("spatial_arm")
    ours = np.concatenate([_body_pi(float(b.mass), b.p_com, b.I_com) for b in model.bodies])
    assert np.allclose(ours, parameters(model).astype(float), rtol=1e-14, atol=1e-15)


@pytest.mark.parametrize("term", ["tau", "M", "G"])
def test_one_mass_typed_wrong_is_named_with_its_value_in_the_notebook(term):
    p = my_robot("two_link").parameters
    verdict = notebook(of({**p, "m2": 1.0}), f"{term}_two_link")
    assert verdict.status == "wrong"
    assert f"your dynamics are right; your link 2 has m = 1 kg where the handout has {p['m2']:.4g} kg" in verdict.lines


def test_the_textbook_s_numbers_are_named_in_the_notebook():
    p = my_robot("two_link").parameters
    for term in TERMS:
        verdict = notebook(CLOSED_FORMS, f"{term}_two_link")
        [line] = [line for line in verdict.lines if line.startswith("your dynamics are right, but these are")]
        assert "the course robot's own numbers" in line and f"m1 = 2 kg where your handout has {p['m1']:.4g} kg" in line


def test_the_spatial_arm_with_the_course_robot_s_numbers_or_one_mass_wrong():
    textbook = notebook(spatial_newton_euler(load_robot("spatial_arm")), "tau_spatial_arm")
    assert any(line.startswith("your dynamics are right, but these are the course robot's own numbers")
               for line in textbook.lines), textbook.text()
    mine = my_robot("spatial_arm").model
    source = spatial_newton_euler(mine).replace(f"m = {[float(b.mass) for b in mine.bodies]!r}",
                                                f"m = {[float(mine.bodies[0].mass), 2.0, float(mine.bodies[2].mass)]!r}")
    verdict = notebook(source, "tau_spatial_arm")
    expected = f"your dynamics are right; your link 2 has m = 2 kg where the handout has {mine.bodies[1].mass:.4g} kg"
    assert expected in verdict.lines, verdict.text()


def test_only_the_combinations_the_term_determines_are_said():
    """G sees masses through their moments m·l only: with other masses and lengths, the combinations of first
    moments that differ are named, and no inertia (which G cannot see) is."""
    other = robot_variant("two_link", "grace").parameters
    verdict = notebook(of(other), "G_two_link")
    [line] = [line for line in verdict.lines if line.startswith("your dynamics are right, with other numbers")]
    assert "mcx_1" in line and "mcx_2" in line and "Izz" not in line


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    """A class graded per student, with a roster: ada hands in grace's numbers, alan the course robot's (the
    textbook's), edsger his own with m₂ typed as 1.0 kg, barbara her own."""
    folder = tmp_path_factory.mktemp("numbers")
    own = {name: robot_variant("two_link", name).parameters for name in ("ada", "grace", "alan", "edsger", "barbara")}
    files = {"ada": of(own["grace"]), "alan": CLOSED_FORMS, "edsger": of({**own["edsger"], "m2": 1.0}),
             "barbara": of(own["barbara"])}
    paths = []
    for name, source in files.items():
        (folder / f"{name}.py").write_text(source)
        paths.append(folder / f"{name}.py")
    assignment = Assignment(folder / "a.toml", "two_link", ARM, {term: 1.0 for term in TERMS}, samples=12, seed=3,
                            variant="per-student", roster=tuple(own))
    return {g.student: g for g in grade_class(assignment, paths)}, own


def test_grade_names_another_student_s_numbers_without_naming_the_student(graded):
    grades, own = graded
    assert grades["barbara"].total == 4.0
    for diagnosis in grades["ada"].diagnoses:
        [line] = [f for f in diagnosis.findings if f.startswith("your dynamics are right")]
        assert "another student's robot's numbers" in line and "other numbers" in diagnosis.tags
        assert "grace" not in " ".join(diagnosis.findings)
        assert f"m1 = {own['grace']['m1']:.4g} kg where your handout has {own['ada']['m1']:.4g} kg" in line


def test_grade_names_the_textbook_s_numbers_and_one_wrong_mass(graded):
    grades, own = graded
    for diagnosis in grades["alan"].diagnoses:
        assert any(f.startswith("your dynamics are right, but these are the course robot's own numbers")
                   for f in diagnosis.findings), diagnosis.findings
    for diagnosis in grades["edsger"].diagnoses:
        said = f"your dynamics are right; your link 2 has m = 1 kg where the handout has {own['edsger']['m2']:.4g} kg"
        if diagnosis.term == "V":  # V = m₂l₁l₂ s₂ (…), a factor alone: τ, M and G tell which parameter it is
            said += " (as your τ, M and G show)"
        assert said in diagnosis.findings, (diagnosis.term, diagnosis.findings)


def test_numbers_are_named_before_a_constant_factor_but_a_uniform_scale_stays_one():
    """Every parameter doubled is τ times 2, a constant factor (a missing ½ looks the same): not a robot."""
    p = my_robot("two_link").parameters
    verdict = notebook(of({**p, "m1": 2 * p["m1"], "m2": 2 * p["m2"]}), "tau_two_link")
    assert any("constant factor of about 2.0" in line for line in verdict.lines), verdict.text()
    assert not any(re.match("your dynamics are right", line) for line in verdict.lines)


def test_only_a_real_body_is_named():
    """A fit is a robot only when each body is one: a mass above round-off, a pseudo-inertia positive semi-definite
    (so an inertia obeying the triangle inequality); a point mass is one, a negative moment or no mass is not."""
    from course_dynamics.grading.numbers import Scales, physical, physical_robot

    scales = Scales.of(ARM)
    pi = parameters(ARM).astype(float)
    assert physical(pi, scales)  # two point masses: J of rank one each
    negative, massless = pi.copy(), pi.copy()
    negative[9] -= 0.5  # link 1's I_C,zz = −0.5 kg·m², the worked example's ¹F₁ = m₁ ¹v̇₁ read as numbers
    massless[0] = 1.11e-15
    assert not physical(negative, scales) and not physical(massless, scales)
    # what a term does not see may move: G sees first moments only, so another point mass's h is a real robot
    h_moved = pi.copy()
    h_moved[1] *= 1.3
    Y = np.eye(len(pi))[[1, 11]]  # a "term" that sees link 1's and link 2's mcx alone
    assert not physical(h_moved, scales) and physical_robot(Y, h_moved, scales)
    assert not physical_robot(np.eye(len(pi)), negative, scales)  # seen whole: no move makes it real


def test_the_worked_example_s_F1_is_not_called_other_numbers():
    """τ of ¹F₁ = m₁ ¹v̇₁ on link 1 is no real robot's: the fit says nothing of numbers (never I_C,zz = −0.5 kg·m²),
    nor of M's as a massless link 1 (m = 1.11e-15 kg) or round-off (x = 1.984e-06 m); through every check the slip
    on link 1 is named."""
    from pathlib import Path

    from submissions import worked_example

    from course_dynamics.grading.diagnosis import diagnose
    from course_dynamics.grading.harness import evaluate
    from course_dynamics.grading.numbers import other_parameters
    from course_dynamics.grading.plan import Answers, expected_terms, make_plan
    from course_dynamics.grading.score import score, term_answer

    namespace = {}
    exec(compile(worked_example("example-F1-m1-v1"), "student.py", "exec"), namespace)
    assignment = Assignment(Path("f1.toml"), "two_link", ARM, {"tau": 1.0, "M": 1.0}, samples=12, seed=7)
    plan = make_plan(assignment)
    answers = Answers.read(evaluate({"tau": namespace["tau"]}, plan.harness_functions()), plan)
    # M alone is link 1's mass on its joint axis, a real robot (a point mass at x = 0, exactly 0): its fit says so
    alone = {"tau": [], "M": ["your dynamics are right; your link 1 has centre of mass x = 0 m where the handout has "
                              "0.5 m"]}
    for term in ("tau", "M"):
        answer = term_answer(term, answers, plan, expected_terms(assignment, plan), assignment)
        assert answer.wrong and [f.text for f in diagnose(answer, (other_parameters,))] == alone[term], term
        [first, *_] = score(answer).findings
        assert first.startswith("[notes-6.48]") and "on link 1 only" in first, (term, first)
