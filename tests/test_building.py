"""course_dynamics/core/compiled/building.py: a native build is bounded, never stalls a run, and is tried once.

A fake C compiler (a shell script first on PATH, named as ``native.compiler`` looks for it) sleeps or fails and
writes one line per run to a log, so a test can count the builds that started.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import sysconfig
import time
from pathlib import Path

import numpy as np
import pytest
from helpers import chain_urdf

from course_dynamics import load_robot, load_urdf
from course_dynamics.core import evaluator
from course_dynamics.core.compiled import MAX_OPERATIONS, building, compile_model, native, trace_programs
from course_dynamics.core.compiled.cache import Cache

HAS_COMPILER = native.compiler() is not None and native.enabled()
HAS_HEADERS = (Path(sysconfig.get_paths()["include"]) / "Python.h").is_file()  # what a fake compiler cannot give


@pytest.fixture(autouse=True)
def forget_failures(monkeypatch):
    """Failures are remembered per process and model: each test starts with none, and leaves none behind."""
    monkeypatch.setattr(building, "_FAILED", {})


def fake_compiler(tmp_path, monkeypatch, script: str) -> Path:
    """A fake ``cc``/``gcc`` first on PATH running ``script`` (sh), and the one ``native.compiler`` picks in this
    process; returns its log (one line per run: the mode of its folder, the folder, its TMPDIR, its pid)."""
    folder = tmp_path / "bin"
    folder.mkdir()
    log = tmp_path / "compiler.log"
    for name in {"cc", "gcc", os.path.basename(native.compiler() or "cc")}:
        path = folder / name
        path.write_text(f'#!/bin/sh\necho "$(stat -c %a .) $PWD $TMPDIR $$" >> {log}\n{script}\n')
        path.chmod(0o755)
    monkeypatch.setenv("PATH", f"{folder}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setattr(native, "compiler", lambda: str(folder / "cc"))
    return log


def runs(log: Path) -> int:
    return len(log.read_text().splitlines()) if log.exists() else 0


def test_every_native_function_is_of_bounded_size_and_the_bound_covers_every_compilable_robot():
    """gcc's time grows faster than a function's size: the C comes in parts, and the estimate stays linear."""
    ur5 = load_robot("ur5")
    source = native.c_source(trace_programs(ur5), ur5.n, "k" * 64, ur5.name)
    bodies = re.split(r"\n(?=static |HIDDEN )", source)
    sizes = [body.count("    const double t") for body in bodies]
    assert max(sizes) <= native.PART_OPERATIONS and "coriolis_part1(" in source  # UR5's C takes 4 199 operations
    assert building.START_SECONDS + building.SECONDS_PER_OPERATION * MAX_OPERATIONS < building.MAX_BUILD_SECONDS


def test_a_chain_over_the_bound_is_not_built_and_says_why(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    log = fake_compiler(tmp_path, monkeypatch, "exit 1")
    monkeypatch.setattr(building, "MAX_BUILD_SECONDS", 1.0)  # a 6-joint chain's C: about 1.3 s
    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(6))
    chain = load_urdf(path)
    c = compile_model(chain)
    assert c.native == {} and runs(log) == 0
    assert re.fullmatch(r"its C would take about 1\.\d s to build, over the bound of 1 s", c.native_reason)
    monkeypatch.setattr(building, "_FAILED", {})  # a new process: the cache remembers
    again = compile_model(chain)
    assert "an earlier build failed (its C would take" in again.native_reason and runs(log) == 0
    np.testing.assert_allclose(again.inverse_dynamics(np.ones(6), np.ones(6), np.ones(6)),
                               c.inverse_dynamics(np.ones(6), np.ones(6), np.ones(6)), rtol=1e-15)


def test_a_build_that_times_out_is_stopped_and_never_tried_again(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    log = fake_compiler(tmp_path, monkeypatch, "sleep 30")
    monkeypatch.setattr(native, "BUILD_SECONDS", 1)
    start = time.perf_counter()
    c = compile_model(load_robot("pendulum"))  # native_code=True: this call waits, for its time bound at most
    assert time.perf_counter() - start < 10 and c.native == {} and runs(log) == 1
    assert c.native_reason == "the C compiler took longer than 1 s and was stopped"
    mode, cwd, tmpdir, _ = log.read_text().split()
    assert mode == "700" and cwd == tmpdir and not Path(cwd).exists()  # its own private folder, gone after
    monkeypatch.setattr(building, "_FAILED", {})  # a new process: the marker in the cache remembers
    again = compile_model(load_robot("pendulum"))
    assert again.native_reason.startswith("an earlier build failed (the C compiler took longer than 1 s")
    assert "native-failed to try again" in again.native_reason and runs(log) == 1


def test_without_a_usable_cache_a_failed_build_is_remembered_in_the_process(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(blocker / "cache"))
    log = fake_compiler(tmp_path, monkeypatch, "echo 'broken: no such compiler' >&2; exit 1")
    first, second = compile_model(load_robot("two_link")), compile_model(load_robot("two_link"))
    assert first.native == second.native == {} and runs(log) == 1
    assert first.native_reason == second.native_reason == "the C compiler failed (exit 1): broken: no such compiler"


def test_the_evaluator_builds_in_the_background_and_takes_the_library_up_between_calls(tmp_path, monkeypatch):
    monkeypatch.setenv("COURSE_DYNAMICS_CACHE", str(tmp_path / "cache"))
    arm = load_robot("rp_arm")
    started = evaluator.implementation(arm, calls=10_000)  # work that pays for a native build
    assert started.native == {} and started.native_source == ""
    if not HAS_COMPILER:
        assert started.native_build is None and started.native_reason
        return
    assert started.native_build is not None and started.native_reason == "it is being built in the background"
    started.native_build.process.wait(timeout=60)
    time.sleep(building.POLL_SECONDS)
    taken_up = evaluator.implementation(arm, calls=0, states=0)
    assert taken_up is not started and taken_up.native and started.native == {}  # a running call keeps its own
    q = np.array([0.3, 0.1])
    np.testing.assert_allclose(taken_up.inverse_dynamics(q, q, q), started.inverse_dynamics(q, q, q), rtol=1e-12)
    assert list((tmp_path / "cache").glob("*.native")) and not list((tmp_path / "cache").glob("*.native-building"))


SIMULATE = """
import os, sys, time
from course_dynamics.core.compiled import native
native.BUILD_SECONDS = 2  # the background build's time bound, as the child process is told it
from course_dynamics.cli import main
code = main(["simulate", "pendulum", "--q0", "0.5", "--duration", "1", "--dt", "0.001", "--integrator", "rk4",
             "--out", sys.argv[1], "--quiet"])
