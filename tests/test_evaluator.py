"""course_dynamics/core/evaluator.py: one rule chooses the implementation, the same for the same call whatever
ran before, and every path agrees with Pinocchio."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time
import warnings

import numpy as np
import pytest
import sympy as sp
from helpers import ROOT, SAMPLES, assert_agrees, chain_urdf, urdf_of

import course_dynamics
from course_dynamics import load_robot, load_urdf
from course_dynamics.core import evaluator
from course_dynamics.core.compiled import (CompiledModel, CompileWarning, ProgramTooLargeError, compile_model, looped,
                                           native)
from course_dynamics.core.compiled.building import BUSY
from course_dynamics.core.compiled.cache import Cache
from course_dynamics.core.evaluator import COMPILE_SECONDS, Interpreted, choice, implementation, interpreted_seconds

API = ("inverse_dynamics", "mass_matrix", "coriolis_matrix", "gravity_torques", "forward_dynamics", "regressor")
#: What runs a float call the compiled model does not: the native loop, where it was built with the package.
UNCOMPILED, UNCOMPILED_RUN = ("loop", looped.Looped) if looped.library() is not None else ("interpreted", Interpreted)


@pytest.fixture
def cold_cache(tmp_path, monkeypatch):
    """A cache folder that holds nothing yet, for this test alone."""
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_the_package_functions_are_the_evaluators():
    assert all(getattr(course_dynamics, name) is getattr(evaluator, name) for name in API)


def test_the_rule_reads_the_call_and_the_cache(cold_cache):
    arm = load_robot("two_link")
    assert choice(arm, calls=1000, compiled=False) == evaluator.Choice("interpreted", evaluator.ASKED, None)
    assert choice(arm, floats=False).reason == evaluator.NOT_FLOATS
    little = choice(arm, calls=1, states=10)
    assert (little.path, little.reason, type(little.run)) == (UNCOMPILED, evaluator.LITTLE, UNCOMPILED_RUN)
    batch = int(np.ceil((COMPILE_SECONDS - interpreted_seconds(1, 0)) / evaluator.STATE_SECONDS))
    assert choice(arm, calls=1, states=batch - 1).reason == evaluator.LITTLE
    pays = choice(arm, calls=1, states=batch)                       # about 20 000 states: this call pays
    assert (pays.path, pays.reason) == ("compiled", evaluator.PAYS) and isinstance(pays.run, CompiledModel)
    assert list(cold_cache.glob("*.entry"))                         # ... and was kept in the cache
    again = choice(arm, calls=1, states=10)
    assert (again.path, again.reason) == ("compiled", evaluator.CACHED) and again.run is pays.run
    other = load_robot("two_link")                                  # the same numbers, another model object
    assert choice(other).reason == evaluator.CACHED and choice(other).run is pays.run  # loaded once
    assert choice(arm, floats=False).path == choice(arm, compiled=False).path == "interpreted"


def test_without_a_cache_the_call_alone_decides(monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", "off")
    arm = load_robot("two_link")
    assert choice(arm, calls=1000).path == "compiled"               # compiled in memory ...
    assert choice(arm, calls=1, states=10).path == UNCOMPILED       # ... which no cache holds


SAME_CALL = """
import json, sys
import numpy as np
import course_dynamics
from course_dynamics import load_robot
from course_dynamics.core import evaluator
from course_dynamics.core.compiled import CompiledModel, looped

ran = []
def spy(cls, name, path):
    original = getattr(cls, name)
    setattr(cls, name, lambda self, *a: (ran.append(path), original(self, *a))[1])
spy(evaluator.Interpreted, "inverse_dynamics", "interpreted")
spy(CompiledModel, "inverse_dynamics", "compiled")
spy(CompiledModel, "native_call", "compiled")           # the one-state shortcut to C
spy(looped.Looped, "inverse_dynamics", "loop")
spy(looped.Looped, "native_call", "loop")

