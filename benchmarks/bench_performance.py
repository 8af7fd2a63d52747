"""Speed of course_dynamics against Pinocchio and against itself, measured side by side in one run.

Run:  python benchmarks/bench_performance.py [--batch 4000] [--repeat 5] [--duration 2] [--members 1000]

Every figure is the best of --repeat runs of the same loop. It prints, for UR5:

1. one state, interpreted: τ (µs), and M (composite rigid bodies), C (the O(n²)
   recursion) and forward dynamics as multiples of τ; the same four compiled;
2. a batch of --batch states, per sample: our τ, M and C (interpreted and
   compiled) against ``pin.rneaInParallel`` with one thread, and against Python
   loops over ``pin.crba`` and ``pin.computeCoriolisMatrix``;
3. ``simulate``, --duration s of RK4 at 1 ms, in the same RK4 loop
   (``course_dynamics.tools.simulation``) with our compiled forward dynamics (cache
   warm) or with ``pin.aba``;
4. --members double pendulums for 0.5 s of RK4 at 1 ms as one ensemble, against
   the same RK4 loop calling ``pin.aba`` for every member, and how far apart the
   final states are;
5. how long compiling takes, first and from the cache, for UR5 and Panda.
"""
from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np
import pinocchio as pin
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states

from course_dynamics import (
    coriolis_matrix,
    inverse_dynamics,
    load_robot,
    mass_matrix,
    robot_path,
)
from course_dynamics.core.compiled import compile_model
from course_dynamics.core.forward_dynamics import forward_dynamics
from course_dynamics.tools.simulation import simulate

TARGETS = {"M/τ": 2.5, "C/τ": 6, "FD/τ": 4, "τ batch": 1.0, "M batch": 2, "C batch": 3, "simulate": 8, "ensemble": 1}


