"""course_dynamics/teaching/course.py and the notebooks: every notebook and every student version runs top to bottom.

The solution versions must answer every exercise right; the student versions must run without an error, report
every exercise as not done yet, and keep no line of any solution. Both run in a fresh Jupyter kernel (nbclient),
from a folder outside the repository, each within the course's per-cell time limit.
"""
from __future__ import annotations

import json
import time

import pytest

from course_dynamics.cli import main
from course_dynamics.output.folders import MANIFEST
from course_dynamics.teaching.course import (
    BEGIN,
    END,
    SOLUTIONS_ONLY,
    execute,
    first_heading,
    notebook_paths,
    read_notebook,
    solution_regions,
    solution_version,
    student_version,
)

NOTEBOOKS = notebook_paths()
NOTEBOOK_SECONDS = 120  # the course's budget per notebook; a cell has CELL_TIMEOUT on top


def outputs_of(cell) -> str:
    return "".join(o.get("text", "") + o.get("data", {}).get("text/plain", "") for o in cell.outputs)


def test_one_notebook_per_section_in_reading_order():
    assert [p.name[:2] for p in NOTEBOOKS] == [f"{k:02d}" for k in range(1, 11)]
    for path in NOTEBOOKS:
        notebook = read_notebook(path)
        first = notebook.cells[0]
        assert first.cell_type == "markdown" and "What this notebook teaches" in first.source, path.name
        assert first_heading(notebook).startswith(f"{int(path.name[:2])}. ")


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_exercise_has_a_check_after_it(path):
    cells = read_notebook(path).cells
    exercises = [k for k, c in enumerate(cells) if c.cell_type == "code" and solution_regions(c.source)]
    assert len(exercises) >= 2, path.name
    for k in exercises:
        assert "check(" in cells[k + 1].source, (path.name, cells[k].source[:80])


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_solution_version_runs_and_answers_every_exercise(path, tmp_path):
    start = time.monotonic()
    notebook = execute(solution_version(read_notebook(path), path.stem), tmp_path)
    assert time.monotonic() - start < NOTEBOOK_SECONDS
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    checks = [outputs_of(c) for c in notebook.cells if c.cell_type == "code" and c.source.startswith("check(")]
    assert checks and all("✓ right" in text for text in checks), checks
    assert any("image/png" in o.get("data", {}) or "iframe srcdoc" in o.get("data", {}).get("text/html", "")
               for o in outputs), "no figure or animation"


SECOND_STUDENT = ("03", "05")  # the notebooks whose exercises use the most robots: run again for another student


