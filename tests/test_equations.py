"""reference/equations.py: every equation label of the lecture notes is listed, with the kind of place it has in
the notes, and each is covered by a test and a notebook cell that exist.

The labels are read from the notes' own text (course_dynamics_reference.equations.labels_in), so that the list
cannot silently miss one. The notes are found through $COURSE_NOTES, else in the course's shared folder beside
the checkout (shared/notes/).
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from course_dynamics_reference.equations import EQUATIONS, KINDS, NOTES_FILE, PRINTED, UNLABELLED, kind_in, labels_in
from helpers import ROOT

NOTES_PLACES = [Path(os.environ["COURSE_NOTES"])] if os.environ.get("COURSE_NOTES") else []
NOTES_PLACES += [ROOT.parent / "shared" / "notes" / NOTES_FILE, Path("/work/shared/notes") / NOTES_FILE]


@pytest.fixture(scope="module")
def notes() -> str:
    for place in NOTES_PLACES:
        if place.is_file():
            return place.read_text(encoding="utf-8")
    pytest.fail(f"the lecture notes {NOTES_FILE} are not at {', '.join(map(str, NOTES_PLACES))}: "
                "set COURSE_NOTES to their path")


def number(label: str) -> tuple:
    """(6.15'') → (6, 15, 2): the order of the notes' numbering, primes after their equation."""
    major, minor = label.strip("()").rstrip("'").split(".")
    return int(major), int(minor), label.count("'")


def cells(notebook: str) -> list[str]:
    """The cells of a percent-format notebook, each as its source text."""
    return re.split(r"^# %%.*$", (ROOT / notebook).read_text(encoding="utf-8"), flags=re.MULTILINE)


def test_every_label_of_the_notes_is_listed_once(notes):
    listed = [e.label for e in EQUATIONS]
    assert len(listed) == len(set(listed)), "a label is listed twice"
    assert listed == sorted(listed, key=number), "the list is not in the notes' numbering order"
    in_notes = labels_in(notes)
    assert len(in_notes) >= 50
    assert [label for label in in_notes if label not in listed] == []
    assert [e.label for e in EQUATIONS if e.label not in in_notes and e.kind != UNLABELLED] == []


def test_every_label_has_the_kind_it_has_in_the_notes(notes):
    for equation in EQUATIONS:
        assert equation.kind in KINDS, equation
        assert kind_in(notes, equation.label) == equation.kind, equation.label
        if equation.kind != PRINTED:
            assert equation.reading, f"{equation.label} is {equation.kind} in the notes: say how it is read"


def test_every_named_test_exists():
    for equation in EQUATIONS:
        assert equation.tests, equation.label
        for node in equation.tests:
            path, _, name = node.partition("::")
            function, _, parameter = name.partition("[")
            assert path.startswith("tests/test_") and (ROOT / path).is_file(), node
            assert re.search(rf"^def {function}\(", (ROOT / path).read_text(encoding="utf-8"), re.MULTILINE), node
            if parameter:  # a parametrized case: its id is written in the test file or in the oracle it runs
                places = (ROOT / path, ROOT / "reference" / "misprints.py")
                assert any(parameter[:-1] in place.read_text(encoding="utf-8") for place in places), node


def test_every_named_cell_exists():
    for equation in EQUATIONS:
        if equation.notebook is None:
            assert equation.cell.startswith("none, because "), equation.label
            continue
        assert equation.notebook.startswith("notebooks/") and (ROOT / equation.notebook).is_file(), equation
        assert any(equation.cell in cell for cell in cells(equation.notebook)), (
            f"{equation.label}: no cell of {equation.notebook} contains {equation.cell!r}")


def test_every_label_is_covered():
    tested = [e for e in EQUATIONS if e.tests]
    shown = [e for e in EQUATIONS if e.notebook is not None]
    print(f"\nequation coverage: {len(tested)} of {len(EQUATIONS)} labels of the notes have a test, "
          f"{len(shown)} a notebook cell, {len(EQUATIONS) - len(shown)} none with a reason")
    assert len(tested) == len(EQUATIONS)
    assert len(shown) + sum(e.cell.startswith("none, because ") for e in EQUATIONS if e.notebook is None) == len(EQUATIONS)


def test_the_errata_point_to_the_coverage():
    errata = (ROOT / "reference" / "errata.md").read_text(encoding="utf-8")
    assert "reference/equations.py" in errata
