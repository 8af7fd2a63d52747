"""course_dynamics/core/compiled.py: traced programs against Pinocchio and the interpreted recursions; the cache."""
from __future__ import annotations

import numpy as np
import pytest
from helpers import arm_urdf, assert_agrees

from course_dynamics import (
    coriolis_matrix,
    inverse_dynamics,
    load_robot,
    load_urdf,
    mass_matrix,
)
from course_dynamics.core.compiled import compile_model, native, trace_programs
from course_dynamics.core.dynamics import mass_matrix_and_bias
from course_dynamics.core.regressor import regressor
from course_dynamics.core.forward_dynamics import (
    SingularMassMatrixError,
    forward_dynamics,
)


@pytest.fixture(scope="module", params=["python", "native"])
def compiled(robot, request):
    """Each robot's compiled model twice: the Python programs alone, and with their C version (native.py) where
    a compiler exists (everything below then runs natively)."""
    name, model, oracle, states = robot
    c = compile_model(model, native_code=request.param == "native")
    assert bool(c.native) == (request.param == "native" and native.compiler() is not None and native.enabled())
    return name, model, oracle, states, c


def test_every_program_agrees_with_pinocchio(compiled):
    name, model, oracle, (q, qd, qdd), c = compiled
    tau, M, C = c.inverse_dynamics(q, qd, qdd), c.mass_matrix(q), c.coriolis_matrix(q, qd)
    bias, qdd_fd = c.bias(q, qd), c.forward_dynamics(q, qd, qdd)
    for k in range(len(q)):
        M_ref = oracle.M(q[k])
        scale = np.abs(M_ref).max()
        speed, accel = np.abs(qd[k]).max(), np.abs(qdd[k]).max()
        assert_agrees(tau[k], oracle.tau(q[k], qd[k], qdd[k]), scale * (accel + speed**2), what=f"{name} tau {k}")
        assert_agrees(M[k], M_ref, what=f"{name} M {k}")
        assert_agrees(C[k], oracle.C(q[k], qd[k]), scale * speed, what=f"{name} C {k}")
        assert_agrees(bias[k], oracle.V(q[k], qd[k]) + oracle.G(q[k]), scale * (speed**2 + 9.81), what=f"{name} bias {k}")
        assert_agrees(qdd_fd[k], oracle.aba(q[k], qd[k], qdd[k]), what=f"{name} forward dynamics {k}")


def test_programs_equal_the_interpreted_recursions(compiled):
    """The same operations in the same order: τ, M and C come out identical to the last bit or nearly."""
    name, model, _, (q, qd, qdd), c = compiled
    M_ref, bias_ref = mass_matrix_and_bias(model, q, qd)
    for ours, ref in ((c.inverse_dynamics(q, qd, qdd), inverse_dynamics(model, q, qd, qdd)),
                      (c.mass_matrix(q), mass_matrix(model, q)), (c.coriolis_matrix(q, qd), coriolis_matrix(model, q, qd)),
                      (c.bias(q, qd), bias_ref), (c.forward_dynamics(q, qd, qdd), forward_dynamics(model, q, qd, qdd))):
        np.testing.assert_allclose(ours, ref, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(ref).max()))


def test_the_regressor_agrees_with_pinocchio_and_equals_the_recursion(compiled):
    """Y compiled (τ on dual numbers, traced) on every robot: the recursion's to 1e-12, Pinocchio's to 1e-9."""
    from test_regressor import pinocchio_columns

    name, model, oracle, (q, qd, qdd), c = compiled
    assert "regressor" in c.functions and ("regressor" in c.native) == bool(c.native)
    ours, ref = c.regressor(q, qd, qdd), regressor(model, q, qd, qdd)
    assert ours.shape == (len(q), model.n, 10 * model.n_bodies)
    np.testing.assert_allclose(ours, ref, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(ref).max()))
    columns = pinocchio_columns(model, oracle)
    for k in range(len(q)):
        one = c.regressor(q[k], qd[k], qdd[k])
        np.testing.assert_allclose(one, ours[k], rtol=1e-14, atol=1e-14 * max(1.0, np.abs(ref).max()))
        assert_agrees(one, oracle.regressor(q[k], qd[k], qdd[k])[:, columns], what=f"{name} compiled Y, state {k}")


