"""course_dynamics/tools/resampling.py: dropped samples filled and said, long gaps refused or split, resampling."""
from __future__ import annotations

import numpy as np
import pytest
from logmakers import dropped, multisine

from course_dynamics import InputError, load_robot
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.tools.logs import joint_log, torques_from_log
from course_dynamics.tools.resampling import MAX_FILLED_PERIODS, even_clock

UR5 = load_robot("ur5")
MOTION = multisine(UR5, duration=2.0, rate=500.0, seed=3)   # exact q, qd, qdd at 500 Hz


def columns(motion, rates=False):
    data = {"t": motion.t, **{f"q_{j}": motion.q[:, i] for i, j in enumerate(UR5.joint_names)}}
    if rates:
        data |= {f"qd_{j}": motion.qd[:, i] for i, j in enumerate(UR5.joint_names)}
    return data


def test_isolated_drops_are_filled_with_the_motions_own_values_and_said():
    drops = [100, 101, 102, 103, 400, 731]                  # a run of 4 (a 5-period step) and two single drops
    log = dropped(MOTION, drops)
    clock = even_clock(log.t, {"q": log.q[:, 1]})
    np.testing.assert_allclose(clock.t, MOTION.t, rtol=0, atol=1e-12)
    assert clock.notes == ("filled 6 dropped samples (3 gaps; the largest 5 periods long, at t = 0.198 s)",)
    assert clock.filled.sum() == 6 and clock.filled[drops].all()
    logged = ~clock.filled
    np.testing.assert_array_equal(clock.columns["q"][logged], log.q[:, 1])        # logged samples kept as logged
    # a cubic spline's error bound, 5/384 h^4 max|q''''|, for the longest gap h = 5 periods (q'''' from the exact qdd)
    q4 = np.gradient(np.gradient(MOTION.qdd[:, 1], MOTION.t), MOTION.t)
    bound = 5 / 384 * (5 / 500) ** 4 * np.abs(q4).max()
    assert np.abs(clock.columns["q"][drops] - MOTION.q[drops, 1]).max() < bound


def test_torques_of_a_log_with_drops_are_the_torques_of_the_whole_log():
    whole = torques_from_log(UR5, columns(MOTION, rates=True))
    holes = torques_from_log(UR5, columns(dropped(MOTION, [50, 51, 300, 700]), rates=True))
    assert any(n.startswith("filled 4 dropped samples") for n in holes.notes)
    interior = slice(20, -20)
    scale = np.abs(whole.tau).max()
    assert np.abs(holes.tau - whole.tau)[interior].max() < 1e-6 * scale
    exact = inverse_dynamics(UR5, MOTION.q, MOTION.qd, MOTION.qdd)
    assert np.abs(holes.tau - exact)[interior].max() < 1e-3 * scale


def test_a_long_gap_is_refused_with_its_time_or_split_into_segments():
    log = dropped(MOTION, range(200, 200 + MAX_FILLED_PERIODS))   # a step of 6 periods
    data = columns(log)
    with pytest.raises(InputError, match=r"0.012 s pass between t = 0.398 s and t = 0.41 s \(row 201\), 6.0 sample "
                                         r"periods: more than 5 are not filled in; --split-gaps"):
        joint_log(UR5, data)
    split = joint_log(UR5, data, split_gaps=True)
    assert split.segments == ((0, 200), (200, len(log.t)))
    assert "split at 1 long gap into 2 segments, each differentiated on its own" in split.notes
    np.testing.assert_array_equal(split.t, log.t)
    exact = inverse_dynamics(UR5, log.q, log.qd, log.qdd)
    tau = inverse_dynamics(UR5, split.q, split.qd, split.qdd)
    assert np.abs(tau - exact).max() < 0.05 * np.abs(exact).max()   # no artefact across the gap


def test_a_jittering_clock_is_refused_until_resampled():
    jitter = MOTION.t + np.random.default_rng(0).uniform(-0.3, 0.3, len(MOTION.t)) / 500
    data = columns(MOTION) | {"t": jitter}
    with pytest.raises(InputError, match=r"the step before row 2 is 0.00155939 s, 0.78 sample periods of 0.00198715 s: the samples are not on one clock; --resample HZ"):
        joint_log(UR5, data)
    even = joint_log(UR5, data, resample=250)
    assert np.allclose(np.diff(even.t), 1 / 250) and even.notes[0].startswith("resampled to 250 Hz")


def test_a_lone_sample_between_gaps_and_a_bad_rate_are_refused():
    log = dropped(MOTION, list(range(100, 110)) + list(range(111, 120)))
    with pytest.raises(InputError, match=r"the segment at t = 0.22 s \(row 101\) has a single sample"):
        even_clock(log.t, {"q": log.q[:, 0]}, split_gaps=True)
    with pytest.raises(InputError, match="the resampling rate must be a positive number of Hz, got -5"):
        even_clock(MOTION.t, {}, resample=-5)
    with pytest.raises(InputError, match="need the log's own times"):
        joint_log(UR5, {k: v for k, v in columns(MOTION).items() if k != "t"}, dt=0.002, resample=100)
