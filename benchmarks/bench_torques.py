"""The engineer's path, timed stage by stage: a long UR5 log (positions only) to torques and a limits report.

Run:  python benchmarks/bench_torques.py [--rows 100000] [--repeat 3]

It writes a log of --rows samples at 1 kHz (t and six positions, plus an
ignored column) to a temporary folder, then takes the best of --repeat runs of
each stage of ``course_dynamics.tools.logs.torques_from_log``: reading the file
(``read_table``), differentiating (Savitzky–Golay), τ by the compiled model
(``compile_model(ur5).inverse_dynamics``, cache warm; its native batches held to
one thread, then to two) and the limits report; and, on the very same q, q̇, q̈
as Pinocchio's own arrays (one state a column, made before timing), τ by
``pin.rneaInParallel`` with one thread, then two, measured the same way (best of
--repeat). Each τ row says the threads each side ran on, and the ratios printed
are ours / Pinocchio's at the same thread count. The end-to-end time is
``torques_from_log(..., compiled=True)`` on the table as read, with our threads
at the package's default.
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
from course_dynamics.tools.logs import ROWS_AT_A_TIME, joint_log, torques_from_log
from course_dynamics.tools.tables import read_table

from measure import our_threads, print_conditions, print_load, threads, threads_used  # this folder is on the path


def best(function, repeat: int) -> tuple[float, object]:
    """measure.best's statistic (the best of ``repeat`` rounds of one call), keeping the last result."""
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
    print_conditions(f"UR5 log, {args.rows} rows at 1 kHz, positions only (best of {args.repeat} on both sides)")
    model = load_robot("ur5")
    t = np.arange(args.rows) * 1e-3
    q = 0.5 * np.sin(np.outer(t, 0.3 * np.arange(1, model.n + 1)))
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "log.csv"
        header = "t," + ",".join(f"q_{j}" for j in model.joint_names) + ",temperature"
        np.savetxt(path, np.column_stack([t, q, np.full(len(t), 35.0)]), delimiter=",", header=header, comments="",
                   fmt="%.6f")
        compiled = compile_model(model)  # warm the cache and build the native code: both timed by bench_performance.py
        read, table = best(lambda: read_table(path), args.repeat)
        derive, log = best(lambda: joint_log(model, table), args.repeat)

        oracle = PinocchioOracle(robot_path("ur5"), model.joint_names, model.gravity)
        Q, V, A = (np.asfortranarray(np.array([convert(x) for x in states]).T)  # Pinocchio's layout: (nq, N)
                   for convert, states in ((oracle.configuration, log.q), (oracle.velocity, log.qd),
                                           (oracle.velocity, log.qdd)))
        out = np.zeros((oracle.model.nv, args.rows), order="F")
        pool = pin.ModelPool(oracle.model, 2)
        ratios = {}
        for count in (1, 2):
            with our_threads(count):
                used = threads_used(compiled, "inverse_dynamics", log.q, log.qd, log.qdd)
                ours, tau = best(lambda: compiled.inverse_dynamics(log.q, log.qd, log.qdd), args.repeat)
            theirs, _ = best(lambda: pin.rneaInParallel(count, pool, Q, V, A, out), args.repeat)
            difference = np.abs(oracle._ours(out).T - tau).max()
            ran = threads(used, count)
            rows += [(f"tau, compiled (ours {used} thread{'s' * (used != 1)})", ours),
                     (f"tau, pin.rneaInParallel (pin {count} thread{'s' * (count != 1)})", theirs)]
            ratios[ran] = (ours / theirs, difference)
        report, _ = best(lambda: limits_report(model, log.t, log.qd, tau), args.repeat)
        block = min(args.rows, ROWS_AT_A_TIME)
        default = threads_used(compiled, "inverse_dynamics", log.q[:block], log.qd[:block], log.qdd[:block])
        end_to_end, result = best(lambda: torques_from_log(model, read_table(path), compiled=True), args.repeat)
    print(f"{'stage':<58}{'seconds':>10}")
    for label, seconds in (("read the CSV (read_table)", read), ("differentiate (Savitzky-Golay)", derive), *rows,
                           ("limits report", report),
                           (f"torques_from_log, reading included (ours {default} thread{'s' * (default != 1)})",
                            end_to_end)):
        print(f"{label:<58}{seconds:>10.3f}")
    for ran, (ratio, difference) in ratios.items():
        print(f"tau stage, ours / Pinocchio ({ran}): {ratio:.2f}; largest difference {difference:.1e} N m")
    print(f"limits exceeded: {result.report.exceeded}")
    print_load()


if __name__ == "__main__":
    main()
