"""reference/validate.py: the agreement report and its sampling."""
from __future__ import annotations

import numpy as np
from course_dynamics_reference.validate import (
    TERMS,
    random_states,
    sampling_bounds,
    validate,
)

from course_dynamics import load_robot


def test_states_are_seeded_and_within_limits():
    arm = load_robot("panda")
    q1, _, _ = random_states(arm, 50, seed=4)
    q2, _, _ = random_states(arm, 50, seed=4)
    np.testing.assert_array_equal(q1, q2)
    assert np.all(q1 >= arm.lower) and np.all(q1 <= arm.upper)


def test_empty_limits_are_sampled_over_a_turn():
    """double_pendulum.urdf writes lower = upper = 0; sampling only q = 0 would test nothing."""
    lower, upper = sampling_bounds(load_robot("double_pendulum"))
    np.testing.assert_array_equal(lower, -np.pi)
    np.testing.assert_array_equal(upper, np.pi)


def test_report_covers_every_term():
    report = validate("rp_arm", samples=10, seed=1)
    assert report.ok and set(report.terms) == set(TERMS)
    assert all(t.max_rel <= 1e-9 for t in report.terms.values())
    assert report.as_dict()["ok"] is True
