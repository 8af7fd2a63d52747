"""course_dynamics/tools/differentiation.py: the noise estimate, the windows chosen from it, the edges, and the torques.

The motion is the multi-sine of ``logmakers.multisine`` (exact Θ, Θ̇, Θ̈); the noise is added by
``logmakers.noisy`` with the amounts stated here. The benchmark log: a UR5 at 500 Hz with 2e-5 rad of
position noise and 2e-3 rad/s of rate noise.
"""
from __future__ import annotations

import numpy as np
import pytest
from logmakers import multisine, noisy
from scipy.signal import savgol_filter

from course_dynamics import InputError, load_robot
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.tools.differentiation import MIN_WINDOW, derivatives, noise_level

RATE = 500.0                 # Hz
STEP = 1 / RATE              # s
SIGMA_Q = 2e-5               # rad
SIGMA_QD = 2e-3              # rad/s
# A fixed window as one would pick it by hand: the odd count of samples nearest 20 ms, at least 7.
FIXED_WINDOW = 11
PEAK_TOLERANCE = 0.05        # the bar a torque log must meet: each joint's peak |τ| within 5 % of the exact motion's
SEEDS = range(30)            # noise draws for the statistics of qdd's error


@pytest.fixture(scope="module")
def ur5():
    return load_robot("ur5")


@pytest.fixture(scope="module")
def noisy_ur5_log(ur5):
    """4 s of the motion (seed 1) with the benchmark log's noise (seeds 1 and 2), and the exact peak |τ| per joint."""
    motion = multisine(ur5, duration=4.0, rate=RATE, seed=1)
    peak = np.abs(inverse_dynamics(ur5, motion.q, motion.qd, motion.qdd)).max(axis=0)
    return motion, noisy(motion.q, SIGMA_Q, seed=1), noisy(motion.qd, SIGMA_QD, seed=2), peak


def peak_errors(model, q, result, peak):
    """Each joint's relative error of peak |τ| computed from the logged Θ and the derivatives ``result``."""
    tau = inverse_dynamics(model, q, result.qd, result.qdd)
    return np.abs(tau).max(axis=0) / peak - 1


@pytest.mark.parametrize("logged", ["positions and rates", "positions only"])
def test_peak_torques_of_a_noisy_500_hz_log_are_within_5_percent(ur5, noisy_ur5_log, logged):
    _, q, qd, peak = noisy_ur5_log
    rates = qd if logged == "positions and rates" else None
    chosen = derivatives(STEP, q, rates)
    assert np.all(np.abs(peak_errors(ur5, q, chosen, peak)) < PEAK_TOLERANCE), peak_errors(ur5, q, chosen, peak)
    # Measured: at most 0.12 % (rates logged) and 0.4 % (positions only); today's 11 samples: 5.2 % and 9.6 % here,
    # 4.9–8.6 % and 6.5–13 % over twelve other draws of the noise.
    fixed = derivatives(STEP, q, rates, window=FIXED_WINDOW)
    assert np.abs(peak_errors(ur5, q, fixed, peak)).max() > PEAK_TOLERANCE


@pytest.mark.parametrize("rate", [125.0, 500.0, 1000.0])
@pytest.mark.parametrize("sigma", [1e-5, 1e-4, 1e-3])
def test_the_noise_estimate_is_within_a_factor_1_5(ur5, rate, sigma):
    motion = multisine(ur5, duration=4.0, rate=rate, seed=3)
    q, qd = noisy(motion.q, sigma, seed=5), noisy(motion.qd, 100 * sigma, seed=6)   # rad, rad/s
    for estimate, truth in ((noise_level(q), sigma), (noise_level(qd), 100 * sigma)):
        assert np.all((truth / 1.5 < estimate) & (estimate < 1.5 * truth)), (estimate, truth)
    result = derivatives(1 / rate, q, qd)
    np.testing.assert_array_equal(result.noise_q, noise_level(q))
    np.testing.assert_array_equal(result.noise_qd, noise_level(qd))


@pytest.fixture(scope="module")
def draws(ur5):
    """qdd's error (vs exact) and its reported σ over SEEDS noise draws on 2 s of the motion: {case: (error, sigma)}."""
    motion = multisine(ur5, duration=2.0, rate=RATE, seed=7)
    found = {}
    for case in ("positions and rates", "positions only", "fixed window, positions only"):
        errors, sigmas = [], []
        for seed in SEEDS:
            q = noisy(motion.q, SIGMA_Q, seed=100 + seed)
            qd = noisy(motion.qd, SIGMA_QD, seed=200 + seed) if case == "positions and rates" else None
            result = derivatives(STEP, q, qd, window=FIXED_WINDOW if case.startswith("fixed") else None)
            errors.append(result.qdd - motion.qdd)
            sigmas.append(result.sigma_qdd)
        found[case] = np.array(errors), np.array(sigmas)
    return found


INTERIOR = slice(150, -150)  # rows farther from the ends than any chosen half-window


