"""course_dynamics/tools/resampling.py: dropped samples filled and said, long gaps refused or split, resampling, and
a real log's clock (jitter, gaps, a lone sample, drops) named in one message or repaired at once."""
from __future__ import annotations

import numpy as np
import pytest
from logmakers import dropped, multisine, real_clock, sampled_at

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
    with pytest.raises(InputError, match=r"the table: it has 1 gap longer than 5 sample periods \(12 ms = 6.0 periods "
                                         r"after t = 0.398 s, before row 201\): --repair splits at the gaps \(as "
                                         r"--split-gaps does\)$"):
        joint_log(UR5, data)
    split = joint_log(UR5, data, split_gaps=True)
    assert split.segments == ((0, 200), (200, len(log.t)))
    assert "split at 1 long gap (after t = 0.398 s) into 2 segments, each differentiated on its own" in split.notes
    np.testing.assert_array_equal(split.t, log.t)
    exact = inverse_dynamics(UR5, log.q, log.qd, log.qdd)
    tau = inverse_dynamics(UR5, split.q, split.qd, split.qdd)
    assert np.abs(tau - exact).max() < 0.05 * np.abs(exact).max()   # no artefact across the gap


def test_a_jittering_clock_is_refused_until_resampled():
    jitter = MOTION.t + np.random.default_rng(0).uniform(-0.3, 0.3, len(MOTION.t)) / 500
    data = columns(MOTION) | {"t": jitter}
    with pytest.raises(InputError, match=r"the table: the samples are not on one clock \(median step 1.99 ms, steps "
                                         r"from 0.828 ms to 3.14 ms; 709 not a whole number of periods, the first "
                                         r"before row 2\): --repair resamples on the median period$"):
        joint_log(UR5, data)
    even = joint_log(UR5, data, resample=250)
    assert np.allclose(np.diff(even.t), 1 / 250) and even.notes[0].startswith("resampled to 250 Hz")


def test_a_lone_sample_between_gaps_and_a_bad_rate_are_refused():
    log = dropped(MOTION, list(range(100, 110)) + list(range(111, 120)))
    with pytest.raises(InputError, match=r"the log: 1 lone sample cut off by the gaps \(row 101, t = 0.22 s, between "
                                         r"two gaps\): --repair drops the lone sample$"):
        even_clock(log.t, {"q": log.q[:, 0]}, split_gaps=True)
    first = dropped(MOTION, range(1, 11))                    # the log's first sample alone: no gap before it
    with pytest.raises(InputError, match=r"1 lone sample cut off by the gaps \(row 1, t = 0 s, before the first gap\)"):
        even_clock(first.t, {"q": first.q[:, 0]}, split_gaps=True)
    with pytest.raises(InputError, match="the resampling rate must be a positive number of Hz, got -5"):
        even_clock(MOTION.t, {}, resample=-5)
    with pytest.raises(InputError, match="need the log's own times"):
        joint_log(UR5, {k: v for k, v in columns(MOTION).items() if k != "t"}, dt=0.002, resample=100)


# A real log, as the tools meet them: UR5 at about 500 Hz for 2 s, every step within ±20 % of the period, a gap of 40
# periods, a lone sample between two gaps of 20, two single rows dropped (logmakers.real_clock); the motion exact at
# its stamps, so the torques it should give are known.
REAL_T = real_clock(500.0, 2.0, seed=0)
REAL = sampled_at(UR5, REAL_T, seed=3)


def test_a_real_logs_every_problem_is_named_in_one_message():
    with pytest.raises(InputError) as caught:
        joint_log(UR5, columns(REAL))
    message = str(caught.value)
    assert "\n" not in message
    assert message == (
        "the table: the samples are not on one clock (median step 2 ms, steps from 1.61 ms to 3.85 ms; 240 not a whole "
        "number of periods, the first before row 5) and it has 3 gaps longer than 5 sample periods (79.6 ms = 39.8 "
        "periods after t = 0.600159 s, before row 301; 40.3 ms = 20.1 periods after t = 1.1998 s, before row 562; "
        "39.8 ms = 19.9 periods after t = 1.24007 s, before row 563) and 1 lone sample cut off by the gaps (row 562, "
        "t = 1.24007 s, between two gaps): --repair resamples on the median period, splits at the gaps and drops the "
        "lone sample")
    with pytest.raises(InputError, match=r"^the table: the samples are not on one clock .* and 1 lone sample cut off "
                                         r"by the gaps \(row 562, .*\): --repair resamples on the median period and "
                                         r"drops the lone sample$"):
        joint_log(UR5, columns(REAL), split_gaps=True)          # what --split-gaps leaves is named, all of it
    with pytest.raises(InputError, match=r"^the table: it has 3 gaps .* and 1 lone sample .*: --repair splits at the "
                                         r"gaps and drops the lone sample$"):
        joint_log(UR5, columns(REAL), resample=500)


