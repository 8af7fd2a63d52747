"""course_dynamics/tools/simulation.py: integrators, energy, round trip, limits, bad input."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from course_dynamics import inverse_dynamics, load_robot, robot_path
from course_dynamics.core.forward_dynamics import forward_dynamics
from course_dynamics.cli.commands import simulate as simulate_command
from course_dynamics.core.drives import Drives
from course_dynamics.core.friction import Friction
from course_dynamics.tools.simulation import (
    STABLE_STEP,
    SimulationError,
    TorqueTable,
    simulate,
    total_energy,
)

# Released 65° from hanging (q1 = 0 is upright for this URDF): large, nonlinear swings of both links.
DOUBLE_PENDULUM_START = ([2.0, 0.0], [0.0, 0.0])


@pytest.fixture(scope="module")
def double_pendulum():
    return load_robot("double_pendulum_continuous")


def test_rk4_conserves_energy_over_ten_seconds(double_pendulum):
    """10 s, dt = 1 ms, no torque, no friction: |E − E₀| ≤ 1e-6 |E₀|."""
    trajectory = simulate(double_pendulum, *DOUBLE_PENDULUM_START, duration=10.0, dt=1e-3, integrator="rk4")
    assert len(trajectory.t) == 10_001 and trajectory.t[-1] == 10.0
    drift = np.abs(trajectory.energy - trajectory.energy[0]).max() / abs(trajectory.energy[0])
    assert drift <= 1e-6, drift
    assert np.abs(trajectory.q[:, 0] - 2.0).max() > 1.0  # it really swung


def test_notes_euler_drifts_where_rk4_does_not(double_pendulum):
    runs = {name: simulate(double_pendulum, *DOUBLE_PENDULUM_START, duration=1.0, dt=1e-3, integrator=name)
            for name in ("euler", "semi-implicit", "rk4", "adaptive")}
    drift = {name: np.abs(r.energy - r.energy[0]).max() / abs(r.energy[0]) for name, r in runs.items()}
    assert drift["euler"] > drift["semi-implicit"] > 1e-2  # first order: percent-level energy errors
    assert drift["rk4"] < 1e-6
    assert drift["adaptive"] < 1e-8
    np.testing.assert_allclose(runs["rk4"].q, runs["adaptive"].q, atol=1e-7)


def test_euler_step_is_exactly_6_116_and_6_117(double_pendulum):
    q0, qd0, dt = np.array([2.0, 0.3]), np.array([0.5, -1.0]), 0.01
    # the recursions on both sides (an earlier test's work may have switched this model to its compiled path)
    trajectory = simulate(double_pendulum, q0, qd0, duration=dt, dt=dt, integrator="euler", compiled=False)
    qdd = forward_dynamics(double_pendulum, q0, qd0, np.zeros(2))
    np.testing.assert_array_equal(trajectory.qd[1], qd0 + qdd * dt)  # (6.116)
    np.testing.assert_array_equal(trajectory.q[1], q0 + qd0 * dt + 0.5 * qdd * dt**2)  # (6.117)


def test_friction_never_adds_energy(double_pendulum):
    friction = Friction(viscous=[0.002, 0.002], coulomb=[0.001, 0.001], smoothing=0.05)
    trajectory = simulate(double_pendulum, *DOUBLE_PENDULUM_START, duration=3.0, dt=1e-3, friction=friction)
    steps = np.diff(trajectory.energy)
    assert np.all(steps <= 1e-9 * abs(trajectory.energy[0])), steps.max()
    assert trajectory.energy[-1] < trajectory.energy[0] - 0.01


@pytest.mark.parametrize("integrator", ["euler", "semi-implicit", "rk4"])
def test_friction_too_steep_for_the_step_is_warned_where_the_step_cannot_follow_it(integrator):
    """A free pendulum (I = 1 kg·m², no gravity) sliding on tanh friction of slope c / smoothing = 100 N·m·s/rad:
    below the integrator's bound dt · 100 < STABLE_STEP its velocity dies out and nothing is said; above it the
    velocity keeps oscillating about zero from step to step, and the warning names the joint and the step."""
    arm = load_robot("pendulum").with_gravity([0.0, 0.0, 0.0])
    friction = Friction(viscous=[0.0], coulomb=[1.0], smoothing=0.01)
    for factor, steep in ((0.9, False), (1.1, True)):
        dt = factor * STABLE_STEP[integrator] / 100.0
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            run = simulate(arm, [0.0], [1e-3], 400 * dt, dt, integrator=integrator, friction=friction)
        said = [str(w.message) for w in caught if "too steep" in str(w.message)]
        assert bool(said) == steep, said
        late = np.abs(run.qd[-50:, 0]).max()
        assert (late > 1e-4) if steep else (late < 1e-12), (factor, late)
        if steep:
            limit = {"euler": "0.02", "semi-implicit": "0.02", "rk4": "0.027"}[integrator]  # 2.785/100 rounded down
            assert "joint 'theta'" in said[0] and f"dt below {limit} s" in said[0], said[0]
    with pytest.warns(UserWarning, match="member 0's joint 'theta'"):  # an ensemble's: the steepest member's
        simulate(arm, [[0.0], [1.0]], [1e-3], 10 * dt, dt, integrator=integrator, friction=friction)


def test_coulomb_friction_without_smoothing_and_gentle_friction_are_not_warned():
    arm = load_robot("ur5")
    for friction in (Friction(viscous=np.full(6, 0.05), coulomb=np.full(6, 0.5)),               # sgn: no slope
                     Friction(viscous=np.full(6, 0.05), coulomb=np.full(6, 0.5), smoothing=0.1)):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            simulate(arm, np.zeros(6), np.zeros(6), 0.02, 5e-3, integrator="euler", friction=friction)


def test_round_trip_recovers_applied_torques():
    """Simulate under a callable torque, then feed Θ, Θ̇, Θ̈ back to inverse dynamics."""
    model = load_robot("ur5")
    torque = lambda t, q, qd: np.array([2.0 * np.sin(3 * t), 10.0, -5.0, 1.0, 0.5 * t, -0.2]) - 0.5 * qd  # noqa: E731
    trajectory = simulate(model, np.zeros(6), np.zeros(6), duration=0.3, dt=1e-3, torque=torque)
    recovered = inverse_dynamics(model, trajectory.q, trajectory.qd, trajectory.qdd)
    np.testing.assert_allclose(recovered, trajectory.tau, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(trajectory.tau[:, 1], 10.0 - 0.5 * trajectory.qd[:, 1])


def test_torque_table_interpolates_linearly():
    table = TorqueTable(t=[0.0, 1.0], tau=[[0.0, 2.0], [1.0, 4.0]])
    np.testing.assert_allclose(table(0.25), [0.25, 2.5])
    np.testing.assert_allclose(table(5.0), [1.0, 4.0])  # held after the last row
    model = load_robot("two_link")
    trajectory = simulate(model, [0, 0], [0, 0], duration=0.1, dt=0.01, torque=table)
    np.testing.assert_allclose(trajectory.tau[:, 0], trajectory.t)


def test_energy_is_kinetic_plus_potential():
    model = load_robot("pendulum")
    trajectory = simulate(model, [1.0], [0.0], duration=0.5, dt=1e-3)
    expected = 0.5 * trajectory.qd[:, 0] ** 2 - 9.81 * np.cos(trajectory.q[:, 0])  # m = l = 1; u_ref at the pivot
    np.testing.assert_allclose(trajectory.energy, expected, rtol=1e-12, atol=1e-12)


def test_total_energy_agrees_with_pinocchio():
    """k + u (6.71), (6.73) against Pinocchio's computeKineticEnergy + computePotentialEnergy."""
    from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
    from course_dynamics_reference.validate import random_states

    model = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), model.joint_names)
    q, qd, _ = random_states(model, 20, seed=4)
    energy = total_energy(model, q, qd)
    for k in range(len(q)):
        expected = oracle.kinetic_energy(q[k], qd[k]) + oracle.potential_energy(q[k])
        assert abs(energy[k] - expected) <= 1e-12 * (1 + abs(expected))


