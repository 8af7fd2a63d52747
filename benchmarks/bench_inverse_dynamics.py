"""Inverse dynamics speed: course_dynamics against Pinocchio, measured side by side in one run.

Run:  python benchmarks/bench_inverse_dynamics.py [--batch 10000] [--repeat 5]

For UR5 and Panda it prints the time per state of
  * our τ for one state               vs  pin.rnea on one state,
  * our τ over a batch of N states    vs  pin.rnea in a Python loop and pin.rneaInParallel (1 thread),
and the ratios (ours / Pinocchio). Each figure is the best of --repeat runs.
"""
from __future__ import annotations

import argparse
import time

import numpy as np
import pinocchio as pin

from course_dynamics import inverse_dynamics, load_robot, robot_path
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states


def best_time(function, repeat: int, number: int) -> float:
    """Best wall time of one call, over ``repeat`` rounds of ``number`` calls (s)."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            function()
        best = min(best, (time.perf_counter() - start) / number)
    return best


def bench(name: str, batch: int, repeat: int) -> dict[str, float]:
    model = load_robot(name)
    oracle = PinocchioOracle(robot_path(name), model.joint_names)
    q, qd, qdd = random_states(model, batch, seed=0)
    q_pin = np.array([oracle.configuration(x) for x in q])
    v_pin = np.array([oracle.velocity(x) for x in qd])
    a_pin = np.array([oracle.velocity(x) for x in qdd])
    pmodel, pdata = oracle.model, oracle.data
    pool = pin.ModelPool(pmodel, 1)
    tau_out = np.zeros((pmodel.nv, batch), order="F")
    qT, vT, aT = (np.asfortranarray(x.T) for x in (q_pin, v_pin, a_pin))

    def pin_loop():
        for k in range(batch):
            pin.rnea(pmodel, pdata, q_pin[k], v_pin[k], a_pin[k])

    return {
        "ours_single": best_time(lambda: inverse_dynamics(model, q[0], qd[0], qdd[0]), repeat, 2000),
        "pin_single": best_time(lambda: pin.rnea(pmodel, pdata, q_pin[0], v_pin[0], a_pin[0]), repeat, 20000),
        "ours_batch": best_time(lambda: inverse_dynamics(model, q, qd, qdd), repeat, 1) / batch,
        "pin_loop": best_time(pin_loop, repeat, 1) / batch,
        "pin_parallel": best_time(lambda: pin.rneaInParallel(1, pool, qT, vT, aT, tau_out), repeat, 1) / batch,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(f"inverse dynamics, µs per state (best of {args.repeat}); batch N = {args.batch}")
    print(f"{'robot':<7} {'ours 1':>9} {'rnea 1':>8} {'ratio':>7} | {'ours N':>8} {'rnea loop':>10} {'ratio':>7} "
          f"{'rneaInPar(1)':>13} {'ratio':>7}")
    for name in ("ur5", "panda"):
        t = {k: v * 1e6 for k, v in bench(name, args.batch, args.repeat).items()}
        print(f"{name:<7} {t['ours_single']:>9.1f} {t['pin_single']:>8.2f} {t['ours_single'] / t['pin_single']:>7.0f} | "
              f"{t['ours_batch']:>8.2f} {t['pin_loop']:>10.2f} {t['ours_batch'] / t['pin_loop']:>7.2f} "
              f"{t['pin_parallel']:>13.3f} {t['ours_batch'] / t['pin_parallel']:>7.1f}")


if __name__ == "__main__":
    main()
