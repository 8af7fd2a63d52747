"""Speed of course_dynamics against Pinocchio, both sides written as a user writes them, measured in one run.

Run:  python benchmarks/bench_performance.py [--batch 4000] [--repeat 5] [--duration 2] [--members 1000]
                                             [--chains 6,30,100,300]

Every figure is the best of --repeat runs of the same work; every ratio is ours / Pinocchio's and is printed
beside its target. It prints, for UR5 unless said otherwise:

1. one state: the compiled model's own methods (``compile_model(model).inverse_dynamics(q, qd, qdd)``, its
   native code where a compiler exists) against ``pin.rnea``, ``pin.crba`` and ``pin.aba`` called from
   Python; the default API (``inverse_dynamics(model, q, qd, qdd)``, warm) and the interpreted recursion;
2. a batch of --batch states, per sample, through the default API (warm: the evaluator has chosen) against
   Pinocchio's fastest single-thread path: ``rneaInParallel``/``abaInParallel`` with one thread, Python loops
   over ``pin.crba`` and ``pin.computeCoriolisMatrix``;
3. the same τ batch on 2 threads against ``rneaInParallel`` with 2;
4. ``simulate(ur5, q0, 0, duration, 1e-3)`` as a user calls it (RK4), against a bare RK4 loop on ``pin.aba``;
5. --members double pendulums for 0.5 s as one ensemble, against the same RK4 loop calling ``pin.aba`` for
   every member;
6. compiling, first and from the cache: the Python programs, then the native library;
7. start-up: ``course-dynamics info ur5`` against importing numpy and pinocchio;
8. chains of --chains joints: the cost per joint of τ, M, C and forward dynamics, interpreted and compiled
   ("over bound" where a robot is too large to compile), so the O(n), O(n²) and O(n³) growth shows.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states

from course_dynamics import (
    coriolis_matrix,
    forward_dynamics,
    inverse_dynamics,
    load_robot,
    load_urdf,
    mass_matrix,
    robot_path,
)
from course_dynamics.core import compiled as compiled_module
from course_dynamics.core import dynamics, newton_euler
from course_dynamics.core import forward_dynamics as interpreted_forward
from course_dynamics.core.compiled import ProgramTooLargeError, compile_model
from course_dynamics.tools.simulation import simulate

TARGETS = {"one τ": 2.0, "one M": 2.0, "one FD": 2.0, "τ batch": 1.0, "M batch": 1.0, "C batch": 1.0,
           "FD batch": 1.0, "2 threads": 1.0, "simulate": 3.0, "ensemble": 0.1}


def best(function, repeat: int, number: int = 1) -> float:
    """Best wall time of one call (s) over ``repeat`` rounds of ``number`` calls."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            function()
        times.append((time.perf_counter() - start) / number)
    return min(times)


def line(label: str, ours: float, theirs: float, unit: str, target: str | None = None) -> None:
    ratio = ours / theirs
    scale = 1e6 if unit == "µs" else 1.0
    verdict = "" if target is None else f"  target ≤ {TARGETS[target]:g}: {'met' if ratio <= TARGETS[target] else 'NOT met'}"
    print(f"  {label:<58} {ours * scale:>10.3g} {theirs * scale:>10.3g} {unit:<3} {ratio:>7.2f}{verdict}")


def pinocchio_dynamics(oracle: PinocchioOracle):
    """(q, qd, tau) → Θ̈ by pin.aba for arrays (..., n) in our joint order, member by member."""
    model, data = oracle.model, oracle.data

    def aba(q, qd, tau):
        if q.ndim == 1:
            return oracle._ours(pin.aba(model, data, oracle.configuration(q), oracle.velocity(qd), oracle.velocity(tau)))
        rows = [aba(a, b, c) for a, b, c in zip(q.reshape(-1, q.shape[-1]), qd.reshape(-1, q.shape[-1]),
                                                 tau.reshape(-1, q.shape[-1]))]
        return np.reshape(rows, q.shape)

    return aba