arm = load_robot("two_link").with_gravity([0, 0, -9.8])
rng = np.random.default_rng(0)
if sys.argv[1] == "loop":                               # what the evaluator once counted until it switched
    for _ in range(3000):
        course_dynamics.inverse_dynamics(arm, *rng.uniform(-1, 1, (3, 2)))
    for _ in range(100):
        course_dynamics.mass_matrix(arm, rng.uniform(-1, 1, (500, 2)))
elif sys.argv[1] == "batch":                           # a batch whose own work pays for compiling
    course_dynamics.inverse_dynamics(arm, *rng.uniform(-1, 1, (3, 40_000, 2)))
ran.clear()
q, qd, qdd = rng.uniform(-1, 1, (3, 2))
course_dynamics.inverse_dynamics(arm, q, qd, qdd)
entry = looped.remembered(arm)                          # the native entry runs a remembered choice's C
if not ran:
    ran.append({CompiledModel: "compiled", looped.Looped: "loop"}[type(entry)])
chosen = evaluator.choice(arm, calls=1, states=1)
print(json.dumps({"ran": ran[0], "path": chosen.path, "reason": chosen.reason}))
"""


def one_state_call_after(before: str, cache: str) -> dict:
    """What ran a one-state τ in a fresh process after ``before`` ("nothing", "loop", "batch")."""
    environment = dict(os.environ, COURSE_DYNAMICS_CACHE=cache, PYTHONPATH=str(ROOT))
    done = subprocess.run([sys.executable, "-c", SAME_CALL, before], capture_output=True, text=True, timeout=120,
                          env=environment, check=True)
    return json.loads(done.stdout.splitlines()[-1])


def test_the_same_call_runs_the_same_implementation_whatever_ran_before(tmp_path, monkeypatch):
    """Fresh processes: a one-state call alone, after thousands of calls and batches, and after a batch that
    compiles; the same path as long as the cache holds the same, and the choice names what ran."""
    arm = load_robot("two_link").with_gravity([0, 0, -9.8])
    warm = tmp_path / "warm"
    with monkeypatch.context() as patched:
        patched.setenv("COURSE_DYNAMICS_CACHE", str(warm))
        compile_model(arm)                                            # the cache holds it, C where a compiler is
    seen = {}
    for cache in ("off", str(tmp_path / "cold"), str(warm)):
        for before in ("nothing", "loop", "batch"):
            if cache.endswith("cold") and before == "batch":
                continue                                              # that batch fills the cache: below
            seen[cache, before] = one_state_call_after(before, cache)
            assert seen[cache, before]["ran"] == seen[cache, before]["path"], seen[cache, before]
    for cache, path in (("off", UNCOMPILED), (str(tmp_path / "cold"), UNCOMPILED), (str(warm), "compiled")):
        assert {seen[cache, before]["path"] for before in ("nothing", "loop", "batch") if (cache, before) in seen} \
               == {path}, seen
    assert seen[str(warm), "nothing"]["reason"] == evaluator.CACHED  # from the first call of the process
    filled = one_state_call_after("batch", str(tmp_path / "filled"))   # the batch put it in the cache: it says so
    assert (filled["ran"], filled["reason"]) == ("compiled", evaluator.CACHED)


def test_c_another_process_was_building_is_taken_up_once_it_is_in_the_cache(tmp_path, monkeypatch):
    """A model chosen while another process builds its C runs without it; once that C is in the cache, a later
    call looks again and runs it (the choice depends on the cache now, not on when the first call came)."""
    if native.compiler() is None:
        pytest.skip("no C compiler: no native library to wait for")
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path))
    arm = load_robot("two_link").with_gravity([0.0, 0.0, -9.1])  # a content no other test compiles
    assert compile_model(arm).native
    (library,) = tmp_path.glob("*.native")
    key = library.name[:-len(".native")]
    with Cache(tmp_path) as store:
        built = store.load_bytes(f"{key}.native")
        store.remove(f"{key}.native")
        store.store_bytes(f"{key}.native-building", repr(time.time()).encode())  # as another process's build does
    first = choice(arm, calls=1)
    assert first.path == "compiled" and not first.run.native and first.run.native_reason == BUSY
    with Cache(tmp_path) as store:  # that process's build is done
        store.remove(f"{key}.native-building")
        store.store_bytes(f"{key}.native", built)
    monkeypatch.setattr(evaluator, "BUSY_SECONDS", 0.0)  # as the evaluator reads it
    later = choice(arm, calls=1)
    assert later.path == "compiled" and later.run.native and later.reason == evaluator.CACHED


@pytest.mark.parametrize("by", ["this process", "another process"])
def test_c_that_reaches_the_cache_after_the_choice_is_taken_up(by, tmp_path, monkeypatch):
    """A model whose choice found its compiled model but no C runs the loop in its place; C this process then
    builds (``compile_model``) is run by the next one-state call, and C another process leaves in the cache by
    the next choice a second on."""
    if native.compiler() is None or looped.library() is None:
        pytest.skip("no C compiler: no native library to take up")
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    arm = load_robot("two_link").with_gravity([0.0, 0.0, -9.2])  # a content no other test compiles
    assert not compile_model(arm, native_code=None).native            # the cache holds its programs, no C
    q, qd, tau = np.array([0.3, -0.2]), np.array([0.1, 0.4]), np.array([5.0, 1.0])
    expected = course_dynamics.core.forward_dynamics.forward_dynamics(arm, q, qd, tau)
    assert_agrees(course_dynamics.forward_dynamics(arm, q, qd, tau), expected, rtol=1e-12)
    first = looped.remembered(arm)
    assert isinstance(first, CompiledModel) and not first.native and first.loop is not None
    if by == "this process":
        assert compile_model(arm).native
    else:
        subprocess.run([sys.executable, "-c", "from course_dynamics import load_robot\n"
                        "from course_dynamics.core.compiled import compile_model\n"
                        "assert compile_model(load_robot('two_link').with_gravity([0.0, 0.0, -9.2])).native"],
                       env=dict(os.environ), check=True, timeout=300)
        monkeypatch.setattr(evaluator, "BUSY_SECONDS", 0.0)
        choice(arm, calls=1)                                           # a second on: a choice looks again
    assert_agrees(course_dynamics.forward_dynamics(arm, q, qd, tau), expected, rtol=1e-12)
    assert looped.remembered(arm).native and choice(arm, calls=1).run.native


def test_one_long_run_compiles_at_its_start(cold_cache):
    assert choice(load_robot("two_link"), calls=100, states=1).reason == evaluator.PAYS   # 100 Euler steps
    assert choice(load_robot("rrr_arm"), calls=1, states=20_000).reason == evaluator.PAYS   # a 20 000-row log


@pytest.mark.parametrize("native", ["on", "off"])
def test_a_robot_too_large_to_compile_runs_the_loop_or_warns_once_and_runs_interpreted(native, tmp_path, monkeypatch):
    """The native loop takes any size; without it (here: turned off) the recursions run, after one warning."""
    if native == "off":
        monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    expected, run = (UNCOMPILED, UNCOMPILED_RUN) if native == "on" else ("interpreted", Interpreted)
    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(60))
    chain = load_urdf(path)
    with pytest.raises(ProgramTooLargeError):
        implementation(chain, compiled=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert isinstance(implementation(chain, calls=10_000), run)
        assert choice(chain, calls=10_000).path == expected and "too large" in choice(chain, calls=10_000).reason
        q = np.random.default_rng(1).uniform(-1, 1, (3, 50, chain.n))
        tau = course_dynamics.inverse_dynamics(chain, *q)
        one = course_dynamics.inverse_dynamics(chain, *q[:, 0])
    assert [w.category for w in caught] == ([CompileWarning] if expected == "interpreted" else [])
    ref = course_dynamics.core.newton_euler.inverse_dynamics(chain, *q)
    np.testing.assert_allclose(tau, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    np.testing.assert_allclose(one, ref[0], rtol=0, atol=1e-12 * np.abs(ref).max())


def test_symbols_and_duals_take_the_recursion_even_when_cached():
    arm = load_robot("two_link")
    compile_model(arm)
    assert choice(arm).reason == evaluator.CACHED
    t1, t2 = sp.symbols("theta1 theta2")
    G = course_dynamics.gravity_torques(arm, np.array([t1, t2], dtype=object))
    assert all(isinstance(g, sp.Expr) for g in G) and G[1].has(t1)


@pytest.mark.parametrize("path", ["interpreted", UNCOMPILED, "compiled"])
def test_the_package_functions_agree_with_pinocchio_on_every_path(robot, path, tmp_path, monkeypatch):
    name, _, oracle, (q, qd, qdd) = robot
    model = load_urdf(urdf_of(name))                                  # a model of this test's own
    if path == "compiled":
        compile_model(model)                                          # into the session's cache
    else:
        monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cold"))   # a cache that holds nothing
        if path == "interpreted":
            monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")      # and no native loop
    assert choice(model, calls=1, states=SAMPLES).path == path        # 200 states: too little to compile
    tau = course_dynamics.inverse_dynamics(model, q, qd, qdd)
    M = course_dynamics.mass_matrix(model, q)
    C = course_dynamics.coriolis_matrix(model, q, qd)
    G = course_dynamics.gravity_torques(model, q)
    qdd_back = course_dynamics.forward_dynamics(model, q, qd, tau)
    assert choice(model, calls=1, states=SAMPLES).path == path        # and still, after five calls
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
    assert choice(model, calls=1, states=1).path == path
    with pytest.raises(course_dynamics.StateError, match="is nan"):
        course_dynamics.inverse_dynamics(model, np.full(model.n, np.nan), qd[0], qdd[0])


@pytest.mark.parametrize("name", ["two_link", "ur5"])
def test_the_regressor_is_chosen_by_its_work(name, cold_cache):
    """One state of Y is little work, a log's worth pays for compiling: either way Y is the recursion's."""
    from course_dynamics.core.regressor import regressor as interpreted

    model = load_urdf(urdf_of(name))
    q, qd, qdd = np.random.default_rng(3).uniform(-1, 1, (3, 200, model.n))
    assert choice(model, calls=evaluator.REGRESSOR_WORK, states=1).path == UNCOMPILED   # Y: the recursion's
    np.testing.assert_array_equal(evaluator.regressor(model, q[0], qd[0], qdd[0]), interpreted(model, q[0], qd[0], qdd[0]))
    assert choice(model, calls=evaluator.REGRESSOR_WORK, states=200).path == "compiled"
    Y = evaluator.regressor(model, q, qd, qdd)
    assert choice(model, calls=1, states=1).reason == evaluator.CACHED
    ref = interpreted(model, q, qd, qdd)
    np.testing.assert_allclose(Y, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
    np.testing.assert_allclose(evaluator.regressor(model, q[5], qd[5], qdd[5]), ref[5], rtol=1e-12,
                               atol=1e-12 * np.abs(ref).max())


def test_a_large_interpreted_batch_is_computed_in_blocks_to_the_same_bits(monkeypatch, cold_cache):
    """Blocks keep the recursion's temporaries small; every term comes out as one call on the whole batch gives it."""
    from course_dynamics.core import dynamics, newton_euler
    from course_dynamics.core import forward_dynamics as interpreted_forward
    from course_dynamics.core.friction import Friction
    from course_dynamics.core.regressor import regressor as interpreted_regressor

    arm = load_robot("rrr_arm")
    monkeypatch.setattr(evaluator, "BLOCK_STATES", 7)
    q, qd, qdd = np.random.default_rng(5).uniform(-1, 1, (3, 2, 10, arm.n))     # a (2, 10) batch: 20 states
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")                          # the recursions as written
    assert choice(arm, calls=evaluator.REGRESSOR_WORK, states=20).path == "interpreted"     # little work, no cache
    friction = Friction(viscous=[0.1, 0.2, 0.3], coulomb=[0.5, 0.0, 0.1])
    for ours, whole in ((evaluator.inverse_dynamics, newton_euler.inverse_dynamics),
                        (evaluator.regressor, interpreted_regressor)):
        np.testing.assert_array_equal(ours(arm, q, qd, qdd), whole(arm, q, qd, qdd))
    np.testing.assert_array_equal(evaluator.mass_matrix(arm, q), dynamics.mass_matrix(arm, q))
    np.testing.assert_array_equal(evaluator.coriolis_matrix(arm, q, qd[0]), dynamics.coriolis_matrix(arm, q, qd[0]))
    np.testing.assert_array_equal(evaluator.gravity_torques(arm, q[:, :1]), dynamics.gravity_torques(arm, q[:, :1]))
    np.testing.assert_array_equal(evaluator.forward_dynamics(arm, q, qd, qdd, friction),
                                  interpreted_forward.forward_dynamics(arm, q, qd, qdd, friction))
    assert evaluator.mass_matrix(arm, q).shape == (2, 10, 3, 3)


