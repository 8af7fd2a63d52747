"""course_dynamics/tools/logs.py: logs in every shape, differentiated rates, torques and the limits report."""
from __future__ import annotations

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import assert_agrees, urdf_of

from course_dynamics import InputError, inverse_dynamics, load_robot, load_urdf
from course_dynamics.core.friction import Friction
from course_dynamics.tools.loads import Payload, Wrench, with_payload, wrench_torques
from course_dynamics.tools.columns import parse_column_map
from course_dynamics.tools.differentiation import MIN_WINDOW
from course_dynamics.tools.logs import joint_log, torques_from_log

OMEGA = np.array([1.3, 2.1])


def sine_motion(dt=1e-3, duration=2.0):
    """Θ = 0.4 sin(ωt) + offsets on the two-link arm, with exact Θ̇ and Θ̈."""
    t = np.arange(0, duration, dt)
    q = 0.4 * np.sin(np.outer(t, OMEGA)) + [0.2, -0.3]
    qd = 0.4 * OMEGA * np.cos(np.outer(t, OMEGA))
    qdd = -0.4 * OMEGA**2 * np.sin(np.outer(t, OMEGA))
    return t, q, qd, qdd


def columns(t, q, qd=None, qdd=None, joints=("theta1", "theta2")):
    table = {"t": t} if t is not None else {}
    for kind, values in (("q", q), ("qd", qd), ("qdd", qdd)):
        if values is not None:
            table.update({f"{kind}_{j}": values[:, i] for i, j in enumerate(joints)})
    return table


def test_full_state_logs_give_exactly_our_torques_and_pinocchios():
    model = load_robot("two_link")
    t, q, qd, qdd = sine_motion(dt=0.01)
    result = torques_from_log(model, columns(t, q, qd, qdd))
    np.testing.assert_array_equal(result.tau, inverse_dynamics(model, q, qd, qdd))
    assert result.notes == ()
    oracle = PinocchioOracle(urdf_of("two_link"), model.joint_names, model.gravity)
    for k in range(0, len(t), 20):
        assert_agrees(result.tau[k], oracle.tau(q[k], qd[k], qdd[k]), what=f"row {k}")


def test_positions_only_are_differentiated_and_said_so():
    model = load_robot("two_link")
    t, q, qd, qdd = sine_motion()
    log = joint_log(model, columns(t, q))
    # A cubic fitted over 21 samples (21 ms) of sines with ωT ≈ 0.04: the fit's bias is of order (ωT)² for Θ̈
    # (a few 1e-5 of its amplitude) and smaller for Θ̇; the end windows are one-sided fits and a few times worse.
    inner = slice(10, -10)
    np.testing.assert_allclose(log.qd[inner], qd[inner], atol=1e-8 * np.abs(qd).max())
    np.testing.assert_allclose(log.qdd[inner], qdd[inner], atol=1e-4 * np.abs(qdd).max())
    np.testing.assert_allclose(log.qd, qd, atol=1e-5 * np.abs(qd).max())
    np.testing.assert_allclose(log.qdd, qdd, atol=1e-3 * np.abs(qdd).max())
    assert [note.split(":")[0] for note in log.notes] == ["qd", "qdd", "edges"]
    # exact data: no noise to smooth, so the shortest window (a noisy log gets a longer one: test_differentiation)
    assert f"window {MIN_WINDOW} samples" in log.notes[0] and "derivative of q," in log.notes[1]


def test_given_rates_are_differentiated_for_accelerations_only():
    model = load_robot("two_link")
    t, q, qd, qdd = sine_motion()
    log = joint_log(model, columns(t, q, qd))
    np.testing.assert_array_equal(log.qd, qd)
    # A first derivative of the exact qd by the same 21-sample cubic fit: its bias is of order (ωT)² ≈ 1e-5 at
    # the ends (one-sided windows); this is the filter's accuracy, not agreement with Pinocchio.
    np.testing.assert_allclose(log.qdd, qdd, atol=1e-5 * np.abs(qdd).max())
    assert [note.split(":")[0] for note in log.notes] == ["qdd", "edges"]
    assert log.notes[0].startswith("qdd: first Savitzky-Golay derivative of qd,")


def test_the_window_is_chosen_or_set():
    model = load_robot("two_link")
    t, q, _, _ = sine_motion(dt=0.01)
    assert f"window {MIN_WINDOW} samples" in joint_log(model, columns(t, q)).notes[0]  # exact data: the shortest
    assert "31-sample" in joint_log(model, columns(t, q), window=31).notes[0]
    for bad in (4, 6, 3):
        with pytest.raises(InputError, match="odd number of samples"):
            joint_log(model, columns(t, q), window=bad)