def test_repair_resamples_splits_and_drops_with_notes_and_gives_the_motions_torques():
    result = torques_from_log(UR5, columns(REAL), repair=True)
    log = result.log
    assert log.notes[:3] == (
        "resampled on the median period 2 ms (500.259 Hz; the logged steps 1.61 ms to 3.85 ms): 923 samples from 921, "
        "by cubic splines",
        "split at 3 long gaps (after t = 0.600159 s, 1.1998 s, 1.24007 s) into 4 segments, each differentiated on its "
        "own",
        "dropped 1 lone sample cut off by the gaps (row 562, t = 1.24007 s, between two gaps): 3 segments left")
    assert log.segments == ((0, 301), (301, 562), (562, 923))
    for start, stop in log.segments:                        # one clock within each segment, never across a gap
        assert np.allclose(np.diff(log.t[start:stop]), np.diff(log.t[start:stop]).mean(), rtol=0, atol=1e-12)
    assert log.t[301] == REAL_T[300] and log.t[562] == REAL_T[562]          # each segment starts at a logged stamp
    exact = sampled_at(UR5, log.t, seed=3)
    # the resampling itself: a cubic spline's error bound 5/384 h⁴ max|q⁗|, h the longest logged step in a segment
    h = 3.85e-3
    q4 = np.abs(np.gradient(np.gradient(exact.qdd, axis=0), axis=0)).max(axis=0) / np.median(np.diff(log.t)) ** 2
    assert np.all(np.abs(log.q - exact.q).max(axis=0) <= 5 / 384 * h**4 * q4)
    # what that leaves in τ is far below what differentiating the rates leaves (measured 8e-5 of the peak, segment
    # edges included): held to the 1e-3 of the peak that an even log's differentiation is held to above
    tau = inverse_dynamics(UR5, exact.q, exact.qd, exact.qdd)
    assert np.abs(result.tau - tau).max() < 1e-3 * np.abs(tau).max()


def test_a_clean_log_is_the_same_with_or_without_repair():
    for data, split in ((columns(MOTION), False), (columns(dropped(MOTION, [100, 101, 400]), rates=True), False),
                        (columns(dropped(MOTION, range(200, 230))), True)):     # even; drops filled; a long gap
        plain = joint_log(UR5, data, split_gaps=split)
        mended = joint_log(UR5, data, repair=True)
        assert plain.notes == mended.notes and plain.segments == mended.segments
        for name in ("t", "q", "qd", "qdd"):
            np.testing.assert_array_equal(getattr(mended, name), getattr(plain, name))


def test_repair_with_a_rate_resamples_at_that_rate():
    log = joint_log(UR5, columns(REAL), repair=True, resample=250)
    assert log.notes[0] == "resampled to 250 Hz (461 samples from 921) by cubic splines"
    assert all(np.allclose(np.diff(log.t[a:b]), 1 / 250) for a, b in log.segments)


# Every segment a lone sample cannot be: at least half the steps are at most the median period, so some segment
# holds two samples. The nearest: pairs of samples, each pair cut off by gaps.
@pytest.mark.parametrize("pattern, fragment", [
    # pairs of samples 2 ms apart, each pair 50 ms from the next: every segment is two rows, the filter needs five
    (np.repeat(np.arange(40) * 0.05, 2) + np.tile([0.0, 0.002], 40),
     r"every segment between its 39 long gaps is too short to differentiate \(fewer than 5 rows each\)"),
    # t beyond any clock: the steps are refused before anything is resampled
    (1e300 * (1 + np.arange(50) * 1e-3), "the sample step 1e[+]297 s is outside 1e-9 s to 1e6 s"),
])
def test_hostile_logs_are_refused_not_emptied(pattern, fragment):
    motion = sampled_at(UR5, np.arange(len(pattern)) * 2e-3)
    with pytest.raises(InputError, match=fragment):
        joint_log(UR5, columns(motion) | {"t": pattern}, repair=True)


def test_repair_never_sorts_and_keeps_a_stamps_milliseconds_since_the_epoch():
    backwards = columns(REAL) | {"t": REAL_T.copy()}
    backwards["t"][400], backwards["t"][401] = REAL_T[401], REAL_T[400]
    with pytest.raises(InputError, match=r"^the table: row 402: t = 0.8\d+ s does not come after 0.8\d+ s"):
        joint_log(UR5, backwards, repair=True)
    with pytest.raises(InputError, match=r"^the log: row 4: t = 0.019 s does not come after 0.02 s \(t must increase; "
                                         r"a log is never sorted\)"):
        even_clock(np.array([0.0, 0.01, 0.02, 0.019, 0.03]), {}, repair=True)
    epoch = 1.7e9
    late = joint_log(UR5, columns(REAL) | {"t": REAL_T + epoch}, repair=True)
    near = joint_log(UR5, columns(REAL), repair=True)
    assert late.notes[2].startswith("dropped 1 lone sample cut off by the gaps (row 562, t = 1700000001.24007 s,")
    assert late.segments == near.segments
    # stamps of 1.7e9 s are rounded to 2.4e-7 s: the median period moves by as much, and the grid drifts by under
    # 1e-4 s over a segment; at its own times the repaired q is the motion's to that round-off times |qd| (< 3 rad/s)
    assert np.abs(late.t - epoch - near.t).max() < 1e-4
    assert np.abs(late.q - sampled_at(UR5, late.t - epoch, seed=3).q).max() < 3 * 2.4e-7