def test_a_regressor_over_its_bound_leaves_the_other_programs_compiled(monkeypatch):
    from course_dynamics.core.compiled import tracing

    arm = load_robot("spatial_arm")
    monkeypatch.setattr(tracing, "MAX_REGRESSOR_OPERATIONS", 50)
    assert "regressor" not in trace_programs(arm) and "tau" in trace_programs(arm)
    c = compile_model(arm, cache=False, native_code=False)
    q = np.array([0.3, -0.2, 0.5])
    assert "regressor" not in c.functions and "tau" in c.functions
    np.testing.assert_array_equal(c.regressor(q, q, q), regressor(arm, q, q, q))    # the recursion answers


def test_one_state_equals_the_batch(compiled):
    name, model, _, (q, qd, qdd), c = compiled
    batch = c.forward_dynamics(q[:10], qd[:10], qdd[:10])
    for k in range(10):
        np.testing.assert_allclose(c.forward_dynamics(q[k], qd[k], qdd[k]), batch[k], rtol=1e-13, atol=1e-13)
        np.testing.assert_allclose(c.inverse_dynamics(q[k], qd[k], qdd[k]), c.inverse_dynamics(q, qd, qdd)[k],
                                   rtol=1e-14, atol=1e-14)


def test_the_source_is_readable_python():
    c = compile_model(load_robot("two_link"))
    lines = c.source.splitlines()
    assert lines[0].startswith("# course-dynamics compiled model ")
    assert "def tau(q, qd, qdd):" in c.source and "def forward_dynamics_batch(q, qd, tau):" in c.source
    assert "    q0, q1 = q" in c.source and "cos(q0)" in c.source
    assert all(len(line) < 200 for line in lines)
    assert c.generation_seconds > 0


def test_the_key_covers_every_module_an_import_reaches():
    """traced_sources scans with a pattern (fast: the evaluator asks on a process's first call); the files are
    the ones Python's own parser finds through every relative import, lazy ones included."""
    import ast
    from pathlib import Path

    from course_dynamics.core import compiled as package
    from course_dynamics.core.compiled import codegen, tracing

    pending = [Path(m.__file__).resolve() for m in (package, tracing, codegen)]
    found: set[Path] = set()
    while pending:
        path = pending.pop()
        if path in found:
            continue
        found.add(path)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level:
                base = path.parents[node.level - 1]
                target = base.joinpath(*(node.module.split(".") if node.module else []))
                candidates = [target.with_suffix(".py"), target / "__init__.py"] + [target / f"{a.name}.py"
                                                                                 for a in node.names]
                pending += [c.resolve() for c in candidates if c.is_file() and c.resolve().is_relative_to(package.PACKAGE)]
    assert set(package.traced_sources()) == found and len(found) > 10


def test_second_compile_comes_from_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    model = load_robot("rp_arm")
    first, second = compile_model(model), compile_model(model)
    assert not first.from_cache and second.from_cache and second.path == first.path
    assert second.source == first.source
    assert (tmp_path / "cache").stat().st_mode & 0o777 == 0o700