def test_a_log_without_t_takes_dt():
    model = load_robot("two_link")
    t, q, qd, qdd = sine_motion(dt=0.005)
    log = joint_log(model, columns(None, q, qd, qdd), dt=0.005)
    np.testing.assert_allclose(log.t, t)
    with pytest.raises(InputError, match="no column 't'"):
        joint_log(model, columns(None, q, qd, qdd))
    with pytest.raises(InputError, match="only for logs without one"):
        joint_log(model, columns(t, q, qd, qdd), dt=0.005)
    with pytest.raises(InputError, match="dt must be a positive number"):
        joint_log(model, columns(None, q, qd, qdd), dt=-1.0)


def test_column_maps_and_ignored_columns():
    model = load_robot("two_link")
    t, q, qd, qdd = sine_motion(dt=0.01)
    log = {"time": t, "j1": q[:, 0], "j2": q[:, 1], "temperature": np.ones_like(t)}
    for k, kind in enumerate(("qd", "qdd")):
        log.update({f"{kind}1": (qd, qdd)[k][:, 0], f"{kind}2": (qd, qdd)[k][:, 1]})
    mapping = parse_column_map("t=time,q_theta1=j1,q_theta2=j2,qd_theta1=qd1,qd_theta2=qd2,qdd_theta1=qdd1,qdd_theta2=qdd2")
    result = torques_from_log(model, log, columns=mapping)
    np.testing.assert_array_equal(result.tau, inverse_dynamics(model, q, qd, qdd))


def test_column_map_from_toml(tmp_path):
    path = tmp_path / "map.toml"
    path.write_text('[columns]\nt = "time_s"\nq_theta1 = "a"\n')
    assert parse_column_map(str(path)) == {"t": "time_s", "q_theta1": "a"}
    path.write_text('t = 3\n')
    with pytest.raises(InputError, match="every entry must be"):
        parse_column_map(str(path))


@pytest.mark.parametrize("mapping, fragment", [
    ({"q_elbow": "j1"}, "'q_elbow' is none of our columns"),
    ({"q_theta1": "nope"}, "no column 'nope' (mapped from q_theta1)"),
])
def test_bad_column_maps(mapping, fragment):
    t, q, _, _ = sine_motion(dt=0.01)
    with pytest.raises(InputError, match=fragment.replace("(", r"\(").replace(")", r"\)")):
        joint_log(load_robot("two_link"), columns(t, q), columns=mapping)


def test_inconsistent_logs_are_refused():
    model = load_robot("two_link")
    t, q, qd, _ = sine_motion(dt=0.01)
    with pytest.raises(InputError, match="missing columns: q_theta2"):
        joint_log(model, {"t": t, "q_theta1": q[:, 0]})
    backwards = columns(t.copy(), q)
    backwards["t"][5] = backwards["t"][4]
    with pytest.raises(InputError, match="row 6: t = 0.04 s does not come after 0.04 s"):
        joint_log(model, backwards)
    uneven = columns(np.concatenate([t[:50], t[50:] + 0.5]), q)
    with pytest.raises(InputError, match=r"it has 1 gap longer than 5 sample periods \(510 ms = 51.0 periods after "
                                         r"t = 0.49 s, before row 51\): --repair splits at the gaps"):
        joint_log(model, uneven)
    jitter = columns(np.concatenate([t[:50], t[50:] + 0.004]), q)
    with pytest.raises(InputError, match=r"not on one clock \(median step 10 ms, steps from 10 ms to 14 ms; 1 not a "
                                         r"whole number of periods, the first before row 51\): --repair resamples"):
        joint_log(model, jitter)
    with pytest.raises(InputError, match="too few to differentiate"):
        joint_log(model, columns(t[:3], q[:3]))
    with pytest.raises(InputError, match="must be finite"):
        joint_log(model, columns(t, np.where(np.arange(len(t))[:, None] == 7, np.nan, q)))


class FakeFrame:
    """What a pandas DataFrame offers that the log reader uses: ``columns`` and ``frame[name]``."""

    def __init__(self, data):
        self._data = data
        self.columns = list(data)

    def __getitem__(self, name):
        return self._data[name]


