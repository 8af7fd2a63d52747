"""course_dynamics/tools/retiming.py and ``torques --retime``: the smallest uniform time scaling within the limits."""
from __future__ import annotations

import json

import numpy as np
import pytest

from helpers import ROOT, run
from course_dynamics import load_robot
from course_dynamics.core import evaluator
from course_dynamics.core.friction import Friction
from course_dynamics.tools.loads import Payload, with_payload
from course_dynamics.tools.logs import torques_from_log
from course_dynamics.tools.retiming import retime, retimed_log
from course_dynamics.tools.tables import joint_columns

LOG = ROOT / "examples" / "ur5_log.csv"
MAP = ROOT / "examples" / "ur5_log_columns.toml"
Q0 = np.array([0.0, -1.3, 1.1, -1.4, -1.57, 0.0])
STROKE = np.array([0.8, 0.9, -1.0, 0.4, 0.4, 0.3])     # rad, rest to rest
SWING = np.array([1.2, 0.9, -1.4, 1.0, 1.1, 1.5])      # rad, rest to rest: the wrists too fast
PERIOD = 0.8                                           # s: too fast for the UR5 with a 8 kg payload
FRICTION = Friction(viscous=[2.0, 2.0, 1.5, 0.4, 0.4, 0.3], coulomb=[3.0, 3.0, 2.5, 0.6, 0.6, 0.5])


def rest_to_rest(samples: int = 801, stroke=STROKE) -> dict:
    """q = q₀ + s (ωt − sin ωt)/2π over one period: monotone, starting and ending at rest; exact rates."""
    t = np.linspace(0.0, PERIOD, samples)
    w = 2 * np.pi / PERIOD
    q = Q0 + np.outer((w * t - np.sin(w * t)) / (2 * np.pi), stroke)
    qd = np.outer(w * (1 - np.cos(w * t)) / (2 * np.pi), stroke)
    qdd = np.outer(w * w * np.sin(w * t) / (2 * np.pi), stroke)
    names = load_robot("ur5").joint_names
    table = {"t": t}
    for kind, values in (("q", q), ("qd", qd), ("qdd", qdd)):
        table.update(zip(joint_columns((kind,), names), values.T))
    return table


def loaded():
    return with_payload(load_robot("ur5"), Payload(mass=8.0, link="tool0"))


def within(model, log, k, friction, margin) -> bool:
    """τ(k) from the dynamics, Θ̇/k and Θ̈/k² (no split into terms), against the limits less the margin."""
    tau = evaluator.inverse_dynamics(model, log.q, log.qd / k, log.qdd / k**2)
    if friction is not None:
        tau = tau + friction.torques(log.qd / k)
    keep = 1 - margin
    return bool(np.all(np.abs(tau) <= keep * model.effort) and np.all(np.abs(log.qd / k) <= keep * model.velocity))


def brute_force_k(model, log, friction, margin) -> float:
    """The smallest k on a grid (2.3 % steps) beyond which every grid k is within, then bisected to 1e-12."""
    grid = np.geomspace(0.05, 50.0, 300)
    ok = np.array([within(model, log, k, friction, margin) for k in grid])
    assert ok[-1] and not ok[0]
    first = int(np.flatnonzero(~ok)[-1]) + 1          # every grid k from here on is within
    low, high = grid[first - 1], grid[first]
    while high - low > 1e-12 * high:
        middle = 0.5 * (low + high)
        low, high = (low, middle) if within(model, log, middle, friction, margin) else (middle, high)
    return high


@pytest.mark.parametrize("friction", [None, FRICTION], ids=["no friction", "viscous and Coulomb"])
@pytest.mark.parametrize("margin", [0.0, 0.05, 0.1])
def test_k_is_the_brute_force_search_over_k(friction, margin):
    model = loaded()
    result = torques_from_log(model, rest_to_rest(), friction=friction)
    assert result.report.exceeded
    timing = retime(result, friction, margin)
    expected = brute_force_k(model, result.log, friction, margin)
    assert timing.k == pytest.approx(expected, rel=1e-6)
    assert timing.new_duration == pytest.approx(expected * PERIOD, rel=1e-6)
    slower = retimed_log(result, timing.k, friction)
    keep = 1 - margin
    assert not slower.report.exceeded
    assert np.all(slower.report.peak_tau <= keep * model.effort * (1 + 1e-9))
    assert np.all(slower.report.peak_qd <= keep * model.velocity * (1 + 1e-9))
    assert np.allclose(slower.t, timing.k * result.t)


