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
from submissions import CLOSED_FORMS, SPATIAL_SLIPS, closed_forms, spatial_newton_euler, worked_example

from course_dynamics import gravity_torques
from course_dynamics.core.newton_euler import newton_euler_links
from course_dynamics.core.operations import EXACT
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
    "gravity-frame-unrotated": ("gravity-frame", "in (6.49) (⁰g used in frame i as it is"),
    "gravity-frame-rotated": ("gravity-frame", "in (6.49) (⁰g rotated by ⁰ᵢR, not by its transpose"),
    "com-wrong-link": ("com-wrong-link", "in every equation where it appears, (6.48) and (6.52)"),
    "tau-from-N": ("tau-wrong-moment", "in (6.53) (τᵢ read from ⁱNᵢ, the inertial moment"),
    "tau-from-child": ("tau-wrong-moment", "in (6.53) (τᵢ read from the child's ⁱ⁺¹nᵢ₊₁"),
    "notes-6.48": ("notes-6.48", "in (6.48) (with the parent's ⁱω̇ᵢ for ⁱ⁺¹ω̇ᵢ₊₁)"),
    "notes-worked-F1": ("notes-6.48", "in (6.48) (with ⁱ⁺¹Pᵢ₊₁ = 0 for ⁱ⁺¹P_Cᵢ₊₁)"),
    "notes-6.50": ("notes-6.50", "in (6.50)"),
    "notes-6.51": ("notes-6.51", "in (6.51)"),
    "notes-6.52": ("notes-6.52", "in (6.52) (all three misprints"),
    "notes-6.52-N": ("notes-6.52", "in (6.52) (one of its misprints: the child's ⁱ⁺¹Nᵢ₊₁ for ⁱNᵢ)"),
    "notes-6.52-PxF": ("notes-6.52", "in (6.52) (one of its misprints: ⁱPᵢ × ⁱFᵢ with Pᵢ the joint's offset"),
    "notes-6.52-identity": ("notes-6.52", "in (6.52) (one of its misprints: ⁱ⁺¹R^{i+1} = 1"),
    "first-moment-missing": ("first-moment-missing", "in (6.52)"),
}
# On the two-link arm ⁰g lies along every joint axis: gravity added unrotated is gravity left out, the simpler
# mistake, which is named; and its rotations are about parallel axes, so (6.52)'s unrotated force is any rotation of
# (6.52) left out, named as that (whose advice names the notes' misprint).
ON_TWO_LINK = {"gravity-frame-unrotated": ("gravity-missing", "in the base acceleration ⁰v̇₀"),
               "notes-6.52-identity": ("rotation-identity", "(6.52)")}
# On the two-link arm (point masses, ᶜI = 0; parallel joint axes) these change nothing (tested below); and τ read
# from ⁱNᵢ = 0 is zero everywhere, what a function not written yet returns (tests/test_score.py).
HARMLESS_ON_TWO_LINK = ("cross-reversed", "gyroscopic-missing", "notes-6.50", "notes-6.51", "notes-6.52-N")
TWO_LINK_SLIPS = [slip for slip in EXPECTED if slip not in HARMLESS_ON_TWO_LINK + ("tau-from-N",)]


@pytest.fixture(scope="module")
def graded_slips(tmp_path_factory):
    """Every slip of SPATIAL_SLIPS handed in as a student's file and graded in the sandbox on the spatial arm."""
    folder = tmp_path_factory.mktemp("slips")
    paths = []
    for slip in ["", "gravity-per-link"] + list(SPATIAL_SLIPS):
        path = folder / f"{slip or 'right'}.py"
        path.write_text(spatial_newton_euler(SPATIAL, slip))
        paths.append(path)
    assignment = Assignment(folder / "a.toml", "spatial_arm", SPATIAL, {"tau": 1.0}, samples=12, seed=4)
    return {g.path.stem: g for g in grade_class(assignment, paths)}


def test_the_right_recursion_gets_full_marks(graded_slips):
    assert graded_slips["right"].total == 1.0
    assert graded_slips["gravity-per-link"].total == 1.0  # gravity link by link, rotated by ⁰ᵢRᵀ: right too


@pytest.fixture(scope="module")
def graded_two_link_slips(tmp_path_factory):
    """The same slips, written into the same student's recursion with the two-link arm's numbers, graded on it."""
    folder = tmp_path_factory.mktemp("two_link_slips")
    arm = load_robot("two_link")
    paths = []
    for slip in ["", *TWO_LINK_SLIPS, *HARMLESS_ON_TWO_LINK]:
        path = folder / f"{slip or 'right'}.py"
        path.write_text(spatial_newton_euler(arm, slip))
        paths.append(path)
    assignment = Assignment(folder / "a.toml", "two_link", arm, {"tau": 1.0}, samples=12, seed=4)
    return {g.path.stem: g for g in grade_class(assignment, paths)}