@pytest.mark.parametrize("case", ["positions and rates", "positions only"])
def test_sigma_qdd_is_the_size_of_the_error(draws, case):
    """σ_Θ̈ is the noise left after filtering and the fit's bias in quadrature. The bias is estimated over the
    whole log (β² Rₘ, Rₘ a mean), so row by row only the noise part can be held to it; over the log, the whole."""
    errors, sigmas = draws[case]
    spread = errors.std(axis=0) / sigmas.mean(axis=0)                 # the noise part, per row and joint
    assert np.all(spread[INTERIOR] < 1.5), spread.max()               # never more than σ
    whole = np.sqrt(np.mean(errors[:, INTERIOR] ** 2, axis=(0, 1))) / np.sqrt(np.mean(sigmas[:, INTERIOR] ** 2, axis=(0, 1)))
    assert np.all(np.abs(whole - 1) < 0.25), whole                    # noise and bias together: measured 0.92-1.06
    ends = np.r_[0:5, -5:0]
    assert np.all(spread[ends] < 1.5)                                 # the edge rows' larger σ covers them too
    assert np.all(sigmas.mean(axis=0)[0] > 2 * sigmas.mean(axis=0)[INTERIOR].max(axis=0))


@pytest.mark.parametrize("case, bound", [
    # A quintic fit of the end's 90–120 samples, as long as the model's optimum: its end row errs by about
    # 2.4 × the centred filter inside (the least a one-sided fit reaches on this motion, computed from its
    # exact derivatives); with the bias of the motion's phase at the ends, 2.3–3.1 × measured.
    ("positions only", 3.5),
    # A first derivative from one side is far worse than the centred one inside (its bias is of Θ⁽⁵⁾,
    # not Θ⁽⁶⁾, and its noise gain four times larger): the best edge fits measured reach 6–8 × the interior.
    ("positions and rates", 10.0),
])
def test_edge_rows_are_no_artefact(draws, case, bound):
    errors, _ = draws[case]
    rms = np.sqrt(np.mean(errors**2, axis=0))                        # per row and joint, over the draws
    interior = rms[INTERIOR].mean(axis=0)
    edges = np.maximum(rms[:150], rms[-150:][::-1]).max(axis=0)
    assert np.all(edges < bound * interior), edges / interior        # measured: ≤ 3.1 and ≤ 8.3
    # Either way no end row errs by more than 3.5 × what positions alone give inside (rates: about 2.3 ×).
    positions = np.sqrt(np.mean(draws["positions only"][0] ** 2, axis=0))[INTERIOR].mean(axis=0)
    assert np.all(rms[np.r_[0:5, -5:0]] < 3.5 * positions)


def test_a_fixed_window_has_the_edge_artefact(draws):
    fixed = np.sqrt(np.mean(draws["fixed window, positions only"][0] ** 2, axis=0))
    new = np.sqrt(np.mean(draws["positions only"][0] ** 2, axis=0))
    assert np.all(np.maximum(fixed[0], fixed[-1]) > 3.5 * fixed[INTERIOR].mean(axis=0))    # measured: 4.2 to 7.1
    assert np.all(np.maximum(new[0], new[-1]) < np.maximum(fixed[0], fixed[-1]) / 2)


def test_noise_free_data_keep_the_shortest_window_and_polynomials_stay_exact():
    t = np.arange(0, 1, 1e-3)[:, None]                               # s
    a, b, c, d = np.array([[0.3, -1.2], [2.0, 0.5], [-1.0, 3.0], [0.5, -4.0]])   # two joints' cubics, rad
    q = a + b * t + c * t**2 + d * t**3
    qd, qdd = b + 2 * c * t + 3 * d * t**2, 2 * c + 6 * d * t
    positions = derivatives(1e-3, q, None)
    assert list(positions.window) == [MIN_WINDOW, MIN_WINDOW]
    # Exact up to rounding: 1e-16 of |Θ| through a second difference over (1 ms)² is about 1e-10.
    np.testing.assert_allclose(positions.qd, qd, rtol=0, atol=1e-11)
    np.testing.assert_allclose(positions.qdd, qdd, rtol=0, atol=1e-8)
    rates = derivatives(1e-3, q, qd)
    assert rates.qd is qd or np.array_equal(rates.qd, qd)
    np.testing.assert_allclose(rates.qdd, qdd, rtol=0, atol=1e-10)
    still = derivatives(1e-3, np.full((50, 1), 0.7), None)
    assert np.abs(still.qd).max() < 1e-20 and np.abs(still.qdd).max() < 1e-20 and still.window[0] == MIN_WINDOW


def test_noise_free_motion_is_not_smoothed(ur5):
    motion = multisine(ur5, duration=2.0, rate=RATE, seed=7)
    result = derivatives(STEP, motion.q, None)
    assert np.all(result.window == MIN_WINDOW)
    fixed = derivatives(STEP, motion.q, None, window=FIXED_WINDOW)
    assert np.abs(result.qdd - motion.qdd).max() < np.abs(fixed.qdd - motion.qdd).max() / 4