def bare_rk4(model, data, q, v, duration: float, dt: float) -> np.ndarray:
    """The 20-line RK4 loop a Pinocchio user writes: zero torque, pin.aba four times a step."""
    tau = np.zeros(model.nv)
    for _ in range(int(round(duration / dt))):
        a1 = pin.aba(model, data, q, v, tau)
        q2, v2 = q + 0.5 * dt * v, v + 0.5 * dt * a1
        a2 = pin.aba(model, data, q2, v2, tau)
        q3, v3 = q + 0.5 * dt * v2, v + 0.5 * dt * a2
        a3 = pin.aba(model, data, q3, v3, tau)
        q4, v4 = q + dt * v3, v + dt * a3
        a4 = pin.aba(model, data, q4, v4, tau)
        q, v = q + dt / 6 * (v + 2 * v2 + 2 * v3 + v4), v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
    return q


def chain_urdf(n: int) -> str:
    """A serial chain of n revolute joints with alternating axes and offset, tilted inertias."""
    links = ['<link name="base"/>']
    joints = []
    for i in range(n):
        axis = ("0 0 1", "0 1 0", "1 0 0")[i % 3]
        links.append(f'<link name="l{i}"><inertial><origin xyz="0.05 0.01 0.02"/><mass value="{1 + 0.1 * (i % 5)}"/>'
                     f'<inertia ixx="0.02" ixy="0.001" ixz="0" iyy="0.03" iyz="0.002" izz="0.04"/></inertial></link>')
        parent = "base" if i == 0 else f"l{i - 1}"
        joints.append(f'<joint name="j{i}" type="revolute"><parent link="{parent}"/><child link="l{i}"/>'
                      f'<origin xyz="0.1 0 0.02" rpy="0.1 0 0"/><axis xyz="{axis}"/>'
                      f'<limit lower="-3" upper="3" effort="100" velocity="5"/></joint>')
    return f'<robot name="chain{n}">' + "".join(links + joints) + "</robot>"


def one_state(model, oracle, compiled, x, xd, xdd, r) -> None:
    native = "native code" if compiled.native else "pure Python: no C compiler here"
    print(f"1. one state (the compiled model's {native}; µs)")
    qp, vp, ap = oracle.configuration(x), oracle.velocity(xd), oracle.velocity(xdd)
    pm, pd = oracle.model, oracle.data
    rnea = best(lambda: pin.rnea(pm, pd, qp, vp, ap), r, 20000)
    line("τ: compile_model(ur5).inverse_dynamics / pin.rnea", best(lambda: compiled.inverse_dynamics(x, xd, xdd), r, 20000),
         rnea, "µs", "one τ")
    line("M: compile_model(ur5).mass_matrix / pin.crba", best(lambda: compiled.mass_matrix(x), r, 20000),
         best(lambda: pin.crba(pm, pd, qp), r, 20000), "µs", "one M")
    line("FD: compile_model(ur5).forward_dynamics / pin.aba", best(lambda: compiled.forward_dynamics(x, xd, xdd), r, 20000),
         best(lambda: pin.aba(pm, pd, qp, vp, ap), r, 20000), "µs", "one FD")
    for _ in range(200):  # the default API's evaluator has chosen by now
        inverse_dynamics(model, x, xd, xdd)
    line("τ: default API inverse_dynamics(ur5, q, qd, qdd) / pin.rnea", best(lambda: inverse_dynamics(model, x, xd, xdd),
                                                                            r, 20000), rnea, "µs")
    line("τ: the interpreted recursion / pin.rnea", best(lambda: newton_euler.inverse_dynamics(model, x, xd, xdd), r, 500),
         rnea, "µs")