def test_dataframes_and_structured_arrays_are_logs_too():
    model = load_robot("two_link")
    t, q, qd, qdd = sine_motion(dt=0.01)
    log = columns(t, q, qd, qdd)
    expected = inverse_dynamics(model, q, qd, qdd)
    np.testing.assert_array_equal(torques_from_log(model, FakeFrame(log)).tau, expected)
    structured = np.zeros(len(t), dtype=[(name, float) for name in log])
    for name, values in log.items():
        structured[name] = values
    np.testing.assert_array_equal(torques_from_log(model, structured).tau, expected)
    with pytest.raises(InputError, match="named columns"):
        torques_from_log(model, np.zeros((3, 3)))


def test_physics_options_add_up():
    """τ with gravity, friction, payload and wrench = the sum of the library's own terms."""
    model = load_robot("ur5")
    t = np.arange(0, 0.5, 0.01)
    rng = np.random.default_rng(4)
    q, qd, qdd = (rng.standard_normal((len(t), 6)) for _ in range(3))
    log = columns(t, q, qd, qdd, joints=model.joint_names)
    g = np.array([0.0, 3.0, -9.0])
    friction = Friction(viscous=np.full(6, 0.3), coulomb=np.full(6, 1.5))
    payload, wrench = Payload(mass=3.0, link="tool0", com=(0, 0, 0.05)), Wrench("tool0", (0, 0, -20.0), (0, 1.0, 0))
    result = torques_from_log(model.with_gravity(g), log, friction=friction, payload=payload, wrench=wrench)
    loaded = with_payload(model.with_gravity(g), payload)
    expected = inverse_dynamics(loaded, q, qd, qdd) + friction.torques(qd) + wrench_torques(loaded, q, wrench)
    np.testing.assert_allclose(result.tau, expected, rtol=1e-13, atol=1e-12)


def test_compiled_and_interpreted_agree_on_long_logs():
    model = load_urdf(urdf_of("ur5"))
    t = np.arange(6000) * 1e-3
    q = 0.5 * np.sin(np.outer(t, np.arange(1, 7)))
    log = columns(t, q, joints=model.joint_names)
    fast, slow = torques_from_log(model, log), torques_from_log(model, log, compiled=False)
    np.testing.assert_allclose(fast.tau, slow.tau, rtol=1e-12, atol=1e-10)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_overflowing_values_are_refused_not_written_as_nan():
    model = load_robot("two_link")
    t, q, qd, qdd = sine_motion(dt=0.01)
    qd[3] = 1e200
    with pytest.raises(InputError, match="torques overflow at t = 0.03 s"):
        torques_from_log(model, columns(t, q, qd, qdd))


def test_rates_given_for_some_joints_are_used_and_the_others_differentiated():
    model = load_robot("two_link")
    t, q, qd, qdd = sine_motion()
    partial = columns(t, q)
    partial["qd_theta1"] = qd[:, 0]
    log = joint_log(model, partial)
    np.testing.assert_array_equal(log.qd[:, 0], qd[:, 0])
    # Differentiated by the filter, with its accuracy (see test_positions_only_are_differentiated_and_said_so).
    np.testing.assert_allclose(log.qd[:, 1], qd[:, 1], atol=1e-5 * np.abs(qd).max())
    np.testing.assert_allclose(log.qdd, qdd, atol=1e-3 * np.abs(qdd).max())
    assert log.notes[0].startswith("qd: first Savitzky-Golay derivative of q,") and log.notes[0].endswith("(joints theta2)")
    assert any(n.startswith("qdd: first Savitzky-Golay derivative of qd,") and n.endswith("(joints theta1)")
               for n in log.notes)


def test_time_units_and_constants_for_unlogged_joints():
    model = load_robot("panda")
    arm = [j for j in model.joint_names if "finger" not in j]
    t = np.arange(0, 1, 0.004)
    q = 0.3 * np.sin(np.outer(t, np.arange(1, 8)))
    log = {"t_ms": t * 1000, **{f"q_{j}": q[:, i] for i, j in enumerate(arm)}}
    fingers = {f"q_{j}": 0.02 for j in model.joint_names if "finger" in j}
    result = torques_from_log(model, log, columns={"t": "t_ms"}, time_unit="ms", constants=fingers)
    np.testing.assert_allclose(result.t, t)
    held = [model.joint_names.index(j) for j in model.joint_names if "finger" in j]
    assert np.all(result.log.q[:, held] == 0.02) and np.all(result.log.qd[:, held] == 0)
    assert any("q_panda_finger_joint1 = 0.02 throughout" in n for n in result.notes)
    with pytest.raises(InputError, match="unknown time unit 'min'"):
        joint_log(model, log, columns={"t": "t_ms"}, time_unit="min", constants=fingers)
    with pytest.raises(InputError, match="both given a constant value and read"):
        joint_log(model, log, columns={"t": "t_ms"}, constants={f"q_{arm[0]}": 0.0})