@pytest.mark.parametrize("damage", ["truncate", "other key", "wrong number", "garbage"])
def test_a_stale_or_corrupt_cache_is_rebuilt(tmp_path, monkeypatch, damage):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path))
    model = load_robot("two_link")
    path = compile_model(model).path
    data = path.read_bytes()
    if damage == "truncate":
        path.write_bytes(data[: len(data) // 2])
    elif damage == "other key":  # a valid entry of another robot, put under this robot's key
        path.write_bytes(compile_model(load_robot("pendulum")).path.read_bytes())
    elif damage == "wrong number":  # one number changed in the stored source: the keyed hash no longer matches
        assert b"0.5 * " in data
        path.write_bytes(data.replace(b"0.5 * ", b"0.6 * ", 1))
    else:
        path.write_bytes(b"\x00\xff" * 100)
    rebuilt = compile_model(model)
    assert not rebuilt.from_cache
    q, qd, qdd = [0.3, -0.2], [1.0, 0.5], [0.2, 0.1]
    np.testing.assert_allclose(rebuilt.inverse_dynamics(q, qd, qdd), inverse_dynamics(model, q, qd, qdd), rtol=1e-14)
    assert compile_model(model).from_cache


PLANTED = """# course-dynamics compiled model {key}
open({mark!r}, "w").write("owned")
"""


def _plant(folder, model, mark):
    """What an attacker who can compute the key writes: a module and an entry that run code when loaded."""
    import marshal

    from course_dynamics.core.compiled import model_key

    key = model_key(model)
    source = PLANTED.format(key=key, mark=str(mark))
    (folder / f"{key}.py").write_text(source)
    body = len(source).to_bytes(8, "little") + source.encode() + marshal.dumps(compile(source, "x", "exec"))
    (folder / f"{key}.entry").write_bytes(b"\0" * 32 + body)
    return key


def test_a_planted_entry_is_never_run(tmp_path, monkeypatch):
    """An entry with the right key but no valid keyed hash: checked before anything is executed."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(folder))
    model = load_robot("two_link")
    compile_model(load_robot("pendulum"))  # the folder exists and has its secret
    mark = tmp_path / "PWNED"
    _plant(folder, model, mark)
    c = compile_model(model)
    assert not mark.exists() and not c.from_cache
    assert compile_model(model).from_cache and not mark.exists()


@pytest.mark.parametrize("how", ["world-writable folder", "group-writable folder", "another user's folder",
                                 "world-writable parent", "another user's secret"])
def test_an_untrusted_cache_folder_is_not_used(tmp_path, monkeypatch, how):
    import os

    from course_dynamics.core.compiled import CacheWarning

    parent = tmp_path / "shared"
    parent.mkdir(mode=0o755)
    folder = parent / "cache"
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(folder))
    model = load_robot("two_link")
    compile_model(load_robot("pendulum"))
    mark = tmp_path / "PWNED"
    _plant(folder, model, mark)
    if how == "world-writable folder":
        folder.chmod(0o777)
    elif how == "group-writable folder":
        folder.chmod(0o770)
    elif how == "another user's folder":
        if os.getuid() != 0:
            pytest.skip("needs root to give a folder to another user")
        os.chown(folder, 65534, 65534)
    elif how == "world-writable parent":
        parent.chmod(0o777)
    else:
        if os.getuid() != 0:
            pytest.skip("needs root to give a file to another user")
        os.chown(folder / "secret", 65534, 65534)
    with pytest.warns(CacheWarning, match="is not used"):
        c = compile_model(model)
    assert not mark.exists() and not c.from_cache and c.path is None
    np.testing.assert_allclose(c.inverse_dynamics([0.1, 0.2], [0, 0], [0, 0]),
                               inverse_dynamics(model, [0.1, 0.2], [0, 0], [0, 0]), rtol=1e-14)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", CacheWarning)  # warned once per folder
        compile_model(model)


def test_an_entry_through_a_link_or_of_another_mode_is_not_read(tmp_path, monkeypatch):
    import os

    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    model = load_robot("two_link")
    path = compile_model(model).path
    elsewhere = tmp_path / "entry"
    path.rename(elsewhere)
    path.symlink_to(elsewhere)
    assert not compile_model(model).from_cache
    path.chmod(0o622)
    if os.getuid() == 0:  # root bypasses modes; the check is on the bits, not on access
        assert not compile_model(model).from_cache


def test_the_cache_can_be_turned_off(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", "off")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    c = compile_model(load_robot("two_link"))
    assert c.path is None and not c.from_cache and not any(tmp_path.iterdir())


def test_a_robot_too_large_to_compile_is_refused_quickly(tmp_path):
    import time

    from helpers import chain_urdf

    from course_dynamics.core.compiled import ProgramTooLargeError

    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(60))
    model = load_urdf(path)
    start = time.perf_counter()
    with pytest.raises(ProgramTooLargeError, match="60 joints.*too large to compile"):
        compile_model(model, cache=False)
    assert time.perf_counter() - start < 10


def test_no_cache_where_none_can_be_written(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(blocker / "cache"))
    c = compile_model(load_robot("pendulum"))
    assert c.path is None and not c.from_cache
    assert c.inverse_dynamics([0.5], [0.0], [0.0])[0] == pytest.approx(9.81 * np.sin(0.5))


def test_a_singular_mass_matrix_is_named(tmp_path):
    path = tmp_path / "massless.urdf"
    path.write_text(arm_urdf(mass="0", ixx="0", iyy="0", izz="0"))
    c = compile_model(load_urdf(path), cache=False)
    with pytest.raises(SingularMassMatrixError, match="joint 'joint2' moves no mass"):
        c.forward_dynamics([0.1, 0.2], [0, 0], [0, 0])
    with pytest.raises(SingularMassMatrixError):
        c.forward_dynamics(np.zeros((3, 2)), np.zeros((3, 2)), np.zeros((3, 2)))


def test_urdf_names_cannot_become_code_in_the_generated_module(tmp_path, monkeypatch):
    """A joint or robot name holding quotes and line breaks stays a comment in the generated source.

    The URDF loader refuses line breaks in names; the generator must not rely on it.
    """
    from dataclasses import replace

    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    mark = tmp_path / "PWNED"
    hostile = f'x"""\nimport os; open({str(mark)!r}, "w").write("owned")\n"""'
    model = load_robot("two_link")
    model = replace(model, name=hostile, bodies=(model.bodies[0], replace(model.bodies[1], joint=hostile)))
    compiled = compile_model(model)
    q = np.array([0.3, -0.2])
    np.testing.assert_allclose(compiled.inverse_dynamics(q, q, q), inverse_dynamics(model, q, q, q), rtol=1e-12)
    assert not mark.exists()
    # The C source (built where a compiler exists) carries the name only in its first comment, with nothing
    # that could end it: a name holding "*/" and a line break stays a comment there too.
    c_source = native.c_source(trace_programs(model), model.n, "k", 'x */ int pwned; /*\n#include "x"')
    first = c_source.splitlines()[0]
    assert "*/" not in first[2:] and "pwned" in first and "#include \"x\"" not in c_source
    assert compiled.native_source == "" or hostile not in compiled.native_source


def test_simulate_through_the_cli_never_runs_a_planted_cache(tmp_path, monkeypatch, capsys):
    """The attack as a hostile local user makes it: a world-writable cache folder with a planted module."""
    from helpers import run

    folder = tmp_path / "cache"
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(folder))
    compile_model(load_robot("pendulum"))
    mark = tmp_path / "PWNED"
    _plant(folder, load_robot("two_link"), mark)
    folder.chmod(0o777)
    code, out, err = run(capsys, "simulate", "two_link", "--q0", "0.1,0.2", "--dt", "0.001", "--duration", "0.2",
                         "--out", str(tmp_path / "run.csv"))
    assert code == 0 and not mark.exists()
    assert err.count("warning: the compiled-model cache") == 1 and "other users can write to it" in err


@pytest.mark.parametrize("loop", ["installed", "off"])
def test_simulate_of_a_robot_too_large_to_compile_runs_the_loop_or_interpreted(loop, tmp_path, capsys, monkeypatch):
    """The native loop runs any size without a word; without it, the recursions run after one warning."""
    from helpers import chain_urdf, run

    from course_dynamics.core.compiled import looped

    if loop == "off":
        monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(40))
    code, out, err = run(capsys, "simulate", str(path), "--q0", ",".join(["0.1"] * 40), "--dt", "0.001",
                         "--duration", "0.1", "--out", str(tmp_path / "run.csv"), "--quiet")
    assert code == 0, err
    warned = "warning: robot 'chain' (40 joints) is too large to compile" in err
    assert warned == (looped.library() is None) and "Traceback" not in err
    assert (tmp_path / "run.csv").is_file()


def test_a_link_to_a_private_folder_placed_by_another_user_is_not_trusted(tmp_path, monkeypatch):
    """The link decides where entries go: one in another user's folder could be swapped at any moment."""
    import os

    from course_dynamics.core.compiled import CacheWarning

    if os.getuid() != 0:
        pytest.skip("needs root to give a folder to another user")
    mine = tmp_path / "mine"
    mine.mkdir(mode=0o700)
    theirs = tmp_path / "theirs"
    theirs.mkdir()
    (theirs / "cache").symlink_to(mine)
    os.chown(theirs, 65534, 65534)
    os.lchown(theirs / "cache", 65534, 65534)
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(theirs / "cache"))
    with pytest.warns(CacheWarning, match="belongs to another user"):
        c = compile_model(load_robot("two_link"))
    assert c.path is None and not any(mine.iterdir())


@pytest.mark.parametrize("kind", ["fifo", "device link"])
def test_an_entry_that_is_no_regular_file_is_replaced_never_opened(tmp_path, monkeypatch, kind):
    import os
    import stat

    from course_dynamics.core.compiled import model_key

    folder = tmp_path / "cache"
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(folder))
    model = load_robot("two_link")
    compile_model(load_robot("pendulum"))
    entry = folder / f"{model_key(model)}.entry"
    device = tmp_path / "null"
    if kind == "fifo":
        os.mkfifo(entry)
    else:
        os.mknod(device, 0o666 | stat.S_IFCHR, os.makedev(1, 3))  # a /dev/null of our own
        os.chmod(device, 0o666)  # whatever the umask
        entry.symlink_to(device)
    c = compile_model(model)  # would block forever on a FIFO opened for writing
    assert entry.is_file() and not entry.is_symlink() and c.path == entry
    if kind == "device link":
        assert stat.S_IMODE(os.stat(device).st_mode) == 0o666  # never chmod'ed through the link
    assert compile_model(model).from_cache


