"""course_dynamics/teaching/exercises.py: each kind of check says right, wrong (and why) or not done yet, and never raises."""
from __future__ import annotations

import numpy as np
import pytest
import sympy

from course_dynamics.teaching.exercises import EXERCISES, check, given, symbols


def test_not_done_yet_for_missing_placeholder_and_empty_function():
    assert check("M_two_link", None).status == "not done"
    assert check("omega_dot_C", ...).status == "not done"

    def empty(q):
        ...

    def unfinished(q):
        raise NotImplementedError

    assert check("M_two_link", empty).status == "not done"
    assert check("M_two_link", unfinished).status == "not done"
    assert check("k_pendulum").status == "not done"  # no such name in this test's globals


def test_a_function_of_the_robot_gets_the_graders_diagnosis():
    def swapped_gravity(q):
        c1, c12 = np.cos(q[0]), np.cos(q[0] + q[1])
        return -np.array([1.0 * 0.4 * 9.81 * c12 + 3.0 * 0.5 * 9.81 * c1, 1.0 * 0.4 * 9.81 * c12])

    verdict = check("G_two_link", swapped_gravity)
    assert verdict.status == "wrong" and not verdict
    assert any("opposite sign" in line for line in verdict.lines) and any("worst state" in line for line in verdict.lines)
    assert any(line.startswith("hint: (6.62)") for line in verdict.lines)


def test_values_name_their_wrong_entries():
    right = np.linalg.eigvalsh(given("principal_moments")["I"])
    assert check("principal_moments", right)
    wrong = right.copy()
    wrong[1] += 1.0
    verdict = check("principal_moments", wrong)
    assert "entries 2 are wrong" in verdict.text()
    assert "has shape (2,)" in check("principal_moments", right[:2]).text()


def test_values_get_the_graders_checks():
    """A value goes through grading.score like a graded term: the same named mistakes, in the same words."""
    tensor = given("principal_moments")["I"]
    counted_twice = check("principal_moments", np.linalg.eigvalsh(tensor + tensor)).text()
    assert "is the right answer times a constant factor 2" in counted_twice
    d = given("I_xy_corner")
    with_the_notes_minus = d["m"] * 0 - d["m"] * (d["w"] / 2) * (d["l"] / 2)  # ᶜI_xy − m x_c y_c, ᶜI_xy = 0
    assert "has the opposite sign everywhere" in check("I_xy_corner", with_the_notes_minus).text()
    assert "expected numbers, got 'abc'" in check("principal_moments", "abc").text()


def test_formulas_are_compared_exactly():
    m, l, g, theta, theta_dot = symbols("m", "l", "g", "theta", "theta_dot")
    assert check("k_pendulum", m * l**2 * theta_dot**2 / 2)
    assert "times 2" in check("k_pendulum", m * l**2 * theta_dot**2).text()
    assert "uses symbols x" in check("k_pendulum", sympy.Symbol("x")).text()
    assert check("u_pendulum", -m * g * l * sympy.cos(theta) + 42 * m * g)  # any reference height


def test_functions_on_random_inputs():
    assert check("euler_step", lambda q, qd, qdd, dt: (q + qd * dt + qdd * dt**2 / 2, qd + qdd * dt))
    verdict = check("euler_step", lambda q, qd, qdd, dt: (q + qd * dt, qd + qdd * dt))
    assert verdict.status == "wrong" and "value 1" in verdict.text()
    assert "raised ZeroDivisionError" in check("inward_force", lambda R, f, F: 1 / 0).text()


def test_autograde_mode_raises(monkeypatch):
    monkeypatch.setenv("NBGRADER_EXECUTION", "autograde")
    with pytest.raises(AssertionError, match="not done yet"):
        check("omega_dot_C", None)


def test_every_exercise_has_a_hint_and_unknown_names_are_an_error():
    assert all(exercise.hint for exercise in EXERCISES.values())
    with pytest.raises(KeyError, match="no exercise named"):
        check("flux_capacitor", 1)