def test_one_log_column_for_two_of_ours_and_a_key_mapped_twice_are_refused():
    t, q, _, _ = sine_motion(dt=0.01)
    log = {"t": t, "a": q[:, 0]}
    with pytest.raises(InputError, match="q_theta1 and q_theta2 are both mapped to the log's column 'a'"):
        joint_log(load_robot("two_link"), log, columns={"q_theta1": "a", "q_theta2": "a"})
    with pytest.raises(InputError, match="'q_theta1' is mapped twice"):
        parse_column_map("q_theta1=a,q_theta1=b")


def test_torques_in_blocks_of_rows_are_the_torques_at_once(monkeypatch):
    """τ is computed ROWS_AT_A_TIME rows at a time to bound memory; the rows' results do not depend on it."""
    model = load_robot("ur5")
    t = np.arange(0, 0.5, 0.01)
    rng = np.random.default_rng(5)
    q, qd, qdd = (rng.standard_normal((len(t), 6)) for _ in range(3))
    friction = Friction(viscous=np.full(6, 0.3), coulomb=np.full(6, 1.5))
    wrench = Wrench("tool0", (0, 0, -20.0), (0, 1.0, 0))
    monkeypatch.setattr("course_dynamics.tools.logs.ROWS_AT_A_TIME", 7)
    blocks = torques_from_log(model, columns(t, q, qd, qdd, joints=model.joint_names), friction=friction, wrench=wrench,
                              compiled=False)
    expected = inverse_dynamics(model, q, qd, qdd) + friction.torques(qd) + wrench_torques(model, q, wrench)
    np.testing.assert_array_equal(blocks.tau, expected)


def test_a_column_map_that_is_no_regular_file_or_too_large_is_refused(tmp_path):
    import os
    import signal

    fifo = tmp_path / "map.toml"
    os.mkfifo(fifo)  # reading it would wait for a writer forever
    signal.signal(signal.SIGALRM, lambda *_: pytest.fail("parse_column_map waited on a pipe"))
    signal.alarm(10)
    try:
        with pytest.raises(InputError, match=r"map.toml: not a regular file \(a named pipe\), not a column map"):
            parse_column_map(str(fifo))
    finally:
        signal.alarm(0)
    fifo.unlink()
    with open(fifo, "wb") as handle:
        handle.truncate(2 * 2**20)
    with pytest.raises(InputError, match="map.toml: 2 MiB is more than a column map may be"):
        parse_column_map(str(fifo))


@pytest.mark.parametrize("rates", [True, False], ids=["positions and rates", "positions only"])
def test_a_noisy_500_hz_ur5_log_gives_every_peak_torque_within_5_percent(rates):
    """The multisine of tests/logmakers.py (4 s, seed 7) at 500 Hz, 2e-5 rad of position noise and 2e-3 rad/s of
    rate noise: the default window, chosen from the noise, keeps each joint's peak |τ| within 5 % of the exact one,
    and the band it reports covers the error it leaves."""
    from logmakers import multisine, noisy

    model = load_robot("ur5")
    motion = multisine(model, duration=4.0, rate=500.0, seed=7)
    log = {"t": motion.t} | {f"q_{j}": v for j, v in zip(model.joint_names, noisy(motion.q, 2e-5, seed=1).T)}
    if rates:
        log |= {f"qd_{j}": v for j, v in zip(model.joint_names, noisy(motion.qd, 2e-3, seed=2).T)}
    result = torques_from_log(model, log)
    exact = inverse_dynamics(model, motion.q, motion.qd, motion.qdd)
    peak, exact_peak = np.abs(result.tau).max(axis=0), np.abs(exact).max(axis=0)
    assert np.all(np.abs(peak - exact_peak) <= 0.05 * exact_peak), (peak - exact_peak) / exact_peak
    assert any("chosen from the" in n and "noise" in n for n in result.notes)
    covered = np.abs(result.tau - exact) <= 2 * result.tau_sigma        # the ± of the report: 2 σ_τ
    assert covered.mean() > 0.9                                          # measured 0.94 both ways (Gaussian: 0.95)