if len(sys.argv) > 2:  # wait for the compiler to have started, so that it runs when this process ends
    deadline = time.monotonic() + 5
    while not os.path.exists(sys.argv[2]) and time.monotonic() < deadline:
        time.sleep(0.05)
sys.exit(code)
"""


def test_a_command_never_waits_for_a_background_build_and_the_next_run_does_not_retry(tmp_path, monkeypatch):
    """A real subprocess per run, with a compiler that would take 30 s: each run ends in seconds."""
    cache = tmp_path / "cache"
    log = fake_compiler(tmp_path, monkeypatch, "sleep 30")
    environment = dict(os.environ, COURSE_DYNAMICS_CACHE=str(cache))

    def simulate():
        start = time.perf_counter()
        done = subprocess.run([sys.executable, "-c", SIMULATE, str(tmp_path / "out.csv")], env=environment,
                              capture_output=True, text=True, timeout=60)
        seconds = time.perf_counter() - start
        assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
        assert seconds < 15, f"{seconds:.1f} s: the run waited for its build (which would take 30 s)"
        return done

    simulate()
    deadline = time.monotonic() + 20
    while not list(cache.glob("*.native-failed")) and time.monotonic() < deadline:  # its child stops it at 2 s
        time.sleep(0.2)
    failed = list(cache.glob("*.native-failed"))
    if not HAS_HEADERS:  # nothing is ever built: without Python's headers no compiler is tried
        assert not failed and runs(log) == 0
        return
    assert len(failed) == 1 and runs(log) == 1 and not list(cache.glob("*.native-building"))
    with Cache(cache) as store:
        assert store.load_bytes(failed[0].name) == b"the C compiler took longer than 2 s and was stopped"
    simulate()
    time.sleep(2)  # what a second build would need to start its compiler
    assert runs(log) == 1 and not list(cache.glob("*.native"))


def test_without_a_cache_a_command_stops_its_build_when_it_ends(tmp_path, monkeypatch):
    """No cache to fill: the build would be lost, so the command's end stops it (its compiler too), at once."""
    log = fake_compiler(tmp_path, monkeypatch, "sleep 30")
    environment = dict(os.environ, COURSE_DYNAMICS_CACHE="off")
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", SIMULATE, str(tmp_path / "out.csv"), str(log)], env=environment,
                          capture_output=True, text=True, timeout=60)
    seconds = time.perf_counter() - start
    assert done.returncode == 0, done.stderr
    assert seconds < 20, f"{seconds:.1f} s (up to 5 s of it waiting for the compiler to start): it waited for it"
    if not HAS_HEADERS:
        assert runs(log) == 0
        return
    _, folder, _, pid = log.read_text().split()
    with pytest.raises(ProcessLookupError):  # the fake compiler (and its sleep) was killed with the command
        os.kill(int(pid), 0)
    assert not Path(folder).exists()