@pytest.mark.parametrize("window", [5, FIXED_WINDOW, 51])
def test_an_explicit_window_is_scipys_savgol_filter(noisy_ur5_log, window):
    _, q, qd, _ = noisy_ur5_log

    def savgol(y, deriv):
        return savgol_filter(y, window, 3, deriv=deriv, delta=STEP, axis=0, mode="interp")
    positions = derivatives(STEP, q, None, window=window)
    np.testing.assert_allclose(positions.qd, savgol(q, 1), rtol=1e-9, atol=1e-11)
    np.testing.assert_allclose(positions.qdd, savgol(q, 2), rtol=1e-9, atol=1e-8)
    rates = derivatives(STEP, q, qd, window=window)
    np.testing.assert_array_equal(rates.qd, qd)
    np.testing.assert_allclose(rates.qdd, savgol(qd, 1), rtol=1e-9, atol=1e-10)
    assert list(rates.window) == [window] * q.shape[1]
    how = f"Savitzky-Golay derivative ({window}-sample window = {window * STEP:.4g} s, cubic)"
    assert positions.notes == (f"qd: first {how} of q", f"qdd: second {how} of q")
    assert rates.notes == (f"qdd: first {how} of qd",)


def test_the_notes_say_what_was_chosen(noisy_ur5_log):
    _, q, qd, _ = noisy_ur5_log
    positions, rates = derivatives(STEP, q, None), derivatives(STEP, q, qd)
    assert [n.split(":")[0] for n in positions.notes] == ["qd", "qdd", "edges"]
    assert "chosen from the position noise" in positions.notes[1] and "rad (or m) estimated" in positions.notes[1]
    assert [n.split(":")[0] for n in rates.notes] == ["qdd", "edges"] and "rate noise" in rates.notes[0]
    assert rates.noise_qd is not None and positions.noise_qd is None
    assert np.all(rates.window % 2 == 1) and rates.window.dtype.kind == "i"


@pytest.mark.parametrize("rows, window, message", [
    (100, 4, "the smoothing window must be an odd number of samples, at least 5; got 4"),
    (100, 3, "the smoothing window must be an odd number of samples, at least 5; got 3"),
    (9, 11, "the log: the smoothing window (11 samples) is longer than the log (9 rows)"),
    (4, None, "the log: 4 rows are too few to differentiate (at least 5 are needed)"),
])
def test_bad_windows_and_short_logs_are_input_errors(rows, window, message):
    with pytest.raises(InputError) as caught:
        derivatives(STEP, np.zeros((rows, 2)), None, window=window)
    assert str(caught.value) == message


def test_short_logs_are_differentiated_with_what_they_have():
    t = np.arange(6)[:, None] * 0.01
    result = derivatives(0.01, t**2, None)
    assert result.window[0] == 5
    np.testing.assert_allclose(result.qdd, 2.0, atol=1e-9)


@pytest.mark.parametrize("samples, window", [(3000, 31), (60_000, 801)])  # numpy's direct sum, and its FFT
def test_the_correlation_is_scipys_without_importing_scipy_signal(samples, window, monkeypatch):
    """The filter's sum is numpy's (direct or FFT, by the work): scipy.signal.correlate's to round-off; the
    differentiation imports neither scipy.signal nor scipy.stats (0.4 s of a command's start)."""
    import subprocess
    import sys

    from scipy.signal import correlate

    from course_dynamics.tools import differentiation

    t = np.arange(samples) * 1e-3
    q = np.column_stack([np.sin(2 * t) + 1e-4 * np.random.default_rng(1).standard_normal(samples), np.cos(t)])
    ours = derivatives(1e-3, q, window=window)
    monkeypatch.setattr(differentiation, "_correlate", lambda y, h: correlate(y, h, mode="valid"))
    theirs = derivatives(1e-3, q, window=window)
    for name in ("qd", "qdd"):
        scale = np.abs(getattr(theirs, name)).max()
        np.testing.assert_allclose(getattr(ours, name), getattr(theirs, name), rtol=0, atol=1e-12 * scale)
    script = ("import sys, numpy as np\nfrom course_dynamics.tools.differentiation import derivatives\n"
              f"derivatives(1e-3, np.sin(np.arange({samples}) * 1e-3)[:, None], window={window})\n"
              "print(sorted(m for m in ('scipy.signal', 'scipy.stats') if m in sys.modules))")
    assert subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True).stdout == "[]\n"


def test_a_table_that_is_not_finite_is_named_as_such():
    q = np.r_[np.zeros((10, 2)), [[0.0, np.nan]], np.zeros((10, 2))]
    with pytest.raises(InputError, match="the log: q in row 10, column 1 is nan: a table to differentiate must be"):
        derivatives(1e-3, q, window=5)
    with pytest.raises(InputError, match="qd in row 0, column 0 is inf"):
        derivatives(1e-3, np.zeros((21, 1)), np.r_[[[np.inf]], np.zeros((20, 1))])