def best(function, repeat: int, number: int = 1) -> float:
    """Best wall time of one call (s) over ``repeat`` rounds of ``number`` calls."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            function()
        times.append((time.perf_counter() - start) / number)
    return min(times)


def pinocchio_dynamics(oracle: PinocchioOracle):
    """(q, qd, tau) → Θ̈ by pin.aba for arrays (..., n) in our joint order: the same contract as ours."""
    model, data = oracle.model, oracle.data

    def aba(q, qd, tau):
        if q.ndim == 1:
            return oracle._ours(pin.aba(model, data, oracle.configuration(q), oracle.velocity(qd), oracle.velocity(tau)))
        rows = [aba(a, b, c) for a, b, c in zip(q.reshape(-1, q.shape[-1]), qd.reshape(-1, q.shape[-1]),
                                                 tau.reshape(-1, q.shape[-1]))]
        return np.reshape(rows, q.shape)

    return aba


def line(label: str, ours: float, theirs: float, unit: str, target: str | None = None) -> None:
    ratio = ours / theirs
    verdict = "" if target is None else f"  target ≤ {TARGETS[target]:g}: {'met' if ratio <= TARGETS[target] else 'NOT met'}"
    print(f"  {label:<52} {ours * 1e6 if unit == 'µs' else ours:>10.3g} {theirs * 1e6 if unit == 'µs' else theirs:>10.3g} "
          f"{unit:<3} {ratio:>7.2f}{verdict}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=4000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--duration", type=float, default=2.0, help="simulated seconds of UR5 (default 2)")
    parser.add_argument("--members", type=int, default=1000, help="double pendulums in the ensemble (default 1000)")
    args = parser.parse_args()
    model = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), model.joint_names)
    compiled = compile_model(model)
    q, qd, qdd = random_states(model, args.batch, seed=0)
    x, xd, xdd = q[0], qd[0], qdd[0]
    r = args.repeat
    print(f"UR5 ({model.n} joints), best of {r}; columns: ours, reference, unit, ratio")

    print("1. one state (reference: our interpreted τ)")
    tau_1 = best(lambda: inverse_dynamics(model, x, xd, xdd), r, 500)
    line("τ, interpreted (µs)", tau_1, tau_1, "µs")
    line("M by composite rigid bodies / τ", best(lambda: mass_matrix(model, x), r, 500), tau_1, "µs", "M/τ")
    line("C by the O(n²) recursion / τ", best(lambda: coriolis_matrix(model, x, xd), r, 200), tau_1, "µs", "C/τ")
    line("forward dynamics / τ", best(lambda: forward_dynamics(model, x, xd, xdd), r, 500), tau_1, "µs", "FD/τ")
    line("τ compiled / τ interpreted", best(lambda: compiled.inverse_dynamics(x, xd, xdd), r, 2000), tau_1, "µs")
    line("M compiled / τ interpreted", best(lambda: compiled.mass_matrix(x), r, 2000), tau_1, "µs")
    line("C compiled / τ interpreted", best(lambda: compiled.coriolis_matrix(x, xd), r, 1000), tau_1, "µs")
    line("forward dynamics compiled / τ interpreted", best(lambda: compiled.forward_dynamics(x, xd, xdd), r, 2000), tau_1, "µs")
    qp, vp, ap = oracle.configuration(x), oracle.velocity(xd), oracle.velocity(xdd)
    line("τ compiled / pin.rnea", best(lambda: compiled.inverse_dynamics(x, xd, xdd), r, 2000),
         best(lambda: pin.rnea(oracle.model, oracle.data, qp, vp, ap), r, 20000), "µs")

    N = args.batch
    print(f"2. a batch of {N} states, per sample")
    Q = np.array([oracle.configuration(s) for s in q])
    V = np.array([oracle.velocity(s) for s in qd])
    A = np.array([oracle.velocity(s) for s in qdd])
    pool = pin.ModelPool(oracle.model, 1)
    out = np.zeros((oracle.model.nv, N), order="F")
    QT, VT, AT = (np.asfortranarray(a.T) for a in (Q, V, A))
    parallel = best(lambda: pin.rneaInParallel(1, pool, QT, VT, AT, out), r) / N
    pm, pd = oracle.model, oracle.data
    crba_loop = best(lambda: [pin.crba(pm, pd, a) for a in Q], r) / N
    coriolis_loop = best(lambda: [pin.computeCoriolisMatrix(pm, pd, a, b) for a, b in zip(Q, V)], r) / N
    line("τ compiled / rneaInParallel(1 thread)", best(lambda: compiled.inverse_dynamics(q, qd, qdd), r) / N,
         parallel, "µs", "τ batch")
    line("τ interpreted / rneaInParallel(1 thread)", best(lambda: inverse_dynamics(model, q, qd, qdd), r) / N,
         parallel, "µs")
    line("M compiled / pin.crba loop", best(lambda: compiled.mass_matrix(q), r) / N, crba_loop, "µs", "M batch")
    line("M interpreted / pin.crba loop", best(lambda: mass_matrix(model, q), r) / N, crba_loop, "µs")
    line("C compiled / pin.computeCoriolisMatrix loop", best(lambda: compiled.coriolis_matrix(q, qd), r) / N,
         coriolis_loop, "µs", "C batch")
    line("C interpreted / pin.computeCoriolisMatrix loop", best(lambda: coriolis_matrix(model, q, qd), r) / N,
         coriolis_loop, "µs")

    print(f"3. simulate {args.duration:g} s of UR5, RK4 at 1 ms, the same RK4 loop (s)")
    q0, qd0 = np.array([0.0, -1.2, 1.0, -0.5, 0.5, 0.0]), np.zeros(6)
    aba = pinocchio_dynamics(oracle)
    runs = {}

    def ours_run():
        runs["ours"] = simulate(model, q0, qd0, args.duration, 1e-3, compiled=True)

    def their_run():
        runs["pin"] = simulate(model, q0, qd0, args.duration, 1e-3, dynamics=aba)

    line("compiled forward dynamics / pin.aba", best(ours_run, min(r, 3)), best(their_run, min(r, 3)), "s", "simulate")
    print(f"  final states differ by {np.abs(runs['ours'].q[-1] - runs['pin'].q[-1]).max():.1e} rad")

    K = args.members
    print(f"4. {K} double pendulums, 0.5 s of RK4 at 1 ms (s)")
    pendulum = load_robot("double_pendulum_continuous")
    pendulum_aba = pinocchio_dynamics(PinocchioOracle(robot_path("double_pendulum_continuous"), pendulum.joint_names))
    start = np.array([2.0, 0.0]) + 1e-3 * np.random.default_rng(1).standard_normal((K, 2))
    ensemble = {}

    def ours_ensemble():
        ensemble["ours"] = simulate(pendulum, start, np.zeros(2), 0.5, 1e-3, compiled=True)

    def their_ensemble():
        ensemble["pin"] = simulate(pendulum, start, np.zeros(2), 0.5, 1e-3, dynamics=pendulum_aba)

    line("one ensemble, compiled / aba for every member", best(ours_ensemble, min(r, 3)), best(their_ensemble, 1), "s",
         "ensemble")
    print(f"  final states differ by {np.abs(ensemble['ours'].q[-1] - ensemble['pin'].q[-1]).max():.1e} rad "
          "(required: 1e-6)")

    print("5. compiling (s): first time, then from the cache")
    with tempfile.TemporaryDirectory() as folder:
        os.environ["COURSE_DYNAMICS_CACHE"] = folder
        for name in ("ur5", "panda"):
            robot = load_robot(name)
            first, again = compile_model(robot), compile_model(robot)
            print(f"  {name:<6} {first.generation_seconds:6.3f} s first, {again.generation_seconds:6.4f} s from the cache "
                  f"({len(first.source.splitlines())} lines)")


if __name__ == "__main__":
    main()