def batches(model, oracle, q, qd, qdd, r) -> None:
    N = len(q)
    print(f"2. a batch of {N} states through the default API (warm), per sample (µs)")
    Q = np.array([oracle.configuration(s) for s in q])
    V = np.array([oracle.velocity(s) for s in qd])
    A = np.array([oracle.velocity(s) for s in qdd])
    QT, VT, AT = (np.asfortranarray(a.T) for a in (Q, V, A))
    pool = pin.ModelPool(oracle.model, 2)
    out = np.zeros((oracle.model.nv, N), order="F")
    pm, pd = oracle.model, oracle.data
    for _ in range(3):  # warm: the evaluator compiles after a few calls, as it would in a user's loop
        inverse_dynamics(model, q, qd, qdd), mass_matrix(model, q), coriolis_matrix(model, q, qd)
        forward_dynamics(model, q, qd, qdd)
    rnea_1 = best(lambda: pin.rneaInParallel(1, pool, QT, VT, AT, out), r) / N
    line("τ / rneaInParallel(1 thread)", best(lambda: inverse_dynamics(model, q, qd, qdd), r) / N, rnea_1, "µs",
         "τ batch")
    line("M / a pin.crba loop", best(lambda: mass_matrix(model, q), r) / N,
         best(lambda: [pin.crba(pm, pd, a) for a in Q], r) / N, "µs", "M batch")
    line("C / a pin.computeCoriolisMatrix loop", best(lambda: coriolis_matrix(model, q, qd), r) / N,
         best(lambda: [pin.computeCoriolisMatrix(pm, pd, a, b) for a, b in zip(Q, V)], r) / N, "µs", "C batch")
    line("forward dynamics / abaInParallel(1 thread)", best(lambda: forward_dynamics(model, q, qd, qdd), r) / N,
         best(lambda: pin.abaInParallel(1, pool, QT, VT, AT, out), r) / N, "µs", "FD batch")
    used = min(2, N // compiled_module.THREAD_STATES) if compiled_module.native.compiler() else 1
    print(f"3. the τ batch on 2 threads, per sample (µs; this machine has {os.cpu_count()} cores; ours shares a "
          f"batch from {compiled_module.THREAD_STATES} states a thread, so {max(used, 1)} here)")
    threads = compiled_module.THREADS
    compiled_module.THREADS = 2
    ours_2 = best(lambda: inverse_dynamics(model, q, qd, qdd), r) / N
    compiled_module.THREADS = 1
    ours_1 = best(lambda: inverse_dynamics(model, q, qd, qdd), r) / N
    compiled_module.THREADS = threads
    theirs_2 = best(lambda: pin.rneaInParallel(2, pool, QT, VT, AT, out), r) / N
    line(f"τ on {max(used, 1)} thread(s) / rneaInParallel(2 threads)", ours_2, theirs_2, "µs", "2 threads")
    print(f"  ours: {ours_1 / ours_2:.2f}× the throughput of one thread; Pinocchio's 2 threads: "
          f"{rnea_1 / theirs_2:.2f}× its one" + ("  (slower than one: the machine was busy, measure again)"
                                                   if theirs_2 > rnea_1 else ""))


def simulation(model, oracle, duration: float, r) -> None:
    print(f"4. simulate {duration:g} s of UR5, RK4 at 1 ms, as a user calls it (s)")
    q0, qd0 = np.array([0.0, -1.2, 1.0, -0.5, 0.5, 0.0]), np.zeros(6)
    simulate(model, q0, qd0, duration, 1e-3)  # warm: a first run may build the native code (see 6)
    runs = {}

    def ours():
        runs["ours"] = simulate(model, q0, qd0, duration, 1e-3, integrator="rk4")

    def theirs():
        runs["pin"] = bare_rk4(oracle.model, oracle.data, oracle.configuration(q0), oracle.velocity(qd0), duration, 1e-3)

    line("simulate(ur5, q0, 0, …) / a bare RK4 loop on pin.aba", best(ours, min(r, 3)), best(theirs, min(r, 3)), "s",
         "simulate")
    print(f"  final states differ by {np.abs(runs['ours'].q[-1] - oracle._ours(runs['pin'])).max():.1e} rad")


def ensemble(members: int, r) -> None:
    print(f"5. {members} double pendulums, 0.5 s of RK4 at 1 ms (s)")
    pendulum = load_robot("double_pendulum_continuous")
    pendulum_aba = pinocchio_dynamics(PinocchioOracle(robot_path("double_pendulum_continuous"), pendulum.joint_names))
    start = np.array([2.0, 0.0]) + 1e-3 * np.random.default_rng(1).standard_normal((members, 2))
    runs = {}

    def ours():
        runs["ours"] = simulate(pendulum, start, np.zeros(2), 0.5, 1e-3)

    def theirs():
        runs["pin"] = simulate(pendulum, start, np.zeros(2), 0.5, 1e-3, dynamics=pendulum_aba)

    line("one ensemble, compiled / aba for every member", best(ours, min(r, 3)), best(theirs, 1), "s", "ensemble")
    print(f"  final states differ by {np.abs(runs['ours'].q[-1] - runs['pin'].q[-1]).max():.1e} rad (required: 1e-6)")


def compiling() -> None:
    print("6. compiling (s): the Python programs, then the native library; first time, then from the cache")
    with tempfile.TemporaryDirectory() as folder:
        os.environ["COURSE_DYNAMICS_CACHE"] = folder
        for name in ("ur5", "panda"):
            robot = load_robot(name)
            first, again = compile_model(robot), compile_model(robot)
            print(f"  {name:<6} Python {first.generation_seconds:6.3f} s first, "
                  f"{again.generation_seconds:6.4f} s cached; native {first.native_seconds:6.2f} s "
                  f"first, {again.native_seconds:6.4f} s cached ({len(first.source.splitlines())} lines of Python, "
                  f"{len(first.native_source.splitlines())} of C)")
        del os.environ["COURSE_DYNAMICS_CACHE"]


def start_up(r) -> None:
    print("7. start-up (s)")
    command = [sys.executable, "-m", "course_dynamics.cli", "info", "ur5"]
    ours = best(lambda: subprocess.run(command, capture_output=True, check=True), min(r, 3))
    imports = best(lambda: subprocess.run([sys.executable, "-c", "import numpy, pinocchio"], capture_output=True,
                                          check=True), min(r, 3))
    line("course-dynamics info ur5 / python -c 'import numpy, pinocchio'", ours, imports, "s")


def chains(sizes, r) -> None:
    print("8. chains: cost per joint of one state, µs (interpreted; compiled, or 'over bound')")
    print(f"  {'joints':>6} {'τ':>9} {'M':>9} {'C':>9} {'FD':>9} | {'τ':>9} {'M':>9} {'C':>9} {'FD':>9}")
    with tempfile.TemporaryDirectory() as folder:
        for n in sizes:
            path = Path(folder) / f"chain{n}.urdf"
            path.write_text(chain_urdf(n))
            model = load_urdf(path)
            q, qd, qdd = (np.random.default_rng(n).uniform(-1, 1, (3, n)))
            rounds = 1 if n >= 100 else r
            number = max(1, 2000 // (n * n))
            interpreted = [best(lambda: newton_euler.inverse_dynamics(model, q, qd, qdd), rounds, number),
                           best(lambda: dynamics.mass_matrix(model, q), rounds, number),
                           best(lambda: dynamics.coriolis_matrix(model, q, qd), rounds, number),
                           best(lambda: interpreted_forward.forward_dynamics(model, q, qd, qdd), rounds, number)]
            try:
                c = compile_model(model)
                fast = [f"{best(f, r, 2000) / n * 1e6:9.3g}" for f in (lambda: c.inverse_dynamics(q, qd, qdd),
                                                                      lambda: c.mass_matrix(q),
                                                                      lambda: c.coriolis_matrix(q, qd),
                                                                      lambda: c.forward_dynamics(q, qd, qdd))]
            except ProgramTooLargeError:
                fast = [f"{'over bound':>9}"] + [" " * 9] * 3
            print(f"  {n:>6} " + " ".join(f"{t / n * 1e6:9.3g}" for t in interpreted) + " | " + " ".join(fast))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=4000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--duration", type=float, default=2.0, help="simulated seconds of UR5 (default 2)")
    parser.add_argument("--members", type=int, default=1000, help="double pendulums in the ensemble (default 1000)")
    parser.add_argument("--chains", default="6,30,100,300", help="chain lengths for the cost per joint")
    args = parser.parse_args()
    model = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), model.joint_names)
    compiled = compile_model(model)
    q, qd, qdd = random_states(model, args.batch, seed=0)
    r = args.repeat
    print(f"UR5 ({model.n} joints), best of {r}; columns: ours, Pinocchio's, unit, ratio (ours / Pinocchio's)")
    one_state(model, oracle, compiled, q[0], qd[0], qdd[0], r)
    batches(model, oracle, q, qd, qdd, r)
    simulation(model, oracle, args.duration, r)
    ensemble(args.members, r)
    compiling()
    start_up(r)
    chains([int(n) for n in args.chains.split(",")], r)


if __name__ == "__main__":
    main()
