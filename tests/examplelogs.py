"""The sample robot logs in ``examples/``, written by the tests' own generators from a known motion.

``python tests/examplelogs.py`` writes them again; ``tests/test_examplelogs.py`` checks that the files in
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
from logmakers import dropped, multisine, noisy, write_ur_rtde  # noqa: E402

from course_dynamics import load_robot  # noqa: E402
from course_dynamics.core.newton_euler import inverse_dynamics  # noqa: E402
from course_dynamics.tools.loads import Payload, with_payload  # noqa: E402

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
TOOL = Payload(mass=1.5, link="tool0", com=(0.0, 0.0, 0.05))   # what the UR5 carries and its URDF does not
UR5_TORQUE_CONSTANTS = (13.0, 13.0, 9.3, 4.5, 4.5, 4.5)        # N m/A, as given to --torque-constant
DROPPED = (137, 138, 301)                                       # samples the recorder lost


def ur5_recording():
    """UR5, 2 s at 250 Hz (t from 3021.5 s, the controller's clock): q, qd and the measured torques, as recorded."""
    model = load_robot("ur5")
    motion = dropped(multisine(model, duration=2.0, rate=250.0, seed=21, start=3021.5), DROPPED)
    tau = inverse_dynamics(with_payload(model, TOOL), motion.q, motion.qd, motion.qdd)
    return motion, noisy(motion.q, 2e-5, seed=1), noisy(motion.qd, 2e-3, seed=2), noisy(tau, 0.05, seed=3)


def write_examples(folder: Path = EXAMPLES) -> dict[str, Path]:
    """Every sample log, into ``folder``; their paths by name."""
    ur5 = load_robot("ur5")
    motion, q, qd, tau = ur5_recording()
    paths = {"ur5_rtde": folder / "ur5_rtde.csv"}
    current = tau / np.array(UR5_TORQUE_CONSTANTS)
    write_ur_rtde(paths["ur5_rtde"], motion.t, q, qd, current=current, target_q=motion.q, mode_words=True)
    paths["ur5_joint_states.bag"] = write_joint_states(folder / "ur5_joint_states", "ros1", ur5.joint_names,
                                                       motion.t, q, qd, tau)
    paths["ur5_joint_states.mcap"] = write_joint_states(folder / "ur5_joint_states", "mcap", ur5.joint_names,
                                                        motion.t, q, qd, tau)
    panda = load_robot("panda")
    arm = multisine(panda, duration=2.0, rate=50.0, seed=22, start=80.0)   # franka_states at 50 Hz: small
    state = [np.column_stack([x[:, :7], np.full((len(arm.t), 2), fill)]) for x, fill in
             ((arm.q, 0.02), (arm.qd, 0.0), (arm.qdd, 0.0))]
    tau_j = inverse_dynamics(panda, *state)[:, :7]
    paths["panda_franka.bag"] = write_franka(folder / "panda_franka", "ros1", panda.joint_names,
                                             arm.t, noisy(arm.q[:, :7], 1e-5, seed=4), noisy(arm.qd[:, :7], 1e-3, seed=5),
                                             noisy(tau_j, 0.05, seed=6))
    return paths


NAMES = ("ur5_rtde.csv", "ur5_joint_states.bag", "ur5_joint_states.mcap", "panda_franka.bag")


if __name__ == "__main__":   # the examples are ours: written again from scratch
    for name in NAMES:
        (EXAMPLES / name).unlink(missing_ok=True)
    for path in write_examples().values():
        print(f"wrote {path.relative_to(EXAMPLES.parent)} ({path.stat().st_size // 1024} KiB)")
