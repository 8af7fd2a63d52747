"""reference/misprints.py: every demonstrated misprint is wrong as printed and right as corrected, against its truth."""
from __future__ import annotations

import pytest
from course_dynamics_reference.misprints import demonstrations
from helpers import ROOT

DEMONSTRATIONS = demonstrations()


@pytest.mark.parametrize("misprint", DEMONSTRATIONS, ids=lambda m: m.where)
def test_printed_is_wrong_and_corrected_is_right(misprint):
    assert misprint.corrected_error <= 1e-12, misprint
    assert misprint.printed_error >= 1e-2, misprint


def test_every_demonstration_is_in_the_errata():
    errata = (ROOT / "reference" / "errata.md").read_text()
    for misprint in DEMONSTRATIONS:
        assert misprint.where.split(",")[0].split("–")[0] in errata, misprint.where
    assert len(DEMONSTRATIONS) >= 10