@pytest.mark.parametrize("slip", TWO_LINK_SLIPS)
def test_grade_names_each_slip_on_the_two_link_arm(graded_two_link_slips, slip):
    code, where = ON_TWO_LINK.get(slip, EXPECTED[slip])
    [diagnosis] = graded_two_link_slips[slip].diagnoses
    assert diagnosis.points < 1 and code in diagnosis.tags, diagnosis.findings  # a state at rest may agree
    [finding] = [f for f in diagnosis.findings if f.startswith(f"[{code}]")]
    assert where in finding


def test_slips_that_change_nothing_on_the_two_link_arm_get_full_marks(graded_two_link_slips):
    """ᶜI = 0 for the two-link arm's point masses, and its joint axes are parallel: the stray inertia of (6.51), the
    tensor about the origin in ω × I ω (ω along Z, a principal axis of ⁱIᵢ), the gyroscopic term and the order of
    ⁱ⁺¹ᵢR ⁱωᵢ × θ̇ᵢ₊₁Ẑ (parallel vectors) leave τ right; on the spatial arm each is named."""
    assert graded_two_link_slips["right"].total == 1.0
    for slip in HARMLESS_ON_TWO_LINK:
        assert graded_two_link_slips[slip].total == 1.0


@pytest.mark.parametrize("slip", TWO_LINK_SLIPS)
def test_the_notebook_check_names_each_slip_on_the_two_link_arm(slip):
    namespace = {}
    exec(compile(spatial_newton_euler(my_robot("two_link").model, slip), "student.py", "exec"), namespace)
    verdict = check("tau_two_link", namespace["tau"])
    code, where = ON_TWO_LINK.get(slip, EXPECTED[slip])
    assert verdict.status == "wrong" and any(line.startswith(f"[{code}]") and where in line for line in verdict.lines)


@pytest.mark.parametrize("variant", ["6.51", "6.52"])
def test_the_notes_slips_are_the_errata_s_printed_equations(variant):
    """The slip ``notes-6.51`` / ``notes-6.52`` of the one recursion is the printed equation that reference/misprints.py
    evaluates for the errata, by its own serial inward iteration (a second path, tied here)."""
    from reference.misprints import serial_inward

    from course_dynamics.core.kinematics import joint_transforms
    from course_dynamics.core.state import entries

    ur5 = load_robot("ur5")
    q, qd, qdd = np.array([0.3, -1.1, 0.8, 0.4, -0.6, 1.2]), np.full(6, 0.7), np.linspace(-1, 1, 6)
    printed = serial_inward(ur5, newton_euler_links(ur5, q, qd, qdd), joint_transforms(ur5, entries(q)), variant)
    slipped = newton_euler_links(ur5, q, qd, qdd, Slip(f"notes-{variant}", (variant,))).tau
    assert np.allclose(slipped, printed, rtol=1e-12, atol=1e-12)
    assert relative_error(slipped, newton_euler_links(ur5, q, qd, qdd).tau) > 1e-3


def test_the_notes_6_65_is_named_in_V_and_in_tau(tmp_path):
    """V written by (6.63) as B[Θ̇Θ̇] + C[Θ̇²] with the notes' printed [Θ̇²] = [θ̇₁² θ̇₁²]."""
    path = tmp_path / "student.py"
    path.write_text(closed_forms(
        "\ndef V(q, qd):\n    h = m2 * l1 * l2 * np.sin(q[1])\n    B = np.array([[-2 * h], [0.0]])\n"
        "    C = np.array([[0.0, -h], [h, 0.0]])\n    squares = np.array([qd[0] ** 2, qd[0] ** 2])  # (6.65)\n"
        "    return B @ np.array([qd[0] * qd[1]]) + C @ squares\n"))
    assignment = Assignment(tmp_path / "a.toml", "two_link", load_robot("two_link"), {"V": 1.0, "tau": 1.0},
                            samples=12, seed=2)
    [graded] = grade_class(assignment, [path])
    for diagnosis in graded.diagnoses:
        assert "notes-6.65" in diagnosis.tags, (diagnosis.term, diagnosis.findings)
    p = my_robot("two_link").parameters
    namespace = {}
    exec(compile(path.read_text().replace("m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 9.81",
                                          f"m1, m2, l1, l2, g = {p['m1']}, {p['m2']}, {p['l1']}, {p['l2']}, {p['g']}"),
                 "student.py", "exec"), namespace)
    assert any(line.startswith("[notes-6.65]") for line in check("V_two_link", namespace["V"]).lines)


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
    # M and V right: τ's error is G's, not "that mistake and another" (c₁ ↔ c₁₂ is in G alone: τ is that slip's)
    [tau] = [d for d in graded.diagnoses if d.term == "tau"]
    said = {"sin-cos-swapped": "τ's error is all in the gravity part G", "c1-c12-swapped": "matches"}[code]
    assert tau.findings[0].startswith(f"[{code}] {said}"), tau.findings
    assert not any("another?" in f for f in tau.findings)
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