def test_the_tools_take_the_evaluators_choice(cold_cache):
    """simulate and the torques of a log run what the evaluator chose for their whole work, nothing else."""
    from course_dynamics.tools.logs import torques_from_log
    from course_dynamics.tools.simulation import simulate

    arm = load_robot("pendulum")
    short = simulate(arm, [0.5], [0.0], 0.01, 0.001, integrator="euler")        # 10 steps, a cold cache
    assert choice(arm, calls=10).path == UNCOMPILED
    long = simulate(arm, [0.5], [0.0], 0.2, 0.001, integrator="euler")         # 200 steps pay
    assert choice(arm, calls=10).reason == evaluator.CACHED
    np.testing.assert_allclose(long.q[:len(short.q)], short.q, rtol=1e-12, atol=1e-15)
    t = np.linspace(0, 1, 200)
    table = {"t": t, "q_theta": np.sin(t), "qd_theta": np.cos(t), "qdd_theta": -np.sin(t)}
    ours = torques_from_log(arm, table).tau
    forced = torques_from_log(arm, table, compiled=False).tau
    np.testing.assert_allclose(ours, forced, rtol=1e-12, atol=1e-12)


def test_a_batch_of_one_keeps_its_shape_on_every_path(tmp_path, monkeypatch):
    """A (1, n) batch is a batch, whether the interpreted, the compiled or the native code answers."""
    z = np.zeros((1, 3))
    shapes = []
    for cache in (str(tmp_path / "cold"), str(tmp_path / "warm")):
        monkeypatch.setenv("COURSE_DYNAMICS_CACHE", cache)
        model = load_robot("rrr_arm")
        if cache.endswith("warm"):
            compile_model(model)
        shapes.append((choice(model).path, course_dynamics.inverse_dynamics(model, z, z, z).shape,
                       course_dynamics.mass_matrix(model, z).shape, course_dynamics.forward_dynamics(model, z, z, z).shape))
    assert shapes == [(UNCOMPILED, (1, 3), (1, 3, 3), (1, 3)), ("compiled", (1, 3), (1, 3, 3), (1, 3))]


def test_batches_of_different_lengths_are_one_clear_error():
    model = load_robot("two_link")
    with pytest.raises(course_dynamics.StateError, match=r"batches of different lengths \(10,\), \(9,\)"):
        course_dynamics.inverse_dynamics(model, np.zeros((10, 2)), np.zeros((9, 2)), np.zeros(2))
