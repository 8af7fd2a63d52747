"""course_dynamics/core/evaluator.py: one place chooses the implementation, and both agree with Pinocchio."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import sympy as sp
from helpers import SAMPLES, assert_agrees, chain_urdf, urdf_of

import course_dynamics
from course_dynamics import load_robot, load_urdf
from course_dynamics.core import evaluator
from course_dynamics.core.compiled import CompiledModel, CompileWarning, ProgramTooLargeError
from course_dynamics.core.evaluator import COMPILE_SECONDS, implementation, interpreted_seconds

API = ("inverse_dynamics", "mass_matrix", "coriolis_matrix", "gravity_torques", "forward_dynamics")


def compiled_now(model):
    """The evaluator's compiled model for ``model`` if it has one, without counting any work."""
    return implementation(model, calls=0, states=0)


def test_the_package_functions_are_the_evaluators():
    assert all(getattr(course_dynamics, name) is getattr(evaluator, name) for name in API)


def test_little_work_stays_interpreted_and_a_loop_of_calls_switches_once():
    arm = load_robot("two_link")
    assert implementation(arm, calls=1000, states=1, compiled=False) is None
    assert implementation(arm, calls=1, states=10) is None and compiled_now(arm) is None
    calls = math.ceil((COMPILE_SECONDS - interpreted_seconds(1, 10)) / interpreted_seconds(1, 100))  # then it pays
    chosen = [implementation(arm, calls=1, states=100) for _ in range(calls)]
    assert all(c is None for c in chosen[:-1]) and isinstance(chosen[-1], CompiledModel)
    assert compiled_now(arm) is chosen[-1] and implementation(arm, compiled=False) is None
    other = load_robot("two_link")                                   # the same numbers, another model object
    assert compiled_now(other) is None and implementation(other, compiled=True) is not None


def test_one_long_run_compiles_at_its_start():
    arm = load_robot("two_link")
    assert isinstance(implementation(arm, calls=100, states=1), CompiledModel)      # 100 Euler steps of simulate
    assert implementation(load_robot("two_link"), calls=1, states=20_000) is not None  # a 20 000-row log


def test_a_robot_too_large_to_compile_warns_once_and_runs_interpreted(tmp_path):
    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(60))
    chain = load_urdf(path)
    with pytest.raises(ProgramTooLargeError):
        implementation(chain, compiled=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert implementation(chain, calls=10_000) is None and implementation(chain, calls=10_000) is None
        q = np.random.default_rng(1).uniform(-1, 1, (3, 50, chain.n))
        tau = course_dynamics.inverse_dynamics(chain, *q)
    assert [w.category for w in caught] == [CompileWarning]
    np.testing.assert_array_equal(tau, course_dynamics.core.newton_euler.inverse_dynamics(chain, *q))


def test_symbols_and_duals_take_the_recursion_even_when_compiled():
    arm = load_robot("two_link")
    implementation(arm, compiled=True)
    t1, t2 = sp.symbols("theta1 theta2")
    G = course_dynamics.gravity_torques(arm, np.array([t1, t2], dtype=object))
    assert all(isinstance(g, sp.Expr) for g in G) and G[1].has(t1)


@pytest.mark.parametrize("path", ["interpreted", "compiled"])
def test_the_package_functions_agree_with_pinocchio_on_either_path(robot, path):
    name, _, oracle, (q, qd, qdd) = robot
    model = load_urdf(urdf_of(name))                                  # a model of this test's own
    if path == "compiled":
        implementation(model, compiled=True)
    tau = course_dynamics.inverse_dynamics(model, q, qd, qdd)
    M = course_dynamics.mass_matrix(model, q)
    C = course_dynamics.coriolis_matrix(model, q, qd)
    G = course_dynamics.gravity_torques(model, q)
    qdd_back = course_dynamics.forward_dynamics(model, q, qd, tau)
    assert (compiled_now(model) is not None) == (path == "compiled")  # 200 states, 5 calls: too little to switch
    for i in range(SAMPLES):
        scale = np.abs(oracle.tau(q[i], qd[i], qdd[i])).max()
        assert_agrees(tau[i], oracle.tau(q[i], qd[i], qdd[i]), what=f"{name} tau {i}")
        assert_agrees(M[i], oracle.M(q[i]), what=f"{name} M {i}")
        assert_agrees(C[i], oracle.C(q[i], qd[i]), scale=scale, what=f"{name} C {i}")
        assert_agrees(G[i], oracle.G(q[i]), scale=scale, what=f"{name} G {i}")
        assert_agrees(qdd_back[i], oracle.aba(q[i], qd[i], tau[i]), scale=np.abs(qdd[i]).max(), what=f"{name} qdd {i}")
    for i in range(5):  # one state at a time: compiled, the native code where it was built, with no other check
        assert_agrees(course_dynamics.inverse_dynamics(model, q[i], qd[i], qdd[i]), oracle.tau(q[i], qd[i], qdd[i]),
                      what=f"{name} one-state tau {i}")
        assert_agrees(course_dynamics.mass_matrix(model, q[i]), oracle.M(q[i]), what=f"{name} one-state M {i}")
        assert_agrees(course_dynamics.forward_dynamics(model, q[i], qd[i], tau[i]), oracle.aba(q[i], qd[i], tau[i]),
                      scale=np.abs(qdd[i]).max(), what=f"{name} one-state qdd {i}")
    with pytest.raises(course_dynamics.StateError, match="is nan"):
        course_dynamics.inverse_dynamics(model, np.full(model.n, np.nan), qd[0], qdd[0])


def test_a_batch_of_one_keeps_its_shape_on_every_path():
    """A (1, n) batch is a batch, whether the interpreted, the compiled or the native code answers."""
    model = load_robot("rrr_arm")
    z = np.zeros((1, model.n))
    shapes = []
    for compiled in (False, True):
        if compiled:
            implementation(model, compiled=True)
        shapes.append((course_dynamics.inverse_dynamics(model, z, z, z).shape, course_dynamics.mass_matrix(model, z).shape,
                       course_dynamics.forward_dynamics(model, z, z, z).shape))
    assert shapes[0] == shapes[1] == ((1, 3), (1, 3, 3), (1, 3))


def test_batches_of_different_lengths_are_one_clear_error():
    model = load_robot("two_link")
    with pytest.raises(course_dynamics.StateError, match=r"batches of different lengths \(10,\), \(9,\)"):
        course_dynamics.inverse_dynamics(model, np.zeros((10, 2)), np.zeros((9, 2)), np.zeros(2))
