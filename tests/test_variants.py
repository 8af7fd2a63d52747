"""course_dynamics/tools/variants.py: each student their own robot, the same every time, written out as a URDF that
our loader and Pinocchio read as the same robot; rosters and ids checked; the grader and the notebooks agree."""
from __future__ import annotations

import json

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import assert_agrees

from course_dynamics import inverse_dynamics, load_urdf, mass_matrix
from course_dynamics.base.errors import InputError
from course_dynamics.cli import main
from course_dynamics.core.parameters import parameter_values
from course_dynamics.core.robots import COURSE_ROBOTS, load_robot
from course_dynamics.core.sampling import random_states
from course_dynamics.grading.assignment import load_assignment
from course_dynamics.grading.grade import grade_class
from course_dynamics.output.urdf_writer import model_urdf
from course_dynamics.teaching.exercises import check, my_robot, use_student
from course_dynamics.tools.variants import check_student_id, read_roster, robot_variant


@pytest.mark.parametrize("robot", list(COURSE_ROBOTS))
def test_a_variant_is_reproducible_differs_per_student_and_stays_physical(robot):
    ada, again, grace = robot_variant(robot, "ada"), robot_variant(robot, "ada"), robot_variant(robot, "grace")
    assert ada.parameters == again.parameters and ada.parameters != grace.parameters
    original = load_robot(robot)
    assert ada.parameters != robot_variant(robot, "course").parameters
    assert robot_variant(robot, "course").parameters != parameter_values(original)  # never the worked examples' robot
    for mine, theirs in zip(ada.model.bodies, original.bodies, strict=True):
        assert 0.6 * float(theirs.mass) - 0.01 <= float(mine.mass) <= 1.6 * float(theirs.mass) + 0.01
        assert np.array_equal(mine.axis, theirs.axis) and np.array_equal(mine.R0, theirs.R0)
        assert np.all(np.linalg.eigvalsh(mine.I_com) >= -1e-15)


@pytest.mark.parametrize("robot", list(COURSE_ROBOTS))
def test_the_written_urdf_is_the_same_robot_for_us_and_for_pinocchio(robot, tmp_path):
    variant = robot_variant(robot, "ada.lovelace")
    path = tmp_path / f"{robot}.urdf"
    path.write_bytes(model_urdf(variant.model, "a student's robot"))
    loaded = load_urdf(path)
    q, qd, qdd = random_states(variant.model, 6, np.random.default_rng(3))
    ours = inverse_dynamics(variant.model, q, qd, qdd)
    assert_agrees(inverse_dynamics(loaded, q, qd, qdd), ours, what="reloaded τ")
    oracle = PinocchioOracle(path, loaded.joint_names, loaded.gravity)
    for k in range(6):
        assert_agrees(ours[k], oracle.tau(q[k], qd[k], qdd[k]), what=f"τ against Pinocchio, state {k}")
        assert_agrees(mass_matrix(variant.model, q[k]), oracle.M(q[k]), what=f"M against Pinocchio, state {k}")
    assert {f.name: f.P.tolist() for f in loaded.frames} == {f.name: f.P.tolist() for f in variant.model.frames}


@pytest.mark.parametrize("bad", ["", "a/b", "..", "-x", "x y", "ü", "a" * 65, "name."])
def test_unsafe_ids_are_refused(bad):
    with pytest.raises(InputError, match="student id"):
        check_student_id(bad)


def test_rosters_are_read_and_checked(tmp_path):
    roster = tmp_path / "roster.csv"
    roster.write_text("\ufeffName,ID\nAda,ada\n\nGrace,grace.h\n", encoding="utf-8")
    assert read_roster(roster) == ["ada", "grace.h"]
    for text, message in (("name\nada\n", "names an 'id' column"), ("id\nada\nada\n", "row 3: student id 'ada' repeats"),
                          ("id\n../x\n", "row 2: student id '../x'"), ("id\n", "lists no students")):
        roster.write_text(text)
        with pytest.raises(InputError, match=message.replace("(", r"\(").replace(".", r"\.")):
            read_roster(roster)


def test_student_notebooks_for_a_student_and_a_roster(tmp_path, capsys):
    assert main(["student-notebooks", str(tmp_path / "one"), "--student", "ada", "--only", "03"]) == 0
    cells = json.loads((tmp_path / "one" / "03_newton_euler.ipynb").read_text())["cells"]
    assert "use_student('ada')" in "".join(next(c for c in cells if c["cell_type"] == "code")["source"])
    (tmp_path / "roster.csv").write_text("id\nada\ngrace\n")
    assert main(["student-notebooks", str(tmp_path / "class"), "--roster", str(tmp_path / "roster.csv"),
                 "--only", "04"]) == 0
    assert sorted(p.parent.name for p in (tmp_path / "class").glob("*/04_*.ipynb")) == ["ada", "grace"]
    assert main(["student-notebooks", str(tmp_path / "bad"), "--student", "../etc"]) == 2
    assert "error: student id '../etc'" in capsys.readouterr().err and not (tmp_path / "bad").exists()


def closed_forms_for(student: str) -> str:
    """The two-link closed forms (6.60)-(6.62) as a student writes them with their own numbers."""
    p = robot_variant("two_link", student).parameters
    return f'''
import numpy as np

m1, m2, l1, l2, g = {p["m1"]!r}, {p["m2"]!r}, {p["l1"]!r}, {p["l2"]!r}, {p["g"]!r}


def G(q):
    c1, c12 = np.cos(q[0]), np.cos(q[0] + q[1])
    return np.array([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])
'''


def test_grade_per_student_grades_each_on_their_own_robot_and_hands_it_out(tmp_path, capsys):
    (tmp_path / "a.toml").write_text('robot = "two_link"\nvariant = "per-student"\nsamples = 8\n[points]\nG = 1\n')
    assignment = load_assignment(tmp_path / "a.toml")
    for student, numbers_of in (("ada", "ada"), ("grace", "grace"), ("alan", "ada")):  # alan copied Ada's
        (tmp_path / f"{student}.py").write_text(closed_forms_for(numbers_of))
    grades = {g.student: g.total for g in grade_class(assignment, [tmp_path / f"{s}.py" for s in ("ada", "grace", "alan")])}
    assert grades == {"ada": 1.0, "grace": 1.0, "alan": 0.0}
    use_student("grace")  # the notebook's check agrees: Grace's own numbers pass, Ada's do not
    namespace_ada, namespace_grace = {}, {}
    exec(closed_forms_for("ada"), namespace_ada)
    exec(closed_forms_for("grace"), namespace_grace)
    assert check("G_two_link", namespace_grace["G"]) and not check("G_two_link", namespace_ada["G"])
    assert my_robot("two_link").parameters == robot_variant("two_link", "grace").parameters
    use_student("course")
    assert main(["grade", str(tmp_path / "a.toml"), "--handout", "ada", "--out", str(tmp_path / "handout")]) == 0
    printed = capsys.readouterr().out
    assert f"m1 = {robot_variant('two_link', 'ada').parameters['m1']:g}" in printed
    handed = load_urdf(tmp_path / "handout" / "two_link_ada.urdf")
    q = np.array([0.3, 1.2])
    assert_agrees(inverse_dynamics(handed, q, q, q), inverse_dynamics(assignment.for_student("ada").robot, q, q, q))
    (tmp_path / "bad.toml").write_text('robot = "ur5"\nvariant = "per-student"\n[points]\nG = 1\n')
    assert main(["grade", str(tmp_path / "bad.toml"), "--handout", "ada"]) == 2
    assert "needs a course robot" in capsys.readouterr().err
