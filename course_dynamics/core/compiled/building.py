"""Building a model's native library: bounded before it starts, limited while it runs, remembered if it fails.

gcc's time grows faster than the size of one function, so :mod:`~course_dynamics.core.compiled.native`
cuts every program into C functions of at most :data:`~course_dynamics.core.compiled.native.PART_OPERATIONS`
operations; gcc's time is then about linear in the operations. Measured here (gcc 12, -O1, on 2 cores
shared with other work, so ±30 %; UR5 and Panda run as fast either way, to the same bits):

============  ==========  ==========================  =========================
robot         operations  one function per program    parts of 1000 operations
============  ==========  ==========================  =========================
UR5           7 600       1.7 s, 86 MB                1.0 s, 71 MB
Panda         19 400      4.9 s, 179 MB               2.3 s, 101 MB
chain of 10   20 400      5.7 s, 238 MB               2.7 s, 111 MB
chain of 14   37 800      24 s, 588 MB                4.0 s, 165 MB
chain of 17   54 500      34 s, 946 MB                5.1 s, 221 MB
chain of 20   74 100      129 s, 1.6 GB               7.8 s, 292 MB
============  ==========  ==========================  =========================

A library of more than :data:`~course_dynamics.core.compiled.native.SPLIT_OPERATIONS` operations comes in
:data:`~course_dynamics.core.compiled.native.UNITS` translation units compiled at once (UR5's C then takes
0.6–0.9 s instead of 0.9–1.5 s here); the estimate below stays that of one compiler, an upper bound.

So a build is estimated before it starts (:func:`estimated_seconds`: :data:`START_SECONDS` plus
:data:`SECONDS_PER_OPERATION` an operation) and not started when the estimate passes
:data:`MAX_BUILD_SECONDS`; every robot within :data:`~course_dynamics.core.compiled.tracing.MAX_OPERATIONS`
is under it today, and the bound keeps a larger part or operation limit from bringing minute-long builds back.
A build that starts runs under limits (:func:`~course_dynamics.core.compiled.native.compile_library`:
:data:`~course_dynamics.core.compiled.native.BUILD_SECONDS` of time, then its whole process group is killed,
:data:`~course_dynamics.core.compiled.native.BUILD_MEMORY` of address space, files of at most
:data:`~course_dynamics.core.compiled.native.BUILD_FILE_BYTES`), in a new private folder (``mkdtemp``, mode
0700; the compiler's temporary files too).

Its outcome is kept in the cache behind the folder's keyed hash: the library as ``<key>.native``, or why it
failed (too large, timed out, the compiler's error) as ``<key>.native-failed``, so no later run tries again
(delete that file, or the cache, to retry). A failure is also remembered in this process, which is all there
is where the cache cannot be used. While a build runs, ``<key>.native-building`` says so to other processes.

Who waits: ``compile_model(native_code=True)`` waits for its build (bounded as above). The evaluator asks for
``native_code="background"``: the build runs in a detached child process (``_start``) and the Python
programs answer at once; a later choice in this process takes the library up once it is there
(``collect``), never in the middle of a call. A command that ends first leaves its child to finish and
fill the cache (with no cache to fill, the child is stopped).
"""
from __future__ import annotations

import atexit
import dataclasses
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from . import native
from .cache import WRITES, Cache
from .tracing import Program, trace_programs

#: The estimated build time per operation, s (gcc -O1 on parts of 1000 operations).
SECONDS_PER_OPERATION = 1.1e-4  # gcc -O1 on parts of 1000 operations (table), a little above the measured 1.0e-4
#: The estimated time of starting a build (the child's Python and the compiler's start), s.
START_SECONDS = 0.5             # the child's Python and the compiler's start
#: A build estimated to take longer than this, s, is not started (and that is remembered).
MAX_BUILD_SECONDS = 15.0        # a build estimated longer is not started (the 20-joint chain: 8.7 s estimated)
POLL_SECONDS = 0.25             # a running build is looked at no more often than this
PACKAGE_ROOT = Path(__file__).resolve().parents[3]  # the folder that holds course_dynamics/
BUSY = "another process is building it"  # the reason a compiled model has no C while another process builds it
BUSY_SECONDS = 1.0  # how often the evaluator looks in the cache again for the C another process was building
NO_LIBRARY = "the cache holds no native library for it"  # the reason where only the cache was asked