@pytest.mark.parametrize("path", [p for p in NOTEBOOKS if p.name[:2] in SECOND_STUDENT], ids=lambda p: p.stem)
def test_a_second_students_solutions_pass_on_their_own_robot(path, tmp_path):
    """The solutions read the student's numbers: for a named student (the cell student-notebooks adds first) every
    check is right on that student's robot, and the robot is theirs, not the default one."""
    notebook = execute(solution_version(read_notebook(path), path.stem, student="grace.h"), tmp_path)
    code = [c for c in notebook.cells if c.cell_type == "code"]
    assert "use_student('grace.h')" in code[0].source
    assert not [o for c in code for o in c.outputs if o.output_type == "error"]
    checks = [outputs_of(c) for c in code if c.source.startswith("check(")]
    assert checks and all("✓ right" in text for text in checks), checks


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_student_version_runs_clean_with_no_solution_left(path, tmp_path):
    source = read_notebook(path)
    student = student_version(source, path.stem)
    text = "\n".join(c.source for c in student.cells)
    assert BEGIN not in text and END not in text
    assert SOLUTIONS_ONLY not in text  # the library's closed forms of what the student derives stay out
    for cell in source.cells:
        lines = cell.source.splitlines()
        for first, last in solution_regions(cell.source):
            for line in lines[first + 1:last]:
                if len(line.strip()) > 12 and not line.strip().startswith("#"):
                    assert line.strip() not in text, (path.name, line)
    assert all(not c.get("outputs") for c in student.cells if c.cell_type == "code")
    executed = execute(student, tmp_path)
    outputs = [o for cell in executed.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    checks = [outputs_of(c) for c in executed.cells if c.cell_type == "code" and c.source.startswith("check(")]
    assert checks and all("not done yet" in text for text in checks), checks


def test_the_closed_forms_that_answer_exercises_are_shown_with_the_solutions_only():
    for stem in ("04_structure", "05_lagrange", "06_cartesian"):
        source = read_notebook(next(p for p in NOTEBOOKS if p.stem == stem))
        marked = [c for c in source.cells if SOLUTIONS_ONLY in c.source]
        assert marked, stem
        assert len(solution_version(source, stem).cells) == len(source.cells)
        assert len(student_version(source, stem).cells) == len(source.cells) - len(marked)


@pytest.mark.parametrize("version", [student_version, solution_version])
def test_nbgrader_metadata_marks_solutions_and_checks_with_no_points(version):
    """Check cells run in the student's kernel, where they can be made to pass: read-only, no grade, no points."""
    for path in NOTEBOOKS:
        notebook = version(read_notebook(path), path.stem)
        marked = [c.metadata["nbgrader"] for c in notebook.cells if "nbgrader" in c.metadata]
        solutions = [m for m in marked if m["solution"]]
        checks = [c.metadata["nbgrader"] for c in notebook.cells
                  if c.cell_type == "code" and c.source.startswith("check(") and "nbgrader" in c.metadata]
        assert len(solutions) >= 2 and len(checks) == len(solutions), path.name
        assert all(m["locked"] and not m["grade"] and "points" not in m for m in checks), path.name
        assert not [m for m in marked if m["grade"] or "points" in m], path.name
        assert len({m["grade_id"] for m in marked}) == len(marked), path.name


def test_student_notebooks_command_writes_the_course(tmp_path, capsys):
    assert main(["student-notebooks", str(tmp_path / "course")]) == 0
    written = sorted((tmp_path / "course").glob("*.ipynb"))
    assert [p.stem for p in written] == [p.stem for p in NOTEBOOKS]
    document = json.loads(written[0].read_text())
    assert document["nbformat"] == 4 and all(not c.get("outputs") for c in document["cells"] if c["cell_type"] == "code")
    assert "YOUR CODE HERE" in written[0].read_text()
    assert main(["student-notebooks", str(tmp_path / "key"), "--solutions"]) == 0
    assert BEGIN in (tmp_path / "key" / written[0].name).read_text()


def test_publish_renders_pages_with_an_index(tmp_path):
    assert main(["publish-notebooks", str(tmp_path / "site"), "--only", "01", "--solutions", "--quiet"]) == 0
    assert sorted(p.name for p in (tmp_path / "site").iterdir()) == [MANIFEST, "01_acceleration.html", "index.html"]
    listed = json.loads((tmp_path / "site" / MANIFEST).read_text())["files"]
    assert {name: entry["command"] for name, entry in listed.items()} == {"01_acceleration.html": "publish-notebooks",
                                                                           "index.html": "publish-notebooks"}
    page = (tmp_path / "site" / "01_acceleration.html").read_text()
    assert "Acceleration of a rigid body" in page and "data:image/png;base64" in page and "✅" in page
    index = (tmp_path / "site" / "index.html").read_text()
    assert 'href="01_acceleration.html"' in index


def test_publish_rejects_an_unknown_notebook(tmp_path, capsys):
    assert main(["publish-notebooks", str(tmp_path / "site"), "--only", "42"]) == 2
    assert "no notebook numbered 42" in capsys.readouterr().err
    assert not (tmp_path / "site").exists()


def test_publish_refuses_a_page_it_did_not_write_before_running_anything(tmp_path, capsys):
    site = tmp_path / "site"
    site.mkdir()
    (site / "index.html").write_text("the course's own front page")
    start = time.monotonic()
    assert main(["publish-notebooks", str(site), "--only", "01", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"error: {site / 'index.html'}: exists and was not written by course-dynamics" in err
    assert time.monotonic() - start < 10  # refused before a notebook ran
    assert sorted(p.name for p in site.iterdir()) == ["index.html"]
    assert (site / "index.html").read_text() == "the course's own front page"


def answered(path):
    """A notebook as a student leaves it: an answer typed into the first exercise."""
    document = json.loads(path.read_text())
    cell = next(c for c in document["cells"] if c["cell_type"] == "code" and "YOUR CODE HERE" in "".join(c["source"]))
    cell["source"] = "answer = 42  # my work\n"
    path.write_text(json.dumps(document))
    return path.read_text()


def test_student_notebooks_never_replace_a_students_work(tmp_path, capsys):
    course = tmp_path / "course"
    assert main(["student-notebooks", str(course)]) == 0
    first, second = sorted(course.glob("*.ipynb"))[:2]
    work = answered(first)
    second.unlink()
    capsys.readouterr()
    assert main(["student-notebooks", str(course)]) == 0  # again: adds what is missing, keeps the rest
    err = capsys.readouterr().err
    assert first.read_text() == work and second.exists()
    assert f"note: {first} exists, kept (student-notebooks --force replaces it, keeping a backup)" in err
    assert f"wrote 1 notebooks (student versions) to {course}, kept {len(NOTEBOOKS) - 1} already there" in err
    assert main(["student-notebooks", str(course), "--solutions"]) == 0
    assert first.read_text() == work and sorted(p.name for p in course.iterdir()) == sorted(
        f"{p.stem}.ipynb" for p in NOTEBOOKS)


def test_student_notebooks_force_keeps_a_backup_of_each_notebook_replaced(tmp_path, capsys, monkeypatch):
    import course_dynamics.output.io

    monkeypatch.setattr(course_dynamics.output.io.time, "strftime", lambda _: "20250102-030405")
    course = tmp_path / "course"
    assert main(["student-notebooks", str(course)]) == 0
    first = sorted(course.glob("*.ipynb"))[0]
    work = answered(first)
    taken = first.with_name(first.name + ".bak-20250102-030405")
    taken.write_text("a backup already there")
    capsys.readouterr()
    assert main(["student-notebooks", str(course), "--solutions", "--force"]) == 0
    err = capsys.readouterr().err
    backup = first.with_name(first.name + ".bak-20250102-030405-2")
    assert backup.read_text() == work and taken.read_text() == "a backup already there"
    assert BEGIN in first.read_text() and f"note: kept the notebook it replaces as {backup}" in err
    assert f"wrote {len(NOTEBOOKS)} notebooks (with solutions)" in err


def test_student_notebooks_never_write_through_a_link_or_into_a_folder(tmp_path, capsys):
    course, victim = tmp_path / "course", tmp_path / "victim.ipynb"
    course.mkdir()
    victim.write_text("precious")
    link = course / f"{NOTEBOOKS[0].stem}.ipynb"
    link.symlink_to(victim)
    (course / f"{NOTEBOOKS[1].stem}.ipynb").mkdir()
    assert main(["student-notebooks", str(course), "--force"]) == 0
    err = capsys.readouterr().err
    assert victim.read_text() == "precious" and link.is_symlink() and (course / f"{NOTEBOOKS[1].stem}.ipynb").is_dir()
    assert f"note: {link} is a symbolic link, left alone (nothing is written through it, even with --force)" in err
    assert "is not a regular file, left alone" in err and not list(course.glob("*.bak-*"))


def test_without_the_installed_package_data_the_checkouts_notebooks_are_found(monkeypatch):
    from course_dynamics.teaching import course

    def not_installed(name):
        raise ModuleNotFoundError(name)

    monkeypatch.setattr(course.resources, "files", not_installed)
    assert len(list(course.notebooks_folder().glob("[0-9][0-9]_*.py"))) == 10


def test_publishing_without_the_notebook_extra_says_what_to_install(tmp_path, monkeypatch, capsys):
    """The base install leaves out the execution stack: publish-notebooks says, in one line, what to install."""
    import sys

    monkeypatch.setitem(sys.modules, "nbclient", None)  # as if not installed
    monkeypatch.setitem(sys.modules, "ipykernel", None)
    assert main(["publish-notebooks", str(tmp_path / "site"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: running the notebooks needs nbclient, ipykernel") and err.count("\n") == 1
    assert "pip install 'course-dynamics[notebooks]'" in err and not (tmp_path / "site").exists()