def test_limits_are_reported_or_enforced():
    model = load_robot("rp_arm")  # d2 in [0.1, 0.8]; held horizontal, d2 slides freely
    push = [0.0, 5.0]
    reported = simulate(model, [0.0, 0.5], [0.0, 0.0], duration=1.0, dt=1e-3, torque=push, limits="report")
    assert reported.q[:, 1].max() > 0.8
    assert len(reported.events) == 1 and "joint 'd2' passed its upper limit 0.8" in reported.events[0]
    stopped = simulate(model, [0.0, 0.5], [0.0, 0.0], duration=1.0, dt=1e-3, torque=push, limits="stop")
    assert stopped.q[:, 1].max() == 0.8 and stopped.qd[-1, 1] == 0.0
    assert "joint 'd2' stopped at its upper limit 0.8" in stopped.events[0]


@pytest.mark.parametrize("kwargs, message", [
    (dict(dt=0.0), "dt must be a positive number"),
    (dict(dt=-1e-3), "dt must be a positive number"),
    (dict(duration=0.0), "duration must be a positive number"),
    (dict(duration=float("nan")), "duration must be a positive number"),
    (dict(integrator="leapfrog"), "unknown integrator 'leapfrog'"),
    (dict(limits="bounce"), "unknown limits mode 'bounce'"),
    (dict(integrator="adaptive", limits="stop"), "needs a fixed-step integrator"),
    (dict(torque=lambda t, q, qd: np.array([np.inf, 0.0])), "the torque at t = 0 s is \\[inf, 0.0\\]"),
])
def test_bad_input(kwargs, message):
    model = load_robot("two_link")
    arguments = {"duration": 0.1, "dt": 0.01, **kwargs}
    with pytest.raises(SimulationError, match=message):
        simulate(model, [0, 0], [0, 0], **arguments)