_FAILED: dict[str, str] = {}      # key -> why its native library was not built, for this process
_RUNNING: dict[str, "_Build"] = {}  # key -> a build this process started and has not collected


def estimated_seconds(programs: dict[str, Program]) -> float:
    """The estimated time of building ``programs`` natively on this machine, s (module docstring).

    :data:`START_SECONDS` plus :data:`SECONDS_PER_OPERATION` for each operation of the programs.

    Parameters
    ----------
    programs : dict of str to Program
        The traced programs (:func:`~course_dynamics.core.compiled.tracing.trace_programs`).

    Returns
    -------
    float
        The estimate, s.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> 1 < estimated_seconds(trace_programs(load_robot("ur5"))) < 2
    True
    """
    return START_SECONDS + SECONDS_PER_OPERATION * sum(len(p.nodes) for p in programs.values())


@dataclasses.dataclass
class _Build:
    """A build running in a child process: its private folder, the cache it fills (None: the folder only)."""

    key: str
    source: str
    folder: str
    cache: Path | None
    process: subprocess.Popen
    started: float = dataclasses.field(default_factory=time.monotonic)
    looked: float = 0.0

    def finished(self, wait: float = 0.0) -> bool:
        """Whether the child has ended (looked at once per :data:`POLL_SECONDS`, unless waiting)."""
        if wait:
            try:
                self.process.wait(timeout=wait)
            except subprocess.TimeoutExpired:
                pass
        elif time.monotonic() - self.looked < POLL_SECONDS:
            return False
        self.looked = time.monotonic()
        return self.process.poll() is not None

    def outcome(self) -> tuple[bytes | None, str]:
        """(library, "") or (None, why not) of a finished build, kept (:func:`_remember`); its folder is removed."""
        try:  # in the folder where the child could not fill the cache
            fd = os.open(os.path.join(self.folder, "outcome.json"), os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
            with os.fdopen(fd, encoding="utf-8") as handle:
                reason = str(json.loads(handle.read(4096))["reason"])
            data = None if reason else native.read_library(self.folder, native.module_name(self.key),
                                                            native.BUILD_FILE_BYTES)
            reason = reason or ("" if data else "the C compiler wrote no library")
        except (OSError, ValueError, KeyError):
            data, reason = None, None
        with Cache(self.cache) as store:
            if reason is not None:
                _remember(store, self.key, data, reason)
            else:  # the child kept its outcome in the cache, unless it ended before
                data = store.load_bytes(f"{self.key}.native")
                failed = store.load_bytes(f"{self.key}.native-failed")
                if data is not None:
                    reason = ""
                elif failed is not None:
                    reason = _FAILED[self.key] = failed.decode("utf-8", "replace")
                else:
                    reason = f"the build process ended with exit code {self.process.returncode}"
                    _remember(store, self.key, None, reason)
        shutil.rmtree(self.folder, ignore_errors=True)
        _RUNNING.pop(self.key, None)
        return data, reason


def _remember(store: Cache, key: str, data: bytes | None, reason: str) -> None:
    """Keep a build's outcome: the library, or why there is none (in the cache and in this process)."""
    if data is None:
        _FAILED[key] = reason
    if store.folder is not None:
        if data is not None:
            store.store_bytes(f"{key}.native", data)
        else:
            store.store_bytes(f"{key}.native-failed", reason.encode("utf-8"))
        store.remove(f"{key}.native-building")


def why_not(key: str, store: Cache) -> str | None:
    """Why no build of ``key`` should start now (failed before, being built, no compiler), or None.

    >>> _remember(Cache(None), "k" * 64, None, "the C compiler failed (exit 1)")   # no cache: this process only
    >>> why_not("k" * 64, Cache(None))
    'the C compiler failed (exit 1)'
    """
    if key in _FAILED:
        return _FAILED[key]
    if key in _RUNNING:
        return "it is being built in the background"
    if native.compiler() is None:
        return "no C compiler with Python's headers here"
    failed = store.load_bytes(f"{key}.native-failed")
    if failed is not None:
        _FAILED[key] = (f"an earlier build failed ({failed.decode('utf-8', 'replace')}); delete "
                        f"{store.folder / (key + '.native-failed')} to try again")
        return _FAILED[key]
    building = store.load_bytes(f"{key}.native-building")
    try:
        since = time.time() - float(building or b"nan")
    except ValueError:
        since = float("nan")
    if 0 <= since < native.BUILD_SECONDS + 60:
        return BUSY
    return None


def _start(source: str, key: str, store: Cache) -> _Build:
    """Build ``source`` in a detached child process; the outcome goes to the cache (or the folder, without one)."""
    folder = tempfile.mkdtemp(prefix="course-dynamics-build-")  # 0700, a name no one can guess
    name = native.module_name(key)
    fd = os.open(os.path.join(folder, f"{name}.c"), os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
    with os.fdopen(fd, "w", encoding="utf-8") as handle:
        handle.write(source)
    if store.folder is not None:
        store.store_bytes(f"{key}.native-building", repr(time.time()).encode())
    job = {"folder": folder, "key": key, "cache": None if store.folder is None else str(store.folder),
           "compiler": native.compiler(), "seconds": native.BUILD_SECONDS, "memory": native.BUILD_MEMORY,
           "parent": os.getpid()}
    # The child's first folder on sys.path is its own private folder (cwd); ours goes last, so that nothing
    # else beside an uninstalled course_dynamics/ can stand in for a module of the standard library.
    code = "import sys; sys.path.append(sys.argv[1]); from course_dynamics.core.compiled.building import _child; " \
           "_child(sys.argv[2])"
    try:
        process = subprocess.Popen([sys.executable, "-c", code, str(PACKAGE_ROOT), json.dumps(job)], cwd=folder,
                                   stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                   start_new_session=True)
    except OSError:
        shutil.rmtree(folder, ignore_errors=True)
        store.remove(f"{key}.native-building")
        raise
    build = _Build(key, source, folder, store.folder, process)
    _RUNNING[key] = build
    return build


def _child(job_text: str) -> None:
    """The child process of :func:`start`: build, then keep the outcome in the cache, else in the folder."""
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))  # compile_library then stops the compiler too
    job = json.loads(job_text)
    folder, key = job["folder"], job["key"]
    name = native.module_name(key)
    reason = native.compile_library(folder, name, job["compiler"], job["seconds"], job["memory"],
                                    native.BUILD_FILE_BYTES)
    data = None if reason else native.read_library(folder, name, native.BUILD_FILE_BYTES)
    if not reason and not data:
        reason = "the C compiler wrote no library"
    with Cache(Path(job["cache"]) if job["cache"] else None, make=False) as store:  # deleted meanwhile: gone
        if store.folder is not None:
            _remember(store, key, data, reason)
            shutil.rmtree(folder, ignore_errors=True)
            return
    if os.getppid() != job["parent"]:  # the process that started it has ended: no one will read the folder
        shutil.rmtree(folder, ignore_errors=True)
        return
    fd = os.open(os.path.join(folder, "outcome.json"), os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
    with os.fdopen(fd, "w", encoding="utf-8") as handle:
        json.dump({"reason": reason}, handle)


def may_be_built(reason: str, folder: str, key: str) -> bool:
    """Whether the cache folder may now hold the native library a compiled model had not found there (the
    evaluator asks again): its reason was :data:`BUSY` or :data:`NO_LIBRARY`, and ``<key>.native`` is there.

    Parameters
    ----------
    reason : str
        The compiled model's ``native_reason``.
    folder : str
        The cache folder ("" for none).
    key : str
        The model's key (:func:`~course_dynamics.core.compiled.model_key`).

    Returns
    -------
    bool
        Whether loading the compiled model again may find its C.

    Examples
    --------
    >>> may_be_built("its C would take about 9.0 s to build, over the bound of 8 s", "/tmp", "k")
    False
    """
    return reason in (BUSY, NO_LIBRARY) and bool(folder) and os.path.exists(os.path.join(folder, f"{key}.native"))


def attach(compiled, programs: dict[str, Program] | None, key: str, store: Cache, mode, agrees) -> None:
    """Give ``compiled`` its native functions: from the cache, or built (``mode`` True: now, waiting;
    "background": in a child process, taken up by :func:`collect`; None: from the cache only).

    ``agrees(model, functions, native_out=True)`` checks loaded functions against the recursions. Sets
    ``compiled.native_reason`` to why there are none (yet).

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.compiled import compile_model
    >>> compile_model(load_robot("pendulum"), cache=False, native_code=None).native_reason   # calls attach
    'the cache holds no native library for it'
    """
    if not native.enabled():
        compiled.native_reason = "native code is turned off (COURSE_DYNAMICS_NATIVE=off)"
        return
    begun = time.perf_counter()
    model = compiled.model
    data = store.load_bytes(f"{key}.native")
    source = ""
    if data is None:
        reason = why_not(key, store)
        if reason is None and mode is None:
            reason = NO_LIBRARY
        if reason is None:
            programs = programs or trace_programs(model)
            seconds = estimated_seconds(programs)
            if seconds > MAX_BUILD_SECONDS:
                reason = f"its C would take about {seconds:.1f} s to build, over the bound of {MAX_BUILD_SECONDS:g} s"
                _remember(store, key, None, reason)
        if reason is not None:
            compiled.native_reason = reason
            return
        source = native.c_source(programs, model.n, key, model.name)
        if mode == "background":
            try:
                compiled.native_build = _start(source, key, store)
                compiled.native_reason = "it is being built in the background"
            except OSError as exc:
                compiled.native_reason = f"its build could not be started ({exc.strerror})"
                _remember(store, key, None, compiled.native_reason)
            return
        data, reason = native.build(source, key)
        _remember(store, key, data, reason)
        if data is None:
            compiled.native_reason = reason
            return
    functions = native.load(data, key)
    if not functions or not agrees(model, functions, native_out=True):
        compiled.native_reason = "its native library did not load, or disagreed with the recursions"
        return
    compiled.native, compiled.native_source, compiled.native_seconds = functions, source, time.perf_counter() - begun
    compiled.native_reason = ""
    WRITES[0] += 1  # a library this process has taken up: the one-state entry's choices are made again


def collect(compiled, agrees, wait: float = 0.0):
    """``compiled`` with its background build taken up if the build has ended (a new CompiledModel; the same
    one while it runs). ``wait``: at most this long, s, for it to end.

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.compiled import compile_model
    >>> python_only = compile_model(load_robot("pendulum"), cache=False, native_code=False)
    >>> collect(python_only, agrees=None) is python_only          # no build running: the same model
    True
    """
    build = compiled.native_build
    if build is None or not build.finished(wait):
        return compiled
    data, reason = build.outcome()
    functions = native.load(data, build.key) if data is not None else None
    if functions and agrees(compiled.model, functions, native_out=True):
        return dataclasses.replace(compiled, native=functions, native_source=build.source, native_build=None,
                                   native_seconds=time.monotonic() - build.started, native_reason="")
    _FAILED.setdefault(build.key, reason or "its native library did not load, or disagreed with the recursions")
    return dataclasses.replace(compiled, native_build=None, native_reason=_FAILED[build.key])


@atexit.register
def _at_exit() -> None:
    """A build with a cache to fill is left to finish; one without is stopped (its outcome would be lost); an
    ended one is taken up, so that a failure is remembered."""
    for build in list(_RUNNING.values()):
        if build.process.poll() is None:
            if build.cache is not None:
                continue
            for stop in (signal.SIGTERM, signal.SIGKILL):  # SIGTERM: the child stops its compiler first
                if build.process.poll() is None:
                    try:
                        os.killpg(build.process.pid, stop)
                        build.process.wait(timeout=3)
                    except (OSError, subprocess.TimeoutExpired):
                        pass
        try:
            build.outcome()
        except Exception:  # nothing at exit is worth a traceback; the folder goes in any case
            shutil.rmtree(build.folder, ignore_errors=True)


__all__ = ["MAX_BUILD_SECONDS", "SECONDS_PER_OPERATION", "START_SECONDS", "estimated_seconds"]
