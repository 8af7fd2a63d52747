"""course_dynamics/grading/mistakes.py, with the recursion's slips (grading/slips.py): every mistake a student
makes, made by a student's own code, is named by its code through ``grade`` and through the notebook check.

The wrong answers are students' programs (tests/submissions.py): a Newton–Euler recursion for the spatial arm
written out with numpy as a student writes it, with one slip edited into its text, and the two-link arm's closed
forms with a trigonometric slip. None is made by editing our numbers.
"""
from __future__ import annotations

from itertools import combinations
from pathlib import Path

import numpy as np
import pytest
from submissions import CLOSED_FORMS, SPATIAL_SLIPS, spatial_newton_euler

from course_dynamics.core.newton_euler import EXACT, newton_euler_links
from course_dynamics.grading.slips import SLIP_EQUATIONS, Slip, slips
from course_dynamics.core.robots import load_robot
from course_dynamics.core.sampling import relative_error
from course_dynamics.grading.assignment import Assignment
from course_dynamics.grading.grade import grade_class
from course_dynamics.grading.mistakes import MISTAKES, mistaken_terms
from course_dynamics.teaching.exercises import check, my_robot

SPATIAL = load_robot("spatial_arm")
TOLERANCE = 1e-6  # the grader's default


def test_every_pair_of_slips_gives_different_torques_on_the_spatial_arm():
    rng = np.random.default_rng(5)
    q, qd, qdd = rng.uniform(-2, 2, (20, 3)), rng.standard_normal((20, 3)), rng.standard_normal((20, 3))
    torques = {slip: newton_euler_links(SPATIAL, q, qd, qdd, slip).tau for slip in (EXACT, *slips())}
    closest = min(max(relative_error(torques[a][k], torques[b][k], 1e-12) for k in range(20))
                  for a, b in combinations(torques, 2))
    assert closest > 1000 * TOLERANCE  # measured 2.8e-3: the gyroscopic term left out or reversed in (6.50)
    assert {slip.code for slip in slips()} == set(SLIP_EQUATIONS) <= set(MISTAKES)


def test_a_slip_names_only_equations_it_can_be_made_in():
    with pytest.raises(ValueError, match="no slip 'gyroscopic-missing'"):
        Slip("gyroscopic-missing", ("6.47",))
    assert Slip("centripetal-missing", ("6.47", "6.48")).where == "every equation where it appears, (6.47) and (6.48)"


def test_the_inertia_about_the_origin_is_the_parallel_axis_tensor():
    """``inertia-about-origin`` equals a model whose COM tensor was moved to the origin (and nothing else)."""
    from dataclasses import replace

    from course_dynamics.core.inertia import parallel_axis

    moved = replace(SPATIAL, bodies=tuple(replace(b, I_com=parallel_axis(b.I_com, b.mass, b.p_com)) for b in SPATIAL.bodies))
    state = ([0.3, -0.7, 1.1], [0.5, 1.2, -0.8], [0.2, -0.4, 0.9])
    assert np.allclose(newton_euler_links(SPATIAL, *state, Slip("inertia-about-origin", ("6.50",))).tau,
                       newton_euler_links(moved, *state).tau, rtol=1e-12, atol=1e-12)


EXPECTED = {  # the student's slip → the code and the words of the equations named
    "rotation-transposed": ("rotation-transposed", "in every equation where it appears"),
    "rotation-transposed-outward": ("rotation-transposed", "in (6.45), (6.46) and (6.47)"),
    "cross-reversed": ("cross-reversed", "in (6.46)"),
    "centripetal-missing": ("centripetal-missing", "in every equation where it appears, (6.47) and (6.48)"),
    "centripetal-missing-6.48": ("centripetal-missing", "in (6.48)"),
    "gyroscopic-missing": ("gyroscopic-missing", "in (6.50)"),
    "inertia-about-origin": ("inertia-about-origin", "in (6.50)"),
    "moment-arm-missing": ("moment-arm-missing", "in (6.52)"),
    "gravity-sign": ("gravity-sign", "in the base acceleration ⁰v̇₀"),
    "degrees": ("degrees", "(positions read as degrees)"),
    "joints-swapped": ("joints-swapped", "wrong order"),
}


@pytest.fixture(scope="module")
def graded_slips(tmp_path_factory):
    """Every slip of SPATIAL_SLIPS handed in as a student's file and graded in the sandbox on the spatial arm."""
    folder = tmp_path_factory.mktemp("slips")
    paths = []
    for slip in [""] + list(SPATIAL_SLIPS):
        path = folder / f"{slip or 'right'}.py"
        path.write_text(spatial_newton_euler(SPATIAL, slip))
        paths.append(path)
    assignment = Assignment(folder / "a.toml", "spatial_arm", SPATIAL, {"tau": 1.0}, samples=12, seed=4)
    return {g.path.stem: g for g in grade_class(assignment, paths)}


def test_the_right_recursion_gets_full_marks(graded_slips):
    assert graded_slips["right"].total == 1.0


