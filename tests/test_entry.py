"""course_dynamics/core/compiled/entry.py (in the native loop's library): a one-state call of the default API on a
remembered model runs its C whole, checks and all, and gives what the checked path gives, for every robot, with
a compiled model's C and with the native loop, agreeing with Pinocchio; anything it should not take (another
shape, dtype or layout, a NaN, a changed environment or cache, another model object) goes down the checked path,
which gives the same numbers or the error; the C refuses what it cannot trust."""
from __future__ import annotations

import ctypes
import gc
import os
import threading
import time

import numpy as np
import pytest
from helpers import arm_urdf, assert_agrees

import course_dynamics
from course_dynamics import load_robot, load_urdf
from course_dynamics.base.errors import StateError
from course_dynamics.core import crba, evaluator, newton_euler
from course_dynamics.core import forward_dynamics as interpreted
from course_dynamics.core.compiled import CompiledModel, compile_model, entry, looped, native
from course_dynamics.core.compiled.cache import WRITES
from course_dynamics.core.forward_dynamics import SingularMassMatrixError

pytestmark = pytest.mark.skipif(native.compiler() is None,
                                reason="no C compiler: the package was installed without the native loop")


def compiled_with_c(model) -> CompiledModel:
    """compile_model(model) with its C, waiting while another test process builds the same library."""
    deadline = time.monotonic() + 120
    while not (fast := compile_model(model)).native and "another process" in fast.native_reason \
            and time.monotonic() < deadline:
        time.sleep(0.5)
    assert fast.native, f"the compiled model has no C: {fast.native_reason}"
    return fast


def checked_calls(monkeypatch) -> list:
    """Count the calls the checked path takes (each checks its states with as_state)."""
    seen = []
    original = evaluator.as_state
    monkeypatch.setattr(evaluator, "as_state", lambda *a: (seen.append(a[2]), original(*a))[1])
    return seen


def calls(model, q, qd, qdd) -> dict:
    return {"tau": course_dynamics.inverse_dynamics(model, q, qd, qdd), "M": course_dynamics.mass_matrix(model, q),
            "qdd": course_dynamics.forward_dynamics(model, q, qd, qdd)}


@pytest.mark.parametrize("source", ["compiled", "loop"])
def test_every_robots_one_state_calls_run_natively_and_agree(robot, source, tmp_path, monkeypatch):
    """τ, M and Θ̈ through the entry: the interpreted recursions to 1e-12, Pinocchio to 1e-9 (the loop takes τ
    and M; its Θ̈ goes down the checked path)."""
    name, model, oracle, (q, qd, qdd) = robot
    model = model.with_gravity(model.gravity * (1 + 1e-9 * (source == "loop")))  # a content of its own here
    if source == "compiled":
        compiled_with_c(model)
    else:
        monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "empty"))
    course_dynamics.inverse_dynamics(model, q[0], qd[0], qdd[0])       # the choice, made and remembered
    kind = CompiledModel if source == "compiled" else looped.Looped
    assert isinstance(looped.remembered(model), kind)
    seen = checked_calls(monkeypatch)
    oracle_model = oracle if source == "compiled" else None
    for k in range(len(q)):
        got = calls(model, q[k], qd[k], qdd[k])
        assert_agrees(got["tau"], newton_euler.inverse_dynamics(model, q[k], qd[k], qdd[k]), rtol=1e-12,
                      what=f"{name} τ {k}")
        assert_agrees(got["M"], crba.mass_matrix(model, q[k]), rtol=1e-12, what=f"{name} M {k}")
        assert_agrees(got["qdd"], interpreted.forward_dynamics(model, q[k], qd[k], qdd[k]), rtol=1e-11,
                      what=f"{name} Θ̈ {k}")
        if oracle_model is not None:
            assert_agrees(got["tau"], oracle.tau(q[k], qd[k], qdd[k]), what=f"{name} τ {k} against Pinocchio")
            assert_agrees(got["qdd"], oracle.aba(q[k], qd[k], qdd[k]), what=f"{name} Θ̈ {k} against Pinocchio")
        assert got["M"].shape == (model.n, model.n) and got["tau"].flags.c_contiguous
    assert seen == ([] if source == "compiled" else ["q", "qd", "tau"] * len(q)), seen  # only the loop's Θ̈


