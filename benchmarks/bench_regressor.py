"""Cost of the inertial-parameter regressor Y against our τ and against Pinocchio's, measured side by side in one run.

Run:  python benchmarks/bench_regressor.py [--batch 1000] [--repeat 5] [--robots ur5 panda]

Every figure is the best of --repeat runs of the same loop. For each robot it prints,
per sample (µs): our Y (``course_dynamics.core.regressor.regressor``, one Newton–Euler
pass on dual numbers carrying 10 n derivatives) against our τ (``inverse_dynamics``,
interpreted) and against ``pin.computeJointTorqueRegressor``, for one state and for a
batch of --batch states (Pinocchio has no batched regressor: a Python loop over the
states, as a user would write it), and the largest relative difference from Pinocchio.
"""
from __future__ import annotations

import argparse

import numpy as np
import pinocchio as pin
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states

from course_dynamics import inverse_dynamics, load_robot, robot_path
from course_dynamics.core.regressor import regressor

from bench_performance import best  # the one timing loop of the benchmarks (this folder is on the path)


def line(label: str, ours: float, theirs: float) -> None:
    print(f"  {label:<52} {ours * 1e6:>10.3g} {theirs * 1e6:>10.3g} µs {ours / theirs:>8.2f}")


def bench(name: str, batch: int, repeat: int) -> None:
    model = load_robot(name)
    oracle = PinocchioOracle(robot_path(name), model.joint_names, model.gravity)
    q, qd, qdd = random_states(model, batch, seed=0)
    x, xd, xdd = q[0], qd[0], qdd[0]
    # Pinocchio's regressor columns in our order: body i is its joint of the same name, ten columns each
    ids = [oracle.model.getJointId(joint) for joint in model.joint_names]
    columns = np.concatenate([np.arange(10 * (j - 1), 10 * j) for j in ids])
    Q = [oracle.configuration(s) for s in q]  # Pinocchio's layout, converted before timing
    V = [oracle.velocity(s) for s in qd]
    A = [oracle.velocity(s) for s in qdd]
    pm, pd = oracle.model, oracle.data
    print(f"{name} ({model.n} joints, {10 * model.n} parameters), best of {repeat}; columns: ours, reference, unit, ratio")

    print("  one state")
    Y_1 = best(lambda: regressor(model, x, xd, xdd), repeat, 50)
    tau_1 = best(lambda: inverse_dynamics(model, x, xd, xdd), repeat, 500)
    pin_1 = best(lambda: pin.computeJointTorqueRegressor(pm, pd, Q[0], V[0], A[0]), repeat, 5000)
    line("Y / our τ", Y_1, tau_1)
    line("Y / pin.computeJointTorqueRegressor", Y_1, pin_1)

    print(f"  a batch of {batch} states, per sample")
    Y_N = best(lambda: regressor(model, q, qd, qdd), repeat) / batch
    tau_N = best(lambda: inverse_dynamics(model, q, qd, qdd), repeat) / batch
    pin_N = best(lambda: [pin.computeJointTorqueRegressor(pm, pd, a, b, c) for a, b, c in zip(Q, V, A)], repeat) / batch
    line("Y batch / our τ batch", Y_N, tau_N)
    line("Y batch / pin.computeJointTorqueRegressor loop", Y_N, pin_N)

    ours = regressor(model, q, qd, qdd)
    theirs = np.array([oracle.regressor(a, b, c)[:, columns] for a, b, c in zip(q, qd, qdd)])
    error = max(np.abs(o - t).max() / np.abs(t).max() for o, t in zip(ours, theirs))
    print(f"  largest difference from Pinocchio, relative to each state's largest entry: {error:.1e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--robots", nargs="+", default=["ur5", "panda"])
    args = parser.parse_args()
    for name in args.robots:
        bench(name, args.batch, args.repeat)


if __name__ == "__main__":
    main()