def native_model(name: str, tmp_path, monkeypatch):
    """``name`` compiled, in a cache of the test's own: with its native code wherever a compiler exists (as on CI),
    with the Python programs alone elsewhere, and the tests below hold either way."""
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    model = load_robot(name)
    c = compile_model(model)
    assert bool(c.native) == (native.compiler() is not None)
    return model, c


def test_the_native_path_checks_what_it_is_given(tmp_path, monkeypatch):
    """One finite float64 state goes straight to C; anything else takes the checked path and its errors."""
    from course_dynamics import StateError

    arm, c = native_model("two_link", tmp_path, monkeypatch)
    q = np.array([0.1, 0.2])
    expected = inverse_dynamics(arm, q, q, q)
    for given in ([0.1, 0.2], q.astype(np.float32), np.array([[0.1, 0.2]])[0], np.array([0.1, 9, 0.2, 9])[::2]):
        # 1e-6: the float32 input itself is 0.1 and 0.2 only to 3e-8, which τ carries with its slope
        np.testing.assert_allclose(c.inverse_dynamics(given, q, q), expected, rtol=1e-6)
    for bad, message in (([np.nan, 0.0], "is nan"), ([np.inf, 0.0], "is inf"), ([0.0], "has 1 values")):
        with pytest.raises(StateError, match=message):
            c.inverse_dynamics(np.array(bad), q, q)
    assert ("double t" in c.native_source and "out[0]" in c.native_source) == bool(c.native)  # the C, for reading
    packed = np.zeros(8 * 4 + 1, np.uint8)[1:].view(np.float64)     # contiguous but not aligned, as a packed log's
    packed[:] = [0.1, 0.2, 0.3, 0.4]
    for state in (packed[:2], packed.reshape(2, 2)):
        np.testing.assert_allclose(c.inverse_dynamics(state, state, state), inverse_dynamics(arm, state, state, state),
                                   rtol=1e-12)
        np.testing.assert_allclose(c.mass_matrix(state), mass_matrix(arm, state), rtol=1e-12)
        np.testing.assert_allclose(c.regressor(state, state, state), regressor(arm, state, state, state), rtol=1e-12,
                                   atol=1e-12)


