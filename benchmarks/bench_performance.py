"""Speed of course_dynamics against Pinocchio, both sides written as a user writes them, measured in one run.

Run:  python benchmarks/bench_performance.py [--batch 4000] [--repeat 5] [--duration 2] [--members 1000]
                                             [--calls 20000] [--chains 6,30,100,300]

Every figure is the best of the same number of rounds on both sides (--repeat, or 3 for the seconds-long
runs); every ratio is ours / Pinocchio's, printed with the threads each side ran on ("ours 1 thread / pin 1
thread") and beside its target. Our side is chosen explicitly, never left to the default API's evaluator: a
compiled model (``compile_model``, its native code where a compiler exists) or the interpreted recursion
(``course_dynamics.core.newton_euler`` …); our native batches are held to one thread for the rows that say one
(``course_dynamics.core.compiled.native.THREADS``: see measure.py). Pinocchio's side is its own numpy arrays in its
own layout, made before timing, passed straight to its functions: ``pin.rnea`` & co. called from Python once a
state, ``rneaInParallel``/``abaInParallel`` with the thread count shown. It prints, for UR5 unless said otherwise:

1. one state: the compiled model's own methods against ``pin.rnea``, ``pin.crba`` and ``pin.aba`` called from
   Python; the default API (``inverse_dynamics(model, q, qd, qdd)``, ``mass_matrix(model, q)`` and
   ``forward_dynamics(model, q, qd, tau)`` in a loop, on whatever path its evaluator takes: the native entry,
   ``core.compiled.entry``, once the choice is remembered) and the interpreted recursion; then Pinocchio's cost of one call from Python beside an estimate of
   its C++ cost: the same call on an empty model (the binding's own cost) subtracted, and, for rnea and aba,
   the per-state time of its batch call on one thread;
2. a batch of --batch states, per sample, our compiled model on 1 thread against Pinocchio's fastest
   single-thread path: ``rneaInParallel``/``abaInParallel`` with one thread, Python loops over ``pin.crba``
   and ``pin.computeCoriolisMatrix`` (with a second ratio against their C++ estimate from 1.);
3. the same τ batch with our threads set to 2 against ``rneaInParallel`` with 2;
4. ``simulate(ur5, q0, 0, duration, 1e-3, compiled=True)`` (RK4), against a bare RK4 loop on ``pin.aba``; and
   the UR5 run into its limits with ``limits="stop"`` against the same loop (which has no stops); and the
   adaptive integrator against native RK4 at a fifth of the step, with each one's error;
5. --members double pendulums (continuous joints) for 0.5 s as one ensemble, against the RK4 a Pinocchio user
   writes: vectorised over the members with ``abaInParallel`` on one thread, and a loop over the members of
   the bare RK4 loop (``pin.aba``, ``pin.integrate``);
6. compiling, first and from the cache: the Python programs, then the native library;
7. start-up: ``course-dynamics info ur5`` and ``course-dynamics --help`` against importing numpy and pinocchio;
8. chains of --chains joints: the cost per joint of τ, M, C and forward dynamics, interpreted and compiled
   ("over bound" where a robot is too large to compile), and of τ, M and forward dynamics by the native loop
   (``core.compiled.looped``), so the O(n), O(n²) and O(n³) growth shows; then
   the default API on each chain against ``pin.rnea`` and ``pin.crba`` at one state and ``rneaInParallel(1)``
   on a --batch of states;
9. against MuJoCo (the test extra installs it): the default API's τ, M and forward dynamics at one state
   against ``mj_inverse``, ``mj_forward`` + ``mj_fullM`` and ``mj_forward`` called from Python on UR5's URDF
   (meshes left out, MuJoCo's damping, armature and limits off), and ``simulate`` against ``mujoco.rollout``
   (RK4, the whole run in one C call);
10. a batch τ call's peak memory over its output's size: --memory UR5 states and states of a 50-joint
   chain, on the path the default API takes (printed);
11. a fresh process with an empty compiled-model cache, the whole process timed: the first τ, and --loop
   one-state τ calls, against the same script with Pinocchio.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pinocchio as pin
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states

from course_dynamics import forward_dynamics, inverse_dynamics, load_robot, load_urdf, mass_matrix, robot_path
from course_dynamics.core import compiled as compiled_module
from course_dynamics.core import dynamics, evaluator, newton_euler
from course_dynamics.core import forward_dynamics as interpreted_forward
from course_dynamics.core.compiled import ProgramTooLargeError, compile_model, looped
from course_dynamics.tools.simulation import simulate

from measure import best, our_threads, print_conditions, print_load, threads, threads_used  # this folder is on the path

TARGETS = {"one τ": 2.0, "one M": 2.0, "one FD": 2.0, "τ batch": 1.0, "M batch": 1.0, "C batch": 1.0,
           "FD batch": 1.0, "2 threads": 1.0, "simulate": 3.0, "ensemble": 0.1,
           "start-up info": 2.0, "start-up help": 1.0, "mujoco one": 1.0, "mujoco rollout": 1.0,
           "memory ur5": 2.0, "memory chain": 4.0, "first τ": 2.0, "fresh loop": 3.0, "chain one": 2.0,
           "chain batch": 1.0, "default one": 1.0, "compile": 1.0}
ONE = threads(1, 1)
MUJOCO_ONE = "ours 1 thread / mujoco 1 thread"


def line(label: str, ours: float, theirs: float, unit: str, ran: str, target: str | None = None) -> None:
    ratio = ours / theirs
    scale = 1e6 if unit == "µs" else 1.0
    verdict = "" if target is None else f"  target ≤ {TARGETS[target]:g}: {'met' if ratio <= TARGETS[target] else 'NOT met'}"
    print(f"  {label:<66} {ours * scale:>9.3g} {theirs * scale:>9.3g} {unit:<2} {ratio:>7.2f}  {ran}{verdict}")


def bare_rk4(model, data, q, v, duration: float, dt: float) -> np.ndarray:
    """The 20-line RK4 loop a Pinocchio user writes for joints whose configuration is their angle: zero
    torque, pin.aba four times a step."""
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


def bare_rk4_integrate(model, data, q, v, duration: float, dt: float) -> np.ndarray:
    """The same loop where the configuration is not a vector of angles (continuous joints: cos θ, sin θ):
    positions advanced by pin.integrate."""
    tau = np.zeros(model.nv)
    for _ in range(int(round(duration / dt))):
        a1 = pin.aba(model, data, q, v, tau)
        q2, v2 = pin.integrate(model, q, 0.5 * dt * v), v + 0.5 * dt * a1
        a2 = pin.aba(model, data, q2, v2, tau)
        q3, v3 = pin.integrate(model, q, 0.5 * dt * v2), v + 0.5 * dt * a2
        a3 = pin.aba(model, data, q3, v3, tau)
        q4, v4 = pin.integrate(model, q, dt * v3), v + dt * a3
        a4 = pin.aba(model, data, q4, v4, tau)
        q, v = pin.integrate(model, q, dt / 6 * (v + 2 * v2 + 2 * v3 + v4)), v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
    return q


def batched_rk4(model, pool, theta, v, duration: float, dt: float, num_threads: int) -> np.ndarray:
    """RK4 for K members at once, each column one member (Pinocchio's layout, (nv, K)), abaInParallel four times a
    step; the angles θ of continuous joints kept, their configuration (cos θ, sin θ) formed for each call."""
    assert model.nq == 2 * model.nv  # every joint continuous: q = (cos θ₁, sin θ₁, cos θ₂, …)
    members = theta.shape[1]
    Q = np.empty((model.nq, members), order="F")
    tau = np.zeros((model.nv, members), order="F")
    out = np.empty((model.nv, members), order="F")

    def aba(angles, velocities):
        Q[0::2], Q[1::2] = np.cos(angles), np.sin(angles)
        pin.abaInParallel(num_threads, pool, Q, np.asfortranarray(velocities), tau, out)
        return out.copy(order="F")

    for _ in range(int(round(duration / dt))):
        a1 = aba(theta, v)
        q2, v2 = theta + 0.5 * dt * v, v + 0.5 * dt * a1
        a2 = aba(q2, v2)
        q3, v3 = theta + 0.5 * dt * v2, v + 0.5 * dt * a2
        a3 = aba(q3, v3)
        q4, v4 = theta + dt * v3, v + dt * a3
        a4 = aba(q4, v4)
        theta, v = theta + dt / 6 * (v + 2 * v2 + 2 * v3 + v4), v + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
    return theta


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


def one_state(model, oracle, compiled, x, xd, xdd, batch, r, number: int) -> dict:
    """Section 1; returns Pinocchio's estimated C++ cost of one call (s) by function name."""
    native = "native code" if compiled.native else "pure Python: no C compiler here"
    print(f"1. one state (the compiled model's {native}), µs; columns: ours, Pinocchio's, unit, ratio, threads")
    qp, vp, ap = oracle.configuration(x), oracle.velocity(xd), oracle.velocity(xdd)  # Pinocchio's arrays, made once
    pm, pd = oracle.model, oracle.data
    calls = {"rnea": lambda: pin.rnea(pm, pd, qp, vp, ap), "crba": lambda: pin.crba(pm, pd, qp),
             "computeCoriolisMatrix": lambda: pin.computeCoriolisMatrix(pm, pd, qp, vp),
             "aba": lambda: pin.aba(pm, pd, qp, vp, ap)}
    python = {name: best(call, r, number) for name, call in calls.items()}
    line("τ: compile_model(ur5).inverse_dynamics / pin.rnea", best(lambda: compiled.inverse_dynamics(x, xd, xdd), r, number),
         python["rnea"], "µs", ONE, "one τ")
    line("M: compile_model(ur5).mass_matrix / pin.crba", best(lambda: compiled.mass_matrix(x), r, number),
         python["crba"], "µs", ONE, "one M")
    line("FD: compile_model(ur5).forward_dynamics / pin.aba", best(lambda: compiled.forward_dynamics(x, xd, xdd), r, number),
         python["aba"], "µs", ONE, "one FD")
    for _ in range(200):  # a user's loop: the evaluator takes whatever path it takes (core/evaluator.py)
        inverse_dynamics(model, x, xd, xdd)
    line("τ: default API inverse_dynamics(ur5, …) in a loop / pin.rnea", best(lambda: inverse_dynamics(model, x, xd, xdd),
                                                                          r, number), python["rnea"], "µs", ONE,
         "default one")
    line("M: default API mass_matrix(ur5, q) in a loop / pin.crba", best(lambda: mass_matrix(model, x), r, number),
         python["crba"], "µs", ONE, "default one")
    line("FD: default API forward_dynamics(ur5, …) in a loop / pin.aba",
         best(lambda: forward_dynamics(model, x, xd, xdd), r, number), python["aba"], "µs", ONE, "default one")
    line("τ: interpreted newton_euler.inverse_dynamics / pin.rnea",
         best(lambda: newton_euler.inverse_dynamics(model, x, xd, xdd), r, max(1, number // 40)), python["rnea"], "µs", ONE)

    empty = pin.Model()  # no joints: a call on it costs the binding, not the algorithm
    ed, z = empty.createData(), np.zeros(0)
    bare = {"rnea": lambda: pin.rnea(empty, ed, z, z, z), "crba": lambda: pin.crba(empty, ed, z),
            "computeCoriolisMatrix": lambda: pin.computeCoriolisMatrix(empty, ed, z, z),
            "aba": lambda: pin.aba(empty, ed, z, z, z)}
    QT, VT, AT, pool = batch
    out = np.zeros((pm.nv, QT.shape[1]), order="F")
    batched = {"rnea": best(lambda: pin.rneaInParallel(1, pool, QT, VT, AT, out), r) / QT.shape[1],
               "aba": best(lambda: pin.abaInParallel(1, pool, QT, VT, AT, out), r) / QT.shape[1]}
    print("  Pinocchio's cost of one UR5 call (µs, 1 thread): called from Python; the same call on an empty model "
          "(the binding's\n  own cost); their difference, an estimate of the C++ cost; and its batch call's time per "
          f"state ({QT.shape[1]} states, 1 thread)")
    cpp = {}
    for name, call in calls.items():
        overhead = best(bare[name], r, number)
        cpp[name] = python[name] - overhead
        also = (f"{'rneaInParallel' if name == 'rnea' else 'abaInParallel'} {batched[name] * 1e6:6.3g}"
                if name in batched else "(no batch call)")
        print(f"    pin.{name:<23} from Python {python[name] * 1e6:6.3g}   empty model {overhead * 1e6:6.3g}   "
              f"≈ C++ {cpp[name] * 1e6:6.3g}   {also}")
    cpp.update({f"{name} batch": seconds for name, seconds in batched.items()})
    return cpp


def batches(compiled, pm, q, qd, qdd, batch, cpp, r) -> None:
    N = len(q)
    QT, VT, AT, pool = batch
    Q, V = QT.T, VT.T  # a Pinocchio user's states one a row, for the loops
    pd = pm.createData()
    out = np.zeros((pm.nv, N), order="F")
    print(f"2. a batch of {N} states, per sample (µs): our compiled model on 1 thread, Pinocchio's single-thread path")
    with our_threads(1):
        used = {m: threads_used(compiled, m, *a) for m, a in (("inverse_dynamics", (q, qd, qdd)), ("mass_matrix", (q,)),
                                                             ("coriolis_matrix", (q, qd)),
                                                             ("forward_dynamics", (q, qd, qdd)))}
        line("τ: compile_model(ur5).inverse_dynamics / rneaInParallel(1)", best(lambda: compiled.inverse_dynamics(q, qd, qdd), r) / N,
             best(lambda: pin.rneaInParallel(1, pool, QT, VT, AT, out), r) / N, "µs",
             threads(used["inverse_dynamics"], 1), "τ batch")
        ours_M = best(lambda: compiled.mass_matrix(q), r) / N
        line("M: .mass_matrix / a Python loop over pin.crba", ours_M, best(lambda: [pin.crba(pm, pd, a) for a in Q], r) / N,
             "µs", threads(used["mass_matrix"], 1), "M batch")
        print(f"    against pin.crba's C++ ≈ {cpp['crba'] * 1e6:.3g} µs a call (1.): {ours_M / cpp['crba']:.2f}")
        ours_C = best(lambda: compiled.coriolis_matrix(q, qd), r) / N
        line("C: .coriolis_matrix / a Python loop over pin.computeCoriolisMatrix", ours_C,
             best(lambda: [pin.computeCoriolisMatrix(pm, pd, a, b) for a, b in zip(Q, V)], r) / N, "µs",
             threads(used["coriolis_matrix"], 1), "C batch")
        print(f"    against pin.computeCoriolisMatrix's C++ ≈ {cpp['computeCoriolisMatrix'] * 1e6:.3g} µs a call (1.): "
              f"{ours_C / cpp['computeCoriolisMatrix']:.2f}")
        line("FD: .forward_dynamics / abaInParallel(1)", best(lambda: compiled.forward_dynamics(q, qd, qdd), r) / N,
             best(lambda: pin.abaInParallel(1, pool, QT, VT, AT, out), r) / N, "µs",
             threads(used["forward_dynamics"], 1), "FD batch")
        ours_1 = best(lambda: compiled.inverse_dynamics(q, qd, qdd), r) / N
        rnea_1 = best(lambda: pin.rneaInParallel(1, pool, QT, VT, AT, out), r) / N
    with our_threads(2):
        used_2 = threads_used(compiled, "inverse_dynamics", q, qd, qdd)
        print(f"3. the τ batch with threads set to 2 on both sides, per sample (µs; ours shares a batch only when each "
              f"thread gets\n  {compiled_module.THREAD_STATES} states or more, so it ran on {used_2} here)")
        ours_2 = best(lambda: compiled.inverse_dynamics(q, qd, qdd), r) / N
        theirs_2 = best(lambda: pin.rneaInParallel(2, pool, QT, VT, AT, out), r) / N
    line("τ: .inverse_dynamics / rneaInParallel(2)", ours_2, theirs_2, "µs", threads(used_2, 2), "2 threads")
    print(f"  throughput against one thread (both measured again just before): ours {ours_1 / ours_2:.2f}×, "
          f"Pinocchio's {rnea_1 / theirs_2:.2f}×" + ("  (2 threads slower than 1: the machine was busy, measure again)"
                                                     if theirs_2 > rnea_1 or ours_2 > ours_1 else ""))


def simulation(model, oracle, duration: float, r) -> None:
    rounds = min(r, 3)
    print(f"4. simulate {duration:g} s of UR5, RK4 at 1 ms, best of {rounds} (s)")
    q0, qd0 = np.array([0.0, -1.2, 1.0, -0.5, 0.5, 0.0]), np.zeros(6)
    qp, vp = oracle.configuration(q0), oracle.velocity(qd0)  # Pinocchio's arrays, made once
    simulate(model, q0, qd0, duration, 1e-3, compiled=True)  # warm: a first run may build the native code (see 6)
    runs = {}

    def ours():
        runs["ours"] = simulate(model, q0, qd0, duration, 1e-3, integrator="rk4", compiled=True)

    def theirs():
        runs["pin"] = bare_rk4(oracle.model, oracle.data, qp, vp, duration, 1e-3)

    line("simulate(ur5, q0, 0, …, compiled=True) / a bare RK4 loop on pin.aba", best(ours, rounds), best(theirs, rounds),
         "s", ONE, "simulate")
    print(f"  final states differ by {np.abs(runs['ours'].q[-1] - oracle._ours(runs['pin'])).max():.1e} rad")
    # joint stops: the UR5 run into its ±2π limits (every joint at 2π/s), stopped and held in native code
    fast = np.array([6.0, -6.0, 3.0, -6.0, 6.0, -6.0]), np.full(6, 2 * np.pi) * np.resize([1.0, -1.0], 6)

    def stopped():
        runs["stop"] = simulate(model, *fast, duration, 1e-3, integrator="rk4", limits="stop", compiled=True)

    line("simulate(…, limits='stop') into the limits / the bare RK4 loop without stops", best(stopped, rounds),
         best(theirs, rounds), "s", ONE)
    print(f"  {len(runs['stop'].stops)} stops; the energy never above the start's: "
          f"{runs['stop'].energy.max() <= runs['stop'].energy[0] + 1e-6}")
    # the adaptive integrator (SciPy's DOP853, its steps in Python) against native RK4 at a fifth of the step
    runs["reference"] = simulate(model, q0, qd0, duration, 1e-5, integrator="rk4", compiled=True)

    def adaptive():
        runs["adaptive"] = simulate(model, q0, qd0, duration, 1e-3, integrator="adaptive", compiled=True)

    def small_steps():
        runs["rk4 2e-4"] = simulate(model, q0, qd0, duration, 2e-4, integrator="rk4", compiled=True)

    line("simulate(…, integrator='adaptive') / simulate(…, dt=2e-4) RK4 natively", best(adaptive, rounds),
         best(small_steps, rounds), "s", "both sides ours, 1 thread")
    error = {name: np.abs(runs[name].q[-1] - runs["reference"].q[-1]).max() for name in ("adaptive", "rk4 2e-4")}
    print(f"  the final state's error against RK4 at 10 µs: adaptive {error['adaptive']:.1e} rad, RK4 at 0.2 ms "
          f"{error['rk4 2e-4']:.1e} rad")


def ensemble(members: int, r) -> None:
    rounds = min(r, 3)
    print(f"5. {members} double pendulums (continuous joints), 0.5 s of RK4 at 1 ms, best of {rounds} (s)")
    pendulum = load_robot("double_pendulum_continuous")
    fast = compile_model(pendulum)
    pm = pin.buildModelFromUrdf(str(robot_path("double_pendulum_continuous")))  # as a Pinocchio user loads it
    assert [pm.names[i] for i in range(1, pm.njoints)] == list(pendulum.joint_names)
    pd, pool = pm.createData(), pin.ModelPool(pm, 1)
    start = np.array([2.0, 0.0]) + 1e-3 * np.random.default_rng(1).standard_normal((members, 2))
    theta0, v0 = np.asfortranarray(start.T), np.zeros((pm.nv, members), order="F")  # Pinocchio's layout: (nv, K)
    configurations = [np.ravel(np.column_stack([np.cos(s), np.sin(s)])) for s in start]  # q = (cos θ₁, sin θ₁, …)
    zero = np.zeros(pm.nv)
    runs = {}

    def ours():
        runs["ours"] = simulate(pendulum, start, np.zeros(2), 0.5, 1e-3, compiled=True)

    def vectorised():
        runs["batched"] = batched_rk4(pm, pool, theta0, v0, 0.5, 1e-3, 1)

    def loop():
        runs["loop"] = [bare_rk4_integrate(pm, pd, q, zero, 0.5, 1e-3) for q in configurations]

    with our_threads(1):
        used = threads_used(fast, "forward_dynamics", start, np.zeros_like(start), np.zeros_like(start))
        ours_seconds = best(ours, rounds)
    line("one ensemble, compiled / RK4 over the members with abaInParallel(1)", ours_seconds, best(vectorised, rounds),
         "s", threads(used, 1))
    line("one ensemble, compiled / a loop of RK4 on pin.aba for every member", ours_seconds, best(loop, rounds), "s",
         threads(used, 1), "ensemble")
    final = runs["ours"].q[-1]
    looped = np.array([[np.arctan2(q[2 * j + 1], q[2 * j]) for j in range(pm.nv)] for q in runs["loop"]])
    print(f"  final states differ by {np.abs(final - runs['batched'].T).max():.1e} rad (vectorised), "
          f"{np.abs(np.angle(np.exp(1j * (final - looped)))).max():.1e} rad (loop); required: 1e-6")


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
            if name == "ur5":
                seconds = first.generation_seconds + first.native_seconds
                print(f"  compile_model(ur5) with an empty cache, whole: {seconds:.2f} s  target ≤ "
                      f"{TARGETS['compile']:g} s: {'met' if seconds <= TARGETS['compile'] else 'NOT met'}")
        del os.environ["COURSE_DYNAMICS_CACHE"]


def against_mujoco(model, duration: float, r, number: int) -> None:
    """9. The default API against MuJoCo's calls as a MuJoCo user writes them, and simulate against
    ``mujoco.rollout`` (RK4, one C call for the whole run)."""
    try:
        import mujoco
        from mujoco import rollout
    except ImportError:
        print("9. against MuJoCo: not installed (pip install 'course-dynamics[engines]')")
        return
    from course_dynamics_reference.engines import MujocoEngine

    import course_dynamics

    engine = MujocoEngine(model, robot_path("ur5"))      # UR5's URDF through MuJoCo's importer, meshes left out
    m = engine.models[-1]                                # damping, friction loss, armature, limits off: our physics
    d = mujoco.MjData(m)
    assert list(engine.dof) == list(range(m.nv))         # the same joint order: the arrays go in as they are
    x, xd, xdd = random_states(model, 1, seed=3)
    x, xd, xdd = x[0], xd[0], xdd[0]
    full = np.zeros((m.nv, m.nv))
    print(f"9. against MuJoCo {mujoco.__version__}, UR5, one state from Python (µs), best of {r}; "
          f"simulate (s), best of {min(r, 3)}")

    def mj_tau():
        d.qpos[:], d.qvel[:], d.qacc[:] = x, xd, xdd
        mujoco.mj_inverse(m, d)
        return d.qfrc_inverse

    def mj_M():
        d.qpos[:] = x
        mujoco.mj_forward(m, d)
        mujoco.mj_fullM(m, d, full)   # MuJoCo ≥ 3.4's signature
        return full

    def mj_forward():
        d.qpos[:], d.qvel[:], d.qfrc_applied[:] = x, xd, xdd
        mujoco.mj_forward(m, d)
        return d.qacc

    course_dynamics.inverse_dynamics(model, x, xd, xdd)
    for label, ours, theirs in (("τ: inverse_dynamics(ur5, q, qd, qdd) / mj_inverse",
                                 lambda: course_dynamics.inverse_dynamics(model, x, xd, xdd), mj_tau),
                                ("M: mass_matrix(ur5, q) / mj_forward + mj_fullM",
                                 lambda: course_dynamics.mass_matrix(model, x), mj_M),
                                ("forward dynamics: forward_dynamics(ur5, q, qd, tau) / mj_forward",
                                 lambda: course_dynamics.forward_dynamics(model, x, xd, xdd), mj_forward)):
        line(label, best(ours, r, number), best(theirs, r, number), "µs", MUJOCO_ONE, "mujoco one")
    np.testing.assert_allclose(course_dynamics.inverse_dynamics(model, x, xd, xdd), mj_tau(), rtol=1e-9, atol=1e-9)
    rounds, steps = min(r, 3), int(round(duration / 1e-3))
    m.opt.integrator, m.opt.timestep = mujoco.mjtIntegrator.mjINT_RK4, 1e-3
    q0 = np.array([0.0, -1.2, 1.0, -0.5, 0.5, 0.0])
    state = np.zeros(mujoco.mj_stateSize(m, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    d.qpos[:], d.qvel[:], d.qfrc_applied[:] = q0, 0.0, 0.0
    mujoco.mj_getState(m, d, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    runs = {}

    def ours():
        runs["ours"] = simulate(model, q0, np.zeros(6), duration, 1e-3, integrator="rk4", compiled=True)

    def theirs():
        runs["mujoco"] = rollout.rollout(m, d, state, nstep=steps)

    line(f"simulate(ur5, q0, 0, {duration:g}, 1e-3) RK4 / mujoco.rollout RK4", best(ours, rounds), best(theirs, rounds),
         "s", MUJOCO_ONE, "mujoco rollout")
    print(f"  final states differ by {np.abs(runs['ours'].q[-1] - runs['mujoco'][0][0, -1, 1:1 + m.nq]).max():.1e} rad")


def memory(ur5_states: int, chain_states: int) -> None:
    """10. The extra peak memory of one batch τ call (what it allocates at most, its output included) over the
    size of its output, by tracemalloc (numpy reports its arrays to it); the states are made before."""
    import tracemalloc

    import course_dynamics

    print("10. a batch τ call's peak memory / the size of its output (the default API)")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "chain50.urdf"
        path.write_text(chain_urdf(50))
        for model, states, target in ((load_robot("ur5"), ur5_states, "memory ur5"),
                                      (load_urdf(path), chain_states, "memory chain")):
            q, qd, qdd = np.random.default_rng(0).uniform(-1, 1, (3, states, model.n))
            course_dynamics.inverse_dynamics(model, q[:2], qd[:2], qdd[:2])   # the choice made, the model loaded
            what = evaluator.choice(model, calls=1, states=states).path
            tracemalloc.start()
            tau = course_dynamics.inverse_dynamics(model, q, qd, qdd)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            ratio = peak / tau.nbytes
            print(f"  {model.name} ({model.n} joints), {states} states ({what}): {peak / 2**20:.0f} MiB at most for "
                  f"{tau.nbytes / 2**20:.0f} MiB of output: {ratio:.2f}  target ≤ {TARGETS[target]:g}: "
                  f"{'met' if ratio <= TARGETS[target] else 'NOT met'}")


FRESH_OURS = """import sys
import numpy as np
import course_dynamics
model = course_dynamics.load_robot("ur5")
q = np.array([0.1, -0.5, 0.3, 0.2, 0.1, 0.0])
for _ in range(int(sys.argv[1])):
    course_dynamics.inverse_dynamics(model, q, q, q)
"""
FRESH_PIN = """import sys
import numpy as np
import pinocchio as pin
from course_dynamics.base.robot_files import robot_path
model = pin.buildModelFromUrdf(str(robot_path("ur5")))
data = model.createData()
q = np.array([0.1, -0.5, 0.3, 0.2, 0.1, 0.0])
for _ in range(int(sys.argv[1])):
    pin.rnea(model, data, q, q, q)
"""


def fresh_process(r, loop: int) -> None:
    """11. A fresh process with an empty compiled-model cache: the first τ, and a loop of one-state τ calls, each
    the whole process (imports, loading UR5), against the same with Pinocchio."""
    rounds = min(r, 3)
    print(f"11. a fresh process, empty cache (s, the whole process), best of {rounds}")
    for calls, target, what in ((1, "first τ", "the first τ"), (loop, "fresh loop", f"{loop} one-state τ calls")):
        def ours():
            with tempfile.TemporaryDirectory() as empty:
                subprocess.run([sys.executable, "-c", FRESH_OURS, str(calls)], check=True, capture_output=True,
                               env=dict(os.environ, COURSE_DYNAMICS_CACHE=empty))

        theirs = best(lambda: subprocess.run([sys.executable, "-c", FRESH_PIN, str(calls)], check=True,
                                             capture_output=True), rounds)
        line(f"{what}: course_dynamics.inverse_dynamics / pin.rnea", best(ours, rounds), theirs, "s",
             "one process each", target)


def start_up(r) -> None:
    rounds = min(r, 3)
    print(f"7. start-up, best of {rounds} (s)")
    imports = best(lambda: subprocess.run([sys.executable, "-c", "import numpy, pinocchio"], capture_output=True,
                                          check=True), rounds)
    for words, target in ((["info", "ur5"], "start-up info"), (["--help"], "start-up help")):
        command = [sys.executable, "-m", "course_dynamics.cli", *words]
        ours = best(lambda: subprocess.run(command, capture_output=True, check=True), rounds)
        line(f"course-dynamics {' '.join(words)} / python -c 'import numpy, pinocchio'", ours, imports, "s",
             "one process each", target)


def chains(sizes, r) -> None:
    print("8. chains: cost per joint of one state, µs, ours on 1 thread (interpreted, numpy's BLAS as above; compiled, "
          "or 'over bound'; the native loop)")
    print(f"  {'joints':>6} {'τ':>9} {'M':>9} {'C':>9} {'FD':>9} | {'τ':>9} {'M':>9} {'C':>9} {'FD':>9} | "
          f"{'τ':>9} {'M':>9} {'FD':>9}")
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
            loop = looped.looped(model)
            loops = [f"{'not built':>9}"] + [" " * 9] * 2 if loop is None else [
                f"{best(f, r, 2000) / n * 1e6:9.3g}" for f in (lambda: loop.native_call("tau", q, qd, qdd),
                                                              lambda: loop.native_call("mass_matrix", q),
                                                              lambda: loop.forward_dynamics(q, qd, qdd))]
            print(f"  {n:>6} " + " ".join(f"{t / n * 1e6:9.3g}" for t in interpreted) + " | " + " ".join(fast) +
                  " | " + " ".join(loops))


def chains_against_pinocchio(sizes, states: int, r) -> None:
    """8b. The same chains through the default API against Pinocchio: one state τ and M, and a batch τ."""
    import course_dynamics

    print(f"8b. the chains, the default API against Pinocchio (one state, µs; a batch of {states}, µs a sample)")
    with tempfile.TemporaryDirectory() as folder:
        for n in sizes:
            path = Path(folder) / f"chain{n}.urdf"
            path.write_text(chain_urdf(n))
            model, pm = load_urdf(path), pin.buildModelFromUrdf(str(path))   # as each side's user loads it
            pd, pool = pm.createData(), pin.ModelPool(pm, 1)
            q, qd, qdd = np.random.default_rng(n).uniform(-1, 1, (3, states, n))
            Q, V, A = (np.asfortranarray(a.T) for a in (q, qd, qdd))      # Pinocchio's layout: a state a column
            out = np.zeros((n, states), order="F")
            rounds, number = (1, 20) if n >= 100 else (r, 200)
            target = "chain one" if n >= 25 else None  # the target is for chains of 25 joints and more
            course_dynamics.inverse_dynamics(model, q[0], qd[0], qdd[0])
            line(f"chain of {n}: one state τ, inverse_dynamics / pin.rnea",
                 best(lambda: course_dynamics.inverse_dynamics(model, q[0], qd[0], qdd[0]), rounds, number),
                 best(lambda: pin.rnea(pm, pd, q[0], qd[0], qdd[0]), rounds, number), "µs", ONE, target)
            line(f"chain of {n}: one state M, mass_matrix / pin.crba",
                 best(lambda: course_dynamics.mass_matrix(model, q[0]), rounds, number),
                 best(lambda: pin.crba(pm, pd, q[0]), rounds, number), "µs", ONE, target)
            with our_threads(1):
                ours = best(lambda: course_dynamics.inverse_dynamics(model, q, qd, qdd), rounds) / states
            theirs = best(lambda: pin.rneaInParallel(1, pool, Q, V, A, out), rounds) / states
            line(f"chain of {n}: batch τ / rneaInParallel(1)", ours, theirs, "µs", ONE, "chain batch" if n >= 25 else None)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=4000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--duration", type=float, default=2.0, help="simulated seconds of UR5 (default 2)")
    parser.add_argument("--members", type=int, default=1000, help="double pendulums in the ensemble (default 1000)")
    parser.add_argument("--calls", type=int, default=20000, help="calls a round for one state (default 20000)")
    parser.add_argument("--chains", default="6,30,100,300", help="chain lengths for the cost per joint")
    parser.add_argument("--loop", type=int, default=10000, help="one-state calls of the fresh process (default 10000)")
    parser.add_argument("--memory", default="1000000,100000",
                        help="UR5 states and 50-joint-chain states of the memory rows (default 1000000,100000)")
    args = parser.parse_args()
    model = load_robot("ur5")
    oracle = PinocchioOracle(robot_path("ur5"), model.joint_names)
    compiled = compile_model(model)  # with its native code where a compiler exists (waits for the build)
    q, qd, qdd = random_states(model, args.batch, seed=0)
    # Pinocchio's arrays, made once before any timing: one state a column, its own joint layout
    QT, VT, AT = (np.asfortranarray(np.array([convert(s) for s in states]).T)
                  for convert, states in ((oracle.configuration, q), (oracle.velocity, qd), (oracle.velocity, qdd)))
    batch = (QT, VT, AT, pin.ModelPool(oracle.model, 2))
    r = args.repeat
    print_conditions(f"UR5 ({model.n} joints), best of {r} rounds on both sides unless said; ratio = ours / Pinocchio's")
    cpp = one_state(model, oracle, compiled, q[0], qd[0], qdd[0], batch, r, args.calls)
    batches(compiled, oracle.model, q, qd, qdd, batch, cpp, r)
    simulation(model, oracle, args.duration, r)
    ensemble(args.members, r)
    compiling()
    start_up(r)
    chains([int(n) for n in args.chains.split(",")], r)
    chains_against_pinocchio([int(n) for n in args.chains.split(",")], args.batch, r)
    against_mujoco(model, args.duration, r, args.calls)
    memory(*(int(n) for n in args.memory.split(",")))
    fresh_process(r, args.loop)
    print_load()


if __name__ == "__main__":
    main()
