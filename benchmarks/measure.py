"""What every benchmark shares: the one timing loop, our batch threading made explicit, and what threads ran.

Our compiled models share a native batch over threads (``course_dynamics.core.compiled.native.THREADS`` threads, each
given at least ``THREAD_STATES`` states; there is no environment variable for it): :func:`our_threads` sets that
count for a block, and :func:`threads_used` runs a call once, untimed, on a copy of the compiled model whose
native functions count their calls (one a piece of the batch, each piece given to a thread of the pool), so a
label says how many threads our side shared its batch over.
Pinocchio's thread count is the ``num_threads`` its ``…InParallel`` functions are given; its other functions run
on the calling thread. numpy's BLAS threads are reported by threadpoolctl where installed, else by asking
numpy's bundled OpenBLAS directly.
"""
from __future__ import annotations

import ctypes
import dataclasses
import glob
import os
import threading
import time
from contextlib import contextmanager

import numpy as np

from course_dynamics.core import compiled as compiled_module
from course_dynamics.core.compiled import native as native_module


def best(function, repeat: int, number: int = 1) -> float:
    """Best wall time of one call (s) over ``repeat`` rounds of ``number`` calls: the statistic of both sides."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            function()
        times.append((time.perf_counter() - start) / number)
    return min(times)


@contextmanager
def our_threads(count: int):
    """Our native batches shared over at most ``count`` threads inside the block (the package default after)."""
    saved = native_module.THREADS
    native_module.THREADS = count
    try:
        yield
    finally:
        native_module.THREADS = saved


def threads_used(compiled, method: str, *arguments) -> int:
    """How many threads ``compiled.<method>(*arguments)`` shares our native code over now (1 for the Python
    programs): the pieces its batch is cut into, one a thread of the pool, counted in one untimed call on a copy
    whose native functions count their calls."""
    pieces = []
    lock = threading.Lock()

    def counting(function):
        def call(*args):
            with lock:
                pieces.append(1)
            return function(*args)
        return call

    probe = dataclasses.replace(compiled, native={name: counting(f) for name, f in compiled.native.items()})
    getattr(probe, method)(*arguments)
    return max(1, len(pieces))


def threads(ours: int | str, theirs: int | str) -> str:
    """The label of one row: 'ours 2 threads / pin 1 thread'."""
    def count(k):
        return f"{k} thread" + ("" if k == 1 else "s")
    return f"ours {count(ours)} / pin {count(theirs)}"


def blas_threads() -> str:
    """numpy's BLAS thread pool, as threadpoolctl reports it, else as numpy's bundled OpenBLAS does."""
    try:
        from threadpoolctl import threadpool_info
    except ImportError:
        pass
    else:
        pools = [f"{p.get('internal_api')} {p.get('num_threads')}" for p in threadpool_info()]
        return ", ".join(pools) + " (threadpoolctl)" if pools else "no BLAS/OpenMP pool loaded (threadpoolctl)"
    libraries = glob.glob(os.path.join(os.path.dirname(np.__file__), os.pardir, "numpy.libs", "*openblas*"))
    for path in libraries:
        library = ctypes.CDLL(path)
        for symbol in ("scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads", "openblas_get_num_threads"):
            function = getattr(library, symbol, None)
            if function is not None:
                return f"OpenBLAS {function()} (threadpoolctl not installed: asked numpy's OpenBLAS)"
    return "unknown (threadpoolctl not installed, no bundled OpenBLAS found)"


def print_conditions(title: str) -> None:
    """The machine's cores and load, our batch threading by default, numpy's BLAS threads."""
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    chosen = {k: os.environ[k] for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS") if k in os.environ}
    print(f"{title}\n  machine: {os.cpu_count()} cores, load average {load} (1, 5, 15 min); "
          f"ours by default shares a native batch over up to {native_module.THREADS} threads, "
          f"{native_module.THREAD_STATES} states a thread at least; numpy's BLAS: {blas_threads()}"
          + (f"; {chosen}" if chosen else ""))


def print_load() -> None:
    print("  load average at the end: " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
