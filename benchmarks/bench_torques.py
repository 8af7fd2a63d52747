"""The engineer's path, timed stage by stage: a long UR5 log (positions only) to torques and a limits report.

Run:  python benchmarks/bench_torques.py [--rows 100000] [--repeat 3]

It writes a log of --rows samples at 1 kHz (t and six positions, plus an
ignored column) to a temporary folder, then takes the best of --repeat runs of
each stage of ``course_dynamics.tools.logs.torques_from_log``: reading the file
(``read_table``), differentiating (Savitzky–Golay), τ by the compiled model
(cache warm) and the limits report; and, on the very same q, q̇, q̈, τ by
Pinocchio's ``rneaInParallel`` with one thread, measured the same way. The
ratio printed is ours / Pinocchio's for the τ stage; the end-to-end time is
``torques_from_log`` on the table as read.
"""
from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle

from course_dynamics import load_robot, robot_path
from course_dynamics.core.compiled import compile_model
from course_dynamics.tools.limits import limits_report
from course_dynamics.tools.logs import joint_log, torques_from_log
from course_dynamics.tools.tables import read_table


def best(function, repeat: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    model = load_robot("ur5")
    t = np.arange(args.rows) * 1e-3
    q = 0.5 * np.sin(np.outer(t, 0.3 * np.arange(1, model.n + 1)))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "log.csv"
        header = "t," + ",".join(f"q_{j}" for j in model.joint_names) + ",temperature"
        np.savetxt(path, np.column_stack([t, q, np.full(len(t), 35.0)]), delimiter=",", header=header, comments="",
                   fmt="%.6f")
        compile_model(model)  # warm the cache: generation is timed by bench_performance.py
        read, table = best(lambda: read_table(path), args.repeat)
        derive, log = best(lambda: joint_log(model, table), args.repeat)
        compiled = compile_model(model)
        ours, tau = best(lambda: compiled.inverse_dynamics(log.q, log.qd, log.qdd), args.repeat)
        report, _ = best(lambda: limits_report(model, log.t, log.qd, tau), args.repeat)
        end_to_end, result = best(lambda: torques_from_log(model, read_table(path)), args.repeat)

        oracle = PinocchioOracle(robot_path("ur5"), model.joint_names, model.gravity)
        Q = np.array([oracle.configuration(x) for x in log.q]).T.copy()  # Pinocchio's layout: (nq, N)
        V = np.array([oracle.velocity(x) for x in log.qd]).T.copy()
        A = np.array([oracle.velocity(x) for x in log.qdd]).T.copy()
        out = np.zeros((oracle.model.nv, args.rows))
        pool = pin.ModelPool(oracle.model, 1)
        theirs, _ = best(lambda: pin.rneaInParallel(1, pool, Q, V, A, out), args.repeat)
        difference = np.abs(oracle._ours(out).T - tau).max()
    print(f"UR5 log, {args.rows} rows at 1 kHz, positions only (best of {args.repeat})")
    print(f"{'stage':<44}{'seconds':>10}")
    for label, seconds in (("read the CSV (read_table)", read), ("differentiate (Savitzky-Golay)", derive),
                           ("tau, compiled", ours), ("tau, pin.rneaInParallel (1 thread)", theirs),
                           ("limits report", report), ("torques_from_log, reading included", end_to_end)):
        print(f"{label:<44}{seconds:>10.3f}")
    print(f"tau stage, ours / Pinocchio: {ours / theirs:.2f}; largest difference {difference:.1e} N m; "
          f"limits exceeded: {result.report.exceeded}")


if __name__ == "__main__":
    main()
