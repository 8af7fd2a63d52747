"""course_dynamics/core/state.py: checking states, splitting them into per-joint entries and assembling results."""
from __future__ import annotations

import numpy as np
import pytest
import sympy

from course_dynamics import StateError, load_robot
from course_dynamics.core.state import as_state, entries, layout_of

ARM = load_robot("two_link")


def test_numbers_become_floats_and_keep_their_shape():
    assert as_state(ARM, [1, 2]).dtype == float
    assert as_state(ARM, np.zeros((5, 2))).shape == (5, 2)
    assert as_state(ARM, [1 + 0j, 2]).dtype.kind == "c"  # complex steps stay complex
    symbols = np.array(sympy.symbols("a b"), dtype=object)
    assert as_state(ARM, symbols).dtype == object


@pytest.mark.parametrize("values, message", [
    (0.5, "q has a scalar but robot 'two_link' has 2 joints"),
    ([0.1, 0.2, 0.3], "q has 3 values"),
    (np.zeros((4, 3)), "q has 3 values"),
    (["a", "b"], "q must be numbers"),
    ([0.0, np.nan], "q for joint 'theta2' is nan \\(must be finite\\)"),
    ([[0.0, 0.0], [0.0, np.nan]], "q for joint 'theta2' is nan at row 1"),
    ([[-np.inf, 0.0], [0.0, 0.0]], "q for joint 'theta1' is -inf at row 0"),
])
def test_bad_states_name_the_problem(values, message):
    with pytest.raises(StateError, match=message):
        as_state(ARM, values)


def test_entries_are_python_floats_or_columns():
    one = entries(np.array([0.25, 0.5]))
    assert one == [0.25, 0.5] and all(type(x) is float for x in one)
    batch = entries(np.arange(6.0).reshape(3, 2))
    np.testing.assert_array_equal(batch[1], [1.0, 3.0, 5.0])


def test_layout_broadcasts_and_assembles():
    layout = layout_of(np.zeros((4, 2)), np.zeros(2))
    assert layout.batch == (4,) and layout.dtype is float
    matrix = layout.assemble([[np.arange(4.0), 1.0], [2.0, 3.0]], (2, 2))
    assert matrix.shape == (4, 2, 2)
    np.testing.assert_array_equal(matrix[:, 0, 0], np.arange(4.0))
    np.testing.assert_array_equal(matrix[:, 1, 1], 3.0)
    assert layout_of(np.zeros(2), np.zeros(2, dtype=object)).dtype is object
    assert layout_of(np.zeros(2, dtype=complex)).dtype is complex
    assert layout_of(np.zeros(2)).assemble([1.0, 2.0], (2,)).tolist() == [1.0, 2.0]