def test_a_native_library_in_the_cache_runs_only_behind_its_keyed_hash(tmp_path, monkeypatch):
    from course_dynamics.core.compiled import model_key

    arm, built = native_model("rp_arm", tmp_path, monkeypatch)
    if not built.native:  # no compiler: nothing is built, so nothing is cached or loaded
        assert compile_model(arm, native_code=None).native == {} and not list((tmp_path / "cache").glob("*.native"))
        return
    again = compile_model(arm, native_code=None)  # from the cache, no build
    assert again.native and again.native_source == "" and again.native_seconds < built.native_seconds
    library = tmp_path / "cache" / f"{model_key(arm)}.native"
    library.write_bytes(library.read_bytes()[:32] + b"\x7fELF planted" + library.read_bytes()[45:])
    assert compile_model(arm, native_code=None).native == {}  # a damaged or planted library is never loaded
    assert compile_model(arm).native  # and is built again when asked


def test_without_a_compiler_or_with_native_off_the_python_programs_run(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    arm = load_robot("rrr_arm")
    q = np.array([0.3, -0.2, 0.5])
    monkeypatch.setattr(native, "compiler", lambda: None)
    without = compile_model(arm)
    assert without.native == {}
    np.testing.assert_allclose(without.inverse_dynamics(q, q, q), inverse_dynamics(arm, q, q, q), rtol=1e-12)
    np.testing.assert_allclose(without.regressor(q, q, q), regressor(arm, q, q, q), rtol=1e-12, atol=1e-12)
    monkeypatch.undo()
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    monkeypatch.setenv("COURSE_DYNAMICS_NATIVE", "off")
    assert compile_model(arm).native == {}


def test_a_native_batch_shared_by_threads_equals_one_thread(tmp_path, monkeypatch):
    from course_dynamics.core.compiled import native as native_module

    ur5, c = native_model("ur5", tmp_path, monkeypatch)
    Q = np.random.default_rng(4).uniform(-1, 1, (3 * native_module.THREAD_STATES + 7, ur5.n))
    shared = c.inverse_dynamics(Q, Q, Q)
    monkeypatch.setattr(native_module, "THREADS", 1)
    np.testing.assert_array_equal(shared, c.inverse_dynamics(Q, Q, Q))
