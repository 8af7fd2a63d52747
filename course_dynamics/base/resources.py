"""The machine's resources: one memory budget, and byte counts for people.

Every check that refuses work too large for this machine (a simulation's time
grid, a log, the comparison with Pinocchio, a robot's n×n matrices, what a
bag's compressed chunks decompress to) asks :func:`memory_budget` (most through
:func:`check_memory`), so they all use the same budget (half the physical
memory, unless :data:`BUDGET_VARIABLE` sets it) and say the same thing.
"""
from __future__ import annotations

import os
import re

from .errors import CourseDynamicsError, InputError

#: The environment variable that sets the memory budget (:func:`memory_budget`).
BUDGET_VARIABLE = "COURSE_DYNAMICS_MEMORY_BUDGET"
UNITS = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}
BUDGET_TEXT = re.compile(r"\s*(\d+(?:\.\d*)?)\s*([KMGT]?)(?:iB)?\s*", re.IGNORECASE)


def memory_budget() -> int:
    """Bytes a run may keep: half the machine's physical memory, or what ``COURSE_DYNAMICS_MEMORY_BUDGET`` says.

    The variable gives bytes, or a number with K, M, G or T (powers of 1024, an ``iB`` after them allowed;
    :func:`parse_budget`): ``512M``, ``1.5G``. It lowers the budget (a test showing a refusal without using
    gigabytes, a shared machine) or raises it (a machine with swap); empty or unset means half the physical memory.

    Returns
    -------
    int
        The budget, bytes.

    Raises
    ------
    InputError
        The variable holds anything else, or zero (``COURSE_DYNAMICS_MEMORY_BUDGET='lots': not a memory budget …``).
    """
    text = os.environ.get(BUDGET_VARIABLE, "")
    if text.strip():
        return parse_budget(text)
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") // 2
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30


def parse_budget(text: str) -> int:
    """Bytes of a budget as :data:`BUDGET_VARIABLE` gives it; InputError naming the variable if it is none.

    Parameters
    ----------
    text : str
        Bytes, or a number with K, M, G or T (powers of 1024), an ``iB`` after them allowed: ``512M``, ``1.5G``.

    Returns
    -------
    int
        The budget, bytes.

    Raises
    ------
    InputError
        Naming the variable, when ``text`` is no such number, or is less than a byte or 8 EiB or more.

    Examples
    --------
    >>> parse_budget("1.5K"), parse_budget("512 MiB"), parse_budget("4096")
    (1536, 536870912, 4096)
    """
    match = BUDGET_TEXT.fullmatch(text)
    budget = float(match[1]) * UNITS[match[2].upper()] if match else 0.0
    if not 1 <= budget < 2**63:  # a budget of a byte refuses everything; more than 8 EiB is a typing slip
        raise InputError(f"{BUDGET_VARIABLE}={text[:40]!r}: not a memory budget; give bytes, "
                         "or a number with K, M, G or T (powers of 1024), such as 512M")
    return int(budget)


def budget_text(budget: int) -> str:
    """What ``budget`` (:func:`memory_budget`'s) is, for a message: "half of this machine's 2 GiB", or the variable's.

    Parameters
    ----------
    budget : int
        The budget, bytes.

    Returns
    -------
    str
        "half of this machine's …", or "the … that COURSE_DYNAMICS_MEMORY_BUDGET allows" when the variable is set.

    Examples
    --------
    >>> budget_text(2**30) if BUDGET_VARIABLE not in os.environ else ''
    "half of this machine's 2 GiB"
    """
    if os.environ.get(BUDGET_VARIABLE, "").strip():
        return f"the {format_bytes(budget)} that {BUDGET_VARIABLE} allows"
    return f"half of this machine's {format_bytes(2 * budget)}"


def format_bytes(count: float) -> str:
    """A byte count for people: 23.5 GiB, 6.94e+283 EiB.

    Parameters
    ----------
    count : float
        Bytes.

    Returns
    -------
    str
        Three significant digits and the largest binary unit (MiB to EiB) it reaches, or whole bytes below 1 MiB.

    Examples
    --------
    >>> format_bytes(3 * 2**30)
    '3 GiB'
    """
    for unit, size in (("EiB", 2**60), ("PiB", 2**50), ("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20)):
        if count >= size:
            return f"{count / size:.3g} {unit}"
    return f"{count:.0f} bytes"


def check_memory(needed: float, what: str, advice: str = "", error: type[CourseDynamicsError] = InputError) -> None:
    """``error`` ("{what} would need about … of memory, more than half of this machine's …{advice}") when it would.

    Parameters
    ----------
    needed : float
        The bytes the work would need.
    what : str
        The work, as the message begins ("a simulation of 10⁹ steps").
    advice : str, optional
        What to do instead, appended to the message as it is (begin it with ": " or "; ").
    error : type, optional
        The :class:`~course_dynamics.base.errors.CourseDynamicsError` subclass raised;
        :class:`~course_dynamics.base.errors.InputError` by default.

    Raises
    ------
    InputError
        When ``needed`` is more than :func:`memory_budget` (or is NaN); ``error`` when that is given.

    Examples
    --------
    >>> check_memory(1024, "a small table")
    """
    budget = memory_budget()
    if not needed <= budget:
        raise error(f"{what} would need about {format_bytes(needed)} of memory, more than {budget_text(budget)}"
                    f"{advice}")


__all__ = ["BUDGET_VARIABLE", "budget_text", "check_memory", "format_bytes", "memory_budget", "parse_budget"]