@pytest.mark.parametrize("slip", list(SPATIAL_SLIPS))
def test_grade_names_each_slip(graded_slips, slip):
    code, where = EXPECTED[slip]
    [diagnosis] = graded_slips[slip].diagnoses
    assert diagnosis.points == 0 and code in diagnosis.tags
    [finding] = [f for f in diagnosis.findings if f.startswith(f"[{code}]")]
    assert where in finding
    assert MISTAKES[code].advice in finding or code == "joints-swapped"  # that one names the joint order itself


@pytest.mark.parametrize("slip", list(SPATIAL_SLIPS))
def test_the_notebook_check_names_each_slip(slip):
    namespace = {}  # the notebook checks the student's own arm: the same code, with their numbers
    exec(compile(spatial_newton_euler(my_robot("spatial_arm").model, slip), "student.py", "exec"), namespace)
    verdict = check("tau_spatial_arm", namespace["tau"])
    code, where = EXPECTED[slip]
    assert verdict.status == "wrong" and any(line.startswith(f"[{code}]") and where in line for line in verdict.lines)


def test_two_slips_at_once_are_closest_to_one_of_them(tmp_path):
    source = spatial_newton_euler(my_robot("spatial_arm").model, "moment-arm-missing").replace(
        "vd = np.zeros(3), np.zeros(3), -g", "vd = np.zeros(3), np.zeros(3), -1.001 * g")
    namespace = {}
    exec(compile(source, "student.py", "exec"), namespace)
    verdict = check("tau_spatial_arm", namespace["tau"])
    assert any(line.startswith("closest to [moment-arm-missing]") for line in verdict.lines), verdict.text()


CLOSED_FORM_SLIPS = {  # two-link closed forms (6.60)-(6.62) with a trigonometric slip in G, and its code
    "sin-cos-swapped": ("c1, c12 = np.cos(q[0]), np.cos(q[0] + q[1])", "c1, c12 = np.sin(q[0]), np.sin(q[0] + q[1])"),
    "c1-c12-swapped": ("c1, c12 = np.cos(q[0]), np.cos(q[0] + q[1])", "c12, c1 = np.cos(q[0]), np.cos(q[0] + q[1])"),
}


@pytest.mark.parametrize("code", list(CLOSED_FORM_SLIPS))
def test_closed_form_slips_are_named_in_G_and_in_tau(tmp_path, code):
    old, new = CLOSED_FORM_SLIPS[code]
    path = tmp_path / "student.py"
    path.write_text(CLOSED_FORMS.replace(old, new))
    arm = load_robot("two_link")
    assignment = Assignment(tmp_path / "a.toml", "two_link", arm, {"G": 1.0, "tau": 1.0}, samples=12, seed=2)
    [graded] = grade_class(assignment, [path])
    for diagnosis in graded.diagnoses:
        assert code in diagnosis.tags, (diagnosis.term, diagnosis.findings)
    p = my_robot("two_link").parameters  # the notebook checks the student's own arm: their numbers
    namespace = {}
    exec(compile(path.read_text().replace("m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 9.81",
                                          f"m1, m2, l1, l2, g = {p['m1']}, {p['m2']}, {p['l1']}, {p['l2']}, {p['g']}"),
                 "student.py", "exec"), namespace)
    assert any(line.startswith(f"[{code}]") for line in check("G_two_link", namespace["G"]).lines)


def test_sin_and_cos_exchanged_in_every_closed_form_are_named_in_tau_too(tmp_path):
    """τ = M Θ̈ + V + G assembled from closed forms that all exchange sin and cos: named in each term and in τ."""
    path = tmp_path / "student.py"
    path.write_text(CLOSED_FORMS.replace("np.sin", "np.SIN").replace("np.cos", "np.sin").replace("np.SIN", "np.cos"))
    assignment = Assignment(tmp_path / "a.toml", "two_link", load_robot("two_link"),
                            {"tau": 1.0, "M": 1.0, "V": 1.0, "G": 1.0}, samples=12, seed=2)
    [graded] = grade_class(assignment, [path])
    assert all("sin-cos-swapped" in d.tags for d in graded.diagnoses), [(d.term, d.findings) for d in graded.diagnoses]


def test_closed_form_slips_are_made_on_the_closed_form():
    """sin ↔ cos in the two-link arm's G (6.62) is g(m₁l₁s₁ + m₂(l₁s₁ + l₂s₁₂)), as written by hand."""
    q = np.array([[0.4, -1.3], [2.0, 0.7]])
    made = mistaken_terms(load_robot("two_link"), q, np.zeros_like(q), np.zeros_like(q))["G"]
    s1, s12 = np.sin(q[:, 0]), np.sin(q[:, 0] + q[:, 1])
    by_hand = 9.81 * np.stack([3.0 * 0.5 * s1 + 1.0 * 0.4 * s12, 1.0 * 0.4 * s12], axis=-1)
    assert np.allclose(made["sin-cos-swapped", ""], by_hand, rtol=1e-12)