def test_a_mimic_joints_own_column_is_checked_not_read(tmp_path):
    """Panda's second finger mimics the first: its logged position is compared with the coupling and never read."""
    from course_dynamics.tools.sources import open_log

    model = load_robot("panda")
    t = np.arange(0.0, 1.0, 0.01)
    q = 0.02 + 0.01 * np.outer(np.sin(3 * t), np.ones(model.n))
    names = ["t"] + [f"q_{j}" for j in model.joint_names] + ["q_panda_finger_joint2"]
    for shift, expected in ((0.0, "within 0.001 throughout): not read"), (0.01, "off by 0.01 at line 53")):
        second = q[:, 7] + shift * (t > 0.505)
        path = tmp_path / f"fingers{shift}.csv"
        rows = np.column_stack([t, q, second])
        path.write_text(",".join(names) + "\n" + "\n".join(",".join(repr(float(x)) for x in r) for r in rows) + "\n")
        log = joint_log(model, open_log(path, model))
        said = [note for note in log.notes if "q_panda_finger_joint2" in note]
        assert len(said) == 1 and "mimics 'panda_finger_joint1'" in said[0] and expected in said[0], said
        np.testing.assert_allclose(log.q, q, rtol=0, atol=1e-15)  # the leader's column, as logged


def test_a_joint_states_bag_with_both_fingers_reads_the_first(tmp_path):
    """ROS joint_states of a Panda list both fingers: the second (a mimic) is checked against the first, not read."""
    import bagmakers

    from course_dynamics.tools.sources import open_log

    model = load_robot("panda")
    t = np.arange(0.0, 1.0, 0.01)
    q = 0.02 + 0.01 * np.outer(np.sin(3 * t), np.ones(model.n))
    both = np.column_stack([q, q[:, 7]])  # every moving joint, the second finger at the first's position
    names = model.joint_names + ("panda_finger_joint2",)
    path = bagmakers.write_joint_states(tmp_path / "fingers", "ros1", names, t, both, np.zeros_like(both),
                                        np.zeros_like(both))
    log = joint_log(model, open_log(path, model))
    said = [note for note in log.notes if "q_panda_finger_joint2" in note]
    assert len(said) == 1 and "within 0.001 throughout): not read" in said[0], log.notes
    assert not any("does not have" in note and "panda_finger_joint2" in note for note in log.notes)
    np.testing.assert_allclose(log.q, q, rtol=0, atol=1e-15)


def test_a_robots_own_recording_on_a_real_clock_is_repaired_as_a_table_is(tmp_path):
    """An RTDE recording and a ROS bag of one motion on a real clock (jitter, a gap, a lone sample, drops) go
    through the one log reader: ``repair`` splits and drops them as it does a table of the same samples."""
    from bagmakers import write_joint_states
    from logmakers import real_clock, sampled_at, write_ur_rtde

    from course_dynamics.tools.sources import open_log

    ur5 = load_robot("ur5")
    t = real_clock(250.0, 2.0, seed=1)
    t -= t[0]                                                # an RTDE recording is read from its start
    motion = sampled_at(ur5, t, seed=2)
    table = {"t": t} | {f"{kind}_{j}": getattr(motion, kind)[:, i] for kind in ("q", "qd")
                        for i, j in enumerate(ur5.joint_names)}
    expected = joint_log(ur5, table, repair=True)
    assert len(expected.segments) == 3 and any(n.startswith("dropped 1 lone sample") for n in expected.notes)
    write_ur_rtde(tmp_path / "rtde.csv", t + 3021.5, motion.q, motion.qd)
    bag = write_joint_states(tmp_path / "run", "ros1", ur5.joint_names, t + 80.0, motion.q, motion.qd)
    for path in (tmp_path / "rtde.csv", bag):
        source = open_log(path, ur5)
        with pytest.raises(InputError, match=r"not on one clock .* and it has 3 gaps .* and 1 lone sample cut off by "
                                             r"the gaps .*: --repair resamples on the median period, splits at the "
                                             r"gaps and drops the lone sample$"):
            joint_log(ur5, source)
        repaired = joint_log(ur5, source, repair=True)
        assert repaired.segments == expected.segments
        said = [[n.split(" (")[0] for n in log.notes if n.startswith(("resampled", "split", "dropped"))]
                for log in (repaired, expected)]                   # a file names its lines, a table its rows
        assert said[0] == said[1] and len(said[0]) == 3
        # stamps written to 1e-8 s (RTDE) or 1 ns (bag) move the median period by about as much: the grid drifts by
        # under 1e-6 s over a segment, and q with it by under that times |qd| (< 3 rad/s)
        np.testing.assert_allclose(repaired.t - repaired.t[0], expected.t, rtol=0, atol=1e-6)   # a bag keeps stamps
        np.testing.assert_allclose(repaired.q, expected.q, rtol=0, atol=3e-6)