WORKED_EXAMPLE = {  # the worked example's misprints copied into the two-link recursion: τ's finding starts so
    "example-F1-m1-v1": "[notes-6.48] matches the right answer computed with this slip: (6.48) as the lecture notes "
                        "misprint it in (6.48) (with ⁱ⁺¹Pᵢ₊₁ = 0 for ⁱ⁺¹P_Cᵢ₊₁) on link 1 only",
    "example-v2-identity": "[rotation-identity] matches the right answer computed with this slip: a rotation left out "
                           "(read as the identity) in (6.47) on link 2 only",
    "no-gravity": "[gravity-missing] matches the right answer computed with this slip: gravity left out",
}


@pytest.fixture(scope="module")
def graded_worked_example(tmp_path_factory):
    folder = tmp_path_factory.mktemp("worked_example")
    paths = []
    for slip in [*WORKED_EXAMPLE, "example-gs1-twice", "G-round-off"]:
        path = folder / f"{slip}.py"
        path.write_text(worked_example(slip))
        paths.append(path)
    assignment = Assignment(folder / "a.toml", "two_link", load_robot("two_link"),
                            {"tau": 1.0, "M": 1.0, "V": 1.0, "G": 1.0}, samples=12, seed=7)
    return {g.path.stem: {d.term: d for d in g.diagnoses} for g in grade_class(assignment, paths)}


@pytest.mark.parametrize("slip", list(WORKED_EXAMPLE))
def test_a_misprint_of_the_worked_example_copied_into_one_link_is_named(graded_worked_example, slip):
    """A printed equation copied into one link's equations only is named, on that link; gravity left out is named
    as that, not as gravity added in the wrong frame (the same answer on this arm, where ⁰g lies along the axes)."""
    tau = graded_worked_example[slip]["tau"]
    assert tau.findings[0].startswith(WORKED_EXAMPLE[slip]), tau.findings
    assert not any("gravity-frame" in f or "your dynamics are right" in f
                   for d in graded_worked_example[slip].values() for f in d.findings)


@pytest.mark.parametrize("slip", list(WORKED_EXAMPLE))
def test_the_notebook_check_names_the_worked_example_s_misprints(slip):
    p = my_robot("two_link").parameters
    namespace = {}
    exec(compile(worked_example(slip).replace(
        "m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, ", f"m1, m2, l1, l2, g = {p['m1']}, {p['m2']}, {p['l1']}, {p['l2']}, "),
        "student.py", "exec"), namespace)
    lines = check("tau_two_link", namespace["tau"]).lines
    code = WORKED_EXAMPLE[slip].split("]")[0] + "]"
    assert any(line.startswith(code) for line in lines), lines


def test_the_worked_example_s_g_s1_is_no_question_of_typed_numbers(graded_worked_example):
    """¹v̇_C₁ with g s₁ in its y component is a robot whose link 1 has its centre of mass off the link's line: said
    as a component in the wrong place, never "check the masses you typed"."""
    for term in ("tau", "G"):
        [line] = [f for f in graded_worked_example["example-gs1-twice"][term].findings if "other numbers" in f]
        assert "mcy_1 = -1 where your handout's numbers give 0" in line
        assert "a component of a vector written in the wrong place" in line and "Check the masses" not in line


def test_a_function_returning_round_off_returns_zeros(graded_worked_example):
    """G returning 1e-13 everywhere is zeros, not "closest to" a mistake whose G is zero."""
    G = graded_worked_example["G-round-off"]["G"]
    assert G.findings == ("returns zeros everywhere: not written yet?",), G.findings


def test_mistakes_are_made_per_coordinate_on_a_robot_with_a_mimic_joint():
    """Panda's nine bodies have eight coordinates (the second finger mimics the first): degrees scale Θ's revolute
    entries, never the prismatic finger's."""
    panda = load_robot("panda")
    rng = np.random.default_rng(3)
    q, qd, qdd = (rng.uniform(-1, 1, (4, panda.n)) * 0.02 for _ in range(3))
    made = mistaken_terms(panda, q, qd, qdd)
    degrees = made["G"]["degrees", "(positions read as degrees)"]
    scaled = q.copy()
    scaled[:, :7] *= np.pi / 180
    assert degrees.shape == (4, panda.n)
    np.testing.assert_allclose(degrees, gravity_torques(panda, scaled), rtol=1e-12, atol=1e-12)
