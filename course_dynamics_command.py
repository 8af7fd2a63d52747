"""The ``course-dynamics`` command's entry point: Ctrl-C is ours from the first line.

Importing :mod:`course_dynamics.cli` takes a noticeable fraction of a second
(numpy, the core, every command's module). A Ctrl-C in that time would end in
Python's own traceback, or be swallowed by a library that catches it, so the
import runs with SIGINT only recorded; the command then stops at once with the
CLI's one line and exit 130, or runs under the CLI's own handling
(:mod:`course_dynamics.cli.interrupts`). ``python -m course_dynamics.cli`` has no
such shim: there Ctrl-C is handled from :func:`course_dynamics.cli.main` on.
"""
import signal
import sys


def main() -> int:
    interrupted = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: interrupted.append(signum))
    try:
        from course_dynamics.cli import main as command
    finally:
        signal.signal(signal.SIGINT, previous)
    if interrupted:
        print("error: interrupted", file=sys.stderr)
        return 130
    return command()


if __name__ == "__main__":
    sys.exit(main())
