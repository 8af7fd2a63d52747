"""course_dynamics/tools/limits.py: peaks, RMS, shares of the limits and violation intervals; and
course_dynamics/teaching/limits.py, the time limit of a check in a student's kernel."""
from __future__ import annotations

import numpy as np
import pytest

from course_dynamics import load_robot
from course_dynamics.teaching.limits import CheckTimeout, time_limit
from course_dynamics.tools.limits import MERGE_GAP, limits_report


def test_peaks_rms_and_shares():
    model = load_robot("ur5")
    t = np.linspace(0, 1, 101)
    tau = np.outer(np.sin(2 * np.pi * t), [10, 20, 30, 1, 2, 3])
    qd = np.outer(np.cos(2 * np.pi * t), [1, 1, 1, 0.5, 0.5, 0.5])
    report = limits_report(model, t, qd, tau)
    np.testing.assert_allclose(report.peak_tau, np.abs(tau).max(axis=0))
    np.testing.assert_allclose(report.rms_tau, np.sqrt((tau**2).mean(axis=0)))
    np.testing.assert_allclose(report.effort_used, report.peak_tau / model.effort)
    np.testing.assert_allclose(report.velocity_used, report.peak_qd / model.velocity)
    assert not report.exceeded and report.violations == ()


def test_violations_are_intervals_with_their_peak():
    model = load_robot("ur5")
    t = np.arange(0, 1, 0.01)
    tau = np.zeros((len(t), 6))
    tau[20:31, 3] = 30.0          # wrist_1 beyond its 28 N m from t = 0.2 to 0.3
    tau[25, 3] = -35.0            # |τ| counts, and the peak is the worst
    tau[70:81, 0] = 151.0         # shoulder_pan beyond 150 from 0.7 to 0.8
    qd = np.zeros((len(t), 6))
    qd[50, 5] = 4.0               # wrist_3 too fast at one sample
    report = limits_report(model, t, qd, tau)
    assert report.exceeded
    found = [(v.joint, v.kind, v.start, v.end, v.peak) for v in report.violations]
    assert found == [("wrist_1_joint", "effort", t[20], t[30], 35.0), ("wrist_3_joint", "velocity", t[50], t[50], 4.0),
                     ("shoulder_pan_joint", "effort", t[70], t[80], 151.0)]
    assert "from t = 0.2 s to t = 0.3 s" in report.violations[0].describe()


@pytest.mark.parametrize("gap, stretches", [(MERGE_GAP, 1), (MERGE_GAP + 1, 2)])
def test_stretches_close_together_count_once(gap, stretches):
    model = load_robot("ur5")
    t = np.arange(200) * 0.01
    tau = np.zeros((200, 6))
    tau[10:15, 0] = 200.0
    tau[15 + gap - 1:15 + gap + 5, 0] = 200.0
    report = limits_report(model, t, np.zeros((200, 6)), tau)
    assert len(report.violations) == stretches


def test_no_limit_means_no_share_and_no_violation():
    model = load_robot("double_pendulum")  # its URDF gives no effort or velocity limits
    t = np.arange(10.0)
    report = limits_report(model, t, np.full((10, 2), 1e6), np.full((10, 2), 1e6))
    assert not report.exceeded
    assert [r["effort_limit"] for r in report.rows()] == [None, None]
    assert report.record()["exceeded"] is False


def test_a_peak_within_the_uncertainty_of_the_rates_is_reported_apart():
    from course_dynamics.tools.limits import UNCERTAINTY_SIGMAS

    model = load_robot("ur5")                       # shoulder_lift_joint's effort limit: 150 N m
    t = np.arange(100) * 0.01
    tau = np.zeros((100, 6))
    sigma = np.full((100, 6), 1.0)                 # N m
    tau[20:25, 1] = 149.0                          # below the limit, but 149 + 2σ is beyond it
    tau[60:65, 1] = 151.0                          # beyond the limit, but 151 − 2σ is not
    tau[80:85, 1] = 150 + UNCERTAINTY_SIGMAS * 1.0 + 0.5   # beyond even after the band
    report = limits_report(model, t, np.zeros_like(tau), tau, sigma)
    assert [(v.start, v.end) for v in report.violations] == [(0.8, 0.84)] and report.exceeded
    assert [(v.start, v.end, v.peak, v.band) for v in report.uncertain] == [(0.2, 0.24, 149.0, 2.0),
                                                                          (0.6, 0.64, 151.0, 2.0)]
    assert "149 ± 2 is within the uncertainty of the rates of the limit 150" in report.uncertain[0].describe()
    assert report.record()["uncertain"][1]["band"] == 2.0
    plain = limits_report(model, t, np.zeros_like(tau), tau)          # no σ: the nominal verdict, no band
    assert len(plain.violations) == 2 and plain.uncertain == () and plain.peak_band is None


def _endless():
    while True:
        pass


def _swallowing():
    while True:  # a bare except around the loop: the time limit raises again inside the handler
        try:
            while True:
                pass
        except BaseException:
            pass


@pytest.mark.parametrize("student", [_endless, _swallowing])
def test_a_timed_out_check_leaves_no_exception_behind(student):
    """After the timeout, the kernel handles no exception: a later error does not carry it as its context."""
    import signal
    import sys

    before = signal.getsignal(signal.SIGALRM)
    with pytest.raises(CheckTimeout):
        with time_limit(0.2):
            student()
    assert sys.exc_info() == (None, None, None)
    try:
        1 / 0
    except ZeroDivisionError as later:
        assert later.__context__ is None
    assert signal.getsignal(signal.SIGALRM) is before