def test_a_motion_bound_by_velocity_is_retimed_by_its_peak_rate():
    model = load_robot("ur5")
    result = torques_from_log(model, rest_to_rest(stroke=SWING))
    timing = retime(result, None, 0.05)
    assert timing.kind == "velocity"
    assert timing.k == pytest.approx(brute_force_k(model, result.log, None, 0.05), rel=1e-6)


def test_the_retimed_log_passes_torques_within_the_margin_through_the_cli(capsys, tmp_path):
    source, out = tmp_path / "fast.csv", tmp_path / "retimed.csv"
    table = rest_to_rest()
    np.savetxt(source, np.column_stack(list(table.values())), delimiter=",", header=",".join(table), comments="")
    code, report, err = run(capsys, "torques", "ur5", "--log", str(source), "--payload", "8@tool0", "--retime",
                            "--margin", "0.1", "--out", str(out))
    assert code == 1 and "LIMIT EXCEEDED" in report
    line = next(x for x in report.splitlines() if x.startswith("retimed: k = "))
    k = float(line.split("k = ")[1].split(",")[0])
    assert f"{PERIOD:g} s -> {k * PERIOD:.6g} s" in line
    assert "wrote 801 rows of the retimed log" in err
    code, document, _ = run(capsys, "torques", "ur5", "--log", str(out), "--payload", "8@tool0", "--json")
    record = json.loads(document)
    assert code == 0 and not record["exceeded"]
    assert max(max(j["effort_used"], j["velocity_used"]) for j in record["joints"]) <= 0.9 + 1e-9
    assert max(max(j["effort_used"], j["velocity_used"]) for j in record["joints"]) >= 0.9 - 1e-6   # k is smallest


def test_gravity_alone_over_the_limit_is_refused_in_one_line(capsys, tmp_path):
    out = tmp_path / "retimed.csv"
    code, report, err = run(capsys, "torques", "ur5", "--log", str(LOG), "--map", str(MAP), "--payload", "20@tool0",
                            "--retime", "--out", str(out))
    assert code == 1 and not out.exists()
    lines = [x for x in report.splitlines() if "retime" in x]
    assert len(lines) == 1 and lines[0].startswith("cannot retime: joint 'shoulder_lift_joint': gravity")
    static = float(lines[0].split("alone need ")[1].split(" ")[0])
    assert 180 < static < 190 and "effort limit 150" in lines[0]
    code, document, _ = run(capsys, "torques", "ur5", "--log", str(LOG), "--map", str(MAP), "--payload", "20@tool0",
                            "--retime", "--json")
    timing = json.loads(document)["retiming"]
    assert timing["k"] is None and timing["kind"] == "static" and timing["static"] == pytest.approx(static, rel=1e-3)


@pytest.mark.parametrize("margin", ["0.1", "0.05"])  # the default's own value, given, is still given
def test_margin_needs_retime(capsys, margin):
    code, _, err = run(capsys, "torques", "ur5", "--log", str(LOG), "--map", str(MAP), "--margin", margin)
    assert code == 2 and err.startswith("error: --margin") and len(err.strip().splitlines()) == 1


def test_the_uniform_duration_is_no_shorter_than_toppras_time_optimal_one():
    import toppra  # the test extra installs it: a missing reference is a failure, not a skip
    import toppra.algorithm
    import toppra.constraint

    model, margin = loaded(), 0.05
    friction = Friction(viscous=np.zeros(6), coulomb=[3.0, 3.0, 2.5, 0.6, 0.6, 0.5])  # TOPP-RA's friction: Coulomb
    result = torques_from_log(model, rest_to_rest(), friction=friction)
    uniform = retime(result, friction, margin).new_duration
    keep = 1 - margin
    s = np.linspace(0.0, 1.0, 101)           # the motion's path: the straight line from Q0 along STROKE
    path = toppra.SplineInterpolator(s, Q0 + np.outer(s, STROKE))
    constraints = [
        toppra.constraint.JointVelocityConstraint(np.column_stack([-keep * model.velocity, keep * model.velocity])),
        toppra.constraint.JointTorqueConstraint(
            lambda q, qd, qdd: evaluator.inverse_dynamics(model, q, qd, qdd),
            np.column_stack([-keep * model.effort, keep * model.effort]), friction.coulomb),
    ]
    gridpoints = np.linspace(0.0, 1.0, 1001)
    algorithm = toppra.algorithm.TOPPRA(constraints, path, gridpoints=gridpoints)
    trajectory = algorithm.compute_trajectory(0.0, 0.0)
    assert trajectory is not None
    optimal = trajectory.duration
    tolerance = 0.01 * optimal          # constraints held at 1001 gridpoints only
    assert uniform >= optimal - tolerance
    assert optimal < uniform            # on this motion the time-optimal one is strictly shorter
