"""Starts the sandbox with limits: ``python -I -S launcher.py CONFIG COMMAND…``.

Run by the grader as a fresh process (standard library only): it moves itself
into the grading cgroups named in CONFIG (JSON), sets the resource limits,
takes the unprivileged user and group CONFIG names (if any: a run without
the sandbox, started by root), installs the seccomp filter CONFIG carries (a
BPF program, hex; see :func:`~course_dynamics.grading.containment.seccomp_program`), and replaces itself
with COMMAND, so that the
limits and the filter hold from the first instruction of the sandbox and of
everything it starts. Doing this in a
process of its own keeps the grader free of ``preexec_fn``, which is unsafe
in a program that runs several submissions at once in threads.
"""
import ctypes
import json
import os
import resource
import sys

PR_SET_NO_NEW_PRIVS = 38
PR_SET_SECCOMP = 22
SECCOMP_MODE_FILTER = 2


class SockFprog(ctypes.Structure):
    _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_char_p)]


def install_filter(program: bytes) -> None:
    """Install a seccomp BPF program (8 bytes per instruction) for this process and all it starts.

    A process that cannot install it ends at once, with status 126 and one line on standard error.

    Parameters
    ----------
    program : bytes
        The program, 8 bytes per instruction.
    """
    libc = ctypes.CDLL(None, use_errno=True)
    fprog = SockFprog(len(program) // 8, program)
    if libc.prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0 or \
            libc.prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, ctypes.byref(fprog), 0, 0) != 0:
        sys.stderr.write(f"course-dynamics launcher: cannot install the seccomp filter: "
                         f"{os.strerror(ctypes.get_errno())}\n")
        os._exit(126)


def main() -> None:
    """The script: join the cgroups, set the limits, take the user, install the filter, then become COMMAND.

    ``python -I -S launcher.py CONFIG COMMAND…``, CONFIG a JSON object with ``cgroups`` (cgroup.procs files),
    ``rlimits`` (name → (soft, hard)), ``user`` ((uid, gid) or null) and ``seccomp`` (the program in hex, or empty).
    It never returns: the process becomes COMMAND, or ends with status 126 when it cannot take the user.
    """
    config = json.loads(sys.argv[1])
    command = sys.argv[2:]
    for procs in config.get("cgroups", []):
        with open(procs, "w") as handle:
            handle.write(str(os.getpid()))
    for name, (soft, hard) in config.get("rlimits", {}).items():
        resource.setrlimit(getattr(resource, name), (soft, hard))
    if config.get("user"):
        uid, gid = config["user"]
        os.setgroups([])
        os.setgid(gid)
        os.setuid(uid)  # for good: a process that is no longer root cannot become root again
        if os.getuid() != uid or os.geteuid() != uid:
            sys.stderr.write("course-dynamics launcher: cannot take the unprivileged user\n")
            os._exit(126)
    if config.get("seccomp"):
        install_filter(bytes.fromhex(config["seccomp"]))
    os.execv(command[0], command)



__all__ = ["install_filter", "main"]


if __name__ == "__main__":
    main()
