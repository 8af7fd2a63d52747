"""Simulation speed: 10 s of UR5 at dt = 1 ms with RK4, our dynamics against Pinocchio's aba, in one run.

Run:  python benchmarks/bench_simulation.py [--duration 10] [--dt 0.001]

Both runs use the same RK4 loop (course_dynamics.simulation) and the same
initial state; only the acceleration function differs: our forward dynamics
(6.115) (M by Newton–Euler with unit accelerations, Cholesky solve) or
``pinocchio.aba``. It prints both wall times, the ratio, and how far apart the
two final states are.
"""
from __future__ import annotations

import argparse
import time

import numpy as np
import pinocchio as pin

from course_dynamics import load_robot, robot_path
from course_dynamics.simulation import simulate
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--dt", type=float, default=1e-3)
    args = parser.parse_args()
    model = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), model.joint_names)
    q0, qd0 = np.array([0.0, -1.2, 1.0, -0.5, 0.5, 0.0]), np.zeros(6)

    start = time.perf_counter()
    ours = simulate(model, q0, qd0, args.duration, args.dt, integrator="rk4")
    t_ours = time.perf_counter() - start

    # The same RK4 loop, with Pinocchio's aba as the acceleration function.
    start = time.perf_counter()
    theirs = simulate(model, q0, qd0, args.duration, args.dt, integrator="rk4", dynamics=oracle.aba)
    t_pin = time.perf_counter() - start

    steps = len(ours.t) - 1
    print(f"UR5, {args.duration:g} s at dt = {args.dt:g} s with RK4 ({steps} steps, {4 * steps + len(ours.t)} dynamics calls)")
    print(f"  our forward dynamics : {t_ours:8.2f} s")
    print(f"  pinocchio.aba        : {t_pin:8.2f} s")
    print(f"  ratio (ours / aba)   : {t_ours / t_pin:8.1f}")
    print(f"  final states differ by {np.abs(ours.q[-1] - theirs.q[-1]).max():.1e} rad")
    print(f"  (the loop itself, RK4 bookkeeping in Python, is common to both; pin.__version__ = {pin.__version__})")


if __name__ == "__main__":
    main()
