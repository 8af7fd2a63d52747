"""What keeps a run's processes and memory in, beside the sandbox: cgroups, a seccomp filter, the subreaper.

==============================================  ============================================================
mechanism                                       what it holds
==============================================  ============================================================
:class:`ControlGroups`                          pids and memory cgroups for one run's whole tree, where the
                                                machine lets us make them (cgroup v1 or v2)
:func:`seccomp_program`                         a BPF filter the launcher installs: no ``memfd_create``
                                                or System V shared memory (memory no limit counts)
:func:`become_subreaper`, :func:`kill_orphans`  without a sandbox, processes a submission detaches are
                                                re-parented to the grader and killed
==============================================  ============================================================
"""
from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

from ..base.errors import CourseDynamicsError

#: The most processes one run may have at once (its pids cgroup, or ``RLIMIT_NPROC`` beyond those already running).
PROCESSES = 64


class ContainmentError(CourseDynamicsError):
    """The processes of submissions cannot be contained here (the message says why)."""


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

    Parameters
    ----------
    machine : str or None
        The machine, as ``platform.machine()`` names it (``x86_64``, ``aarch64``); this one when None.

    Returns
    -------
    bytes or None
        The program's instructions, or None for a machine whose system call numbers are not known here.
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


class ControlGroups:
    """pids and memory cgroups for one run, where this machine lets us make them (cgroup v1 or v2).

    ``procs`` lists the cgroup.procs files the launcher joins; ``available``
    says whether a process limit holds for the whole tree.

    Parameters
    ----------
    name : str
        The cgroups' name, one per run.
    memory_bytes : int
        The memory limit of the whole tree, bytes.
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
        """Whether a pids cgroup, and so a process limit for the whole tree, was made."""
        return any((folder / "pids.max").exists() for folder in self.folders)

    @staticmethod
    def _make(controller: str, name: str, settings: dict) -> Path | None:
        for base in cgroup_bases(controller):
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
        """The processes in the groups now.

        Returns
        -------
        set of int
            Their process ids.
        """
        found = set()
        for procs in self.procs:
            try:
                found |= {int(x) for x in Path(procs).read_text().split()}
            except OSError:
                pass
        return found

    def out_of_memory(self) -> bool:
        """Whether the memory cgroup killed a process (read before :meth:`kill_and_remove`).

        Returns
        -------
        bool
            True when it killed one or refused memory; False without a memory cgroup.
        """
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


def cgroup_bases(controller: str) -> list[Path]:
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


STARTING = threading.Lock()
LAUNCHED: set[int] = set()     # launchers of runs under way: the grader's own children
BEFORE: set[int] | None = None  # the grader's children when it became a subreaper: not ours to kill
PR_SET_CHILD_SUBREAPER = 36


def children() -> set[int]:
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


def become_subreaper() -> None:
    """Make detached descendants of a run children of the grader (module docstring); once per process.

    Raises
    ------
    ContainmentError
        If the system refuses (``prctl(PR_SET_CHILD_SUBREAPER)`` fails).
    """
    global BEFORE
    if BEFORE is not None:
        return
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    if libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) != 0:
        raise ContainmentError("cannot contain the processes of submissions here (prctl PR_SET_CHILD_SUBREAPER "
                               "failed); grade with the sandbox")
    with STARTING:
        BEFORE = children() - LAUNCHED


def kill_orphans() -> None:
    """Kill and reap every child of the grader that is neither a launcher nor one it had before grading."""
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        with STARTING:
            orphans = children() - LAUNCHED - (BEFORE or set())
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


def process_limit(uid: int | None = None) -> int | None:
    """RLIMIT_NPROC counts every process of the user (``uid``, default this process's), so allow the ones already
    running plus PROCESSES.

    None for root, to whom the kernel does not apply the limit.

    Parameters
    ----------
    uid : int or None
        The user the run takes; this process's when None.

    Returns
    -------
    int or None
        The limit, or None for root.
    """
    uid = os.getuid() if uid is None else uid
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


def kill_group(pid: int) -> None:
    """Kill the process group ``pid`` leads (SIGKILL); nothing when it is gone or not ours.

    Parameters
    ----------
    pid : int
        The group leader's process id.
    """
    try:
        os.killpg(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


__all__ = ["PROCESSES", "ContainmentError", "ControlGroups", "become_subreaper", "kill_group", "kill_orphans",
           "process_limit", "seccomp_program"]
