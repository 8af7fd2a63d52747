"""The sample robot logs in ``examples/``, written by the tests' own generators from a known motion.

``python tests/examplelogs.py`` writes them again (the same recording as RTDE, ``rostopic echo -p`` and PlotJuggler
CSVs, and bags); ``tests/test_examplelogs.py`` checks that the files in
``examples/`` are what these generators write today. The motion is the multi-sine of ``logmakers``; the
robot that "recorded" it carries a 1.5 kg tool the URDF lacks (so the residual report has something to find),
and the recorders add noise and drop samples as real ones do.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bagmakers import write_franka, write_joint_states  # noqa: E402
from logmakers import dropped, multisine, noisy, real_clock, sampled_at, write_ur_rtde  # noqa: E402

from course_dynamics import load_robot  # noqa: E402
from course_dynamics.core.newton_euler import inverse_dynamics  # noqa: E402
from course_dynamics.tools.loads import Payload, with_payload  # noqa: E402

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
TOOL = Payload(mass=1.5, link="tool0", com=(0.0, 0.0, 0.05))   # what the UR5 carries and its URDF does not
UR5_TORQUE_CONSTANTS = (13.0, 13.0, 9.3, 4.5, 4.5, 4.5)        # N m/A, as given to --torque-constant
DROPPED = (137, 138, 301)                                       # samples the recorder lost
EPOCH_NS = 1_700_000_000 * 10**9 + 512_000   # a ROS clock: ns since the epoch (the first stamp, a multiple of 256 ns)
ARM_ORDER = (2, 1, 0, 3, 4, 5)               # the order a UR driver publishes its joints in (elbow first)
GRIPPER = ("finger_joint",)                  # a gripper's joint the arm's URDF lacks


def write_rostopic(path, joints, t, q, qd, effort, gripper=GRIPPER, seed=7):
    """``rostopic echo -p /joint_states > path``: one row a message, as rostopic's ``-p`` writes it.

    ``%time`` is the receive time (ns since the epoch: the stamp plus a latency), ``field.header.stamp`` the
    stamp (ns), ``field.header.frame_id`` empty, the names on every row, then ``field.positionK``,
    ``field.velocityK``, ``field.effortK`` (Python's ``str`` of each float) in the message's joint order.
    """
    rng = np.random.default_rng(seed)
    order = [joints[i] for i in ARM_ORDER if i < len(joints)] + [j for j in joints if j not in
                                                                 [joints[i] for i in ARM_ORDER if i < len(joints)]]
    names = order + list(gripper)
    index = [list(joints).index(j) for j in order]
    stamps = EPOCH_NS + np.round((t - t[0]) * 1e9).astype(np.int64)
    received = stamps + rng.integers(300_000, 1_500_000, len(t))
    n = len(names)
    header = (["%time", "field.header.seq", "field.header.stamp", "field.header.frame_id"]
              + [f"field.name{k}" for k in range(n)] + [f"field.{f}{k}" for f in ("position", "velocity", "effort")
                                                        for k in range(n)])
    rows = [",".join(header)]
    for r in range(len(t)):
        finger = 0.4 + 0.3 * np.sin(t[r] - t[0])
        values = [list(x[r, index]) + [v] * len(gripper) for x, v in ((q, finger), (qd, 0.0), (effort, 0.0))]
        cells = [str(received[r]), str(48211 + r), str(stamps[r]), ""] + names
        rows.append(",".join(cells + [str(float(v)) for group in values for v in group]))
    Path(path).write_text("\n".join(rows) + "\n")
    return Path(path)


def write_plotjuggler(path, joints, t, q, qd, effort, topic="/joint_states", gripper=GRIPPER):
    """PlotJuggler's "Export to CSV" of a JointState topic and a gripper's at another rate, as it writes it.

    ``__time`` (s since the epoch, 6 decimals), then the series sorted by name (``<topic>/header/seq``,
    ``<topic>/header/stamp``, ``<topic>/<joint>/position``, …), 9 decimals, one row per time any series has a
    sample, empty where a series has none (the gripper's rows have no arm sample, and the other way round).
    """
    epoch = EPOCH_NS * 1e-9 + (t - t[0])
    series = {f"{topic}/header/seq": (epoch, 48211 + np.arange(len(t))), f"{topic}/header/stamp": (epoch, epoch)}
    for i, joint in enumerate(joints):
        for field, x in (("position", q), ("velocity", qd), ("effort", effort)):
            series[f"{topic}/{joint}/{field}"] = (epoch, x[:, i])
    grip_t = np.arange(epoch[0] + 0.0013, epoch[-1], 0.1)    # the gripper's own topic at 10 Hz
    for joint in gripper:
        series[f"/gripper/joint_states/{joint}/position"] = (grip_t, 0.4 + 0.3 * np.sin(grip_t - grip_t[0]))
        series[f"/gripper/joint_states/{joint}/effort"] = (grip_t, np.zeros(len(grip_t)))
    names = sorted(series)
    times = sorted({f"{x:.6f}" for name in names for x in series[name][0]}, key=float)
    cells = {name: {f"{x:.6f}": f"{v:.9f}" for x, v in zip(*series[name])} for name in names}
    rows = ["__time," + ",".join(names)] + [",".join([time] + [cells[name].get(time, "") for name in names])
                                             for time in times]
    Path(path).write_text("\n".join(rows) + "\n")
    return Path(path)


def ur5_recording():
    """UR5, 2 s at 250 Hz (t from 3021.5 s, the controller's clock): q, qd and the measured torques, as recorded."""
    model = load_robot("ur5")
    motion = dropped(multisine(model, duration=2.0, rate=250.0, seed=21, start=3021.5), DROPPED)
    tau = inverse_dynamics(with_payload(model, TOOL), motion.q, motion.qd, motion.qdd)
    return motion, noisy(motion.q, 2e-5, seed=1), noisy(motion.qd, 2e-3, seed=2), noisy(tau, 0.05, seed=3)


def ur5_real_clock():
    """UR5, 2 s at about 250 Hz on a real recorder's clock (``logmakers.real_clock``: every step within ±20 %, a gap of
    40 periods, a lone sample between two gaps, two rows dropped), t from 3021.5 s; the tool and noise of
    :func:`ur5_recording`."""
    model = load_robot("ur5")
    motion = sampled_at(model, 3021.5 + real_clock(250.0, 2.0, seed=5), seed=21)
    tau = inverse_dynamics(with_payload(model, TOOL), motion.q, motion.qd, motion.qdd)
    return motion, noisy(motion.q, 2e-5, seed=1), noisy(motion.qd, 2e-3, seed=2), noisy(tau, 0.05, seed=3)


def write_examples(folder: Path = EXAMPLES) -> dict[str, Path]:
    """Every sample log, into ``folder``; their paths by name."""
    ur5 = load_robot("ur5")
    motion, q, qd, tau = ur5_recording()
    paths = {"ur5_rtde": folder / "ur5_rtde.csv"}
    current = tau / np.array(UR5_TORQUE_CONSTANTS)
    write_ur_rtde(paths["ur5_rtde"], motion.t, q, qd, current=current, target_q=motion.q, mode_words=True)
    real, real_q, real_qd, real_tau = ur5_real_clock()
    paths["ur5_rtde_real_clock"] = folder / "ur5_rtde_real_clock.csv"
    write_ur_rtde(paths["ur5_rtde_real_clock"], real.t, real_q, real_qd,
                  current=real_tau / np.array(UR5_TORQUE_CONSTANTS))
    paths["ur5_joint_states.bag"] = write_joint_states(folder / "ur5_joint_states", "ros1", ur5.joint_names,
                                                       motion.t, q, qd, tau)
    paths["ur5_joint_states.mcap"] = write_joint_states(folder / "ur5_joint_states", "mcap", ur5.joint_names,
                                                        motion.t, q, qd, tau)
    paths["ur5_rostopic"] = write_rostopic(folder / "ur5_rostopic.csv", ur5.joint_names, motion.t, q, qd, tau)
    paths["ur5_plotjuggler"] = write_plotjuggler(folder / "ur5_plotjuggler.csv", ur5.joint_names, motion.t, q, qd, tau)
    panda = load_robot("panda")
    arm = multisine(panda, duration=2.0, rate=50.0, seed=22, start=80.0)   # franka_states at 50 Hz: small
    state = [np.column_stack([x[:, :7], np.full((len(arm.t), 1), fill)]) for x, fill in
             ((arm.q, 0.02), (arm.qd, 0.0), (arm.qdd, 0.0))]
    tau_j = inverse_dynamics(panda, *state)[:, :7]
    paths["panda_franka.bag"] = write_franka(folder / "panda_franka", "ros1", panda.joint_names,
                                             arm.t, noisy(arm.q[:, :7], 1e-5, seed=4), noisy(arm.qd[:, :7], 1e-3, seed=5),
                                             noisy(tau_j, 0.05, seed=6))
    return paths


NAMES = ("ur5_rtde.csv", "ur5_rtde_real_clock.csv", "ur5_rostopic.csv", "ur5_plotjuggler.csv", "ur5_joint_states.bag",
         "ur5_joint_states.mcap", "panda_franka.bag")


if __name__ == "__main__":   # the examples are ours: written again from scratch
    for name in NAMES:
        (EXAMPLES / name).unlink(missing_ok=True)
    for path in write_examples().values():
        print(f"wrote {path.relative_to(EXAMPLES.parent)} ({path.stat().st_size // 1024} KiB)")
