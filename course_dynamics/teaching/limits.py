"""A time limit for a check in a student's kernel: the student's code is stopped, even inside its own ``except:``.

:func:`time_limit` raises :class:`CheckTimeout` in the kernel's main thread after the given seconds (a SIGALRM),
and from then on at every line and opcode of code outside this package, so that a ``try: … except: pass`` loop
cannot swallow it: the next raise comes from inside its own handler. Code stuck inside one C call (a huge
integer power) is not interrupted until the call returns; the kernel's interrupt button still stops it.

Once the block has ended, the timeout is gone from the kernel: no later exception carries it as its
``__context__``. So it is never raised where the interpreter would lose track of the exception being handled:
at the first instruction of an ``except`` handler (``PUSH_EXC_INFO``, whose cleanup would restore the timeout
itself as the exception handled before), in the frames the block runs in, nor in :mod:`contextlib`'s
``__exit__`` that ends the block.

>>> with time_limit(5):
...     total = sum(range(10))
>>> total
45
"""
from __future__ import annotations

import contextlib
import dis
import signal
import sys
import threading
from pathlib import Path

class CheckTimeout(BaseException):
    """A check ran out of time (the student's function does not return); not an Exception, so that neither the
    student's ``except Exception`` nor the check's own handlers can swallow it."""


OURS = str(Path(__file__).resolve().parents[1])  # the package: the time limit never fires in its own frames
HANDLER_START = dis.opmap["PUSH_EXC_INFO"]  # raised here, the handler's cleanup would keep the timeout as handled


@contextlib.contextmanager
def time_limit(seconds: int):
    """Interrupt the code in the block after ``seconds`` (module docstring); outside the main thread, no limit.

    Parameters
    ----------
    seconds : int
        The time limit, s (of wall-clock time).

    Yields
    ------
    None
        The block runs under the limit.

    Raises
    ------
    CheckTimeout
        In the block's code, once ``seconds`` have passed (and at every line after, until the block ends).
    """
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "SIGALRM"):
        yield
        return

    outside, frame = [], sys._getframe(1)
    while frame is not None:  # the frames the block runs in (contextlib's, the caller's and above): never raised in
        outside.append(frame)
        frame = frame.f_back

    def theirs(frame) -> bool:
        code = frame.f_code
        return (not code.co_filename.startswith(OURS) and code.co_filename != contextlib.__file__
                and not any(frame is f for f in outside))

    def trace(frame, event, arg):
        frame.f_trace_opcodes = True  # a one-line loop (while True: pass) has no new line, but opcodes
        if event in ("line", "opcode") and theirs(frame) and frame.f_code.co_code[frame.f_lasti] != HANDLER_START:
            raise CheckTimeout
        return trace

    def interrupt(signum, frame):
        sys.settrace(trace)
        while frame is not None:
            frame.f_trace, frame.f_trace_opcodes = trace, True
            frame = frame.f_back
        raise CheckTimeout

    previous = signal.signal(signal.SIGALRM, interrupt)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        sys.settrace(None)  # before signal.signal, which is Python code (signal.py) the trace would raise in
        frame = sys._getframe()
        while frame is not None:
            frame.f_trace, frame.f_trace_opcodes = None, False
            frame = frame.f_back
        signal.signal(signal.SIGALRM, previous)


__all__ = ["CheckTimeout", "time_limit"]