def test_a_large_library_is_compiled_in_translation_units_at_once_and_linked(tmp_path, monkeypatch):
    """UR5's C (over SPLIT_OPERATIONS) comes in two units, each compiled by its own compiler at the same time."""
    ur5 = load_robot("ur5")
    source = native.c_source(trace_programs(ur5), ur5.n, "k" * 64, ur5.name)
    assert source.count(native.UNIT_MARK) == native.UNITS
    pendulum = load_robot("pendulum")
    assert native.UNIT_MARK not in native.c_source(trace_programs(pendulum), 1, "p" * 64, pendulum.name)
    starts = tmp_path / "starts"
    fake_compiler(tmp_path, monkeypatch, f'case "$*" in *" -c "*) date +%s.%N >> {starts}; sleep 1; exit 3;; esac')
    begun = time.perf_counter()
    data, reason = native.build(source, "k" * 64)
    assert data is None and reason.startswith("the C compiler failed (exit 3)")
    times = [float(t) for t in starts.read_text().split()]
    assert len(times) == native.UNITS and max(times) - min(times) < 0.9   # started together, not one after another
    assert time.perf_counter() - begun < 1.9


def test_a_unit_that_fails_ends_the_build_at_once_and_is_named_with_its_error(tmp_path, monkeypatch):
    ur5 = load_robot("ur5")
    source = native.c_source(trace_programs(ur5), ur5.n, "k" * 64, ur5.name)
    fake_compiler(tmp_path, monkeypatch, 'case "$*" in *".u1.c"*) echo "u1.c:3:7: error: it is not C"; '
                                         'echo "    3 | x"; echo "      | ^"; exit 1;; *) sleep 5;; esac')
    begun = time.perf_counter()
    data, reason = native.build(source, "k" * 64)
    assert data is None and time.perf_counter() - begun < 3                      # not after unit 0's 5 s
    assert reason == "the C compiler failed (exit 1): u1.c:3:7: error: it is not C (translation unit 1)"


@pytest.mark.skipif(not HAS_COMPILER, reason="needs a C compiler")
def test_the_units_linked_agree_with_the_recursions():
    from course_dynamics.core.newton_euler import inverse_dynamics

    panda = load_robot("panda")
    data, reason = native.build(native.c_source(trace_programs(panda), panda.n, "q" * 64, panda.name), "q" * 64)
    functions = native.load(data, "q" * 64)
    q = np.random.default_rng(2).uniform(-1, 1, panda.n)
    out = np.empty(panda.n)
    functions["tau"](q, q, q, out)
    np.testing.assert_array_equal(out, inverse_dynamics(panda, q, q, q))