def test_constant_torque_must_be_finite():
    with pytest.raises(ValueError, match="torque for joint 'theta2' is nan"):
        simulate(load_robot("two_link"), [0, 0], [0, 0], duration=0.1, dt=0.01, torque=[0.0, float("nan")])


@pytest.mark.parametrize("compiled", [False, True])
def test_a_state_that_blows_up_is_an_error(compiled):
    """Θ̇ overflows on either path (with a τ of 1e300 the compiled programs kept a finite, 1e300-sized state
    where products inside the interpreted recursion overflowed, so which path ran decided the outcome)."""
    model = load_robot("pendulum")
    with np.errstate(over="ignore", invalid="ignore"):
        with pytest.raises(SimulationError, match="the state became non-finite near t = 2 s \\(try a smaller dt\\)"):
            simulate(model, [0.1], [0.0], duration=4.0, dt=2.0, integrator="euler", compiled=compiled,
                     torque=lambda t, q, qd: np.array([1e308]))


def test_compiled_and_interpreted_runs_agree():
    model = load_robot("ur5")
    q0 = np.array([0.0, -1.2, 1.0, -0.5, 0.5, 0.0])
    fast = simulate(model, q0, np.zeros(6), duration=0.3, dt=1e-3, compiled=True)
    slow = simulate(model, q0, np.zeros(6), duration=0.3, dt=1e-3, compiled=False)
    np.testing.assert_allclose(fast.q, slow.q, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(fast.qdd, slow.qdd, rtol=1e-9, atol=1e-10)


@pytest.mark.parametrize("integrator", ["euler", "semi-implicit", "rk4", "adaptive"])
def test_an_ensemble_is_its_members_run_one_by_one(double_pendulum, integrator):
    rng = np.random.default_rng(5)
    q0 = np.array([2.0, 0.0]) + 0.01 * rng.standard_normal((4, 2))
    qd0 = 0.1 * rng.standard_normal((4, 2))
    together = simulate(double_pendulum, q0, qd0, duration=0.2, dt=1e-3, integrator=integrator)
    assert together.q.shape == (201, 4, 2) and together.energy.shape == (201, 4) and together.members == 4
    for k in range(4):
        alone = simulate(double_pendulum, q0[k], qd0[k], duration=0.2, dt=1e-3, integrator=integrator)
        # the adaptive integrator's shared step differs from a member's own: both meet rtol = atol = 1e-10
        tolerance = 1e-7 if integrator == "adaptive" else 1e-12
        np.testing.assert_allclose(together.q[:, k], alone.q, rtol=tolerance, atol=tolerance)
        np.testing.assert_allclose(together.tau[:, k], alone.tau, atol=1e-12)
    header, rows = together.table()
    assert header[:2] == ["t", "member"] and rows.shape == (201 * 4, 2 + 4 * 2 + 1)


def test_ensemble_limits_name_the_member():
    model = load_robot("rp_arm")
    q0 = np.array([[0.0, 0.5], [0.0, 0.3]])
    run = simulate(model, q0, np.zeros(2), duration=1.0, dt=1e-3, torque=[0.0, 5.0], limits="stop")
    assert run.q[:, :, 1].max() == 0.8
    assert any("member 0: joint 'd2' stopped at its upper limit 0.8" in e for e in run.events)
    assert any("member 1: joint 'd2' stopped" in e for e in run.events)


def test_ensemble_matches_pinocchio_aba_members():
    """1000 double pendulums through our compiled dynamics and through aba in the same RK4 loop."""
    from course_dynamics_reference.pinocchio_oracle import PinocchioOracle

    model = load_robot("double_pendulum_continuous")
    oracle = PinocchioOracle(robot_path("double_pendulum_continuous"), model.joint_names)

    def aba(q, qd, tau):
        rows = [oracle.aba(a, b, c) for a, b, c in zip(q.reshape(-1, 2), qd.reshape(-1, 2), tau.reshape(-1, 2))]
        return np.reshape(rows, q.shape)

    q0 = np.array([2.0, 0.0]) + 1e-3 * np.random.default_rng(0).standard_normal((50, 2))
    ours = simulate(model, q0, np.zeros(2), duration=0.1, dt=1e-3)
    theirs = simulate(model, q0, np.zeros(2), duration=0.1, dt=1e-3, dynamics=aba)
    np.testing.assert_allclose(ours.q[-1], theirs.q[-1], rtol=0, atol=1e-12)


def test_a_too_large_ensemble_is_refused_before_its_perturbations_are_drawn(capsys, tmp_path, monkeypatch):
    """K members are checked against the budget first (no (K, n) array is made), and the advice names --ensemble."""
    from helpers import assert_one_line_error, run

    monkeypatch.setattr(np.random, "default_rng", lambda *a, **k: pytest.fail("drew the perturbations before checking"))
    out = tmp_path / "x.csv"
    code, _, err = run(capsys, "simulate", "ur5", "--q0", "0,0,0,0,0,0", "--duration", "1", "--dt", "0.01",
                       "--out", str(out), "--ensemble", "100000000")
    assert_one_line_error(code, err, "of memory", "fewer --ensemble members (100000000 asked)", "larger dt")
    assert not out.exists()


def test_an_ensemble_under_stop_is_its_members_run_one_by_one():
    """Members reaching their limits at different times are stopped each on its own: the ensemble's stops and
    states are those of its members run alone."""
    model = load_robot("rrr_arm")
    q0 = np.array([[0.0, 1.5, 2.0], [0.2, -1.0, 1.0], [0.0, 0.0, 0.0]])
    qd0 = np.array([[1.0, 2.0, 3.0], [-1.0, -3.0, 1.0], [0.0, 0.0, 0.0]])
    together = simulate(model, q0, qd0, duration=0.5, dt=1e-3, limits="stop")
    assert {stop.member for stop in together.stops} == {0, 1, 2}
    assert len({next(s.t for s in together.stops if s.member == k) for k in range(3)}) == 3  # each at its own time
    for k in range(3):
        alone = simulate(model, q0[k], qd0[k], duration=0.5, dt=1e-3, limits="stop")
        np.testing.assert_allclose(together.q[:, k], alone.q, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(together.reaction[:, k], alone.reaction, rtol=1e-10, atol=1e-10)
        mine = [stop for stop in together.stops if stop.member == k]
        assert [(s.t, s.joints) for s in mine] == [(s.t, s.joints) for s in alone.stops]


def test_a_start_beyond_a_limit_is_refused_under_stop():
    with pytest.raises(SimulationError, match="q0 for joint 'd2' is 0.9, beyond its upper limit 0.8"):
        simulate(load_robot("rp_arm"), [0.0, 0.9], [0.0, 0.0], duration=0.1, dt=0.01, limits="stop")
    with pytest.raises(SimulationError, match="is 0.800000001, beyond its upper limit 0.8:"):  # digits that differ
        simulate(load_robot("rp_arm"), [0.0, 0.8 + 1e-9], [0.0, 0.0], duration=0.1, dt=0.01, limits="stop")


def test_the_cli_stops_a_panda_at_its_limits_without_adding_energy(capsys, tmp_path, monkeypatch):
    """`simulate panda --limits stop` from the Panda start that used to gain 570 J: the JSON's energy never rises
    above the start plus the integrator's drift under --limits report, each stop is listed with its time, joints
    and the kinetic energy it took (≤ 0), and the text output says the same."""
    import json

    from helpers import run

    common = ["simulate", "panda", "--q0", "0,0,0,-1.5,0,1.5,0.7,0.02", "--duration", "2", "--dt", "0.001",
              "--quiet", "--json"]
    code, out, _ = run(capsys, *common, "--limits", "report", "--out", str(tmp_path / "report.csv"))
    assert code == 0
    report = np.genfromtxt(tmp_path / "report.csv", delimiter=",", names=True)["energy"]
    drift = np.abs(report - report[0]).max()
    code, out, err = run(capsys, *common, "--limits", "stop", "--out", str(tmp_path / "stop.csv"))
    assert code == 0 and "warning" not in err
    summary = json.loads(out)
    assert summary["energy_max"] <= summary["energy_start"] + drift
    stopped = np.genfromtxt(tmp_path / "stop.csv", delimiter=",", names=True)["energy"]
    assert stopped.max() == summary["energy_max"]
    assert summary["stops"] and all(stop["energy"] <= 1e-12 * (1 + stop["kinetic_before"])
                                    for stop in summary["stops"])
    first = summary["stops"][0]
    assert first["joints"] == ["panda_joint2"] and first["sides"] == ["upper"] and first["limits"] == [1.7628]
    assert 0.4 < first["t"] < 0.55 and first["energy"] == first["kinetic_after"] - first["kinetic_before"] < -10
    assert summary["stops_energy"] == pytest.approx(sum(stop["energy"] for stop in summary["stops"]), rel=1e-12)
    assert len(summary["stops"]) == 9      # the fingers move as one (the second mimics the first)
    monkeypatch.setattr(simulate_command, "STOPS_SHOWN", 5)
    code, out, _ = run(capsys, *common[:-1], "--limits", "stop", "--out", str(tmp_path / "stop.csv"))
    lines = out.splitlines()
    assert lines[1].startswith(f"9 joint stops took {-summary['stops_energy']:.6g} J")
    assert "joint 'panda_joint2' stopped at its upper limit 1.7628 (kinetic energy" in lines[2]
    assert len(lines) == 2 + 5 + 1 and lines[-1] == "  … and 4 more (--json lists every stop)"


def test_a_simulation_with_rotors_conserves_the_energy_that_includes_them():
    """No friction, no torque: k + u + ½ Iₐ Θ̇² stays put (RK4, small dt), and without the rotors' term it would not."""
    arm = load_robot("two_link")
    drives = Drives(armature=[0.3, 0.2], offset=[0.0, 0.0])
    trajectory = simulate(arm, [0.4, -0.3], [1.0, -2.0], duration=1.0, dt=2e-3, drives=drives)
    assert np.ptp(trajectory.energy) < 1e-8 * abs(trajectory.energy).max()
    links_only = total_energy(arm, trajectory.q, trajectory.qd)
    assert np.ptp(links_only) > 1e-3
    plain = simulate(arm, [0.4, -0.3], [1.0, -2.0], duration=1.0, dt=2e-3)
    assert np.abs(plain.q[-1] - trajectory.q[-1]).max() > 1e-2   # the rotors change the motion


def test_a_joint_stop_with_rotors_never_adds_energy():
    arm = load_robot("two_link")
    drives = Drives(armature=[0.3, 0.2], offset=[0.0, 0.0])
    trajectory = simulate(arm, [0.0, 0.0], [0.0, 0.0], duration=1.5, dt=2e-3, torque=[0.0, 40.0], drives=drives,
                    limits="stop")
    assert all(stop.energy <= 1e-12 for stop in trajectory.stops)


def test_drives_need_our_own_dynamics():
    arm = load_robot("two_link")
    with pytest.raises(SimulationError, match="drives"):
        simulate(arm, [0.0, 0.0], [0.0, 0.0], 0.01, 1e-3, drives=Drives([0.1, 0.1], [0.0, 0.0]),
                 dynamics=lambda q, qd, tau: np.zeros_like(q))


def test_simulate_with_drives_reports_the_rotors_energy(capsys, tmp_path):
    import json

    from helpers import run

    drives = tmp_path / "drives.toml"
    drives.write_text("[joint.theta1]\narmature = 0.3\n[joint.theta2]\narmature = 0.2\n")
    code, out, err = run(capsys, "simulate", "two_link", "--q0", "0.4,-0.3", "--qd0", "1,-2", "--duration", "1",
                         "--dt", "0.001", "--drives", str(drives), "--out", str(tmp_path / "sim.csv"), "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["energy_end"] == pytest.approx(summary["energy_start"], rel=1e-8)
    plain = total_energy(load_robot("two_link"), [0.4, -0.3], [1.0, -2.0])
    assert summary["energy_start"] == pytest.approx(plain + 0.5 * (0.3 * 1 + 0.2 * 4), rel=1e-12)


def test_the_energy_of_many_samples_is_taken_a_block_at_a_time_to_the_same_values(monkeypatch):
    """k = ½ Θ̇ᵀ M Θ̇ (6.71) with M by the evaluator, a block of samples at a time (M's memory on a long run)."""
    from course_dynamics.core.dynamics import kinetic_energy
    from course_dynamics.core.kinematics import potential_energy
    from course_dynamics.tools import simulation

    model = load_robot("ur5")
    q, qd = np.random.default_rng(2).uniform(-1, 1, (2, 30, 4, 6))
    whole = total_energy(model, q, qd)
    monkeypatch.setattr(simulation, "ENERGY_BLOCK", 7)
    blocks = total_energy(model, q, qd)
    expected = kinetic_energy(model, q, qd) + potential_energy(model, q)
    assert blocks.shape == (30, 4)
    np.testing.assert_allclose(blocks, whole, rtol=0, atol=1e-13 * np.abs(expected).max())
    np.testing.assert_allclose(blocks, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
