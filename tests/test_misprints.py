"""reference/misprints.py: every demonstrated misprint is wrong as printed and right as corrected, against its truth;
every step the notes leave to other notebooks agrees with its truth."""
from __future__ import annotations

import pytest
from course_dynamics_reference import TOLERANCE
from course_dynamics_reference.misprints import demonstrations, steps
from helpers import ROOT

DEMONSTRATIONS = demonstrations()
STEPS = steps()


@pytest.mark.parametrize("misprint", DEMONSTRATIONS, ids=lambda m: m.where)
def test_printed_is_wrong_and_corrected_is_right(misprint):
    assert misprint.corrected_error <= 1e-12, misprint
    assert misprint.printed_error >= 1e-2, misprint


def test_every_demonstration_is_in_the_errata():
    errata = (ROOT / "reference" / "errata.md").read_text()
    for misprint in DEMONSTRATIONS:
        assert misprint.where.split(",")[0].split("–")[0] in errata, misprint.where
    assert len(DEMONSTRATIONS) >= 17


@pytest.mark.parametrize("check", STEPS, ids=lambda c: c.where)
def test_step_agrees_with_its_truth(check):
    assert check.error <= TOLERANCE, check


def test_every_step_is_found_correct_in_the_errata():
    found_correct = (ROOT / "reference" / "errata.md").read_text().split("## Found correct")[1]
    for check in STEPS:
        assert check.where in found_correct, check.where
