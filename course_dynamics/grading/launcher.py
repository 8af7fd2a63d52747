"""Starts the sandbox with limits: ``python -I -S launcher.py CONFIG COMMAND…``.

Run by the grader as a fresh process (standard library only): it moves itself
into the grading cgroups named in CONFIG (JSON), sets the resource limits, and
replaces itself with COMMAND, so that the limits hold from the first
instruction of the sandbox and of everything it starts. Doing this in a
process of its own keeps the grader free of ``preexec_fn``, which is unsafe
in a program that runs several submissions at once in threads.
"""
import json
import os
import resource
import sys


def main() -> None:
    config = json.loads(sys.argv[1])
    command = sys.argv[2:]
    for procs in config.get("cgroups", []):
        with open(procs, "w") as handle:
            handle.write(str(os.getpid()))
    for name, (soft, hard) in config.get("rlimits", {}).items():
        resource.setrlimit(getattr(resource, name), (soft, hard))
    os.execv(command[0], command)


if __name__ == "__main__":
    main()
