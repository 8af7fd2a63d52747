"""reference/validate.py: the agreement report and its sampling."""
from __future__ import annotations

import numpy as np
import pytest
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


def test_states_are_compared_a_block_at_a_time_with_the_same_figures(monkeypatch):
    """Ours are computed for a bounded block of states (not all N at once); the agreement figures are unchanged."""
    import course_dynamics_reference.validate as module

    whole = validate("ur5", samples=40, seed=3)
    sizes, batch = [], module.ours_batch
    monkeypatch.setattr(module, "BLOCK_BYTES", 7 * module.BYTES_PER_STATE_SQUARE * 36)   # 7 states of a 6-joint arm
    monkeypatch.setattr(module, "ours_batch",
                        lambda model, q, qd, qdd: sizes.append(len(q)) or batch(model, q, qd, qdd))
    blocked = validate("ur5", samples=40, seed=3)
    assert sizes == [7] * 5 + [5]
    assert blocked.as_dict() == whole.as_dict()


def test_the_samples_count_in_the_memory_check_and_the_refusal_names_them(capsys, monkeypatch):
    """--samples multiplies the states and their errors: a run the budget cannot hold is refused before it starts."""
    import course_dynamics_reference.validate as module
    from helpers import assert_one_line_error, run

    assert module.memory_estimate(60, 100_000) > module.memory_estimate(60, 200) + 2**25
    monkeypatch.setenv("COURSE_DYNAMICS_MEMORY_BUDGET", "330M")     # two_link on one state needs about 307 MiB
    monkeypatch.setattr(module, "validate", lambda *a, **k: pytest.fail("compared before checking"))
    code, _, err = run(capsys, "validate", "two_link", "--samples", "100000")
    assert_one_line_error(code, err, "robot 'two_link' has 2 joints", "on --samples 100000 states", "of memory",
                          "take fewer --samples (about")
