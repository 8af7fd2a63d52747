"""The machine's resources: one memory budget, and byte counts for people.

Every check that refuses work too large for this machine (a simulation's time
grid, a log, the comparison with Pinocchio, a robot's n×n matrices) asks
:func:`check_memory`, so they all use the same budget (half the physical
memory) and say the same thing.
"""
from __future__ import annotations

import os

from .errors import CourseDynamicsError, InputError


def memory_budget() -> int:
    """Bytes a run may keep: half the machine's physical memory."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") // 2
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30


def format_bytes(count: float) -> str:
    """A byte count for people: 23.5 GiB, 6.94e+283 EiB.

    >>> format_bytes(3 * 2**30)
    '3 GiB'
    """
    for unit, size in (("EiB", 2**60), ("PiB", 2**50), ("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20)):
        if count >= size:
            return f"{count / size:.3g} {unit}"
    return f"{count:.0f} bytes"


def check_memory(needed: float, what: str, advice: str = "", error: type[CourseDynamicsError] = InputError) -> None:
    """``error`` ("{what} would need about … of memory, more than half of this machine's …{advice}") when it would."""
    budget = memory_budget()
    if not needed <= budget:
        raise error(f"{what} would need about {format_bytes(needed)} of memory, more than half of this machine's "
                    f"{format_bytes(2 * budget)}{advice}")
