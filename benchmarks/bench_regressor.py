"""Cost of the inertial-parameter regressor Y against our τ and against Pinocchio's, measured side by side in one run.

Run:  python benchmarks/bench_regressor.py [--batch 10000] [--repeat 5] [--robots ur5 panda]

Every figure is the best of --repeat rounds on both sides, and every row says the threads each side ran on.
For each robot it prints first the compiled Y against Pinocchio, each beside its target: ``compile_model(model)
.regressor`` (the traced program, its native code where a compiler exists) and the default API
``course_dynamics.regressor`` (the evaluator's choice; the model is compiled and cached by then) for one
state against ``pin.computeJointTorqueRegressor``, and the compiled batch, on one thread, against a Python loop
of it. Then, per sample (µs): the interpreted Y (``course_dynamics.core.regressor.regressor``, one
Newton–Euler pass on dual numbers carrying 10 n derivatives) against our τ by the interpreted
recursion (``course_dynamics.core.newton_euler.inverse_dynamics``, called directly: the package's
``inverse_dynamics`` would switch to the compiled model by itself) and by the compiled model
(``compile_model(model).inverse_dynamics``, its native code where a compiler exists, held to one thread), and
against ``pin.computeJointTorqueRegressor``, for one state and for a batch of --batch states. Pinocchio has no
batched regressor: a Python loop over the states, as a user writes it, on Pinocchio's own arrays made before
timing; beside it, an estimate of its C++ cost per call: the time from Python less that of the same call on an
empty model (the binding's own cost). Last, the largest relative difference between the two Y.
"""
from __future__ import annotations

import argparse

import numpy as np
import pinocchio as pin
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states

import course_dynamics
from course_dynamics import load_robot, robot_path
from course_dynamics.core import newton_euler
from course_dynamics.core.compiled import compile_model
from course_dynamics.core.regressor import regressor

from measure import best, our_threads, print_conditions, print_load, threads, threads_used  # this folder is on the path

TARGETS = {"one": 3.0, "batch": 1.0}  # the compiled rows' targets, ours / Pinocchio's


def line(label: str, ours: float, theirs: float, ran: str, target: str | None = None) -> None:
    ratio = ours / theirs
    verdict = "" if target is None else f"  target ≤ {TARGETS[target]:g}: {'met' if ratio <= TARGETS[target] else 'NOT met'}"
    print(f"  {label:<58} {ours * 1e6:>10.3g} {theirs * 1e6:>10.3g} µs {ratio:>8.2f}  {ran}{verdict}")


