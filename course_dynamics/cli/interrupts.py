"""Ctrl-C that always ends a command, even inside a library that catches it.

Some libraries we import catch ``BaseException`` (trimesh does, in its optional
imports and in mesh loading), so a ``KeyboardInterrupt`` raised there is
swallowed and the command would run on to the end and write its output. While
a command runs, :func:`interruptible` keeps SIGINT's handler our own: the first
Ctrl-C raises ``KeyboardInterrupt`` as Python's default does, and until the
command's top level has received it (:meth:`Interrupts.received`) it is raised
again every :data:`REPEAT` seconds wherever the main thread then is. One swallow
therefore delays the end by a fraction of a second; it never cancels it.

Outside the main thread (a test runner's worker, an embedding program) nothing
is installed, and the previous handler is restored when the command returns.
"""
from __future__ import annotations

import _thread
import contextlib
import signal
import threading

REPEAT = 0.2  # s between repeats of an interrupt the command has not yet received


class Interrupts:
    """The state of one command's SIGINT handling: whether Ctrl-C came, and whether it arrived."""

    def __init__(self):
        self._pending = threading.Event()
        self._received = threading.Event()
        self._lock = threading.Lock()  # no repeat is sent once received() has returned

    def handler(self, signum, frame):
        if self._received.is_set():  # a repeat that was on its way: the command already has its interrupt
            return
        if not self._pending.is_set():
            self._pending.set()
            threading.Thread(target=self._repeat, name="course-dynamics-interrupt", daemon=True).start()
        raise KeyboardInterrupt

    def _repeat(self) -> None:
        while not self._received.wait(REPEAT):
            with self._lock:
                if not self._received.is_set():
                    _thread.interrupt_main(signal.SIGINT)

    @property
    def pending(self) -> bool:
        """Whether a Ctrl-C came during the command (received or not)."""
        return self._pending.is_set()

    def received(self) -> None:
        """The command's top level has the ``KeyboardInterrupt``: stop repeating it."""
        with self._lock:
            self._received.set()


@contextlib.contextmanager
def interruptible():
    """SIGINT handled by a fresh :class:`Interrupts` for the block (the main thread only); yields it or None."""
    if threading.current_thread() is not threading.main_thread():
        yield None
        return
    interrupts = Interrupts()
    previous = signal.signal(signal.SIGINT, interrupts.handler)
    try:
        yield interrupts
    finally:
        interrupts.received()
        signal.signal(signal.SIGINT, previous)
