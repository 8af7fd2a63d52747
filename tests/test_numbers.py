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
