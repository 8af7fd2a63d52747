"""The column plan: one decision, from names alone, of where t, Θ, Θ̇, Θ̈ come from."""
from __future__ import annotations

import numpy as np
import pytest

from course_dynamics import load_robot
from course_dynamics.base.errors import InputError
from course_dynamics.tools.columns import Derived, plan_columns
from course_dynamics.tools.logs import joint_log

TWO = load_robot("two_link")


def test_names_are_read_as_they_are_or_through_the_map():
    plan = plan_columns(TWO, ["time", "q_theta1", "pos2", "qd_theta1", "mode"], columns={"t": "time", "q_theta2": "pos2"})
    assert dict(plan.read) == {"t": "time", "q_theta1": "q_theta1", "q_theta2": "pos2", "qd_theta1": "qd_theta1"}
    assert plan.ignored == ("mode",) and plan.has_time and plan.missing_positions == ()
    assert plan.used_as["pos2"] == "q_theta2"


def test_each_missing_rate_says_what_it_is_differentiated_from():
    plan = plan_columns(TWO, ["t", "q_theta1", "q_theta2", "qd_theta1"])
    assert plan.derived == (Derived("qd_theta2", "theta2", 1, "q"), Derived("qdd_theta1", "theta1", 2, "qd"),
                            Derived("qdd_theta2", "theta2", 2, "q"))
    assert plan.derived_kind("qdd", "qd") == ["theta1"] and plan.derived_kind("qdd", "q") == ["theta2"]


def test_a_constant_position_holds_its_joint_still():
    plan = plan_columns(TWO, ["t", "q_theta1"], constants={"q_theta2": 0.3})
    assert plan.held == ("qd_theta2", "qdd_theta2") and plan.missing_positions == ()
    assert [d.name for d in plan.derived] == ["qd_theta1", "qdd_theta1"]


def test_missing_positions_are_named_but_only_the_reader_refuses_them():
    plan = plan_columns(TWO, ["t", "q_theta1"])
    assert plan.missing_positions == ("q_theta2",) and not plan_columns(TWO, ["q_theta1"]).has_time
    with pytest.raises(InputError, match=r"^log\.csv: missing columns: q_theta2 \("):
        plan.require_positions("log.csv")


@pytest.mark.parametrize("columns, constants, message", [
    ({"q_elbow": "x"}, {}, "column map: 'q_elbow' is none of our columns"),
    ({"q_theta1": "nope"}, {}, "the table: no column 'nope' \\(mapped from q_theta1\\); columns: t, a, b"),
    ({"q_theta1": "a", "q_theta2": "a"}, {}, "q_theta1 and q_theta2 are both mapped to the log's column 'a'"),
    ({}, {"q_theta1": float("nan")}, "the constant value of q_theta1 must be finite"),
    ({"q_theta1": "a"}, {"q_theta1": 1.0}, "q_theta1 is both given a constant value and read from the table"),
])
def test_a_map_that_cannot_be_followed_is_refused_by_name(columns, constants, message):
    with pytest.raises(InputError, match=message):
        plan_columns(TWO, ["t", "a", "b"], columns=columns, constants=constants)


def test_the_reader_follows_the_plan():
    t = np.arange(200) * 1e-3
    log = {"t": t, "q_theta1": np.sin(t), "q_theta2": t**2, "qd_theta1": np.cos(t), "mode": np.zeros_like(t)}
    plan = plan_columns(TWO, log)
    state = joint_log(TWO, log)
    np.testing.assert_array_equal(state.qd[:, 0], log["qd_theta1"])             # read, not differentiated
    said = [n for n in state.notes if n.startswith(("qd:", "qdd:"))]
    assert [n.rsplit(" (joints ", 1)[1].rstrip(")") for n in said] == [
        ",".join(plan.derived_kind("qd")), ",".join(plan.derived_kind("qdd", "q")), ",".join(plan.derived_kind("qdd", "qd"))]
    np.testing.assert_allclose(state.qdd[:, 1], 2.0, rtol=1e-9)                  # d²(t²)/dt², exact for a cubic fit