def test_the_regressor_runs_natively_where_the_compiled_model_has_it():
    model = load_robot("ur5")
    fast = compiled_with_c(model)
    q = np.random.default_rng(4).uniform(-1, 1, (3, 6))
    course_dynamics.regressor(model, *q)
    assert isinstance(looped.remembered(model), CompiledModel)
    Y = course_dynamics.regressor(model, *q)
    np.testing.assert_array_equal(Y, fast.regressor(*q))
    assert Y.shape == (6, 60)


@pytest.mark.parametrize("case", ["list", "batch", "batch of one", "nan", "short", "float32", "int", "strided",
                                  "read-only", "memoryview"])
def test_what_the_entry_does_not_take_goes_down_the_checked_path(case, monkeypatch):
    model = load_robot("ur5")
    compiled_with_c(model)
    rng = np.random.default_rng(5)
    q, qd, qdd = rng.uniform(-1, 1, (3, 6))
    course_dynamics.inverse_dynamics(model, q, qd, qdd)
    assert looped.remembered(model) is not None
    odd = {"list": q.tolist(), "batch": np.stack([q, q]), "batch of one": q[None, :], "nan": np.where(q > 0, np.nan, q),
           "short": q[:5], "float32": q.astype(np.float32), "int": np.round(q).astype(int),
           "strided": np.repeat(q, 2)[::2], "read-only": q.copy(), "memoryview": memoryview(q.copy())}[case]
    if case == "read-only":
        odd.flags.writeable = False
    seen = checked_calls(monkeypatch)
    if case in ("nan", "short"):
        with pytest.raises(StateError):
            course_dynamics.inverse_dynamics(model, odd, qd, qdd)
        assert seen == ["q"]
        return
    got = course_dynamics.inverse_dynamics(model, odd, qd, qdd)
    expected = newton_euler.inverse_dynamics(model, np.asarray(odd, dtype=float), qd, qdd)
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)
    assert seen == ([] if case in ("read-only", "memoryview") else ["q", "qd", "qdd"]), seen  # any float64 buffer


def test_a_changed_environment_or_cache_goes_down_the_checked_path(tmp_path, monkeypatch):
    """The choice depends on the environment and the cache now: the entry gives way, the checked path chooses."""
    model = load_robot("ur5")
    compiled_with_c(model)
    q = np.full(6, 0.3)
    course_dynamics.inverse_dynamics(model, q, q, q)
    seen = checked_calls(monkeypatch)
    course_dynamics.inverse_dynamics(model, q, q, q)
    assert seen == []
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")               # native code off: the recursions run
    np.testing.assert_allclose(course_dynamics.inverse_dynamics(model, q, q, q),
                               newton_euler.inverse_dynamics(model, q, q, q), rtol=1e-12)
    assert seen == ["q", "qd", "qdd"] and evaluator.choice(model).run.native == {}
    monkeypatch.delenv("COURSE_DYNAMICS_NATIVE")
    course_dynamics.inverse_dynamics(model, q, q, q)                  # remembered again
    seen.clear()
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "another"))  # a cache that holds nothing
    course_dynamics.inverse_dynamics(model, q, q, q)
    assert seen == ["q", "qd", "qdd"] and isinstance(looped.remembered(model), looped.Looped)
    seen.clear()
    WRITES[0] += 1                                                    # the cache was written to since
    course_dynamics.inverse_dynamics(model, q, q, q)
    assert seen == ["q", "qd", "qdd"]
    seen.clear()
    course_dynamics.inverse_dynamics(model, q, q, q)
    assert seen == []


def test_an_entry_is_for_its_model_object_only_and_goes_with_it(monkeypatch):
    first = load_robot("two_link").with_gravity([0, 0, -9.77])
    q = np.array([0.1, 0.2])
    course_dynamics.inverse_dynamics(first, q, q, q)
    assert looped.remembered(first) is not None
    twin = load_robot("two_link").with_gravity([0, 0, -9.77])        # the same content, another object
    assert looped.remembered(twin) is None
    course_dynamics.inverse_dynamics(twin, q, q, q)
    assert looped.remembered(twin) is looped.remembered(first)         # its own entry, the same loop
    stand_in = type("Model", (), {})()                                 # an object no entry is for
    assert looped.library().one(stand_in, 0, q, q, q) is None
    forgotten, original = [], evaluator.forget
    monkeypatch.setattr(evaluator, "forget", lambda i: (forgotten.append(i), original(i)))
    key = id(twin)
    del twin                                                           # the loop holds the first model, not
    gc.collect()                                                       # the twin: it goes, its entry with it
    assert key in forgotten and key not in evaluator._KEYS