def bench(name: str, batch: int, repeat: int) -> None:
    model = load_robot(name)
    oracle = PinocchioOracle(robot_path(name), model.joint_names, model.gravity)
    compiled = compile_model(model)  # with its native code where a compiler exists
    q, qd, qdd = random_states(model, batch, seed=0)
    x, xd, xdd = q[0], qd[0], qdd[0]
    # Pinocchio's regressor columns in our order: body i is its joint of the same name, ten columns each
    ids = [oracle.plain.getJointId(body.joint) for body in model.bodies]
    columns = np.concatenate([np.arange(10 * (j - 1), 10 * j) for j in ids])
    # Pinocchio's own arrays, made before timing, for its model without mimic joints (its regressor takes no
    # mimic joint): a mimic's coordinate is S Θ + b, as the oracle forms it
    S = oracle.S
    Q = [oracle.plain_configuration(s) for s in q]
    V = [S @ s for s in qd]
    A = [S @ s for s in qdd]
    pm, pd = oracle.plain, oracle.plain_data
    empty = pin.Model()  # no joints: a call on it costs the binding, not the algorithm
    ed, z = empty.createData(), np.zeros(0)
    native = "native" if compiled.native else "Python programs: no C compiler here"
    print(f"{name} ({model.n} joints, {10 * model.n_bodies} parameters), best of {repeat}; columns: ours, reference, unit, "
          f"ratio, threads (compiled τ: {native})")

    print("  compiled Y (traced τ on dual numbers)")
    course_dynamics.regressor(model, x, xd, xdd)
    pin_1 = best(lambda: pin.computeJointTorqueRegressor(pm, pd, Q[0], V[0], A[0]), repeat, 5000)
    line("one state: compile_model(…).regressor / pin.computeJointTorqueRegressor",
         best(lambda: compiled.regressor(x, xd, xdd), repeat, 5000), pin_1, threads(1, 1), "one")
    line("one state: course_dynamics.regressor (default API) / the same",
         best(lambda: course_dynamics.regressor(model, x, xd, xdd), repeat, 5000), pin_1, threads(1, 1), "one")
    pin_N = best(lambda: [pin.computeJointTorqueRegressor(pm, pd, a, b, c) for a, b, c in zip(Q, V, A)], repeat) / batch
    with our_threads(1):
        compiled_Y = best(lambda: compiled.regressor(q, qd, qdd), repeat) / batch
    line(f"{batch} states, per sample: compiled / a loop of pin.computeJointTorqueRegressor", compiled_Y, pin_N,
         threads(1, 1), "batch")
    assert np.allclose(compiled.regressor(q, qd, qdd), regressor(model, q, qd, qdd), rtol=1e-12, atol=1e-9)

    print("  one state, interpreted")
    Y_1 = best(lambda: regressor(model, x, xd, xdd), repeat, 50)
    interpreted_1 = best(lambda: newton_euler.inverse_dynamics(model, x, xd, xdd), repeat, 500)
    compiled_1 = best(lambda: compiled.inverse_dynamics(x, xd, xdd), repeat, 5000)
    binding = best(lambda: pin.computeJointTorqueRegressor(empty, ed, z, z, z), repeat, 5000)
    cpp = pin_1 - binding
    line("Y / our interpreted τ (newton_euler.inverse_dynamics)", Y_1, interpreted_1, "Y 1 thread / τ 1 thread")
    line("Y / our compiled τ (compile_model(…).inverse_dynamics)", Y_1, compiled_1, "Y 1 thread / τ 1 thread")
    line("Y / pin.computeJointTorqueRegressor from Python", Y_1, pin_1, threads(1, 1))
    line(f"Y / its C++ estimate (less {binding * 1e6:.2g} µs on an empty model)", Y_1, cpp, threads(1, 1))

    print(f"  a batch of {batch} states, per sample, interpreted")
    with our_threads(1):
        used = threads_used(compiled, "inverse_dynamics", q, qd, qdd)
        Y_N = best(lambda: regressor(model, q, qd, qdd), repeat) / batch
        interpreted_N = best(lambda: newton_euler.inverse_dynamics(model, q, qd, qdd), repeat) / batch
        compiled_N = best(lambda: compiled.inverse_dynamics(q, qd, qdd), repeat) / batch
    line("Y batch / our interpreted τ batch", Y_N, interpreted_N, "Y 1 thread / τ 1 thread")
    line("Y batch / our compiled τ batch", Y_N, compiled_N, f"Y 1 thread / τ {used} thread" + "s" * (used != 1))
    line("Y batch / pin.computeJointTorqueRegressor loop", Y_N, pin_N, threads(1, 1))
    line("Y batch / its C++ estimate (one state's, above)", Y_N, cpp, threads(1, 1))

    ours = regressor(model, q, qd, qdd)
    theirs = np.array([oracle.regressor(a, b, c)[:, columns] for a, b, c in zip(q, qd, qdd)])
    error = max(np.abs(o - t).max() / np.abs(t).max() for o, t in zip(ours, theirs))
    print(f"  largest difference from Pinocchio, relative to each state's largest entry: {error:.1e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batch", type=int, default=10000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--robots", nargs="+", default=["ur5", "panda"])
    args = parser.parse_args()
    print_conditions("The regressor Y against τ and Pinocchio's; ratio = ours / reference")
    for name in args.robots:
        bench(name, args.batch, args.repeat)
    print_load()


if __name__ == "__main__":
    main()