def test_a_singular_mass_matrix_is_named_by_the_checked_path(tmp_path):
    path = tmp_path / "massless.urdf"
    path.write_text(arm_urdf(mass="0", ixx="0", iyy="0", izz="0"))
    model = load_urdf(path)
    compile_model(model)
    course_dynamics.inverse_dynamics(model, [0.1, 0.2], [0.0, 0.0], [0.0, 0.0])
    with pytest.raises(SingularMassMatrixError, match="joint 'joint2' moves no mass"):
        course_dynamics.forward_dynamics(model, np.array([0.1, 0.2]), np.zeros(2), np.zeros(2))


def test_threads_calling_one_model_get_their_own_answers():
    model = load_robot("panda")
    compiled_with_c(model)
    rng = np.random.default_rng(8)
    states = rng.uniform(-1, 1, (4, 200, 3, model.n))
    course_dynamics.inverse_dynamics(model, *states[0, 0])
    results = {}

    def work(k):
        results[k] = [(course_dynamics.inverse_dynamics(model, *s), course_dynamics.forward_dynamics(model, *s))
                      for s in states[k]]

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for k in range(4):
        for s, (tau, qdd) in zip(states[k], results[k]):
            np.testing.assert_allclose(tau, newton_euler.inverse_dynamics(model, *s), rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(qdd, interpreted.forward_dynamics(model, *s), rtol=1e-10, atol=1e-10)


def test_the_c_refuses_what_it_cannot_trust():
    lib = looped.library()
    model = load_robot("two_link").with_gravity([0, 0, -9.71])
    run = looped.looped(model)
    q = np.zeros(2)
    environ, names = os.environ._data, (b"HOME",)
    for arguments in ((model,), (model, run, run.array, [], names, WRITES, np.empty),
                      (model, run, run.array, environ, names * (entry.NAMES + 1), WRITES, np.empty),
                      (model, run, run.array, environ, names, [], np.empty)):
        with pytest.raises(TypeError):
            lib.remember(*arguments)
    with pytest.raises(ValueError, match="model array"):
        lib.remember(model, run, run.array[:-1].copy(), environ, names, WRITES, np.empty)
    with pytest.raises(TypeError):
        lib.remember(model, run, run.array.astype(np.float32), environ, names, WRITES, np.empty)
    make = ctypes.pythonapi.PyCapsule_New
    make.restype, make.argtypes = ctypes.py_object, [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_void_p]
    old = (ctypes.c_ssize_t * 16)(1, 2, 1)                            # a version-1 layout: not taken
    with pytest.raises(ValueError, match="not ones the library made"):
        lib.remember(model, run, make(ctypes.addressof(old), b"course_dynamics.terms", None), environ, names,
                     WRITES, np.empty)
    with pytest.raises(ValueError):
        lib.remember(model, run, make(ctypes.addressof(old), b"something.else", None), environ, names, WRITES,
                     np.empty)
    with pytest.raises(TypeError):
        lib.forget("model")
    for empty in (lambda shape: np.empty(shape, dtype=np.float32), lambda shape: np.empty(1)):
        lib.remember(model, run, run.array, environ, names, WRITES, empty)   # an output of another kind or size
        with pytest.raises(TypeError, match="not the float64 array of the program's size"):
            lib.one(model, 1, q)
    lib.remember(model, run, run.array, environ, names, WRITES, np.empty)
    assert lib.remembered(model) is run
    assert lib.one(model, 0, q, q, q).shape == (2,)
    for odd in ((model,), (model, 0, q, q), (model, 1, q, q), (model, 2**70, q), (model, -1, q), (model, 4, q),
                (model, 0.0, q, q, q), (model, True, q), (model, 2, q, q, q), (model, 3, q, q, q)):
        assert lib.one(*odd) is None, odd                             # the loop has no Θ̈ or Y of its own
    lib.forget(id(model))
    assert lib.remembered(model) is None and lib.one(model, 0, q, q, q) is None
    lib.forget(id(model))                                             # forgetting twice is no error


def test_turned_off_at_the_choice_nothing_is_remembered(monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    model = load_robot("two_link").with_gravity([0, 0, -9.72])
    q = np.array([0.3, 0.1])
    np.testing.assert_allclose(course_dynamics.inverse_dynamics(model, q, q, q),
                               newton_euler.inverse_dynamics(model, q, q, q), rtol=1e-12)
    assert looped.remembered(model) is None and native.enabled() is False
